"""Merge Google Benchmark JSON files (one per suite) into one.

usage: merge_bench.py OUT.json IN.json [IN.json ...]

Run as ``tools/merge_bench.py`` by `make bench` to write results/bench.json from the
suites under bench/.
Exit codes: 0 success, 2 usage or input error, 70 internal error (a bug; its traceback
with --debug), 74 OUT.json could not be written.
"""

import json
import sys

from ..errors import OneLineParser, run_main
from ..output import refuse_inputs, write_file
from .gbench import load_benchmark_file, merge_benchmark_files


def main(argv=None):
    return run_main("merge_bench.py", _merge, argv)


def _merge(argv):
    parser = OneLineParser(prog="merge_bench.py", description="Merge Google Benchmark "
                           "JSON files (one per suite) into one.")
    parser.add_argument("out", metavar="OUT.json")
    parser.add_argument("inputs", nargs="+", metavar="IN.json")
    parser.add_argument("--debug", action="store_true", help="a bug's traceback")
    args = parser.parse_args(argv)
    out, inputs = args.out, args.inputs
    refuse_inputs([("the output", out)], [("the input", path) for path in inputs])
    merged = merge_benchmark_files([load_benchmark_file(path) for path in inputs])
    write_file(out, json.dumps(merged, indent=2) + "\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
