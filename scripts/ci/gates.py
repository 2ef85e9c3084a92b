#!/usr/bin/env python3
"""hrbench's CI gates on a change: the exact count baseline and the timing comparison.

usage: gates BASE_REF HEAD_REF [--rounds N] [--threshold T] [--alpha A] [--filter REGEX]
             [--metric cpu_time|real_time] [--min-time S] [--bench-cmd CMD | --time-cmd CMD]
             [--summary FILE] [--workdir DIR] [--base-build DIR] [--head-build DIR]
             [--project DIR] [--jobs N] [--no-ccache] [--skip-counts] [--skip-timing]

Builds BASE_REF and HEAD_REF, each in its own `git worktree` under --workdir (Release,
targets hrbench and refine_bench; a commit's finished build is reused;
hrbench_analysis.bench.builds), or takes prebuilt build directories (--base-build,
--head-build). Then two gates:

- counts: tools/check_baseline.py with HEAD's engine against HEAD's
  tests/baseline/counts.json. Any difference fails and prints the diff of counters. If
  HEAD changed counts.json relative to BASE (updated on purpose), that is reported with
  the diff between the two files, as information.
- timing: --rounds interleaved rounds, one run of each build's benchmarks per round
  (refine_bench, or --bench-cmd: any command writing Google Benchmark JSON), the order
  alternating (base first in odd rounds, head first in even ones). Rounds pair the two
  builds under the same load, so each benchmark is judged on its per-round ratios head /
  base (hrbench_analysis.bench.benchcompare): the two-sided Wilcoxon signed-rank test and the
  confidence interval it gives. A benchmark is SLOWER (the gate fails) if p <= --alpha
  and the ratio exceeds 1 + --threshold; inconclusive if the interval is wider than
  +-threshold and reaches above 1 + threshold; else faster, slower (within the
  threshold) or no significant change. --time-cmd CMD times any shell command instead,
  by the CPU time of its process tree after one warm-up round (hrbench_analysis.bench.cmdtiming,
  as `hrbench-compare commands`): another project's CI gates its own program, built at
  BASE and HEAD.

Prints a Markdown summary and writes it to --summary FILE and, when set, appends it to
$GITHUB_STEP_SUMMARY ($GITHUB_OUTPUT gets verdict= and summary=). Progress goes to
stderr, a line at least every 15 s while a commit builds; so does a warning when BASE
and HEAD build the same program, judged by content: the same source tree, or prebuilt
builds with identical executables (not by the commits' names). Exit codes: 0 both
gates pass; 1 a gate failed (or a build or a benchmark run failed); 2 usage or input
error (unknown ref, missing build or executable, not a git repository, a malformed
baseline file), with one line on stderr; 3 no gate failed but the timing gate is
inconclusive (too noisy, or too few rounds, to resolve the threshold); 70 internal error
(a bug of the gates or of check_baseline.py; its traceback with --debug); 74 the summary
could not be written. See examples/ci/README.md and docs/ci.md.
"""

import io
import json
import math
import os
import shutil
import subprocess
import sys
import time

from hrbench_analysis.bench.baseline import BaselineError, get_counter_changes, load_baseline
from hrbench_analysis.bench.builds import (
    DEFAULT_FILTER,
    BuildError,
    UsageError,
    bench_limit,
    build_commit,
    default_workdir,
    files_digest,
    locate_project,
    prepare_workdir,
    read_file_at,
    resolve_ref,
    run_benchmarks,
    tree_of,
)
from hrbench_analysis.bench.gbench import (
    InputError,
    format_time,
    get_repetition_times,
    load_benchmark_file,
    merge_benchmark_files,
)
from hrbench_analysis.bench.machine import cpu_model
from hrbench_analysis.errors import OneLineParser, run_main

# hrbench_analysis comes from analysis/ of this checkout (the shell script gates puts it on
# the PYTHONPATH): gbench, builds and engine use the standard library only; benchcompare
# needs numpy and scipy and is imported when timing.
_ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))

PROG = "gates"

DEFAULT_ROUNDS = 10
DEFAULT_THRESHOLD = 0.10
DEFAULT_ALPHA = 0.05
DEFAULT_METRIC = "cpu_time"
DEFAULT_MIN_TIME = 0.2
# Bounds of --rounds and --min-time: a typo (--rounds 1000000, --min-time 1e9) would hold
# a CI runner for days.
MAX_ROUNDS = 1000
MAX_MIN_TIME = 60.0
BASELINE_PATH = "tests/baseline/counts.json"
SIDES = ("base", "head")
# The one "benchmark" of --time-cmd: the command's CPU time.
COMMAND_NAME = "cpu time of --time-cmd"
# Lines of a gate's console output kept in the Markdown summary (all are printed).
MAX_SUMMARY_LINES = 150
# Exit codes by overall verdict (2 is a usage or input error).
EXIT_CODES = {"PASS": 0, "FAIL": 1, "INCONCLUSIVE": 3}


