"""The stored runs of a history: recording a benchmark run with its commit, machine and
build (:func:`record_run`), loading them (:func:`load_history`) and their series over
commits, with steps and counter changes (:func:`get_series`)."""

import datetime as dt
import hashlib
import json
import os
import socket
import subprocess
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ...engine import run_engine
from ...errors import (
    AnalysisError,
    OutputError,
    one_line,
    read_json,
)
from ...loader import ResultFormatError, read_record
from ..builds import (
    commits_between,
)
from ..gbench import (
    MAX_FILE_BYTES,
    InputError,
    get_repetition_times,
    iteration_rows,
    load_benchmark_file,
)
from ..machine import cpu_model
from .steps import (
    DEFAULT_MIN_CHANGE,
    DEFAULT_MIN_NOISE,
    DEFAULT_MIN_POINTS,
    DEFAULT_PENALTY,
    Step,
    detect_steps,
)

# Version of the stored run format (the key "hrbench_history" of every run file).
HISTORY_FORMAT = 1


# Numeric fields of a Google Benchmark iteration row that are not user counters.
_NOT_COUNTERS = frozenset({
    "family_index", "per_family_instance_index", "repetitions", "repetition_index",
    "threads", "iterations", "real_time", "cpu_time", "error_occurred",
})


class HistoryError(AnalysisError, ValueError):
    """A history, a benchmark file or an option cannot be used (exit code 2)."""


def _git(args, cwd=None):
    try:
        r = subprocess.run(["git", "--no-optional-locks", *args], cwd=cwd,
                           capture_output=True, text=True, timeout=30)
    except (OSError, subprocess.SubprocessError):
        return None
    return r.stdout if r.returncode == 0 else None


def _commit_info(commit, date, subject, cwd=None):
    """Hash, ISO date, subject and dirtiness of a commit (git where it can, else given)."""
    rev = commit or "HEAD"
    out = _git(["show", "-s", "--format=%H%n%cI%n%s", rev + "^{commit}", "--"], cwd)
    info = {"sha": commit, "date": date, "subject": subject or "", "dirty": None,
            "source": "options"}
    if out is not None:
        sha, git_date, git_subject = (out.split("\n") + ["", "", ""])[:3]
        info.update(sha=sha, date=date or git_date, subject=subject or git_subject,
                    source="git")
        if commit is None:
            status = _git(["status", "--porcelain", "--untracked-files=no"], cwd)
            info["dirty"] = None if status is None else bool(status.strip())
    elif commit is None:
        raise HistoryError("no --commit given and `git rev-parse HEAD` failed here: "
                           "run in the checkout or pass --commit SHA --date ISO")
    if not info["date"]:
        raise HistoryError(f"the date of commit {info['sha']} is unknown (git does not "
                           "know it here): pass --date ISO, the commit date")
    info["date"] = _parse_date(info["date"]).isoformat()
    return info


def _parse_date(text):
    try:
        d = dt.datetime.fromisoformat(str(text))
    except ValueError:
        raise HistoryError(f"{text!r} is not an ISO 8601 date (e.g. 2026-01-31T12:00:00+00:00)"
                           ) from None
    return d if d.tzinfo is not None else d.replace(tzinfo=dt.UTC)


def _engine_info(path):
    """Version and build of the engine at `path`: ``--version`` and a tiny run's context."""
    def call(args):
        r = run_engine([path, *args], timeout=60)
        if r.exit_code != 0:
            raise HistoryError(f"{path} {' '.join(args)} failed (exit code {r.exit_code}): "
                               f"{one_line(r.message, 200)}")
        return r.stdout
    info = {"path": str(path), "version": call(["--version"]).strip()}
    out = call(["run", "parallel", "l=16", "d=1", "--eps", "0.5", "--json", "--count-only"])
    try:
        context = read_record(out).get("context", {})
    except ResultFormatError:
        raise HistoryError(f"{path} run ... --json did not print a JSON record") from None
    for key in ("build_type", "build_flags", "compiler", "git_commit", "cpu_model"):
        if key in context:
            info[key] = context[key]
    return info


def _canonical(data):
    return json.dumps(data, sort_keys=True, separators=(",", ":"), ensure_ascii=True)


def _slug_date(iso):
    return _parse_date(iso).astimezone(dt.UTC).strftime("%Y%m%dT%H%M%SZ")


