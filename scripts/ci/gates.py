#!/usr/bin/env python3
"""hrbench's CI gates on a change: the exact count baseline and the timing comparison.

usage: gates BASE_REF HEAD_REF [--rounds N] [--threshold T] [--alpha A] [--filter REGEX]
             [--metric cpu_time|real_time] [--min-time S] [--summary FILE] [--workdir DIR]
             [--base-build DIR] [--head-build DIR] [--project DIR] [--jobs N]
             [--no-ccache] [--skip-counts] [--skip-timing]

Builds BASE_REF and HEAD_REF, each in its own `git worktree` under --workdir (Release,
targets hrbench and refine_bench; a commit's finished build is reused), or takes
prebuilt build directories (--base-build, --head-build: each must hold the executables
hrbench and refine_bench). Then two gates:

- counts: tools/check_baseline.py with HEAD's engine against HEAD's
  tests/baseline/counts.json. Any difference fails and prints the diff of counters. If
  HEAD changed counts.json relative to BASE (updated on purpose), that is reported with
  the diff between the two files, as information.
- timing: --rounds interleaved rounds, one repetition of each build's refine_bench per
  round, the order alternating (base first in odd rounds, head first in even ones);
  the rounds are merged with tools/merge_bench.py and compared with the one-sided
  Mann-Whitney U test of tools/compare_bench.py (hrbench_analysis.benchcompare): a
  benchmark fails if its median is slower by more than --threshold and p <= --alpha.

Prints a Markdown summary and writes it to --summary FILE and, when set, appends it to
$GITHUB_STEP_SUMMARY ($GITHUB_OUTPUT gets verdict= and summary=). Progress goes to
stderr. Exit codes: 0 both gates pass; 1 a gate failed (or a build or a benchmark run
failed); 2 usage or input error (unknown ref, missing build or executable, not a git
repository), with one line on stderr. See examples/ci/README.md and docs/ci.md.
"""

import argparse
import io
import math
import os
import shutil
import subprocess
import sys
import time

_ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
# tools/ for benchtools, analysis/ for hrbench_analysis (gbench and engine: standard
# library only; benchcompare needs numpy and scipy and is imported when timing).
sys.path[:0] = [os.path.join(_ROOT, "tools"), os.path.join(_ROOT, "analysis")]

from benchtools.baseline import RunError, get_counter_changes, load_baseline  # noqa: E402
from hrbench_analysis.gbench import (  # noqa: E402
    InputError,
    format_time,
    get_repetition_times,
    load_benchmark_file,
)

PROG = "gates"

# Five refine_bench benchmarks, both oracles, count-only and store mode, both sweeps:
# about 0.3 s each at --min-time 0.2, so a round (both builds) takes about 4 s.
DEFAULT_FILTER = ("^BM_EpsSweep/garmann_(count|store)/inv_eps:64/"
                  "|^BM_EpsSweep/hanrahan_count/inv_eps:256/"
                  "|^BM_GeometrySweep/garmann_count/g:256/"
                  "|^BM_GeometrySweep/hanrahan_store/g:16/")
DEFAULT_ROUNDS = 10
DEFAULT_THRESHOLD = 0.10
DEFAULT_ALPHA = 0.05
DEFAULT_METRIC = "cpu_time"
DEFAULT_MIN_TIME = 0.2
BASELINE_PATH = "tests/baseline/counts.json"
SIDES = ("base", "head")
# Lines of a gate's console output kept in the Markdown summary (all are printed).
MAX_SUMMARY_LINES = 150


class UsageError(Exception):
    """A usage or input error: exit code 2, one line."""


class GateFailure(Exception):
    """A build or a benchmark run failed: exit code 1."""


def log(message):
    print(f"{PROG}: {message}", file=sys.stderr, flush=True)


# ---------------------------------------------------------------------------------------
# Options.