class GateFailure(Exception):
    """A benchmark run failed, or its output is unusable: exit code 1."""


def log(message):
    print(f"{PROG}: {message}", file=sys.stderr, flush=True)


# ---------------------------------------------------------------------------------------
# Options.


def parse_args(argv):
    p = OneLineParser(prog=PROG, description="Run hrbench's count and timing gates on BASE_REF "
                "and HEAD_REF; print a Markdown summary. Exit 0 pass, 1 a gate failed, "
                "2 usage or input error, 3 timing inconclusive (too noisy to tell).")
    p.add_argument("base", metavar="BASE_REF", help="the base commit (any git revision)")
    p.add_argument("head", metavar="HEAD_REF", help="the change (any git revision)")
    p.add_argument("--rounds", type=int, default=DEFAULT_ROUNDS,
                   help=f"interleaved timing rounds (default {DEFAULT_ROUNDS})")
    p.add_argument("--threshold", type=float, default=DEFAULT_THRESHOLD,
                   help="relative slowdown that fails, and the largest noise the timing "
                        f"gate can decide at (default {DEFAULT_THRESHOLD} = "
                        f"{DEFAULT_THRESHOLD * 100:g}%%)")
    p.add_argument("--alpha", type=float, default=DEFAULT_ALPHA,
                   help="significance level of the two-sided signed-rank test "
                        f"(default {DEFAULT_ALPHA})")
    p.add_argument("--filter",
                   help="--benchmark_filter of refine_bench (default: five representative "
                        "benchmarks)")
    p.add_argument("--metric", choices=("cpu_time", "real_time"), default=DEFAULT_METRIC,
                   help=f"time compared (default {DEFAULT_METRIC}: machines are shared)")
    p.add_argument("--min-time", type=float,
                   help="--benchmark_min_time of each benchmark per round, seconds "
                        f"(default {DEFAULT_MIN_TIME})")
    p.add_argument("--bench-cmd", metavar="CMD",
                   help="time this shell command instead of refine_bench: run once per "
                        "build and round with $HRBENCH_BUILD (the build directory), "
                        "$HRBENCH_SIDE (base or head), $HRBENCH_ROUND, and it must write "
                        "Google Benchmark JSON to $HRBENCH_BENCH_OUT")
    p.add_argument("--time-cmd", metavar="CMD",
                   help="time this shell command itself, by the CPU time (user + sys) of "
                        "its process tree, instead of a benchmark's JSON: run once per build "
                        "and round (after one warm-up round) with $HRBENCH_BUILD, "
                        "$HRBENCH_SIDE and $HRBENCH_ROUND; any program, built your way at "
                        "BASE and HEAD (--base-build, --head-build)")
    p.add_argument("--summary", metavar="FILE", help="also write the Markdown summary here")
    p.add_argument("--workdir", metavar="DIR", default=default_workdir(),
                   help="worktrees, builds and results, the user's own (default "
                        "$RUNNER_TEMP/hrbench-gates on CI, else "
                        "$XDG_CACHE_HOME/hrbench-gates: ~/.cache/hrbench-gates)")
    p.add_argument("--base-build", metavar="DIR",
                   help="prebuilt build of BASE_REF (refine_bench unless --bench-cmd): do not "
                        "build")
    p.add_argument("--head-build", metavar="DIR",
                   help="prebuilt build of HEAD_REF (hrbench unless --skip-counts, refine_bench "
                        "unless --bench-cmd): do not build")
    p.add_argument("--project", metavar="DIR", default=".",
                   help="the hrbench source directory in the git repository (default: the "
                        "current directory; a subdirectory where a project vendors hrbench)")
    p.add_argument("--jobs", type=int, default=os.cpu_count() or 1,
                   help="parallel build jobs and count runs (default: number of cores)")
    p.add_argument("--no-ccache", action="store_true",
                   help="do not compile through ccache even if it is installed")
    p.add_argument("--skip-counts", action="store_true", help="run the timing gate only")
    p.add_argument("--skip-timing", action="store_true", help="run the count gate only")
    p.add_argument("--debug", action="store_true",
                   help="print the traceback of an internal error (exit code 70)")
    args = p.parse_args(argv)
    if not 1 <= args.rounds <= MAX_ROUNDS:
        p.error(f"--rounds must be from 1 to {MAX_ROUNDS}")
    if not (math.isfinite(args.threshold) and args.threshold >= 0):
        p.error("--threshold must be a finite number >= 0")
    if not 0 < args.alpha < 1:
        p.error("--alpha must be in (0, 1)")
    if args.bench_cmd is not None and args.time_cmd is not None:
        p.error("--bench-cmd and --time-cmd exclude each other: give one command to time")
    for cmd in ("bench_cmd", "time_cmd"):
        if getattr(args, cmd) is None:
            continue
        flag = "--" + cmd.replace("_", "-")
        if not getattr(args, cmd).strip():
            p.error(f"{flag} must not be empty")
        for option in ("filter", "min_time"):
            if getattr(args, option) is not None:
                p.error(f"--{option.replace('_', '-')} is an option of refine_bench: with "
                        f"{flag}, put it in the command")
    if args.time_cmd is not None and args.metric != "cpu_time":
        p.error("--time-cmd measures CPU time; --metric real_time is for benchmark JSON")
    args.filter = DEFAULT_FILTER if args.filter is None else args.filter
    args.min_time = DEFAULT_MIN_TIME if args.min_time is None else args.min_time
    if not (math.isfinite(args.min_time) and 0 < args.min_time <= MAX_MIN_TIME):
        p.error(f"--min-time must be a number of seconds > 0 and at most {MAX_MIN_TIME:g}")
    if args.jobs < 1:
        p.error("--jobs must be at least 1")
    if not args.filter.strip():
        p.error("--filter must not be empty")
    if args.skip_counts and args.skip_timing:
        p.error("--skip-counts and --skip-timing leave nothing to do")
    for name in ("base", "head"):
        if not getattr(args, name).strip():
            p.error(f"{name.upper()}_REF is empty (outside a pull request, give the base "
                    "commit explicitly)")
    return args


