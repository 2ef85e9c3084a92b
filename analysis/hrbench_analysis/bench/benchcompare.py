"""Timing comparison of two Google Benchmark runs with repetitions: ``hrbench-compare``.

Each benchmark is judged on its per-repetition times, in logs (a ratio of times is a
difference of logs):

- the change: the ratio of the medians, new / baseline (unpaired), or the median of the
  per-round ratios (paired: rounds that ran both builds under the same load);
- a two-sided rank test of "no change": Mann-Whitney U (unpaired) or the Wilcoxon
  signed-rank test of the per-round log ratios (paired), both from ``scipy.stats``;
- the confidence interval (level ``1 - alpha``) of the ratio: the shifts that the same
  test does not reject, so the interval excludes 1 exactly when ``p <= alpha``; its
  half-width is the *noise*, the smallest change the measurement can resolve.

The verdict of a benchmark:

``SLOWER``
    ``p <= alpha`` and the change exceeds ``threshold``: a regression.
``inconclusive``
    not a regression, but the noise exceeds ``threshold`` and the interval reaches above
    ``1 + threshold``: a slowdown the size of the threshold can be neither found nor
    ruled out (too noisy, or too few repetitions for the test to reach ``alpha``).
``slower`` / ``faster``
    ``p <= alpha``, a change within the threshold (slower) or a speedup (faster).
``no significant change``
    otherwise.

The geometric mean of the ratios over the benchmarks (Google Benchmark's
``OVERALL_GEOMEAN``) summarises a run. In the spirit of google/benchmark's
``tools/compare.py`` (https://github.com/google/benchmark/blob/main/tools/gbench/report.py).

The command line (``hrbench-compare BASELINE.json NEW.json``, also
``tools/compare_bench.py``) is :func:`main`; its exit codes: 0 no regression and every
benchmark resolved, 1 at least one regression, 2 usage or input error (a missing,
oversized or malformed file, a time that is not a finite number >= 0, no per-repetition
rows, no benchmark in common, unequal rounds with ``--paired``), 3 no regression but at
least one benchmark inconclusive, 70 an internal error (a bug), 74 the report could not
be written. See docs/ci.md.

``hrbench-compare commands --base CMD --head CMD`` times two shell commands in interleaved
rounds and judges their CPU times with the same paired rule and exit codes
(:mod:`hrbench_analysis.bench.cmdtiming`).
"""

import math
import sys
import warnings
from dataclasses import dataclass

import numpy as np

from ..errors import OneLineParser, run_main
from .gbench import InputError, format_time, get_repetition_times, load_benchmark_file

__all__ = ["TimingComparison", "get_timing_comparison", "get_comparison_report",
           "get_geomean", "get_overall_verdict", "print_comparison_report", "min_pvalue",
           "REGRESSION", "SLOWER", "FASTER", "NO_CHANGE", "INCONCLUSIVE", "EXIT_CODES",
           "main"]

# Verdicts of one benchmark.
REGRESSION = "SLOWER"
SLOWER = "slower"
FASTER = "faster"
NO_CHANGE = "no significant change"
INCONCLUSIVE = "inconclusive"

