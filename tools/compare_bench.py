#!/usr/bin/env python3
"""Compare the timings of two Google Benchmark runs: ``hrbench-compare`` (``--help``).

Runs :mod:`hrbench_analysis.bench.compare_bench` of this checkout, without the package
installed: ``analysis/`` goes on the ``PYTHONPATH`` of the Python it starts.
"""

import os
import sys

if __name__ == "__main__":
    analysis = os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))),
                            "analysis")
    paths = [analysis, *filter(None, os.environ.get("PYTHONPATH", "").split(os.pathsep))]
    os.environ["PYTHONPATH"] = os.pathsep.join(paths)
    os.execv(sys.executable, [sys.executable, "-m", "hrbench_analysis.bench.compare_bench",
                              *sys.argv[1:]])