# ---------------------------------------------------------------------------------------
# Git, worktrees and builds.


def check_build_dir(path, option, need):
    if not os.path.isdir(path):
        raise UsageError(f"{option} {path}: no such directory")
    for exe in need:
        f = os.path.join(path, exe)
        if not (os.path.isfile(f) and os.access(f, os.X_OK)):
            raise UsageError(f"{option} {path}: no executable {exe} (configure with "
                             "-DHRBENCH_BUILD_BENCH=ON and build hrbench and refine_bench)")
    return os.path.abspath(path)



# ---------------------------------------------------------------------------------------
# The count gate.


def _format_change(old, new):
    if not (isinstance(old, int) and isinstance(new, int)):
        return f"{old} -> {new}"
    text = f"{old} -> {new}  {new - old:+,}"
    if old:
        text += f" ({100 * (new - old) / old:+.3g}%)"
    return text


def baseline_diff(base_data, head_data, max_runs=20, max_lines_per_run=8):
    """Lines describing how HEAD's baseline file differs from BASE's, run by run."""
    def runs(data):
        return {tuple(r["args"]): r.get("counts") or {} for r in data["runs"]}
    old, new = runs(base_data), runs(head_data)
    lines, changed = [], 0
    for args, counts in new.items():
        cmd = "hrbench run " + " ".join(args)
        if args not in old:
            lines.append(f"added    {cmd}")
            continue
        changes = get_counter_changes(old[args], counts) + [
            c for c in get_counter_changes(counts, old[args]) if c.counter not in old[args]
            and "[" not in c.counter]
        if not changes:
            continue
        changed += 1
        if changed > max_runs:
            continue
        lines.append(f"changed  {cmd}")
        for c in changes[:max_lines_per_run]:
            if c.counter in old[args] or "[" in c.counter:
                lines.append(f"    {c.counter}: {_format_change(c.baseline, c.current)}")
            else:
                lines.append(f"    {c.counter}: new counter ({c.baseline})")
        if len(changes) > max_lines_per_run:
            lines.append(f"    ... and {len(changes) - max_lines_per_run} more")
    if changed > max_runs:
        lines.append(f"... and {changed - max_runs} more changed runs")
    lines += [f"removed  hrbench run {' '.join(a)}" for a in old if a not in new]
    if not lines:
        lines.append("(the runs and counts are equal; only the file's other fields changed)")
    return lines


