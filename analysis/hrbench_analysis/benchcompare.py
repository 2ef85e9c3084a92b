"""Timing comparison of two Google Benchmark runs with repetitions: ``hrbench-compare``.

Each benchmark is judged on its per-repetition times: the relative change of the
median, and a one-sided Mann-Whitney U test of whether the new times are
stochastically greater (slower) than the baseline's. A benchmark is a regression
only if both say so: significant at level `alpha` and slower by more than
`threshold`. In the spirit of google/benchmark's ``tools/compare.py``
(https://github.com/google/benchmark/blob/main/tools/gbench/report.py), which
uses the same test.

The command line (``hrbench-compare BASELINE.json NEW.json``, also
``tools/compare_bench.py``) is :func:`main`; its exit codes: 0 no significant slowdown
beyond the threshold, 1 at least one, 2 usage or input error (a missing or malformed
file, no per-repetition rows, no benchmark in common). See docs/ci.md.
"""

import argparse
import math
import sys
from dataclasses import dataclass

import numpy as np

from .gbench import InputError, format_time, get_repetition_times, load_benchmark_file

__all__ = ["TimingComparison", "get_timing_comparison", "get_comparison_report",
           "print_comparison_report", "min_pvalue", "main"]


@dataclass(frozen=True)
class TimingComparison:
    """The comparison of one benchmark.

    Attributes
    ----------
    name : str
        Benchmark name (``run_name``).
    baseline_median, new_median : float
        Median time per iteration of each run, in nanoseconds.
    change : float
        Relative change of the median, ``new / baseline - 1`` (dimensionless;
        +0.10 is 10% slower).
    statistic : float
        Mann-Whitney U statistic of the new times against the baseline times.
    pvalue : float
        One-sided p-value for "the new times are greater" (nan if a run has no
        repetitions).
    n_baseline, n_new : int
        Number of repetitions of each run.
    slower : bool
        True if ``pvalue <= alpha`` and ``change > threshold``: a regression.
    """

    name: str
    baseline_median: float
    new_median: float
    change: float
    statistic: float
    pvalue: float
    n_baseline: int
    n_new: int
    slower: bool


def min_pvalue(n_baseline, n_new):
    """Smallest one-sided p-value the exact U test can give.

    Parameters
    ----------
    n_baseline, n_new : int
        Number of repetitions of each run.

    Returns
    -------
    float
        ``1 / C(n_baseline + n_new, n_new)``: the p-value when every new time
        exceeds every baseline time. If it exceeds `alpha`, no slowdown can be
        significant, however large.
    """
    return 1.0 / math.comb(n_baseline + n_new, n_new)


def _timing_iv(baseline, new, threshold, alpha):
    baseline = np.asarray(baseline, dtype=float)
    new = np.asarray(new, dtype=float)
    for name, x in (("baseline", baseline), ("new", new)):
        if x.ndim != 1 or x.size == 0:
            raise ValueError(f"`{name}` must be a non-empty 1-d array of times")
        if not np.all(np.isfinite(x)) or np.any(x < 0):
            raise ValueError(f"`{name}` must hold finite non-negative times")
    if not (threshold >= 0 and math.isfinite(threshold)):
        raise ValueError("`threshold` must be a finite number >= 0")
    if not 0 < alpha < 1:
        raise ValueError("`alpha` must be in (0, 1)")
    return baseline, new


def get_timing_comparison(baseline, new, threshold=0.05, alpha=0.05, name=""):
    """Compare the repetition times of one benchmark in two runs.

    Parameters
    ----------
    baseline, new : array_like
        Per-repetition times of the baseline run and of the new run, in any one
        unit (e.g. nanoseconds per iteration).
    threshold : float, optional
        Relative slowdown of the median that counts as a regression (0.05: 5%).
    alpha : float, optional
        Significance level of the one-sided Mann-Whitney U test.
    name : str, optional
        Benchmark name, carried into the result.

    Returns
    -------
    TimingComparison
        Medians, relative change, U statistic, p-value and the verdict.

    Notes
    -----
    The test uses ``scipy.stats.mannwhitneyu(new, baseline, alternative='greater')``,
    exact for small samples without ties. With ``n`` repetitions on each side the
    smallest possible p-value is ``1 / C(2n, n)`` (see `min_pvalue`): 0.05 for
    n = 3, 0.0079 for n = 5, so use at least 5 repetitions at ``alpha = 0.05``.

    Examples
    --------
    >>> r = get_timing_comparison([100, 101, 99, 100, 102], [120, 119, 121, 122, 118])
    >>> round(r.change, 3), r.slower
    (0.2, True)
    """
    baseline, new = _timing_iv(baseline, new, threshold, alpha)
    from scipy.stats import mannwhitneyu

    base_median = float(np.median(baseline))
    new_median = float(np.median(new))
    change = new_median / base_median - 1 if base_median > 0 else (
        0.0 if new_median == 0 else math.inf)
    if baseline.size > 1 or new.size > 1:
        result = mannwhitneyu(new, baseline, alternative="greater")
        statistic, pvalue = float(result.statistic), float(result.pvalue)
    else:
        statistic, pvalue = math.nan, math.nan
    slower = bool(pvalue <= alpha and change > threshold)
    return TimingComparison(name, base_median, new_median, change, statistic, pvalue,
                            int(baseline.size), int(new.size), slower)