def record_run(history, bench_path, commit=None, date=None, subject=None, machine=None,
               hrbench=None, cwd=None, now=None):
    """Store one benchmark run in a history directory.

    Parameters
    ----------
    history : path-like
        The history directory (created if missing).
    bench_path : path-like
        Google Benchmark JSON file with per-repetition rows.
    commit, date, subject : str, optional
        The commit measured (default ``git rev-parse HEAD`` in `cwd`), its ISO commit
        date and subject (default from git).
    machine : str, optional
        Machine name (default: the benchmark context's ``host_name``, else this host).
    hrbench : path-like, optional
        The engine, for its version and build flags.
    cwd : path-like, optional
        Where git runs (default: the current directory).
    now : datetime, optional
        The record time (default: now).

    Returns
    -------
    path : pathlib.Path
        The run file (the existing one if the run was recorded before).
    created : bool
        False if the same run (same content and commit) was already recorded.
    record : dict
        The stored record.

    Raises
    ------
    HistoryError
        A malformed benchmark file, an unknown commit date, the same measurement
        already recorded under another commit, an engine that cannot be run.
    """
    data = load_benchmark_file(bench_path)
    try:
        times = get_repetition_times(data)
    except InputError as e:
        raise HistoryError(f"{bench_path}: {e}") from None
    if not times:
        raise HistoryError(f"{bench_path} has no per-repetition benchmark rows (empty, or "
                           "written with --benchmark_report_aggregates_only)")
    info = _commit_info(commit, date, subject, cwd)
    context = data["context"]
    content = hashlib.sha256(_canonical(data).encode()).hexdigest()
    this_host = socket.gethostname()
    bench_host = context.get("host_name")
    same_host = bench_host in (None, this_host)
    load_avg = context.get("load_avg")
    if isinstance(load_avg, list) and load_avg:
        load_source = "benchmark context"
    elif same_host and hasattr(os, "getloadavg"):
        load_avg, load_source = list(os.getloadavg()), "os.getloadavg() at record time"
    else:
        load_avg, load_source = None, None
    num_cpus = context.get("num_cpus")
    machine_info = {
        "name": machine or bench_host or this_host,
        "host_name": bench_host or this_host,
        "cpu_model": cpu_model() if same_host else None,
        "num_cpus": num_cpus if num_cpus is not None else (os.cpu_count() if same_host
                                                            else None),
        "mhz_per_cpu": context.get("mhz_per_cpu"),
        "load_avg": load_avg,
        "load_avg_source": load_source,
        "recorded_on": this_host,
    }
    build = {"library_build_type": context.get("library_build_type"),
             "engine": _engine_info(hrbench) if hrbench else None}
    now = now or dt.datetime.now(dt.UTC)
    record = {
        "hrbench_history": HISTORY_FORMAT,
        "content_sha256": content,
        "recorded_at": now.isoformat(timespec="microseconds"),
        "source": os.path.basename(str(bench_path)),
        "commit": info,
        "machine": machine_info,
        "build": build,
        "benchmark": data,
    }
    history = Path(history)
    if history.exists() and not history.is_dir():
        raise HistoryError(f"{history} is not a directory")
    history.mkdir(parents=True, exist_ok=True)
    name = f"{_slug_date(info['date'])}-{info['sha'][:12]}-{content[:16]}.json"
    target = history / name
    if target.exists():
        return target, False, _read_run_file(target)
    for other in sorted(history.glob(f"*-{content[:16]}.json")):
        old = _read_run_file(other)
        if old.get("content_sha256") == content:
            raise HistoryError(
                f"{bench_path} is already recorded for commit {old['commit']['sha'][:12]} "
                f"({other.name}); one measurement cannot be a point of two commits")
    tmp = history / f".{name}.{os.getpid()}.tmp"
    try:
        with open(tmp, "w", encoding="utf-8") as f:
            json.dump(record, f, indent=1)
            f.write("\n")
            f.flush()
            os.fsync(f.fileno())  # on the disk before its name is
        try:
            os.link(tmp, target)
            created = True
        except FileExistsError:
            created = False
    except OSError as e:
        raise OutputError(f"{target}: cannot write ({e.strerror or e}); nothing "
                          "recorded") from None
    finally:
        tmp.unlink(missing_ok=True)
    return target, created, record


@dataclass
class Run:
    """One stored run, as read from the history."""

    path: Path
    content: str
    sha: str
    date: dt.datetime
    subject: str
    recorded_at: str
    machine: dict
    build: dict
    times: dict
    counters: dict
    series_key: tuple = ()
    label: str = ""


def _read_run_file(path):
    # A run file holds one benchmark file and a page of metadata.
    record = read_json(path, MAX_FILE_BYTES + (1 << 20), "history run file",
                       f"{path} is not a history run file:", HistoryError)
    if not isinstance(record, dict) or record.get("hrbench_history") != HISTORY_FORMAT:
        raise HistoryError(f"{path} is not a history run file of format {HISTORY_FORMAT} "
                           "(key 'hrbench_history')")
    for key in ("commit", "machine", "build", "benchmark"):
        if not isinstance(record.get(key), dict):
            raise HistoryError(f"{path}: history run file without '{key}'")
    if not isinstance(record["benchmark"].get("benchmarks"), list):
        raise HistoryError(f"{path}: history run file without a benchmarks list")
    return record