class _Parser(argparse.ArgumentParser):
    def error(self, message):
        # One line, as for every other usage error (argparse prints the usage too).
        print(f"{PROG}: error: {message} (see {PROG} --help)", file=sys.stderr)
        sys.exit(2)


def _default_workdir():
    return os.path.join(os.environ.get("RUNNER_TEMP") or "/tmp", "hrbench-gates")


def parse_args(argv):
    p = _Parser(prog=PROG, description="Run hrbench's count and timing gates on BASE_REF "
                "and HEAD_REF; print a Markdown summary. Exit 0 pass, 1 a gate failed, "
                "2 usage or input error.")
    p.add_argument("base", metavar="BASE_REF", help="the base commit (any git revision)")
    p.add_argument("head", metavar="HEAD_REF", help="the change (any git revision)")
    p.add_argument("--rounds", type=int, default=DEFAULT_ROUNDS,
                   help=f"interleaved timing rounds (default {DEFAULT_ROUNDS})")
    p.add_argument("--threshold", type=float, default=DEFAULT_THRESHOLD,
                   help="relative slowdown of a median that fails "
                        f"(default {DEFAULT_THRESHOLD} = {DEFAULT_THRESHOLD * 100:g}%%)")
    p.add_argument("--alpha", type=float, default=DEFAULT_ALPHA,
                   help=f"significance level of the one-sided U test (default {DEFAULT_ALPHA})")
    p.add_argument("--filter", default=DEFAULT_FILTER,
                   help="--benchmark_filter of refine_bench (default: five representative "
                        "benchmarks)")
    p.add_argument("--metric", choices=("cpu_time", "real_time"), default=DEFAULT_METRIC,
                   help=f"time compared (default {DEFAULT_METRIC}: machines are shared)")
    p.add_argument("--min-time", type=float, default=DEFAULT_MIN_TIME,
                   help="--benchmark_min_time of each benchmark per round, seconds "
                        f"(default {DEFAULT_MIN_TIME})")
    p.add_argument("--summary", metavar="FILE", help="also write the Markdown summary here")
    p.add_argument("--workdir", metavar="DIR", default=_default_workdir(),
                   help="worktrees, builds and results (default $RUNNER_TEMP/hrbench-gates, "
                        "else /tmp/hrbench-gates)")
    p.add_argument("--base-build", metavar="DIR",
                   help="prebuilt build of BASE_REF (hrbench, refine_bench): do not build")
    p.add_argument("--head-build", metavar="DIR",
                   help="prebuilt build of HEAD_REF (hrbench, refine_bench): do not build")
    p.add_argument("--project", metavar="DIR", default=".",
                   help="the hrbench source directory in the git repository (default: the "
                        "current directory; a subdirectory where a project vendors hrbench)")
    p.add_argument("--jobs", type=int, default=os.cpu_count() or 1,
                   help="parallel build jobs and count runs (default: number of cores)")
    p.add_argument("--no-ccache", action="store_true",
                   help="do not compile through ccache even if it is installed")
    p.add_argument("--skip-counts", action="store_true", help="run the timing gate only")
    p.add_argument("--skip-timing", action="store_true", help="run the count gate only")
    args = p.parse_args(argv)
    if args.rounds < 1:
        p.error("--rounds must be at least 1")
    if not (math.isfinite(args.threshold) and args.threshold >= 0):
        p.error("--threshold must be a finite number >= 0")
    if not 0 < args.alpha < 1:
        p.error("--alpha must be in (0, 1)")
    if not (math.isfinite(args.min_time) and args.min_time > 0):
        p.error("--min-time must be a number > 0")
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


def git(repo, *args, check=True):
    proc = subprocess.run(["git", "-C", repo, *args], capture_output=True, text=True)
    if check and proc.returncode != 0:
        raise GateFailure(f"git {' '.join(args)} failed: {proc.stderr.strip()}")
    return proc