# Exit codes of the comparison (and of the CI gates) by overall verdict.
EXIT_CODES = {"PASS": 0, "FAIL": 1, "INCONCLUSIVE": 3}


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
        Relative change, ``ratio - 1`` (+0.10 is 10% slower), the ratio being new /
        baseline: of the medians (unpaired) or the median of the per-round ratios
        (paired).
    ci_low, ci_high : float
        Confidence interval of the ratio at level ``1 - alpha`` (``0`` and ``inf`` where
        the test cannot bound it).
    noise : float
        Half-width of the interval, relative (``expm1`` of half its width in logs):
        ``inf`` if unbounded.
    statistic, pvalue : float
        Statistic and two-sided p-value of the test (Mann-Whitney U, or Wilcoxon
        signed-rank when paired).
    n_baseline, n_new : int
        Number of repetitions (rounds) of each run.
    paired : bool
        Whether the repetitions were compared round by round.
    verdict : str
        One of `REGRESSION`, `SLOWER`, `FASTER`, `NO_CHANGE`, `INCONCLUSIVE`.
    """

    name: str
    baseline_median: float
    new_median: float
    change: float
    ci_low: float
    ci_high: float
    noise: float
    statistic: float
    pvalue: float
    n_baseline: int
    n_new: int
    paired: bool
    verdict: str

    @property
    def regression(self):
        """Significantly slower by more than the threshold."""
        return self.verdict == REGRESSION

    @property
    def inconclusive(self):
        return self.verdict == INCONCLUSIVE


def min_pvalue(n_baseline, n_new, paired=False):
    """Smallest two-sided p-value the exact test can give.

    Parameters
    ----------
    n_baseline, n_new : int
        Number of repetitions (rounds) of each run.
    paired : bool, optional
        Wilcoxon signed-rank on ``n_new`` pairs instead of Mann-Whitney U.

    Returns
    -------
    float
        ``2 / C(n_baseline + n_new, n_new)`` (U: every new time above every baseline
        time), or ``2 / 2**n`` (signed-rank: every round slower); at most 1. If it
        exceeds `alpha`, no change can be significant, however large.
    """
    if paired:
        return min(1.0, 2.0 / 2 ** n_new)
    return min(1.0, 2.0 / math.comb(n_baseline + n_new, n_new))


def _timing_iv(baseline, new, threshold, alpha, paired):
    baseline = np.asarray(baseline, dtype=float)
    new = np.asarray(new, dtype=float)
    for name, x in (("baseline", baseline), ("new", new)):
        if x.ndim != 1 or x.size == 0:
            raise ValueError(f"`{name}` must be a non-empty 1-d array of times")
        if not np.all(np.isfinite(x)) or np.any(x <= 0):
            raise ValueError(f"`{name}` must hold finite positive times")
    if paired and baseline.size != new.size:
        raise ValueError(f"paired comparison of {baseline.size} baseline and {new.size} "
                         "new rounds: `baseline` and `new` must have one time per round")
    if not (threshold >= 0 and math.isfinite(threshold)):
        raise ValueError("`threshold` must be a finite number >= 0")
    if not 0 < alpha < 1:
        raise ValueError("`alpha` must be in (0, 1)")
    return baseline, new


def _pvalues(x, y, shifts, paired):
    """Two-sided p-values of "log y - shift has the distribution of log x", per shift."""
    from scipy.stats import mannwhitneyu, wilcoxon

    moved = y[None, :] - shifts[:, None]
    with warnings.catch_warnings(), np.errstate(invalid="ignore", divide="ignore"):
        # A row of zeros (equal times) has p = 1 or nan: both mean "not rejected".
        warnings.simplefilter("ignore", RuntimeWarning)
        if paired:
            # The exact null distribution, also with ties (where scipy rounds the
            # statistic conservatively) rather than a permutation test per shift.
            result = wilcoxon(moved - x[None, :], axis=1,
                              method="exact" if x.size <= 50 else "asymptotic")
        else:
            result = mannwhitneyu(moved, x[None, :], axis=1, alternative="two-sided")
    p = np.asarray(result.pvalue, dtype=float)
    return np.where(np.isnan(p), 1.0, p), np.asarray(result.statistic, dtype=float)


def _confidence_interval(x, y, paired, alpha):
    """The log shifts the test does not reject at `alpha`: (low, high), +-inf if unbounded.

    The p-value changes only where a shift makes two values tie: at the Walsh averages of
    the log ratios (paired) or at the differences of every new and baseline log time
    (unpaired). So the test runs once in each interval between those edges (and beyond
    them), and the interval's closure ends at edges."""
    if paired:
        d = y - x
        i, j = np.triu_indices(d.size)
        edges = np.unique((d[i] + d[j]) / 2)
    else:
        edges = np.unique((y[None, :] - x[:, None]).ravel())
    probes = np.concatenate(([edges[0] - 1], (edges[:-1] + edges[1:]) / 2, [edges[-1] + 1]))
    p, _ = _pvalues(x, y, probes, paired)
    kept = np.flatnonzero(p > alpha)
    if kept.size == 0:  # every interval rejected: the times have no spread at all
        return float(np.median(edges)), float(np.median(edges))
    low = -math.inf if kept[0] == 0 else float(edges[kept[0] - 1])
    high = math.inf if kept[-1] == edges.size else float(edges[kept[-1]])
    return low, high


