#!/usr/bin/env python3
"""Merge Google Benchmark JSON files (one per suite) into one.

usage: merge_bench.py OUT.json IN.json [IN.json ...]

Used by `make bench` to write results/bench.json from the suites under bench/.
Exit codes: 0 success, 2 usage or input error.
"""

import json
import os
import sys

# analysis/ for hrbench_analysis.gbench (standard library only), so that the merge runs
# with any Python 3.11, without the package installed.
sys.path.insert(0, os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))),
                                "analysis"))

from hrbench_analysis.gbench import (  # noqa: E402
    InputError,
    load_benchmark_file,
    merge_benchmark_files,
)


def main(argv=None):
    argv = sys.argv[1:] if argv is None else argv
    if len(argv) < 2 or any(a.startswith("-") for a in argv):
        print(__doc__.strip().splitlines()[2], file=sys.stderr)
        return 2
    out, inputs = argv[0], argv[1:]
    try:
        merged = merge_benchmark_files([load_benchmark_file(path) for path in inputs])
    except InputError as e:
        print(f"merge_bench.py: error: {e}", file=sys.stderr)
        return 2
    with open(out, "w", encoding="utf-8") as f:
        json.dump(merged, f, indent=2)
        f.write("\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
