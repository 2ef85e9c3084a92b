#!/usr/bin/env python3
"""Compare two Google Benchmark runs and fail on a significant slowdown.

usage: compare_bench.py BASELINE.json NEW.json [--threshold 0.05] [--alpha 0.05]
                        [--metric real_time|cpu_time]

Both files come from a suite run with repetitions, e.g.

    build/refine_bench --benchmark_repetitions=5 \\
        --benchmark_out=new.json --benchmark_out_format=json

Per benchmark it prints the median of the repetitions in each run, the relative
change, and the one-sided Mann-Whitney U p-value for "the new run is slower".

Exit codes: 0 no significant slowdown beyond the threshold; 1 at least one;
2 usage or input error (missing or malformed file, no benchmark in common).
See docs/ci.md.
"""

import argparse
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

from benchtools.gbench import InputError, get_repetition_times, load_benchmark_file  # noqa: E402


def _parse_args(argv):
    parser = argparse.ArgumentParser(
        prog="compare_bench.py",
        description="Compare two Google Benchmark JSON files run with repetitions; exit 1 "
                    "on a significant slowdown beyond the threshold.")
    parser.add_argument("baseline", help="Google Benchmark JSON of the baseline run")
    parser.add_argument("new", help="Google Benchmark JSON of the new run")
    parser.add_argument("--threshold", type=float, default=0.05,
                        help="relative slowdown of the median that fails (default 0.05 = 5%%)")
    parser.add_argument("--alpha", type=float, default=0.05,
                        help="significance level of the one-sided U test (default 0.05)")
    parser.add_argument("--metric", choices=("real_time", "cpu_time"), default="real_time",
                        help="which time to compare (default real_time)")
    args = parser.parse_args(argv)
    if not (args.threshold >= 0 and args.threshold < float("inf")):
        parser.error("--threshold must be a finite number >= 0")
    if not 0 < args.alpha < 1:
        parser.error("--alpha must be in (0, 1)")
    return args


def main(argv=None):
    args = _parse_args(argv)
    try:
        from benchtools.compare import get_comparison_report, print_comparison_report
    except ImportError as e:
        print(f"compare_bench.py: error: {e}; install numpy and scipy", file=sys.stderr)
        return 2
    try:
        baseline = get_repetition_times(load_benchmark_file(args.baseline), args.metric)
        new = get_repetition_times(load_benchmark_file(args.new), args.metric)
    except InputError as e:
        print(f"compare_bench.py: error: {e}", file=sys.stderr)
        return 2
    for path, times in ((args.baseline, baseline), (args.new, new)):
        if not times:
            print(f"compare_bench.py: error: {path} has no per-repetition rows; run without "
                  "--benchmark_report_aggregates_only", file=sys.stderr)
            return 2
    comparisons, only_baseline, only_new = get_comparison_report(
        baseline, new, args.threshold, args.alpha)
    if not comparisons:
        print(f"compare_bench.py: error: {args.baseline} and {args.new} have no benchmark "
              "in common", file=sys.stderr)
        return 2
    print(f"baseline {args.baseline}, new {args.new}: {args.metric}, median of repetitions")
    print_comparison_report(comparisons, only_baseline, only_new, args.threshold, args.alpha)
    return 1 if any(c.slower for c in comparisons) else 0


if __name__ == "__main__":
    sys.exit(main())