def get_timing_comparison(baseline, new, threshold=0.05, alpha=0.05, name="", paired=False):
    """Compare the repetition times of one benchmark in two runs.

    Parameters
    ----------
    baseline, new : array_like
        Per-repetition times of the baseline run and of the new run, in any one
        positive unit (e.g. nanoseconds per iteration). Paired: one each per round, in
        round order.
    threshold : float, optional
        Relative slowdown that counts as a regression (0.05: 5%); also the largest noise
        at which the comparison is conclusive.
    alpha : float, optional
        Significance level of the two-sided test, and ``1 - alpha`` the level of the
        confidence interval.
    name : str, optional
        Benchmark name, carried into the result.
    paired : bool, optional
        Compare round by round (Wilcoxon signed-rank of the log ratios) instead of as
        two independent samples (Mann-Whitney U).

    Returns
    -------
    TimingComparison
        Medians, change, confidence interval, noise, test and verdict (see the module).

    Notes
    -----
    The tests are ``scipy.stats.mannwhitneyu`` and ``scipy.stats.wilcoxon``, exact for
    small samples without ties. The smallest p-value they can give (`min_pvalue`) is
    0.0079 for 5 repetitions a side (U) and 0.031 for 6 rounds (signed-rank): with fewer
    the interval is unbounded and the verdict inconclusive.

    Examples
    --------
    >>> r = get_timing_comparison([100, 101, 99, 100, 102], [120, 119, 121, 122, 118])
    >>> round(r.change, 3), r.verdict, r.pvalue < 0.05
    (0.2, 'SLOWER', True)
    """
    baseline, new = _timing_iv(baseline, new, threshold, alpha, paired)
    base_median, new_median = float(np.median(baseline)), float(np.median(new))
    x, y = np.log(baseline), np.log(new)
    ratio = float(np.exp(np.median(y - x))) if paired else new_median / base_median
    p, statistic = _pvalues(x, y, np.zeros(1), paired)
    pvalue, statistic = float(p[0]), float(statistic[0])
    low, high = _confidence_interval(x, y, paired, alpha)
    noise = math.expm1((high - low) / 2) if math.isfinite(high - low) else math.inf
    if pvalue <= alpha and ratio - 1 > threshold:
        verdict = REGRESSION
    elif noise > threshold and math.exp(high) > 1 + threshold:
        verdict = INCONCLUSIVE
    elif pvalue <= alpha:
        verdict = SLOWER if ratio > 1 else FASTER
    else:
        verdict = NO_CHANGE
    return TimingComparison(name, base_median, new_median, ratio - 1, math.exp(low),
                            math.exp(high), noise, statistic, pvalue, int(x.size),
                            int(y.size), bool(paired), verdict)


def get_comparison_report(baseline_times, new_times, threshold=0.05, alpha=0.05,
                          paired=False):
    """Compare every benchmark that two runs have in common.

    Parameters
    ----------
    baseline_times, new_times : dict of str to array_like
        Per-repetition times of each benchmark (as from
        `hrbench_analysis.bench.gbench.get_repetition_times`).
    threshold, alpha, paired : optional
        See `get_timing_comparison`.

    Returns
    -------
    comparisons : list of TimingComparison
        One per common benchmark, in the baseline's order.
    only_baseline, only_new : list of str
        Benchmarks present in one run only.
    """
    comparisons = [get_timing_comparison(times, new_times[name], threshold, alpha, name,
                                         paired)
                   for name, times in baseline_times.items() if name in new_times]
    only_baseline = [n for n in baseline_times if n not in new_times]
    only_new = [n for n in new_times if n not in baseline_times]
    return comparisons, only_baseline, only_new