def count_gate(repo, prefix, base_sha, head_sha, head_build, results, jobs):
    """Run the count gate; return a dict with status, lines and notes."""
    rel = prefix + BASELINE_PATH
    head_text = read_file_at(repo, head_sha, rel)
    if head_text is None:
        raise UsageError(f"HEAD {head_sha[:12]} has no {rel}: nothing to check the counts "
                         "against (write it with `make baseline`)")
    base_text = read_file_at(repo, base_sha, rel)
    # HEAD's file under its own name, so that check_baseline's report names it as such.
    head_dir = os.path.join(results, "counts-head")
    head_file = os.path.join(head_dir, BASELINE_PATH)
    os.makedirs(os.path.dirname(head_file), exist_ok=True)
    with open(head_file, "wb") as f:
        f.write(head_text)
    gate = {"status": "pass", "notes": [], "info": []}
    if base_text is None:
        gate["notes"].append(f"{rel} is new in HEAD (BASE has none)")
    elif base_text != head_text:
        base_file = os.path.join(results, "counts-base.json")
        with open(base_file, "wb") as f:
            f.write(base_text)
        try:
            gate["info"] = baseline_diff(load_baseline(base_file), load_baseline(head_file))
        except BaselineError as e:
            gate["info"] = [f"(cannot compare with BASE's file: {e})"]
        gate["notes"].append(f"HEAD updates {rel} (on purpose): the counts below changed "
                             "relative to BASE; information, not a failure")
    engine = os.path.join(head_build, "hrbench")
    cmd = [sys.executable, os.path.join(_ROOT, "tools", "check_baseline.py"),
           "--hrbench", engine, "--baseline", BASELINE_PATH, "--jobs", str(jobs)]
    log(f"counts: tools/check_baseline.py --hrbench {engine} (HEAD's {rel})")
    proc = subprocess.run(cmd, cwd=head_dir, capture_output=True, text=True)
    gate["output"] = (proc.stdout + proc.stderr).rstrip("\n").splitlines()
    last_line = proc.stderr.strip().splitlines()[-1] if proc.stderr.strip() else ""
    if proc.returncode == 2:
        raise UsageError(f"check_baseline.py: {last_line or 'usage or input error'}")
    if proc.returncode not in (0, 1):
        # Only 1 is a count that changed: a crash (70), a failed write (74) or a signal is
        # the tool's failure, never the change's.
        raise RuntimeError(f"check_baseline.py ended with exit code {proc.returncode}"
                           + (f": {last_line}" if last_line else ""))
    if proc.returncode == 1:
        gate["status"] = "fail"
    last = [line for line in proc.stdout.splitlines() if line.startswith("count baseline:")]
    gate["line"] = last[0][len("count baseline: "):] if last else f"exit code {proc.returncode}"
    return gate


# ---------------------------------------------------------------------------------------
# The timing gate.


def round_order(r):
    """The builds in round _r_ (0-based): base first in even rounds, head first in odd."""
    return SIDES if r % 2 == 0 else SIDES[::-1]


def list_benchmarks(exe, pattern):
    proc = subprocess.run([exe, "--benchmark_list_tests=true", f"--benchmark_filter={pattern}"],
                          capture_output=True, text=True)
    if proc.returncode != 0:
        return []
    return [line.strip() for line in proc.stdout.splitlines() if line.strip()]


def check_filter(exe, pattern, side):
    if not list_benchmarks(exe, pattern):
        raise UsageError(f"--filter {pattern!r} matches no benchmark of {side}'s {exe}")


def _round_times(path, metric):
    """Each benchmark's time in one round's file: the median of its rows (one row per
    round from refine_bench; a --bench-cmd may write repetitions)."""
    import numpy as np
    try:
        times = get_repetition_times(load_benchmark_file(path), metric)
    except InputError as e:
        raise GateFailure(f"the benchmark output {path}: {e}") from None
    return {name: float(np.median(values)) for name, values in times.items()}


def paired_times(rounds):
    """Per benchmark, the base and head times of the rounds that have it on both sides.

    _rounds_: one ``{side: {benchmark: time}}`` per round. Returns ``(base, head)``, two
    dicts of benchmark to list, in the order benchmarks first appear in base's rounds."""
    base, head = {}, {}
    for times in rounds:
        for name, t in times["base"].items():
            if name in times["head"]:
                base.setdefault(name, []).append(t)
                head.setdefault(name, []).append(times["head"][name])
    return base, head


