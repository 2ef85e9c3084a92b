"""Paired timing of two shell commands: ``hrbench-compare commands``.

Any two commands (an outside engine and hrbench, two builds of one program) are run in
interleaved rounds, one run of each per round, and compared by the CPU time of each
run's process tree: the user + system time of the shell and of every descendant it
waited for (the growth of ``getrusage(RUSAGE_CHILDREN)`` across the run; a process left
running in the background when the command exits is ended, and its time is not counted).
Rounds pair the two commands under the same load, so the change is judged on the
per-round ratios head / base exactly as ``hrbench-compare --paired`` judges a benchmark:
:func:`hrbench_analysis.bench.benchcompare.get_timing_comparison` gives the median ratio, the
two-sided Wilcoxon signed-rank test of the log ratios, the confidence interval, the noise
and the verdict (``SLOWER``, ``slower``, ``faster``, ``no significant change``,
``inconclusive``), with the same exit codes: 0 pass, 1 ``SLOWER``, 3 inconclusive, 2 an
error of input or of a command (one that fails or runs past ``--timeout``).

Each command runs with ``sh -c`` (arguments, pipes and redirections as typed), standard
input empty, standard output discarded (or written to ``--output-dir``), in a process
group of its own that is killed with the command's children when it exits or times out
(:func:`hrbench_analysis.engine.run_engine`). Wall time is measured beside CPU time and
reported, not judged: on a shared machine it measures the load as much as the command.

The running part is standard library only (the CI gates use it); the comparison needs
numpy and scipy.
"""

import math
import os
import random
import resource
import statistics
from dataclasses import dataclass

from ..engine import run_engine
from ..errors import AnalysisError, one_line

__all__ = ["CommandError", "CommandRun", "SIDES", "ORDERS", "DEFAULT_TIMEOUT",
           "round_orders", "time_command", "run_rounds", "compare_runs", "wall_ratio", "main"]

SIDES = ("base", "head")
#: ``alternate``: base first in odd rounds (1, 3, ...), head first in even ones, as the CI
#: gates do; ``random``: each round's order drawn from ``random.Random(seed)``.
ORDERS = ("alternate", "random")
#: Seconds one run of a command may take before it is ended with its children.
DEFAULT_TIMEOUT = 600.0
#: Characters of a failing command's standard error quoted in the error line.
STDERR_QUOTED = 300

# Runs stdout of the command named by $1 into the file named by $2 (/dev/null to discard)
# without quoting either into the script.
_WRAPPER = 'exec sh -c "$1" >"$2"'


class CommandError(AnalysisError, RuntimeError):
    """A timed command failed, ran past its timeout or could not be started (exit 2)."""


@dataclass(frozen=True)
class CommandRun:
    """One timed run: CPU time (user + system) of its process tree and wall time, s."""

    cpu_seconds: float
    wall_seconds: float


def round_orders(rounds, order="alternate", seed=0):
    """The sides in the order they run, per round: a list of ``("base", "head")`` or
    ``("head", "base")``, one per round."""
    if order == "alternate":
        return [SIDES if r % 2 == 0 else SIDES[::-1] for r in range(rounds)]
    if order == "random":
        rng = random.Random(seed)
        return [SIDES if rng.random() < 0.5 else SIDES[::-1] for _ in range(rounds)]
    raise ValueError(f"order {order!r} is not one of {', '.join(ORDERS)}")


def _children_cpu():
    usage = resource.getrusage(resource.RUSAGE_CHILDREN)
    return usage.ru_utime + usage.ru_stime