def get_geomean(comparisons):
    """The geometric means over the benchmarks (Google Benchmark's ``OVERALL_GEOMEAN``).

    Returns
    -------
    baseline, new : float
        Geometric means of the baseline and of the new medians, in nanoseconds.
    change : float
        Geometric mean of the benchmarks' ratios, minus 1 (unpaired: ``new / baseline -
        1`` of the two means above).
    """
    def gmean(values):
        return float(np.exp(np.mean(np.log(values))))
    return (gmean([c.baseline_median for c in comparisons]),
            gmean([c.new_median for c in comparisons]),
            gmean([1 + c.change for c in comparisons]) - 1)


def get_overall_verdict(comparisons):
    """``FAIL`` on any regression, else ``INCONCLUSIVE`` if any benchmark is, else
    ``PASS``; its exit code is ``EXIT_CODES[verdict]``."""
    if any(c.regression for c in comparisons):
        return "FAIL"
    return "INCONCLUSIVE" if any(c.inconclusive for c in comparisons) else "PASS"


def format_interval(c):
    """The confidence interval of a comparison as changes: ``[-2.1%, +3.4%]``."""
    def bound(ratio):  # an unbounded interval: ratio 0 (-100%) or +inf
        return f"{ratio - 1:+.1%}" if ratio < math.inf else "+inf"
    return f"[{bound(c.ci_low)}, {bound(c.ci_high)}]"


def format_noise(c):
    return f"{c.noise:.1%}" if math.isfinite(c.noise) else "inf"


def test_name(paired):
    return "Wilcoxon signed-rank of paired rounds" if paired else "Mann-Whitney U"


def summary_line(comparisons, threshold, alpha):
    """The closing line of a report: regressions, inconclusive benchmarks, the rule."""
    paired = any(c.paired for c in comparisons)
    regressions = sum(c.regression for c in comparisons)
    blind = sum(c.inconclusive for c in comparisons)
    return (f"{regressions} of {len(comparisons)} benchmarks significantly slower by more "
            f"than {threshold:.0%}, {blind} inconclusive (noise above {threshold:.0%}); "
            f"two-sided {test_name(paired)}, alpha {alpha}")