def timing_gate(exes, builds, args, results):
    """Run the interleaved rounds, merge them and compare; return a dict."""
    try:
        from hrbench_analysis.bench.benchcompare import (
            get_comparison_report,
            get_geomean,
            get_overall_verdict,
            min_pvalue,
            print_comparison_report,
        )
    except ImportError as e:
        raise UsageError(f"the timing gate needs numpy and scipy ({e}); run scripts/setup.sh "
                         "or pip install numpy scipy") from None
    if not (args.bench_cmd or args.time_cmd):
        for side in SIDES:
            check_filter(exes[side], args.filter, side)
    timing = os.path.join(results, "timing")
    os.makedirs(timing, exist_ok=True)
    start = time.monotonic()
    if args.time_cmd:
        order, rounds, merged, wall_ratio = _command_rounds(builds, args, timing, start)
    else:
        order, rounds, merged = _benchmark_rounds(builds, args, timing, start)
        wall_ratio = None
    with open(os.path.join(timing, "order.txt"), "w") as f:
        for r, sides in enumerate(order):
            f.write(f"round {r + 1}: {' '.join(sides)}\n")
    base, head = paired_times(rounds)
    comparisons, only_base, only_head = get_comparison_report(
        base, head, args.threshold, args.alpha, paired=True)
    if not comparisons:
        raise GateFailure("the two builds have no benchmark in common"
                          + ("" if args.bench_cmd else " under --filter"))
    only_base = sorted({n for t in rounds for n in t["base"]} - set(base))
    only_head = sorted({n for t in rounds for n in t["head"]} - set(head))
    # The text report of tools/compare_bench.py --paired, for the log.
    text = io.StringIO()
    print_comparison_report(comparisons, only_base, only_head, args.threshold, args.alpha,
                            file=text)
    verdict = get_overall_verdict(comparisons)
    return {"status": verdict.lower(), "comparisons": comparisons, "only_base": only_base,
            "only_head": only_head, "order": order,
            "text": text.getvalue().rstrip("\n").splitlines(),
            "geomean": get_geomean(comparisons),
            "weak": any(min_pvalue(c.n_baseline, c.n_new, True) > args.alpha
                        for c in comparisons),
            "seconds": time.monotonic() - start, "merged": merged, "wall_ratio": wall_ratio}


def _benchmark_rounds(builds, args, timing, start):
    """refine_bench or --bench-cmd, one Google Benchmark JSON per build and round: the
    order of each round, its times ``{side: {benchmark: ns}}``, the merged files."""
    files = {side: [] for side in SIDES}
    order, rounds = [], []
    what = "benchmark command" if args.bench_cmd else "refine_bench"
    base_seconds = None  # the base's first run: the measure of every later run's limit
    for r in range(args.rounds):
        sides = round_order(r)
        order.append(sides)
        rounds.append({})
        for side in sides:
            out = os.path.join(timing, f"{side}-{r + 1:03d}.json")
            try:
                seconds = run_benchmarks(
                    builds[side], out, f"{side}'s {what} in round {r + 1}",
                    bench_cmd=args.bench_cmd, bench_filter=args.filter,
                    min_time=args.min_time, timeout=bench_limit(base_seconds),
                    env={"HRBENCH_SIDE": side, "HRBENCH_ROUND": str(r + 1)})
            except BuildError as e:
                raise GateFailure(str(e)) from None
            if side == "base" and base_seconds is None:
                base_seconds = seconds
            files[side].append(out)
            rounds[-1][side] = _round_times(out, args.metric)
        log(f"timing: round {r + 1}/{args.rounds} ({' then '.join(sides)}), "
            f"{time.monotonic() - start:.0f} s")
    merged = {}
    for side in SIDES:
        # Artifacts: one file per build with one row per round, as merge_bench.py writes.
        merged[side] = os.path.join(timing, f"{side}.json")
        with open(merged[side], "w", encoding="utf-8") as f:
            json.dump(merge_benchmark_files([load_benchmark_file(p) for p in files[side]]),
                      f, indent=2)
    return order, rounds, merged


def _command_rounds(builds, args, timing, start):
    """--time-cmd, through hrbench_analysis.bench.cmdtiming: as _benchmark_rounds, with one
    "benchmark", the command's CPU time; the per-run times go to timing/times.json. Also
    returns the median of the per-round wall-time ratios."""
    from hrbench_analysis.bench.cmdtiming import CommandError, run_rounds, wall_ratio

    def env(side, r):
        return {"HRBENCH_BUILD": builds[side], "HRBENCH_SIDE": side, "HRBENCH_ROUND": str(r)}

    try:
        runs, order = run_rounds(
            {side: args.time_cmd for side in SIDES}, args.rounds, warmup=1, env=env,
            log=lambda line: log(f"timing: {line}, {time.monotonic() - start:.0f} s"))
    except CommandError as e:
        raise GateFailure(str(e)) from None
    rounds = [{side: {COMMAND_NAME: runs[side][r].cpu_seconds * 1e9} for side in SIDES}
              for r in range(args.rounds)]
    times = os.path.join(timing, "times.json")
    with open(times, "w", encoding="utf-8") as f:
        json.dump({"command": args.time_cmd, "round_order": [list(o) for o in order],
                   **{side: {"cpu_seconds": [x.cpu_seconds for x in runs[side]],
                             "wall_seconds": [x.wall_seconds for x in runs[side]]}
                      for side in SIDES}}, f, indent=1)
    return order, rounds, {"times": times}, wall_ratio(runs)


# ---------------------------------------------------------------------------------------
# The machine and the summary.


def machine_info():
    model = cpu_model() or "unknown"
    try:
        usable = len(os.sched_getaffinity(0))
    except AttributeError:
        usable = os.cpu_count()
    try:
        load = os.getloadavg()
    except OSError:
        load = None
    return {"cpu": model, "cores": os.cpu_count(), "usable": usable, "load": load}


