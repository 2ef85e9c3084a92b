"""``hrbench-history``: the command line of ``record``, ``measure`` and ``html``."""

import math
import os
import socket
import sys
from pathlib import Path

from ...errors import (
    OneLineParser,
    one_line,
    run_main,
)
from ..builds import (
    DEFAULT_FILTER,
    BuildError,
    bench_limit,
    build_commit,
    commits_between,
    default_workdir,
    locate_project,
    prepare_workdir,
    resolve_ref,
    run_benchmarks,
)
from ..gbench import (
    format_time,
    get_repetition_times,
)
from .page import _format_count, write_html
from .steps import DEFAULT_MIN_CHANGE, DEFAULT_MIN_NOISE, DEFAULT_MIN_POINTS, DEFAULT_PENALTY
from .store import HistoryError, describe_range, get_series, load_history, record_run


def _parser(prog):
    parser = OneLineParser(
        prog=prog, description="Benchmark history over commits (docs/history.md).")
    sub = parser.add_subparsers(dest="command", required=True)
    rec = sub.add_parser("record", help="store one Google Benchmark run with its metadata")
    rec.add_argument("bench", metavar="BENCH.json", help="Google Benchmark JSON with "
                     "repetitions (make bench: results/bench.json)")
    rec.add_argument("--history", required=True, metavar="DIR", help="history directory")
    rec.add_argument("--commit", metavar="SHA", help="commit measured (default: "
                     "git rev-parse HEAD here)")
    rec.add_argument("--date", metavar="ISO", help="its commit date (default: from git)")
    rec.add_argument("--subject", help="its subject line (default: from git)")
    rec.add_argument("--machine", metavar="NAME", help="machine name (default: the "
                     "benchmark's host_name)")
    rec.add_argument("--hrbench", metavar="PATH", help="the engine, for its version and "
                     "build flags")
    page = sub.add_parser("html", help="write the static HTML page of the history")
    page.add_argument("--history", required=True, metavar="DIR", help="history directory")
    page.add_argument("--out", required=True, metavar="PAGE.html", help="the page to write")
    page.add_argument("--machine", metavar="NAME", help="only this machine")
    page.add_argument("--metric", choices=("real_time", "cpu_time"), default="real_time")
    page.add_argument("--penalty", type=float, default=DEFAULT_PENALTY,
                      help=f"cost of a step, in sigma^2 ln n (default {DEFAULT_PENALTY})")
    page.add_argument("--min-change", type=float, default=DEFAULT_MIN_CHANGE,
                      help=f"smallest relative step (default {DEFAULT_MIN_CHANGE})")
    page.add_argument("--min-noise", type=float, default=DEFAULT_MIN_NOISE,
                      help=f"floor of sigma, log units (default {DEFAULT_MIN_NOISE})")
    page.add_argument("--min-points", type=int, default=DEFAULT_MIN_POINTS,
                      help="fewest points on each side of a step (default "
                           f"{DEFAULT_MIN_POINTS})")
    page.add_argument("--repo", metavar="DIR", default=".",
                      help="the git repository of the commits, to list the commits a step "
                           "may be due to (default: the current directory)")
    mes = sub.add_parser("measure", help="build every commit of a range, run its "
                         "benchmarks and record them")
    mes.add_argument("range", metavar="RANGE", help="BASE..HEAD (the commits after BASE "
                     "up to HEAD, as git log shows them) or one commit")
    mes.add_argument("--history", required=True, metavar="DIR", help="history directory")
    mes.add_argument("--machine", metavar="NAME", help="machine name (default: this host)")
    mes.add_argument("--project", metavar="DIR", default=".",
                     help="hrbench's directory in the git repository (default: here)")
    mes.add_argument("--workdir", metavar="DIR", default=default_workdir(),
                     help="worktrees and builds, shared with scripts/ci/gates (default "
                          "$RUNNER_TEMP/hrbench-gates on CI, else "
                          "$XDG_CACHE_HOME/hrbench-gates: ~/.cache/hrbench-gates)")
    mes.add_argument("--filter", default=DEFAULT_FILTER, help="--benchmark_filter of "
                     "refine_bench (default: the five benchmarks of the CI gates)")
    mes.add_argument("--repetitions", type=int, default=5,
                     help="--benchmark_repetitions of refine_bench (default 5)")
    mes.add_argument("--min-time", type=float, default=0.2,
                     help="--benchmark_min_time of refine_bench, seconds (default 0.2)")
    mes.add_argument("--bench-cmd", metavar="CMD",
                     help="run this shell command instead of refine_bench: with "
                          "$HRBENCH_BUILD and $HRBENCH_COMMIT set, it must write Google "
                          "Benchmark JSON with repetitions to $HRBENCH_BENCH_OUT")
    mes.add_argument("--jobs", type=int, default=os.cpu_count() or 1,
                     help="parallel build jobs (default: number of cores)")
    mes.add_argument("--no-ccache", action="store_true", help="compile without ccache")
    mes.add_argument("--rerun", action="store_true", help="measure also the commits this "
                     "machine has measured already (their runs are pooled)")
    for command in (rec, page, mes):
        command.add_argument("--debug", action="store_true",
                             help="print the traceback of an internal error (exit code 70)")
    return parser