def time_command(command, what, timeout=DEFAULT_TIMEOUT, env=None, output=os.devnull):
    """Run a shell command once and measure it.

    Parameters
    ----------
    command : str
        A ``sh -c`` command line.
    what : str
        The run, for the error message (``"base command in round 3"``).
    timeout : float, optional
        Seconds it may take; then its process group is killed and it fails.
    env : dict of str to str, optional
        Variables added to the environment.
    output : str, optional
        File for its standard output (default discarded).

    Returns
    -------
    CommandRun

    Raises
    ------
    CommandError
        Its exit code is not 0 (the message quotes the end of its standard error), it
        ran past `timeout`, or it used no measurable CPU time.

    Notes
    -----
    The CPU time is the growth of this process' ``RUSAGE_CHILDREN`` across the run, so
    no other child of this process may be reaped meanwhile: the runs are sequential.
    """
    argv = ["sh", "-c", _WRAPPER, "sh", command, output]
    if env:
        argv = ["env", *(f"{k}={v}" for k, v in env.items()), *argv]
    before = _children_cpu()
    run = run_engine(argv, timeout=timeout)
    cpu = _children_cpu() - before
    if run.stopped:
        raise CommandError(f"the {what} {run.reason}")
    if run.exit_code != 0:
        tail = one_line(run.stderr.strip())[-STDERR_QUOTED:] or "no message on stderr"
        why = (f"signal {-run.exit_code}" if run.exit_code < 0
               else f"exit code {run.exit_code}")
        raise CommandError(f"the {what} failed ({why}): {tail}")
    if not cpu > 0:
        raise CommandError(f"the {what} used no measurable CPU time; time a command that "
                           "computes for at least a few milliseconds")
    return CommandRun(cpu, run.wall_seconds)


def run_rounds(commands, rounds, warmup=0, order="alternate", seed=0,
               timeout=DEFAULT_TIMEOUT, env=None, output_dir=None, log=None):
    """Time two commands in interleaved rounds.

    Parameters
    ----------
    commands : dict
        ``{"base": str, "head": str}``, the shell commands.
    rounds : int
        Measured rounds (one run of each command per round).
    warmup : int, optional
        Rounds run first and not measured (caches, page cache, CPU frequency).
    order, seed : optional
        See :func:`round_orders`; the warm-up rounds alternate.
    timeout : float, optional
        Seconds per run (:func:`time_command`).
    env : callable, optional
        ``env(side, round)`` (round 1-based; 0 for a warm-up) gives variables for that run.
    output_dir : str, optional
        Write each measured run's standard output to ``{side}-{round:03d}.out`` there.
    log : callable, optional
        Takes a progress line after each round.

    Returns
    -------
    runs : dict
        ``{side: [CommandRun per round]}``.
    orders : list of tuple
        The order of each measured round.
    """
    orders = round_orders(rounds, order, seed)
    runs = {side: [] for side in SIDES}
    plan = [(0, o) for o in round_orders(warmup)] + list(enumerate(orders, 1))
    for r, sides in plan:
        for side in sides:
            label = f"round {r}" if r else "a warm-up round"
            out = (os.path.join(output_dir, f"{side}-{r:03d}.out") if output_dir and r
                   else os.devnull)
            run = time_command(commands[side], f"{side} command in {label}", timeout,
                               env(side, r) if env else None, out)
            if r:
                runs[side].append(run)
        if log:
            log(f"{'round ' + str(r) + '/' + str(rounds) if r else 'warm-up round'} "
                f"({' then '.join(sides)})")
    return runs, orders


def _spread(values):
    """Median, first and third quartile (statistics' inclusive method)."""
    if len(values) < 2:
        return values[0], values[0], values[0]
    q1, q2, q3 = statistics.quantiles(values, n=4, method="inclusive")
    return statistics.median(values), q1, q3


def compare_runs(runs, threshold=0.05, alpha=0.05):
    """The paired comparison of CPU times, head / base (numpy and scipy).

    Returns
    -------
    comparison : hrbench_analysis.bench.benchcompare.TimingComparison
        Named ``"cpu time"``, times in nanoseconds.
    wall_ratio : float
        Median of the per-round wall-time ratios head / base (reported, not judged).
    """
    from .benchcompare import get_timing_comparison

    cpu = {side: [r.cpu_seconds * 1e9 for r in runs[side]] for side in SIDES}
    comparison = get_timing_comparison(cpu["base"], cpu["head"], threshold, alpha,
                                       "cpu time", paired=True)
    return comparison, wall_ratio(runs)