def get_comparison_report(baseline_times, new_times, threshold=0.05, alpha=0.05):
    """Compare every benchmark that two runs have in common.

    Parameters
    ----------
    baseline_times, new_times : dict of str to array_like
        Per-repetition times of each benchmark (as from
        `hrbench_analysis.gbench.get_repetition_times`).
    threshold, alpha : float, optional
        See `get_timing_comparison`.

    Returns
    -------
    comparisons : list of TimingComparison
        One per common benchmark, in the baseline's order.
    only_baseline, only_new : list of str
        Benchmarks present in one run only.
    """
    comparisons = [get_timing_comparison(times, new_times[name], threshold, alpha, name)
                   for name, times in baseline_times.items() if name in new_times]
    only_baseline = [n for n in baseline_times if n not in new_times]
    only_new = [n for n in new_times if n not in baseline_times]
    return comparisons, only_baseline, only_new


def print_comparison_report(comparisons, only_baseline=(), only_new=(), threshold=0.05,
                            alpha=0.05, file=None):
    """Print the comparison as a table, one benchmark per row, and a summary.

    Parameters
    ----------
    comparisons : list of TimingComparison
        As returned by `get_comparison_report`.
    only_baseline, only_new : sequence of str, optional
        Benchmarks present in one run only, listed after the table.
    threshold, alpha : float, optional
        The values used, for the summary line.
    file : file-like, optional
        Where to print (default: standard output).
    """
    def out(line=""):
        print(line, file=file)

    width = max([len("Benchmark")] + [len(c.name) for c in comparisons])
    out(f"{'Benchmark':<{width}}  {'baseline':>11}  {'new':>11}  {'change':>8}  "
        f"{'p(slower)':>9}  {'reps':>5}  verdict")
    for c in comparisons:
        verdict = "SLOWER" if c.slower else (
            "faster" if c.change < -threshold else "same")
        pvalue = "-" if math.isnan(c.pvalue) else f"{c.pvalue:.4f}"
        out(f"{c.name:<{width}}  {format_time(c.baseline_median):>11}  "
            f"{format_time(c.new_median):>11}  {c.change:>+8.1%}  {pvalue:>9}  "
            f"{c.n_baseline:>2}/{c.n_new:<2}  {verdict}")
    for name in only_baseline:
        out(f"only in the baseline: {name}")
    for name in only_new:
        out(f"only in the new run: {name}")
    weak = [c for c in comparisons if min_pvalue(c.n_baseline, c.n_new) > alpha]
    if weak:
        out(f"note: {len(weak)} benchmark(s) have too few repetitions for the test to reach "
            f"alpha {alpha} (use --benchmark_repetitions=5 or more)")
    slower = sum(c.slower for c in comparisons)
    out(f"{slower} of {len(comparisons)} benchmarks significantly slower "
        f"(median slower by more than {threshold:.0%}, one-sided Mann-Whitney U, "
        f"alpha {alpha})")


# ---------------------------------------------------------------------------------------
# The command line.


def _parse_args(argv, prog):
    parser = argparse.ArgumentParser(
        prog=prog,
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


def main(argv=None, prog="hrbench-compare"):
    """Run the command line; return the exit code (0, 1 or 2, see the module).

    Parameters
    ----------
    argv : list of str, optional
        The arguments (default: ``sys.argv[1:]``).
    prog : str, optional
        The command's name in its messages.
    """
    args = _parse_args(argv, prog)
    try:
        baseline = get_repetition_times(load_benchmark_file(args.baseline), args.metric)
        new = get_repetition_times(load_benchmark_file(args.new), args.metric)
    except InputError as e:
        print(f"{prog}: error: {e}", file=sys.stderr)
        return 2
    for path, times in ((args.baseline, baseline), (args.new, new)):
        if not times:
            print(f"{prog}: error: {path} has no per-repetition rows; run without "
                  "--benchmark_report_aggregates_only", file=sys.stderr)
            return 2
    comparisons, only_baseline, only_new = get_comparison_report(
        baseline, new, args.threshold, args.alpha)
    if not comparisons:
        print(f"{prog}: error: {args.baseline} and {args.new} have no benchmark "
              "in common", file=sys.stderr)
        return 2
    print(f"baseline {args.baseline}, new {args.new}: {args.metric}, median of repetitions")
    print_comparison_report(comparisons, only_baseline, only_new, args.threshold, args.alpha)
    return 1 if any(c.slower for c in comparisons) else 0


if __name__ == "__main__":
    sys.exit(main())