def _print_record(path, created, record, source):
    c, m = record["commit"], record["machine"]
    if not created:
        print(f"already recorded: {source} for commit {c['sha'][:12]} is {path}; "
              "nothing written")
        return
    times = get_repetition_times(record["benchmark"])
    reps = sorted({len(v) for v in times.values()})
    load = m["load_avg"]
    load_text = " ".join(f"{x:.2f}" for x in load) if load else "unknown"
    engine = record["build"]["engine"]
    print(f"recorded {path}")
    print(f"  commit  {c['sha'][:12]} {c['date']} {c['subject'][:60]}"
          + ("  (working tree dirty)" if c.get("dirty") else ""))
    print(f"  machine {m['name']}: {m['cpu_model'] or 'CPU model unknown'}, "
          f"{m['num_cpus'] or '?'} cores, load average {load_text} at start")
    print(f"  build   Google Benchmark library {record['build']['library_build_type'] or '?'}"
          + (f"; engine {engine['version']} {engine.get('build_type', '')} "
             f"{engine.get('build_flags', '')}" if engine else ""))
    print(f"  {len(times)} benchmarks, {'/'.join(map(str, reps))} repetitions each")
    if load and m["num_cpus"] and load[0] > m["num_cpus"]:
        print(f"note: load average {load[0]:.2f} above the {m['num_cpus']} cores at the "
              "start: these timings may be noisy")
    if engine and engine.get("git_commit") and not str(engine["git_commit"]).startswith(
            c["sha"]):
        print(f"note: the engine was built from {engine['git_commit']}, not from "
              f"{c['sha']}")


def _measured_commits(history, machine):
    """Hashes of the commits `machine` has runs of in `history` (none if it is empty)."""
    if not Path(history).is_dir() or not any(Path(history).glob("*.json")):
        return set()
    return {r.sha for r in load_history(history)[0] if r.machine.get("name") == machine}


def _main_measure(args):
    if args.repetitions < 1 or args.jobs < 1:
        raise HistoryError("--repetitions and --jobs must be at least 1")
    if not (math.isfinite(args.min_time) and args.min_time > 0):
        raise HistoryError("--min-time must be a number > 0")
    if args.bench_cmd is not None and not args.bench_cmd.strip():
        raise HistoryError("--bench-cmd must not be empty")
    repo, prefix = locate_project(args.project)
    if ".." in args.range:
        base, head = args.range.split("..", 1)
        base_sha = resolve_ref(repo, base or "HEAD", "BASE")
        head_sha = resolve_ref(repo, head or "HEAD", "HEAD")
        commits = commits_between(repo, base_sha, head_sha) or []
    else:
        sha = resolve_ref(repo, args.range, "commit")
        commits = [(sha, "")]
    if not commits:
        raise HistoryError(f"{args.range} holds no commits (BASE..HEAD: the commits after "
                           "BASE up to HEAD)")
    machine = args.machine or socket.gethostname()
    done = set() if args.rerun else _measured_commits(args.history, machine)
    workdir = prepare_workdir(args.workdir)
    runs_dir = os.path.join(workdir, "history-runs")
    os.makedirs(runs_dir, exist_ok=True)

    def log(message):
        print(f"measure: {message}", file=sys.stderr, flush=True)

    failed, recorded = [], 0
    first_seconds = None  # the first commit measured: the measure of the later runs' limit
    for k, (sha, _) in enumerate(commits, 1):
        short = sha[:12]
        if sha in done:
            print(f"[{k}/{len(commits)}] {short}: measured on {machine} already, skipped "
                  "(--rerun to measure again)")
            continue
        print(f"[{k}/{len(commits)}] {short}", flush=True)
        out = os.path.join(runs_dir, f"{short}.json")
        try:
            build = build_commit(repo, prefix, sha, workdir, args.jobs, not args.no_ccache,
                                 "commit", log)
            seconds = run_benchmarks(
                build, out, f"the benchmarks of {short}", bench_cmd=args.bench_cmd,
                bench_filter=args.filter, min_time=args.min_time,
                repetitions=args.repetitions, env={"HRBENCH_COMMIT": sha},
                timeout=bench_limit(first_seconds))
            first_seconds = seconds if first_seconds is None else first_seconds
        except BuildError as e:
            print(f"measure: {short} not measured: {one_line(e, 300)}", file=sys.stderr)
            failed.append(short)
            continue
        engine = os.path.join(build, "hrbench")
        path, created, record = record_run(
            args.history, out, commit=sha, machine=machine, cwd=repo,
            hrbench=engine if os.access(engine, os.X_OK) else None)
        _print_record(path, created, record, out)
        recorded += created
    print(f"{recorded} runs recorded in {args.history}, {len(commits) - recorded - len(failed)} "
          f"commits skipped, {len(failed)} failed" + (f" ({', '.join(failed)})" if failed else "")
          + f"; the page: hrbench-history html --history {args.history} --out PAGE.html")
    return 1 if failed else 0