def _md(text):
    return text.replace("|", "\\|")


_VERDICT_MD = {"SLOWER": "**SLOWER**", "inconclusive": "*inconclusive*"}


def _timing_detail(timing, threshold):
    cs = timing["comparisons"]
    return (f"{sum(c.regression for c in cs)} of {len(cs)} benchmarks significantly slower "
            f"by more than {threshold:.0%}, {sum(c.inconclusive for c in cs)} inconclusive")


def build_identity(repo, prefix, sha, prebuilt, need):
    """What a side's build is, by content: ``(kind, digest, text)``.

    A prebuilt build is its executables that the gates run (the SHA-256 of their bytes;
    with --bench-cmd or --time-cmd, which run no executable the gates know, the folder
    itself); a build from source is the git tree of hrbench's directory at its commit,
    so that two names of one commit, or two commits of one tree, are the same build.
    """
    if prebuilt:
        if need:
            return ("files", files_digest(prebuilt, need),
                    f"identical executables ({', '.join(need)})")
        return ("folder", os.path.realpath(prebuilt), "the same build folder")
    tree = tree_of(repo, sha, prefix)
    return ("tree", tree, f"the same source tree {tree[:12]}")


def same_content_note(ctx):
    """What to say when BASE and HEAD build the same program, or None.

    Judged by content (:func:`build_identity`), not by the commits' names: one commit
    built twice in two ways is two builds to compare; two commits of one tree, or two
    builds with identical executables, are one.
    """
    base, head = ctx["identity"]["base"], ctx["identity"]["head"]
    if base[:2] != head[:2]:
        return None
    args = ctx["args"]
    if ctx["base_sha"] == ctx["head_sha"]:
        what = (f"BASE_REF {args.base} and HEAD_REF {args.head} are the same commit "
                f"{ctx['base_sha'][:12]}" + (f", built to {base[2]}" if base[0] != "tree"
                                              else ""))
    else:
        what = (f"BASE_REF {args.base} ({ctx['base_sha'][:12]}) and HEAD_REF {args.head} "
                f"({ctx['head_sha'][:12]}) have the same content: {base[2]}")
    return (f"{what}: nothing is compared with another version (the timing gate measures "
            "the build against itself: the machine's noise). Give the base commit "
            "explicitly, e.g. `scripts/ci/gates HEAD~1 HEAD` or `make gates BASE=HEAD~1` "
            "(in a fresh clone origin/main is HEAD)")


