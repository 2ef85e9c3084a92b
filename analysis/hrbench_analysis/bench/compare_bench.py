"""Compare two Google Benchmark runs and fail on a significant slowdown.

usage: compare_bench.py BASELINE.json NEW.json [--threshold 0.05] [--alpha 0.05]
                        [--metric real_time|cpu_time]
       compare_bench.py commands --base CMD --head CMD [--rounds 10] [--json] ...
                        (two shell commands timed against each other by CPU time)

Both files come from a suite run with repetitions, e.g.

    build/refine_bench --benchmark_repetitions=5 \\
        --benchmark_out=new.json --benchmark_out_format=json

Per benchmark it prints the median of the repetitions in each run, the relative
change, the two-sided p-value, the confidence interval and the noise of the ratio.

Exit codes: 0 no regression, every benchmark resolved; 1 a benchmark significantly
slower by more than the threshold; 2 usage or input error (a missing, oversized or
malformed file, no benchmark in common); 3 inconclusive; 70 internal error (a bug; its
traceback with --debug); 74 the report could not be written (standard output full or
closed). See docs/ci.md. The same command is ``hrbench-compare`` of the installed analysis
package (:mod:`hrbench_analysis.bench.benchcompare`); ``tools/compare_bench.py`` runs it
from a checkout, without installing the package (it needs numpy and scipy).
"""

import sys


def main(argv=None):
    try:
        from .benchcompare import main as compare_main
    except ImportError as e:
        print(f"compare_bench.py: error: {e}; install numpy and scipy", file=sys.stderr)
        return 2
    return compare_main(argv, prog="compare_bench.py")


if __name__ == "__main__":
    sys.exit(main())