def wall_ratio(runs):
    """Median of the per-round wall-time ratios head / base."""
    return statistics.median(h.wall_seconds / b.wall_seconds
                             for b, h in zip(runs["base"], runs["head"], strict=True))


def result_dict(commands, runs, orders, comparison, wall_median_ratio, args):
    """The JSON object of ``--json`` (fields in docs/benchmarks.md)."""
    from .benchcompare import get_overall_verdict

    def finite(x):  # JSON has no infinity: an unbounded end is null
        return x if math.isfinite(x) else None

    sides = {}
    for side in SIDES:
        cpu = [r.cpu_seconds for r in runs[side]]
        wall = [r.wall_seconds for r in runs[side]]
        median, q1, q3 = _spread(cpu)
        sides[side] = {"command": commands[side], "cpu_seconds": cpu, "wall_seconds": wall,
                       "cpu_median": median, "cpu_q1": q1, "cpu_q3": q3,
                       "wall_median": statistics.median(wall)}
    return {"base": sides["base"], "head": sides["head"],
            "rounds": len(orders), "warmup": args.warmup, "order": args.order,
            "seed": args.seed if args.order == "random" else None,
            "round_order": [list(o) for o in orders], "timeout": args.timeout,
            "ratio": 1 + comparison.change, "ci_low": finite(comparison.ci_low),
            "ci_high": finite(comparison.ci_high), "confidence": 1 - args.alpha,
            "noise": finite(comparison.noise), "test": "wilcoxon signed-rank",
            "statistic": comparison.statistic, "pvalue": comparison.pvalue,
            "alpha": args.alpha, "threshold": args.threshold,
            "verdict": comparison.verdict, "overall": get_overall_verdict([comparison]),
            "wall_ratio": wall_median_ratio}


def _seconds(x):
    from .gbench import format_time
    return format_time(x * 1e9)


def _ratio_interval(c):
    high = f"{c.ci_high:.3f}" if math.isfinite(c.ci_high) else "inf"
    return f"[{c.ci_low:.3f}, {high}]"


def print_report(result, comparison, file=None):
    """The text report: per command the median and quartiles, then the paired ratio."""
    from .benchcompare import format_noise, min_pvalue

    def out(line=""):
        print(line, file=file)

    how = ("alternating, base first in odd rounds" if result["order"] == "alternate"
           else f"random per round, seed {result['seed']}")
    for side in SIDES:
        out(f"{side}: {result[side]['command']}")
    out(f"{result['rounds']} rounds after {result['warmup']} warm-up round(s), order "
        f"{how}; CPU time (user + sys) of each command's process tree")
    out(f"{'':4}  {'cpu median':>10}  {'cpu quartiles':>21}  {'wall median':>11}")
    for side in SIDES:
        s = result[side]
        out(f"{side:<4}  {_seconds(s['cpu_median']):>10}  "
            f"{'[' + _seconds(s['cpu_q1']) + ', ' + _seconds(s['cpu_q3']) + ']':>21}  "
            f"{_seconds(s['wall_median']):>11}")
    c = comparison
    out(f"head/base cpu time: ratio {result['ratio']:.3f} (median of per-round ratios), "
        f"{result['confidence']:.0%} CI {_ratio_interval(c)}, noise {format_noise(c)}, "
        f"Wilcoxon signed-rank p = {c.pvalue:.4f}")
    out(f"head/base wall time: ratio {result['wall_ratio']:.3f} (median of per-round "
        "ratios, not judged)")
    if min_pvalue(c.n_baseline, c.n_new, True) > result["alpha"]:
        out(f"note: {c.n_new} rounds are too few for the test to reach alpha "
            f"{result['alpha']}: inconclusive whatever the times (use 6 or more)")
    out(f"verdict: {c.verdict} (SLOWER: p <= {result['alpha']} and slower by more than "
        f"{result['threshold']:.0%}; inconclusive: noise above {result['threshold']:.0%})")
    out(result["overall"])