def render_summary(ctx):
    """The Markdown summary of a run (ctx: everything main gathered)."""
    args, counts, timing = ctx["args"], ctx.get("counts"), ctx.get("timing")
    statuses = [g["status"] for g in (counts, timing) if g]
    overall = ("FAIL" if "fail" in statuses else
               "INCONCLUSIVE" if "inconclusive" in statuses else "PASS")
    out = [f"## hrbench gates: {overall}", ""]
    out.append(f"base `{ctx['base_sha'][:12]}` ({_md(args.base)}), head "
               f"`{ctx['head_sha'][:12]}` ({_md(args.head)})")
    same = same_content_note(ctx)
    if same:
        out += ["", f"**Same content.** {_md(same)}."]
    out += ["", "| gate | verdict | detail |", "|---|---|---|"]
    if counts:
        detail = counts["line"] + ("; baseline updated on purpose" if counts["info"] else "")
        out.append(f"| counts | {counts['status'].upper()} | {_md(detail)} |")
    else:
        out.append("| counts | skipped | --skip-counts |")
    if timing:
        out.append(f"| timing | {timing['status'].upper()} | "
                   f"{_timing_detail(timing, args.threshold)} |")
    else:
        out.append("| timing | skipped | --skip-timing |")
    if counts:
        out += ["", "### Counts", ""]
        out.append(f"`tools/check_baseline.py` with HEAD's `hrbench` against HEAD's "
                   f"`{BASELINE_PATH}`: **{counts['status'].upper()}** ({_md(counts['line'])}).")
        for note in counts["notes"]:
            out += ["", f"Note: {note}."]
        if counts["info"]:
            out += ["", "Counter changes between BASE's and HEAD's baseline files:", "",
                    "```text", *counts["info"], "```"]
        if counts["status"] == "fail":
            lines = counts["output"]
            if len(lines) > MAX_SUMMARY_LINES:
                lines = lines[:MAX_SUMMARY_LINES] + [
                    f"... {len(counts['output']) - MAX_SUMMARY_LINES} more lines in the log"]
            out += ["", "Diff of counters (HEAD's engine against HEAD's baseline):", "",
                    "```text", *lines, "```"]
    if timing:
        # numpy and scipy: imported only where the timing gate ran.
        from hrbench_analysis.bench.benchcompare import format_interval, format_noise

        level = f"{1 - args.alpha:.0%}"
        what = (f"`{_md(args.bench_cmd)}`" if args.bench_cmd else
                f"`{_md(args.time_cmd)}` (CPU time, user + sys, of its process tree; one "
                "warm-up round first)" if args.time_cmd else
                f"`refine_bench` (--benchmark_min_time {args.min_time:g})")
        out += ["", "### Timing", ""]
        out.append(f"{what}, {args.metric}, {args.rounds} interleaved rounds (one run of "
                   "each build per round, the order alternating). Each benchmark is judged on "
                   "its per-round ratios head / base: change is their median, p the two-sided "
                   "Wilcoxon signed-rank test, CI the ratios the test does not reject at "
                   f"alpha {args.alpha} ({level} confidence), noise its half-width. **SLOWER** "
                   f"(fails): p <= {args.alpha} and a change above +{args.threshold:.0%}; "
                   f"*inconclusive*: noise above {args.threshold:.0%} and the CI reaching above "
                   f"+{args.threshold:.0%}, so that such a slowdown can be neither found nor "
                   "ruled out; faster or slower (within the threshold) when significant, else "
                   "no significant change.")
        if args.metric == "cpu_time" and not (args.bench_cmd or args.time_cmd):
            out[-1] += (" (The names end in `/real_time` because the suite sizes its "
                        "iterations by wall time; the time compared is CPU time.)")
        out += ["", f"| benchmark | base | head | change | {level} CI | p | noise | rounds "
                "| verdict |", "|---|---:|---:|---:|---:|---:|---:|---:|---|"]
        for c in timing["comparisons"]:
            out.append(f"| `{_md(c.name)}` | {format_time(c.baseline_median)} | "
                       f"{format_time(c.new_median)} | {c.change:+.1%} | {format_interval(c)} "
                       f"| {c.pvalue:.4f} | {format_noise(c)} | {c.n_baseline} | "
                       f"{_VERDICT_MD.get(c.verdict, c.verdict)} |")
        base, head, change = timing["geomean"]
        out.append(f"| OVERALL_GEOMEAN | {format_time(base)} | {format_time(head)} | "
                   f"{change:+.1%} | | | | | |")
        out.append("")
        out.append("base, head: medians over the rounds; OVERALL_GEOMEAN: geometric means "
                   "of the medians and of the changes' ratios.")
        if timing["wall_ratio"] is not None:
            out.append(f"Wall time head / base: {timing['wall_ratio']:.3f} (median of the "
                       "per-round ratios; reported, not judged).")
        for name in timing["only_base"]:
            out.append(f"Only in BASE: `{_md(name)}`.")
        for name in timing["only_head"]:
            out.append(f"Only in HEAD: `{_md(name)}`.")
        if timing["weak"]:
            out.append(f"Note: {args.rounds} rounds are too few for the test to reach alpha "
                       f"{args.alpha}: every benchmark is inconclusive (use --rounds 6 or "
                       "more; the default is 10).")
        out += ["", f"**{timing['status'].upper()}**: {_timing_detail(timing, args.threshold)} "
                    f"({timing['seconds']:.0f} s of rounds)."]
    m = ctx["machine"]
    load = ", ".join(f"{x:.2f}" for x in m["load"]) if m["load"] else "unknown"
    out += ["", "### Machine", "",
            f"CPU {_md(m['cpu'])}, {m['cores']} cores ({m['usable']} usable), load average "
            f"at start {load} (1, 5, 15 min)."]
    if ctx.get("builds"):
        out.append("")
        out.append("Builds: " + "; ".join(f"{side} {how}" for side, how in ctx["builds"]))
    out += ["", f"**Overall: {overall}** (wall time {ctx['seconds']:.0f} s)", ""]
    return "\n".join(out), overall


def write_outputs(summary, overall, args, results):
    path = os.path.join(results, "summary.md")
    for target in filter(None, (path, args.summary)):
        os.makedirs(os.path.dirname(os.path.abspath(target)), exist_ok=True)
        with open(target, "w", encoding="utf-8") as f:
            f.write(summary)
    if os.environ.get("GITHUB_STEP_SUMMARY"):
        with open(os.environ["GITHUB_STEP_SUMMARY"], "a", encoding="utf-8") as f:
            f.write(summary)
    if os.environ.get("GITHUB_OUTPUT"):
        with open(os.environ["GITHUB_OUTPUT"], "a", encoding="utf-8") as f:
            f.write(f"verdict={overall.lower()}\nsummary={path}\nresults={results}\n")


# ---------------------------------------------------------------------------------------


