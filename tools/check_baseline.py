#!/usr/bin/env python3
"""Check the exact counters of the engine against tests/baseline/counts.json (``--help``).

Runs :mod:`hrbench_analysis.bench.check_baseline` of this checkout, without the package
installed: ``analysis/`` goes on the ``PYTHONPATH`` of the Python it starts.
"""

import os
import sys

if __name__ == "__main__":
    analysis = os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))),
                            "analysis")
    paths = [analysis, *filter(None, os.environ.get("PYTHONPATH", "").split(os.pathsep))]
    os.environ["PYTHONPATH"] = os.pathsep.join(paths)
    os.execv(sys.executable, [sys.executable, "-m", "hrbench_analysis.bench.check_baseline",
                              *sys.argv[1:]])
