"""``hrbench-compare`` as installed by earlier versions of the package (their console script
names this module): the code is :mod:`hrbench_analysis.bench.benchcompare`."""

from .bench.benchcompare import main

__all__ = ["main"]