def print_comparison_report(comparisons, only_baseline=(), only_new=(), threshold=0.05,
                            alpha=0.05, file=None):
    """Print the comparison as a table, one benchmark per row, the geometric mean and a
    summary.

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

    level = f"{1 - alpha:.0%} CI"
    width = max([len("OVERALL_GEOMEAN")] + [len(c.name) for c in comparisons])
    out(f"{'Benchmark':<{width}}  {'baseline':>11}  {'new':>11}  {'change':>8}  "
        f"{level:>17}  {'p':>6}  {'noise':>6}  {'reps':>5}  verdict")
    for c in comparisons:
        out(f"{c.name:<{width}}  {format_time(c.baseline_median):>11}  "
            f"{format_time(c.new_median):>11}  {c.change:>+8.1%}  {format_interval(c):>17}  "
            f"{c.pvalue:>6.4f}  {format_noise(c):>6}  {c.n_baseline:>2}/{c.n_new:<2}  "
            f"{c.verdict}")
    base, new, change = get_geomean(comparisons)
    out(f"{'OVERALL_GEOMEAN':<{width}}  {format_time(base):>11}  {format_time(new):>11}  "
        f"{change:>+8.1%}")
    for name in only_baseline:
        out(f"only in the baseline: {name}")
    for name in only_new:
        out(f"only in the new run: {name}")
    weak = [c for c in comparisons if min_pvalue(c.n_baseline, c.n_new, c.paired) > alpha]
    if weak:
        out(f"note: {len(weak)} benchmark(s) have too few repetitions for the test to reach "
            f"alpha {alpha}: inconclusive whatever the times (use 6 or more)")
    out(summary_line(comparisons, threshold, alpha))


# ---------------------------------------------------------------------------------------
# The command line.


def _parse_args(argv, prog):
    parser = OneLineParser(
        prog=prog,
        description="Compare two Google Benchmark JSON files run with repetitions; exit 1 "
                    "on a significant slowdown beyond the threshold, 3 if a benchmark is "
                    "too noisy to tell. `%(prog)s commands --base CMD --head CMD` times "
                    "two shell commands instead (`%(prog)s commands --help`).")
    parser.add_argument("baseline", help="Google Benchmark JSON of the baseline run")
    parser.add_argument("new", help="Google Benchmark JSON of the new run")
    parser.add_argument("--threshold", type=float, default=0.05,
                        help="relative slowdown that fails, and the largest noise that "
                             "decides (default 0.05 = 5%%)")
    parser.add_argument("--alpha", type=float, default=0.05,
                        help="significance level of the two-sided test (default 0.05)")
    parser.add_argument("--metric", choices=("real_time", "cpu_time"), default="real_time",
                        help="which time to compare (default real_time)")
    parser.add_argument("--paired", action="store_true",
                        help="the k-th repetitions of both files ran in the same round "
                             "(interleaved rounds merged by merge_bench.py): compare round "
                             "by round, Wilcoxon signed-rank")
    parser.add_argument("--debug", action="store_true",
                        help="print the traceback of an internal error (exit code 70)")
    args = parser.parse_args(argv)
    if not (args.threshold >= 0 and args.threshold < float("inf")):
        parser.error("--threshold must be a finite number >= 0")
    if not 0 < args.alpha < 1:
        parser.error("--alpha must be in (0, 1)")
    return args


def main(argv=None, prog="hrbench-compare"):
    """Run the command line; return the exit code (0, 1, 2, 3, 70 or 74, see the module).

    Parameters
    ----------
    argv : list of str, optional
        The arguments (default: ``sys.argv[1:]``).
    prog : str, optional
        The command's name in its messages.
    """
    argv = sys.argv[1:] if argv is None else list(argv)
    if argv[:1] == ["commands"]:  # a file named "commands" is given as ./commands
        from . import cmdtiming
        return run_main(prog, lambda a: cmdtiming.main(a[1:], prog), argv)
    return run_main(prog, lambda a: _compare(a, prog), argv)


def _compare(argv, prog):
    args = _parse_args(argv, prog)
    times = {}
    for path in (args.baseline, args.new):
        data = load_benchmark_file(path)
        try:
            times[path] = get_repetition_times(data, args.metric)
        except InputError as e:
            raise InputError(f"{path}: {e}") from None
        if not times[path]:
            raise InputError(f"{path} has no per-repetition rows; run without "
                             "--benchmark_report_aggregates_only")
    baseline, new = times[args.baseline], times[args.new]
    try:
        comparisons, only_baseline, only_new = get_comparison_report(
            baseline, new, args.threshold, args.alpha, args.paired)
    except ValueError as e:
        raise InputError(str(e)) from None
    if not comparisons:
        raise InputError(f"{args.baseline} and {args.new} have no benchmark in common")
    print(f"baseline {args.baseline}, new {args.new}: {args.metric}, "
          + ("per-round ratios" if args.paired else "median of repetitions"))
    print_comparison_report(comparisons, only_baseline, only_new, args.threshold, args.alpha)
    overall = get_overall_verdict(comparisons)
    print(overall)
    return EXIT_CODES[overall]


if __name__ == "__main__":
    sys.exit(main())
