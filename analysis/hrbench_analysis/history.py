"""``hrbench-history`` as installed by earlier versions of the package (their console script
names this module): the code is :mod:`hrbench_analysis.bench.history`."""

from .bench.history import main

__all__ = ["main"]