def _main_record(args):
    path, created, record = record_run(args.history, args.bench, args.commit, args.date,
                                       args.subject, args.machine, args.hrbench)
    _print_record(path, created, record, args.bench)
    return 0


def _main_html(args):
    if not (args.penalty >= 0 and args.min_change >= 0 and args.min_noise > 0
            and args.min_points >= 1):
        raise HistoryError("--penalty and --min-change must be >= 0, --min-noise > 0, "
                           "--min-points >= 1")
    runs, notes = load_history(args.history, args.metric)
    labels = sorted({r.label for r in runs})
    if args.machine is not None:
        kept = [r for r in runs if args.machine in (r.label, r.series_key[0])]
        if not kept:
            raise HistoryError(f"no run of machine {args.machine!r} in {args.history} "
                               f"(machines: {', '.join(labels)})")
        runs = kept
    params = {"penalty": args.penalty, "min_change": args.min_change,
              "min_noise": args.min_noise, "min_points": args.min_points}
    commits, series = get_series(runs, **params)
    steps, changes = write_html(args.out, runs, notes, commits, series, metric=args.metric,
                                machine=args.machine, params=params, repo=args.repo)
    shown = sorted({r.label for r in runs})
    print(f"wrote {args.out}: {len(runs)} runs, {len(commits)} commits, "
          f"{len({s.benchmark for s in series})} benchmarks, machines: {', '.join(shown)}")
    if len(shown) > 1:
        print(f"note: {len(shown)} machines, one series each (never averaged); steps are "
              "detected per machine")
    for note in notes:
        print(f"note: {note}")
    if any(r.commits is None for r in steps):
        print(f"note: git does not know these commits in {args.repo}: a step is credited to "
              "the measured commits only, unmeasured ones between are not listed (run in "
              "the repository, or pass --repo DIR)")
    for r in steps:
        st = r.step
        print(f"step    {r.series.benchmark} [{r.series.machine}] {describe_range(r, commits)}"
              f": {format_time(st.before)} -> {format_time(st.after)} (x{st.ratio:.3f})")
    for c in changes:
        sha = [p for p in series if p.benchmark == c.benchmark and p.machine == c.machine
               ][0].points[c.index].sha
        print(f"counter {c.benchmark} [{c.machine}] at {sha[:10]}: {c.counter} "
              f"{_format_count(c.before)} -> {_format_count(c.after)}")
    print(f"{len(steps)} steps, {len(changes)} counter changes")
    return 0


def main(argv=None, prog="hrbench-history"):
    """Run the command line; return the exit code (0; 1 when `measure` could not build or
    run a commit; 2 on a usage or input error; 70 for a bug, its traceback with
    ``--debug``; 74 when the page cannot be written)."""
    return run_main(prog, lambda a: _run(_parser(prog).parse_args(a)), argv)


def _run(args):
    if args.command == "record":
        return _main_record(args)
    if args.command == "measure":
        return _main_measure(args)
    return _main_html(args)