def run(args):
    start = time.monotonic()
    machine = machine_info()
    repo, prefix = locate_project(args.project)
    base_sha = resolve_ref(repo, args.base, "BASE_REF")
    head_sha = resolve_ref(repo, args.head, "HEAD_REF")
    bench = [] if args.skip_timing or args.bench_cmd or args.time_cmd else ["refine_bench"]
    # BASE's engine is not checked: the count gate runs HEAD's only.
    need = {"base": bench, "head": ([] if args.skip_counts else ["hrbench"]) + bench}
    prebuilt = {"base": args.base_build, "head": args.head_build}
    for side in SIDES:
        if prebuilt[side]:
            prebuilt[side] = check_build_dir(prebuilt[side], f"--{side}-build", need[side])
    if not args.skip_counts and read_file_at(repo, head_sha, prefix + BASELINE_PATH) is None:
        raise UsageError(f"HEAD {head_sha[:12]} has no {prefix + BASELINE_PATH}: nothing to "
                         "check the counts against (write it with `make baseline`)")
    if bench:
        for side in SIDES:
            if prebuilt[side]:
                check_filter(os.path.join(prebuilt[side], "refine_bench"), args.filter, side)
    workdir = prepare_workdir(args.workdir)
    results = os.path.join(workdir, "results", f"{base_sha[:12]}-{head_sha[:12]}")
    if os.path.isdir(results):
        shutil.rmtree(results)
    os.makedirs(results)
    log(f"base {base_sha[:12]} ({args.base}), head {head_sha[:12]} ({args.head}); "
        f"results in {results}")
    ctx = {"args": args, "machine": machine, "base_sha": base_sha, "head_sha": head_sha,
           "identity": {side: build_identity(repo, prefix, sha, prebuilt[side], need[side])
                        for side, sha in (("base", base_sha), ("head", head_sha))}}
    if same_content_note(ctx):
        log(f"warning: {same_content_note(ctx)}")
    elif base_sha == head_sha:
        log(f"BASE_REF and HEAD_REF are one commit, {base_sha[:12]}, but the builds differ "
            "in content: comparing the builds")

    builds, how = {}, []
    for side, sha in (("base", base_sha), ("head", head_sha)):
        if side == "base" and args.skip_timing and not prebuilt["base"]:
            continue  # the count gate needs HEAD's engine only
        if prebuilt[side]:
            builds[side] = prebuilt[side]
            how.append((side, f"prebuilt `{_md(prebuilt[side])}`"))
        else:
            t = time.monotonic()
            builds[side] = build_commit(repo, prefix, sha, workdir, args.jobs,
                                        not args.no_ccache, side, log)
            how.append((side, f"built in {time.monotonic() - t:.0f} s"))
    ctx["builds"] = how
    if not args.skip_counts:
        ctx["counts"] = count_gate(repo, prefix, base_sha, head_sha, builds["head"], results,
                                   args.jobs)
        for line in ctx["counts"]["output"]:
            print(line, file=sys.stderr)
    if not args.skip_timing:
        exes = {side: os.path.join(builds[side], "refine_bench") for side in SIDES}
        ctx["timing"] = timing_gate(exes, builds, args, results)
        for line in ctx["timing"]["text"]:
            print(line, file=sys.stderr)
    ctx["seconds"] = time.monotonic() - start
    summary, overall = render_summary(ctx)
    write_outputs(summary, overall, args, results)
    print(summary, end="")
    if overall == "INCONCLUSIVE":
        log("timing inconclusive: the noise exceeds the threshold on "
            f"{sum(c.inconclusive for c in ctx['timing']['comparisons'])} benchmark(s); "
            "rerun with more --rounds or on a quieter machine (exit code 3)")
    if same_content_note(ctx):
        log(f"warning: {same_content_note(ctx)}")
    return EXIT_CODES[overall]


def _write_failure_summary(args, message):
    """A short summary where a build or a run failed before the gates could report."""
    summary = f"## hrbench gates: FAIL\n\n{_md(message)}\n"
    for target in filter(None, (args.summary, os.environ.get("GITHUB_STEP_SUMMARY"))):
        try:
            with open(target, "a" if target != args.summary else "w", encoding="utf-8") as f:
                f.write(summary)
        except OSError:
            pass
    if os.environ.get("GITHUB_OUTPUT"):
        with open(os.environ["GITHUB_OUTPUT"], "a", encoding="utf-8") as f:
            f.write("verdict=fail\n")
    print(summary, end="")


def main(argv=None):
    return run_main(PROG, _gates, argv)


def _gates(argv):
    args = parse_args(argv)
    try:
        return run(args)
    except (GateFailure, BuildError) as e:
        print(f"{PROG}: failed: {e}", file=sys.stderr)
        _write_failure_summary(args, str(e))
        return 1


if __name__ == "__main__":
    sys.exit(main())