# ---------------------------------------------------------------------------------------
# The command line.


def _parse_args(argv, prog):
    import argparse

    from ..cli import Parser, positive_int, positive_number

    def count(text):  # an integer >= 0
        try:
            return positive_int(text) if text.strip() != "0" else 0
        except argparse.ArgumentTypeError:
            raise argparse.ArgumentTypeError(f"{text!r} is not an integer >= 0") from None

    parser = Parser(
        prog=f"{prog} commands",
        description="Time two shell commands in interleaved rounds by the CPU time of "
                    "their process trees and compare them round by round; exit 1 if head "
                    "is significantly slower than base by more than the threshold, 3 if "
                    "too noisy to tell, 2 if a command fails.")
    parser.add_argument("--base", required=True, metavar="CMD", help="the base command")
    parser.add_argument("--head", required=True, metavar="CMD",
                        help="the command compared with it")
    parser.add_argument("--rounds", type=positive_int, default=10,
                        help="measured rounds, one run of each command per round "
                             "(default 10; at least 6 for alpha 0.05)")
    parser.add_argument("--warmup", type=count, default=1, metavar="K",
                        help="rounds run first and not measured (default 1)")
    parser.add_argument("--order", choices=ORDERS, default="alternate",
                        help="alternate (default: base first in odd rounds) or random "
                             "per round")
    parser.add_argument("--seed", type=int, default=0,
                        help="seed of --order random (default 0)")
    parser.add_argument("--threshold", type=float, default=0.05,
                        help="relative slowdown that fails, and the largest noise that "
                             "decides (default 0.05 = 5%%)")
    parser.add_argument("--alpha", type=float, default=0.05,
                        help="significance level of the two-sided test (default 0.05)")
    parser.add_argument("--timeout", type=positive_number, default=DEFAULT_TIMEOUT,
                        metavar="S", help="seconds one run may take before it is ended "
                        f"with its children (default {DEFAULT_TIMEOUT:g})")
    parser.add_argument("--output-dir", metavar="DIR",
                        help="keep each measured run's standard output as "
                             "DIR/{base,head}-NNN.out (default: discarded)")
    parser.add_argument("--json", action="store_true",
                        help="print the result as one JSON object instead of the text")
    args = parser.parse_args(argv)
    if args.rounds > 10000:
        parser.error("--rounds must be at most 10000")
    if not (args.threshold >= 0 and math.isfinite(args.threshold)):
        parser.error("--threshold must be a finite number >= 0")
    if not 0 < args.alpha < 1:
        parser.error("--alpha must be in (0, 1)")
    for side in SIDES:
        if not getattr(args, side).strip():
            parser.error(f"--{side} must not be empty")
    if args.output_dir is not None and not os.path.isdir(args.output_dir):
        parser.error(f"--output-dir {args.output_dir}: no such folder")
    return args


def main(argv, prog="hrbench-compare"):
    """The body of ``hrbench-compare commands`` (run through ``run_main``); returns the
    exit code."""
    import json
    import sys

    args = _parse_args(argv, prog)
    commands = {side: getattr(args, side) for side in SIDES}
    runs, orders = run_rounds(commands, args.rounds, args.warmup, args.order, args.seed,
                              args.timeout, output_dir=args.output_dir)
    comparison, wall = compare_runs(runs, args.threshold, args.alpha)
    result = result_dict(commands, runs, orders, comparison, wall, args)
    if args.json:
        print(json.dumps(result, indent=1))
    else:
        print_report(result, comparison, file=sys.stdout)
    from .benchcompare import EXIT_CODES
    return EXIT_CODES[result["overall"]]