def locate_project(project):
    """(git top level, the project's path inside it with a trailing slash or '')."""
    if not os.path.isdir(project):
        raise UsageError(f"--project {project}: no such directory")
    top = git(project, "rev-parse", "--show-toplevel", check=False)
    if top.returncode != 0:
        raise UsageError(f"{os.path.abspath(project)} is not in a git repository")
    prefix = git(project, "rev-parse", "--show-prefix").stdout.strip()
    return top.stdout.strip(), prefix


def resolve_ref(repo, ref, which):
    proc = git(repo, "rev-parse", "--verify", "--quiet", f"{ref}^{{commit}}", check=False)
    if proc.returncode != 0:
        raise UsageError(f"{which} {ref!r} is not a commit of {repo} (fetch it first: "
                         "actions/checkout needs fetch-depth: 0)")
    return proc.stdout.strip()


def read_file_at(repo, sha, path):
    """The content of _path_ at commit _sha_, or None if it has no such file."""
    proc = subprocess.run(["git", "-C", repo, "show", f"{sha}:{path}"], capture_output=True)
    return proc.stdout if proc.returncode == 0 else None


def check_build_dir(path, option, need):
    if not os.path.isdir(path):
        raise UsageError(f"{option} {path}: no such directory")
    for exe in need:
        f = os.path.join(path, exe)
        if not (os.path.isfile(f) and os.access(f, os.X_OK)):
            raise UsageError(f"{option} {path}: no executable {exe} (configure with "
                             "-DHRBENCH_BUILD_BENCH=ON and build hrbench and refine_bench)")
    return os.path.abspath(path)


def _tail(path, n=30):
    try:
        with open(path, encoding="utf-8", errors="replace") as f:
            return "".join(f.readlines()[-n:])
    except OSError:
        return ""


def build_commit(repo, prefix, sha, workdir, jobs, use_ccache, which):
    """Build hrbench and refine_bench of _sha_ in a worktree; reuse a finished build."""
    short = sha[:12]
    # workdir/commits/SHA/src (the worktree) and .../build: the same relative paths
    # from every build to its sources, so that ccache (CCACHE_BASEDIR) hits across commits.
    tree = os.path.join(workdir, "commits", short, "src")
    build = os.path.join(workdir, "commits", short, "build")
    stamp = os.path.join(build, ".hrbench-gates-built")
    exes = [os.path.join(build, e) for e in ("hrbench", "refine_bench")]
    if os.path.isfile(stamp) and all(os.access(e, os.X_OK) for e in exes):
        with open(stamp) as f:
            if f.read().strip() == sha:
                log(f"{which} {short}: reusing the build in {build}")
                return build
    if not (os.path.isdir(tree) and git(tree, "rev-parse", "HEAD", check=False)
            .stdout.strip() == sha):
        if os.path.exists(tree):
            shutil.rmtree(tree)
        git(repo, "worktree", "prune")
        os.makedirs(os.path.dirname(tree), exist_ok=True)
        git(repo, "worktree", "add", "--detach", "--force", tree, sha)
    source = os.path.join(tree, prefix)
    if not os.path.isfile(os.path.join(source, "CMakeLists.txt")):
        raise UsageError(f"{which} {short} has no {prefix}CMakeLists.txt: not hrbench")
    os.makedirs(build, exist_ok=True)
    configure = ["cmake", "-S", source, "-B", build, "-DCMAKE_BUILD_TYPE=Release",
                 "-DHRBENCH_BUILD_BENCH=ON", "-DHRBENCH_BUILD_TESTS=OFF"]
    if shutil.which("ninja") and not os.path.isfile(os.path.join(build, "Makefile")):
        configure += ["-G", "Ninja"]
    env = dict(os.environ)
    if use_ccache and shutil.which("ccache"):
        configure.append("-DCMAKE_CXX_COMPILER_LAUNCHER=ccache")
        # Paths under the workdir hash alike in every commit's build: a file the change
        # leaves alone is a cache hit.
        env.setdefault("CCACHE_BASEDIR", workdir)
    build_log = os.path.join(build, "hrbench-gates-build.log")
    log(f"{which} {short}: building in {build} (log {build_log})")
    start = time.monotonic()
    with open(build_log, "w") as out:
        for cmd in (configure, ["cmake", "--build", build, "--target", "hrbench",
                                "refine_bench", "--parallel", str(jobs)]):
            out.write("$ " + " ".join(cmd) + "\n")
            out.flush()
            rc = subprocess.run(cmd, stdout=out, stderr=subprocess.STDOUT, env=env).returncode
            if rc != 0:
                sys.stderr.write(_tail(build_log))
                raise GateFailure(f"the build of {which} {short} failed (exit code {rc}); "
                                  f"see {build_log}")
    with open(stamp, "w") as f:
        f.write(sha + "\n")
    log(f"{which} {short}: built in {time.monotonic() - start:.0f} s")
    return build


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
        except RunError as e:
            gate["info"] = [f"(cannot compare with BASE's file: {e})"]
        gate["notes"].append(f"HEAD updates {rel} (on purpose): the counts below changed "
                             "relative to BASE; information, not a failure")
    engine = os.path.join(head_build, "hrbench")
    cmd = [sys.executable, os.path.join(_ROOT, "tools", "check_baseline.py"),
           "--hrbench", engine, "--baseline", BASELINE_PATH, "--jobs", str(jobs)]
    log(f"counts: tools/check_baseline.py --hrbench {engine} (HEAD's {rel})")
    proc = subprocess.run(cmd, cwd=head_dir, capture_output=True, text=True)
    gate["output"] = (proc.stdout + proc.stderr).rstrip("\n").splitlines()
    if proc.returncode == 2:
        raise UsageError(f"check_baseline.py: {proc.stderr.strip().splitlines()[-1]}"
                         if proc.stderr.strip() else "check_baseline.py: usage or input error")
    if proc.returncode != 0:
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