def _get_counters(data):
    counters = {}
    for name, row in iteration_rows(data):
        if name is None:
            continue
        per = counters.setdefault(name, {})
        for key, value in row.items():
            if (key in _NOT_COUNTERS or isinstance(value, bool)
                    or not isinstance(value, (int, float))):
                continue
            per.setdefault(key, []).append(float(value))
    return counters


def load_history(history, metric="real_time"):
    """Read every run of a history directory.

    Parameters
    ----------
    history : path-like
    metric : {'real_time', 'cpu_time'}

    Returns
    -------
    runs : list of Run
        Sorted in commit order (commit date, then record time); each run's
        ``series_key`` and ``label`` name its machine (see Notes).
    notes : list of str
        What the reader saw fit to say: duplicate files skipped, several machines.

    Notes
    -----
    A machine is its name, CPU model and core count: runs under one name with another
    CPU or core count are another machine (labelled with them). A file whose content
    hash another file already has (a copy) is skipped with a note.
    """
    history = Path(history)
    if not history.is_dir():
        raise HistoryError(f"history directory {history} does not exist (record a run "
                           "first: hrbench-history record --history DIR BENCH.json)")
    files = sorted(p for p in history.glob("*.json") if not p.name.startswith("."))
    if not files:
        raise HistoryError(f"history directory {history} holds no runs")
    runs, seen, notes = [], {}, []
    for path in files:
        record = _read_run_file(path)
        content = record.get("content_sha256") or hashlib.sha256(
            _canonical(record["benchmark"]).encode()).hexdigest()
        if content in seen:
            notes.append(f"{path.name} holds the same run as {seen[content]}: skipped, "
                         "so that no point counts twice")
            continue
        seen[content] = path.name
        c, m = record["commit"], record["machine"]
        if not c.get("sha") or not c.get("date"):
            raise HistoryError(f"{path}: history run file without a commit hash or date")
        data = record["benchmark"]
        try:
            times = get_repetition_times(data, metric)
        except InputError as e:
            raise HistoryError(f"{path}: {e}") from None
        runs.append(Run(path, content, str(c["sha"]), _parse_date(c["date"]),
                        c.get("subject") or "", str(record.get("recorded_at", "")),
                        m, record["build"], times, _get_counters(data)))
    first_seen = {}
    for r in sorted(runs, key=lambda r: r.recorded_at):
        first_seen.setdefault(r.sha, (r.date, r.recorded_at))
    runs.sort(key=lambda r: (first_seen[r.sha], r.recorded_at))
    by_name = {}
    for r in runs:
        r.series_key = (str(r.machine.get("name")), r.machine.get("cpu_model"),
                        r.machine.get("num_cpus"))
        by_name.setdefault(r.series_key[0], set()).add(r.series_key)
    for r in runs:
        name, cpu, cores = r.series_key
        r.label = name if len(by_name[name]) == 1 else f"{name} ({cpu or 'CPU ?'}, " \
            f"{cores if cores is not None else '?'} cores)"
    for name, keys in by_name.items():
        if len(keys) > 1:
            notes.append(f"machine name {name!r} covers {len(keys)} different machines (CPU "
                         "model or core count differ): each is its own series")
    return runs, notes


@dataclass(eq=False)
class Point:
    """One commit of one series: the repetitions of every run of it, pooled."""

    commit_index: int
    sha: str
    runs: list
    times: np.ndarray
    counters: dict = field(default_factory=dict)

    @property
    def median(self):
        return float(np.median(self.times))


@dataclass(eq=False)
class Series:
    """One benchmark on one machine, in commit order."""

    benchmark: str
    machine: str
    points: list
    steps: list = field(default_factory=list)


def _exact(values):
    return len(values) > 0 and max(values) == min(values)