def _iqr(values):
    import numpy as np
    q1, med, q3 = np.percentile(values, [25, 50, 75])
    return (q3 - q1) / med if med > 0 else 0.0


def timing_gate(exes, args, results):
    """Run the interleaved rounds, merge them and compare; return a dict."""
    try:
        from hrbench_analysis.benchcompare import get_comparison_report, min_pvalue
    except ImportError as e:
        raise UsageError(f"the timing gate needs numpy and scipy ({e}); run scripts/setup.sh "
                         "or pip install numpy scipy") from None
    for side in SIDES:
        check_filter(exes[side], args.filter, side)
    timing = os.path.join(results, "timing")
    os.makedirs(timing, exist_ok=True)
    files = {side: [] for side in SIDES}
    order = []
    start = time.monotonic()
    for r in range(args.rounds):
        sides = round_order(r)
        order.append(sides)
        for side in sides:
            out = os.path.join(timing, f"{side}-{r + 1:03d}.json")
            cmd = [exes[side], f"--benchmark_filter={args.filter}",
                   f"--benchmark_min_time={args.min_time:g}", f"--benchmark_out={out}",
                   "--benchmark_out_format=json"]
            proc = subprocess.run(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE,
                                  text=True)
            if proc.returncode != 0 or not os.path.isfile(out):
                raise GateFailure(f"{side}'s refine_bench failed in round {r + 1} (exit code "
                                  f"{proc.returncode}): {proc.stderr.strip()[-300:]}")
            files[side].append(out)
        log(f"timing: round {r + 1}/{args.rounds} ({' then '.join(sides)}), "
            f"{time.monotonic() - start:.0f} s")
    with open(os.path.join(timing, "order.txt"), "w") as f:
        for r, sides in enumerate(order):
            f.write(f"round {r + 1}: {' '.join(sides)}\n")
    merged = {}
    for side in SIDES:
        merged[side] = os.path.join(timing, f"{side}.json")
        proc = subprocess.run([sys.executable, os.path.join(_ROOT, "tools", "merge_bench.py"),
                               merged[side], *files[side]], capture_output=True, text=True)
        if proc.returncode != 0:
            raise GateFailure(f"merge_bench.py failed: {proc.stderr.strip()}")
    try:
        times = {side: get_repetition_times(load_benchmark_file(merged[side]), args.metric)
                 for side in SIDES}
    except InputError as e:
        raise GateFailure(str(e)) from None
    comparisons, only_base, only_head = get_comparison_report(
        times["base"], times["head"], args.threshold, args.alpha)
    if not comparisons:
        raise GateFailure("the two builds have no benchmark in common under --filter")
    # The text report of tools/compare_bench.py, for the log.
    from hrbench_analysis.benchcompare import print_comparison_report
    text = io.StringIO()
    print_comparison_report(comparisons, only_base, only_head, args.threshold, args.alpha,
                            file=text)
    noise = {c.name: max(_iqr(times["base"][c.name]), _iqr(times["head"][c.name]))
             for c in comparisons}
    weak = any(min_pvalue(c.n_baseline, c.n_new) > args.alpha for c in comparisons)
    return {"status": "fail" if any(c.slower for c in comparisons) else "pass",
            "comparisons": comparisons, "only_base": only_base, "only_head": only_head,
            "order": order, "text": text.getvalue().rstrip("\n").splitlines(),
            "noise": noise, "weak": weak, "seconds": time.monotonic() - start,
            "merged": merged}


# ---------------------------------------------------------------------------------------
# The machine and the summary.


def machine_info():
    model = "unknown"
    try:
        with open("/proc/cpuinfo", encoding="utf-8") as f:
            for line in f:
                if line.startswith("model name"):
                    model = line.split(":", 1)[1].strip()
                    break
    except OSError:
        pass
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


def _verdict(c, threshold):
    return "**SLOWER**" if c.slower else ("faster" if c.change < -threshold else "same")


def render_summary(ctx):
    """The Markdown summary of a run (ctx: everything main gathered)."""
    args, counts, timing = ctx["args"], ctx.get("counts"), ctx.get("timing")
    statuses = [g["status"] for g in (counts, timing) if g]
    overall = "FAIL" if "fail" in statuses else "PASS"
    out = [f"## hrbench gates: {overall}", ""]
    out.append(f"base `{ctx['base_sha'][:12]}` ({_md(args.base)}), head "
               f"`{ctx['head_sha'][:12]}` ({_md(args.head)})")
    out += ["", "| gate | verdict | detail |", "|---|---|---|"]
    if counts:
        detail = counts["line"] + ("; baseline updated on purpose" if counts["info"] else "")
        out.append(f"| counts | {counts['status'].upper()} | {_md(detail)} |")
    else:
        out.append("| counts | skipped | --skip-counts |")
    if timing:
        slower = sum(c.slower for c in timing["comparisons"])
        out.append(f"| timing | {timing['status'].upper()} | {slower} of "
                   f"{len(timing['comparisons'])} benchmarks significantly slower |")
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
        out += ["", "### Timing", ""]
        out.append(f"`refine_bench`, {args.metric}, median of {args.rounds} interleaved rounds "
                   f"(one repetition of each build per round, the order alternating; "
                   f"--benchmark_min_time {args.min_time:g}). A benchmark is slower if its "
                   f"median is slower by more than {args.threshold:.0%} and the one-sided "
                   f"Mann-Whitney U test gives p <= {args.alpha}.")
        if args.metric == "cpu_time":
            out[-1] += (" (The names end in `/real_time` because the suite sizes its "
                        "iterations by wall time; the time compared is CPU time.)")
        out += ["", "| benchmark | base | head | change | p(slower) | noise | rounds | verdict |",
                "|---|---:|---:|---:|---:|---:|---:|---|"]
        for c in timing["comparisons"]:
            p = "-" if math.isnan(c.pvalue) else f"{c.pvalue:.4f}"
            out.append(f"| `{_md(c.name)}` | {format_time(c.baseline_median)} | "
                       f"{format_time(c.new_median)} | {c.change:+.1%} | {p} | "
                       f"{timing['noise'][c.name]:.1%} | {c.n_baseline}/{c.n_new} | "
                       f"{_verdict(c, args.threshold)} |")
        out.append("")
        out.append("noise: the larger interquartile range of the two builds' rounds, relative "
                   "to the median.")
        for name in timing["only_base"]:
            out.append(f"Only in BASE: `{_md(name)}`.")
        for name in timing["only_head"]:
            out.append(f"Only in HEAD: `{_md(name)}`.")
        if timing["weak"]:
            out.append(f"Note: {args.rounds} rounds are too few for the test to reach alpha "
                       f"{args.alpha}; the timing gate cannot fail (use --rounds 5 or more).")
        slower = sum(c.slower for c in timing["comparisons"])
        out += ["", f"**{timing['status'].upper()}**: {slower} of {len(timing['comparisons'])} "
                    f"benchmarks significantly slower ({timing['seconds']:.0f} s of rounds)."]
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
    need = (["hrbench"] if not args.skip_counts else []) + (
        ["refine_bench"] if not args.skip_timing else [])
    prebuilt = {"base": args.base_build, "head": args.head_build}
    for side in SIDES:
        if prebuilt[side]:
            # BASE's engine is not checked: only its refine_bench is needed.
            prebuilt[side] = check_build_dir(prebuilt[side], f"--{side}-build", need
                                             if side == "head" else need[-1:] if
                                             not args.skip_timing else [])
    if not args.skip_counts and read_file_at(repo, head_sha, prefix + BASELINE_PATH) is None:
        raise UsageError(f"HEAD {head_sha[:12]} has no {prefix + BASELINE_PATH}: nothing to "
                         "check the counts against (write it with `make baseline`)")
    if not args.skip_timing:
        for side in SIDES:
            if prebuilt[side]:
                check_filter(os.path.join(prebuilt[side], "refine_bench"), args.filter, side)
    workdir = os.path.abspath(args.workdir)
    results = os.path.join(workdir, "results", f"{base_sha[:12]}-{head_sha[:12]}")
    if os.path.isdir(results):
        shutil.rmtree(results)
    os.makedirs(results)
    log(f"base {base_sha[:12]} ({args.base}), head {head_sha[:12]} ({args.head}); "
        f"results in {results}")

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
                                        not args.no_ccache, side)
            how.append((side, f"built in {time.monotonic() - t:.0f} s"))
    ctx = {"args": args, "machine": machine, "base_sha": base_sha, "head_sha": head_sha,
           "builds": how}
    if not args.skip_counts:
        ctx["counts"] = count_gate(repo, prefix, base_sha, head_sha, builds["head"], results,
                                   args.jobs)
        for line in ctx["counts"]["output"]:
            print(line, file=sys.stderr)
    if not args.skip_timing:
        exes = {side: os.path.join(builds[side], "refine_bench") for side in SIDES}
        ctx["timing"] = timing_gate(exes, args, results)
        for line in ctx["timing"]["text"]:
            print(line, file=sys.stderr)
    ctx["seconds"] = time.monotonic() - start
    summary, overall = render_summary(ctx)
    write_outputs(summary, overall, args, results)
    print(summary, end="")
    return 0 if overall == "PASS" else 1


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
    args = parse_args(sys.argv[1:] if argv is None else argv)
    try:
        return run(args)
    except UsageError as e:
        print(f"{PROG}: error: {e}", file=sys.stderr)
        return 2
    except GateFailure as e:
        print(f"{PROG}: failed: {e}", file=sys.stderr)
        _write_failure_summary(args, str(e))
        return 1


if __name__ == "__main__":
    sys.exit(main())