def get_series(runs, penalty=DEFAULT_PENALTY, min_change=DEFAULT_MIN_CHANGE,
               min_noise=DEFAULT_MIN_NOISE, min_points=DEFAULT_MIN_POINTS):
    """Build the series of every benchmark and machine, with their steps.

    Parameters
    ----------
    runs : list of Run
        In commit order, as `load_history` returns them.
    penalty, min_change, min_noise, min_points : optional
        The step rule's parameters (see `detect_steps`).

    Returns
    -------
    commits : list of tuple
        ``(sha, date, subject)`` of every commit, in commit order.
    series : list of Series
        Sorted by benchmark (in first-seen order), then machine. The runs of one commit
        on one machine are pooled into one point (their repetitions together); a
        counter's value at a point is kept only if it is exact (the same in every
        repetition of every pooled run) and is not a rate (``*_per_second``).
    """
    commits, index = [], {}
    for r in runs:
        if r.sha not in index:
            index[r.sha] = len(commits)
            commits.append((r.sha, r.date, r.subject))
    bench_order, groups = {}, {}
    for r in runs:
        for bench, times in r.times.items():
            bench_order.setdefault(bench, len(bench_order))
            key = (bench, r.label)
            per = groups.setdefault(key, {})
            p = per.setdefault(index[r.sha], {"runs": [], "times": [], "counters": {}})
            p["runs"].append(r.path.name)
            p["times"].extend(times)
            for name, values in r.counters.get(bench, {}).items():
                p["counters"].setdefault(name, []).extend(values)
    series = []
    for (bench, label), per in sorted(groups.items(),
                                      key=lambda kv: (bench_order[kv[0][0]], kv[0][1])):
        points = []
        for ci in sorted(per):
            p = per[ci]
            counters = {name: values[0] for name, values in p["counters"].items()
                        if not name.endswith("_per_second") and _exact(values)}
            points.append(Point(ci, commits[ci][0], p["runs"], np.asarray(p["times"]),
                                counters))
        medians = [pt.median for pt in points]
        steps = []
        if all(m > 0 for m in medians):
            steps = detect_steps(medians, penalty, min_change, min_noise, min_points)
        series.append(Series(bench, label, points, steps))
    return commits, series


@dataclass(frozen=True)
class CounterChange:
    """An exact counter that changed from one commit to the next of a series."""

    benchmark: str
    machine: str
    index: int
    counter: str
    before: float
    after: float


def get_counter_changes(series):
    """The changes of exact counters between consecutive points of each series.

    Parameters
    ----------
    series : list of Series

    Returns
    -------
    list of CounterChange
        ``index`` is the position in ``series.points`` of the first point with the new
        value. A counter missing or not exact at either point is not compared.
    """
    changes = []
    for s in series:
        for i in range(1, len(s.points)):
            a, b = s.points[i - 1].counters, s.points[i].counters
            for name in sorted(set(a) & set(b)):
                if a[name] != b[name]:
                    changes.append(CounterChange(s.benchmark, s.machine, i, name,
                                                 a[name], b[name]))
    return changes


@dataclass(frozen=True)
class StepRange:
    """The commits a step of a series is credited to: those after the last point at the
    old level (``before``) up to the first at the new one (``after``).

    Attributes
    ----------
    series : Series
    step : Step
    before, after : str
        Hashes of the two measured commits around the step.
    commits : list of (sha, subject) or None
        ``before..after`` in git, oldest first (``after`` last); None where git does not
        know the commits (run in the repository, or pass its path).
    unmeasured : list of (sha, subject) or None
        Those of `commits` that this series has no point for: the step may be any of
        them, or ``after``.
    """

    series: Series
    step: Step
    before: str
    after: str
    commits: list | None
    unmeasured: list | None


def get_step_ranges(series, repo="."):
    """The commits every step of `series` is credited to (`StepRange`), git asked in
    `repo` for the commits between two measured ones."""
    ranges = []
    for s in series:
        measured = {p.sha for p in s.points}
        for st in s.steps:
            before, after = s.points[st.index - 1].sha, s.points[st.index].sha
            commits = commits_between(repo, before, after)
            unmeasured = None if commits is None else [
                c for c in commits if c[0] not in measured]
            ranges.append(StepRange(s, st, before, after, commits, unmeasured))
    return ranges


def _commits(n):
    return f"{n} commit" if n == 1 else f"{n} commits"


def describe_range(r, commits, width=10, limit=8):
    """Where a step lies, in words: ``at SHA``, or the range with its unmeasured commits.

    _commits_ is the history's commit list (`get_series`): without git, the commits that
    other machines measured between the two points are the only ones known."""
    if r.commits is None:
        index = {sha: i for i, (sha, _, _) in enumerate(commits)}
        gap = index[r.after] - index[r.before] - 1
        return f"at {r.after[:width]}" + (
            f" (after {r.before[:width]}, {_commits(gap)} between not measured)" if gap else "")
    if not r.unmeasured:
        return f"at {r.after[:width]}"
    listed = ", ".join(f"{sha[:width]} {subject[:50]!r}" for sha, subject in
                       r.unmeasured[:limit])
    more = len(r.unmeasured) - limit
    return (f"in {r.before[:width]}..{r.after[:width]} ({_commits(len(r.commits))}; not "
            f"measured: {listed}" + (f" and {more} more" if more > 0 else "") + ")")
