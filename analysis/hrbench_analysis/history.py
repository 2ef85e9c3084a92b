"""Benchmark history over commits: ``hrbench-history record``, ``measure`` and ``html``.

``record`` stores one Google Benchmark run (a JSON file as ``make bench`` or
``refine_bench --benchmark_out=F.json`` writes it, with repetitions) in a history
directory, together with its commit (hash, commit date, subject), its machine (name,
CPU model, core count, load average at the start) and its build (Google Benchmark's
``library_build_type``, and the engine's version, build type, compiler and flags when
``--hrbench PATH`` is given).

``html`` draws a static, self-contained HTML page of every benchmark's time (median
of the repetitions, min and max as a band) and exact counters over the commits, one
series per machine, in the spirit of asv (https://asv.readthedocs.io): the commits
where the time steps (:func:`detect_steps`) are listed in a table at the top and
marked on the plots, and so are the commits where an exact counter changes (an
algorithm change).

Storage: one JSON file per run, ``DIR/<commit date>-<commit[:12]>-<content[:16]>.json``,
where ``content`` is the SHA-256 of the benchmark file's canonical JSON. Plain files
can be merged by copying (the runs of several CI machines, artifacts), read and
diffed by people, and committed to a branch; a file is published with a hard link
from a temporary name, which never overwrites, so concurrent recorders cannot clobber
each other and a reader never sees half a file. The name makes a second record of the
same run (same content, same commit) a no-op, and the content hash refuses the same
measurement under another commit: one measurement is never two points. See
docs/history.md.

``measure BASE..HEAD`` builds every commit of a range in its own git worktree (the code
of the CI gates, :mod:`hrbench_analysis.builds`), runs its benchmarks and records them,
as asv's ``asv run`` does.

A step is flagged only with at least 3 points on each side, and is credited to the range
of commits between the last point before it and the first after it: the commits of that
range this machine did not measure are listed (git is asked in ``--repo``).

Exit codes of the command: 0 success (also a run that was already recorded), 1
``measure`` could not build or run some commit (the others are recorded), 2 usage or
input error, 74 the page could not be written (the previous page is kept): one line on
standard error for each error.
"""

import argparse
import base64
import datetime as dt
import hashlib
import html
import io
import json
import math
import os
import socket
import subprocess
import sys
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from .builds import (
    DEFAULT_FILTER,
    BuildError,
    build_commit,
    commits_between,
    locate_project,
    resolve_ref,
    run_benchmarks,
)
from .engine import run_engine
from .errors import (
    AnalysisError,
    InputFileError,
    OutputError,
    one_line,
    parse_json,
    read_bounded,
    run_main,
)
from .gbench import (
    MAX_FILE_BYTES,
    InputError,
    format_time,
    get_repetition_times,
    load_benchmark_file,
    time_unit,
)
from .output import write_file

__all__ = [
    "HistoryError",
    "Step",
    "Run",
    "Point",
    "Series",
    "CounterChange",
    "HISTORY_FORMAT",
    "DEFAULT_PENALTY",
    "DEFAULT_MIN_CHANGE",
    "DEFAULT_MIN_NOISE",
    "DEFAULT_MIN_POINTS",
    "detect_steps",
    "record_run",
    "load_history",
    "get_series",
    "get_counter_changes",
    "write_html",
    "main",
]

# Version of the stored run format (the key "hrbench_history" of every run file).
HISTORY_FORMAT = 1

# Step rule defaults (see detect_steps).
DEFAULT_PENALTY = 6.0
DEFAULT_MIN_CHANGE = 0.05
DEFAULT_MIN_NOISE = 0.005
DEFAULT_MIN_POINTS = 3

# Numeric fields of a Google Benchmark iteration row that are not user counters.
_NOT_COUNTERS = frozenset({
    "family_index", "per_family_instance_index", "repetitions", "repetition_index",
    "threads", "iterations", "real_time", "cpu_time", "error_occurred",
})


class HistoryError(AnalysisError, ValueError):
    """A history, a benchmark file or an option cannot be used (exit code 2)."""


# ---------------------------------------------------------------------------------------
# Step detection.


@dataclass(frozen=True)
class Step:
    """A detected step of a series.

    Attributes
    ----------
    index : int
        Position in the series of the first point at the new level.
    before, after : float
        Level of the segment before and after the step: the geometric mean of the
        medians of its points (same unit as the input).
    ratio : float
        ``after / before`` (1.25: 25% slower).
    """

    index: int
    before: float
    after: float
    ratio: float


def _segment_cost(csum, csum2, s, t):
    # Sum of squared deviations from the mean of y[s:t], vectorised over s.
    n = t - s
    total = csum[t] - csum[s]
    return (csum2[t] - csum2[s]) - total * total / n


def _optimal_partition(y, beta, min_points):
    """Breakpoints of the least-squares piecewise-constant fit with penalty beta per step,
    every segment at least min_points long (the caller ensures n >= min_points)."""
    n = y.size
    csum = np.concatenate(([0.0], np.cumsum(y)))
    csum2 = np.concatenate(([0.0], np.cumsum(y * y)))
    best = np.full(n + 1, np.inf)  # no partition ends before min_points
    best[0] = -beta
    last = np.zeros(n + 1, dtype=int)
    for t in range(min_points, n + 1):
        s = np.arange(t - min_points + 1)
        costs = best[:t - min_points + 1] + _segment_cost(csum, csum2, s, t) + beta
        k = int(np.argmin(costs))
        best[t], last[t] = costs[k], k
    breaks = []
    t = n
    while t > 0:
        t = int(last[t])
        if t > 0:
            breaks.append(t)
    return sorted(breaks)


def noise_level(y):
    """Robust noise of a series of log times: MAD of successive differences / sqrt(2).

    Parameters
    ----------
    y : array_like
        The series (natural log of the medians).

    Returns
    -------
    float
        Estimate of the standard deviation of one point, 0 for fewer than 2 points.
        A step moves one difference only, so it barely affects the estimate.
    """
    y = np.asarray(y, dtype=float)
    if y.size < 2:
        return 0.0
    d = np.diff(y)
    return float(1.4826 * np.median(np.abs(d - np.median(d))) / math.sqrt(2))


def detect_steps(values, penalty=DEFAULT_PENALTY, min_change=DEFAULT_MIN_CHANGE,
                 min_noise=DEFAULT_MIN_NOISE, min_points=DEFAULT_MIN_POINTS):
    """Find the points where a positive series steps to a new level.

    Parameters
    ----------
    values : array_like
        Positive values in commit order (the median time of each commit).
    penalty : float, optional
        Cost of one step in units of ``sigma**2 * ln(n)``: larger finds fewer steps.
    min_change : float, optional
        Smallest relative step kept (0.05: a level 5% higher or lower).
    min_noise : float, optional
        Floor of ``sigma`` (in log units, 0.005 is 0.5%), so that an almost noiseless
        series does not turn every wiggle into a step.
    min_points : int, optional
        Fewest points on each side of a step (3). The `min_points` points just before a
        step and those just after must not overlap (each on its own side of it): two
        commits, one outlying commit, or a level only the last two commits reached, are
        not a step.

    Returns
    -------
    list of Step
        In series order.

    Notes
    -----
    The rule, in the spirit of asv's step detection: fit the logs of the values by a
    piecewise-constant function with segments of at least `min_points` points, minimising
    the sum of squared residuals plus ``beta = penalty * sigma**2 * ln(n)`` per step
    (optimal partitioning, exact, O(n^2)), where ``sigma`` is the robust noise of one
    point (`noise_level`, at least `min_noise`). Then a step whose `min_points` points
    on either side overlap is removed (its two segments merged), and so, while the
    smallest step changes the level by less than `min_change`, is that one.
    Levels are the geometric means of the segments' values.

    Examples
    --------
    >>> s = detect_steps([10, 10.1, 9.9, 10, 12.5, 12.4, 12.6, 12.5])
    >>> [(x.index, round(x.ratio, 2)) for x in s]
    [(4, 1.25)]
    """
    v = np.asarray(values, dtype=float)
    if v.ndim != 1 or not np.all(np.isfinite(v)) or np.any(v <= 0):
        raise ValueError("values must be a 1-d array of finite positive numbers")
    if not (penalty >= 0 and min_change >= 0 and min_noise > 0):
        raise ValueError("penalty and min_change must be >= 0, min_noise > 0")
    if not (isinstance(min_points, int) and min_points >= 1):
        raise ValueError("min_points must be an integer >= 1")
    n = v.size
    if n < max(2, 2 * min_points):
        return []
    y = np.log(v)
    sigma = max(noise_level(y), min_noise)
    beta = penalty * sigma * sigma * math.log(n)
    breaks = _optimal_partition(y, beta, min_points)

    def levels(bs):
        edges = [0, *bs, n]
        return [float(np.mean(y[a:b])) for a, b in zip(edges[:-1], edges[1:], strict=True)]

    def separated(b, up):
        # The min_points points on each side of the step do not overlap.
        before, after = y[b - min_points:b], y[b:b + min_points]
        return before.max() < after.min() if up else before.min() > after.max()

    while breaks:
        lv = levels(breaks)
        mixed = [i for i, b in enumerate(breaks) if not separated(b, lv[i + 1] > lv[i])]
        if mixed:
            del breaks[mixed[0]]
            continue
        sizes = [abs(math.expm1(lv[i + 1] - lv[i])) for i in range(len(breaks))]
        i = int(np.argmin(sizes))
        if sizes[i] >= min_change:
            break
        del breaks[i]
    lv = levels(breaks)
    return [Step(b, math.exp(lv[i]), math.exp(lv[i + 1]), math.exp(lv[i + 1] - lv[i]))
            for i, b in enumerate(breaks)]


# ---------------------------------------------------------------------------------------
# Recording.


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


def _cpu_model():
    try:
        with open("/proc/cpuinfo", encoding="utf-8", errors="replace") as f:
            for line in f:
                key, _, value = line.partition(":")
                if key.strip() in ("model name", "Model", "Hardware", "cpu model"):
                    return value.strip() or None
    except OSError:
        pass
    return None


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
        context = json.loads(out).get("context", {})
    except (json.JSONDecodeError, AttributeError):
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
        "cpu_model": _cpu_model() if same_host else None,
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


# ---------------------------------------------------------------------------------------
# Loading and series.


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
    try:
        record = parse_json(read_bounded(path, MAX_FILE_BYTES + (1 << 20), "history run file"),
                            f"{path} is not a history run file:", HistoryError)
    except InputFileError as e:
        raise HistoryError(str(e)) from None
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
    for row in data["benchmarks"]:
        if not isinstance(row, dict) or row.get("run_type", "iteration") != "iteration":
            continue
        if row.get("error_occurred"):
            continue
        name = row.get("run_name", row.get("name"))
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


# ---------------------------------------------------------------------------------------
# The page.


# ---------------------------------------------------------------------------------------
# The page.


def _commits(n):
    return f"{n} commit" if n == 1 else f"{n} commits"


def _format_count(x):
    return f"{int(x):,}" if float(x).is_integer() and abs(x) < 1e18 else f"{x:.6g}"


def _figure_png(bench, series, commits, changes):
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure
    from matplotlib.ticker import FixedLocator, NullLocator

    changed = sorted({c.counter for c in changes})
    nrows = 2 if changed else 1
    fig = Figure(figsize=(9.0, 3.2 * nrows), layout="constrained")
    FigureCanvasAgg(fig)
    axes = fig.subplots(nrows, 1, sharex=True, squeeze=False)[:, 0]
    unit, scale = time_unit(np.median([p.median for s in series for p in s.points]))
    ax = axes[0]
    for s in series:
        x = np.array([p.commit_index for p in s.points])
        med = np.array([p.median for p in s.points]) / scale
        lo = np.array([p.times.min() for p in s.points]) / scale
        hi = np.array([p.times.max() for p in s.points]) / scale
        (line,) = ax.plot(x, med, "o-", ms=3.5, lw=1.2, label=f"{s.machine} (median)")
        ax.fill_between(x, lo, hi, color=line.get_color(), alpha=0.2, lw=0,
                        label=f"{s.machine} (min..max)")
        for st in s.steps:
            xi = s.points[st.index].commit_index
            ax.axvline(xi - 0.5, color=line.get_color(), ls="--", lw=1)
            ax.annotate(f"x{st.ratio:.3g}", (xi - 0.5, st.after / scale), fontsize=8,
                        xytext=(3, 3), textcoords="offset points", color=line.get_color())
    ax.set_ylabel(f"time ({unit})")
    ax.set_title(bench, fontsize=9)
    ax.legend(fontsize=7, loc="best")
    ax.grid(alpha=0.3)
    if changed:
        ax2 = axes[1]
        for s in series:
            for name in changed:
                pts = [(p.commit_index, p.counters[name]) for p in s.points
                       if name in p.counters]
                if not pts:
                    continue
                x, v = zip(*pts, strict=True)
                v = np.asarray(v, dtype=float)
                ref = v[0] if v[0] != 0 else 1.0
                ax2.plot(x, v / ref, ".-", lw=1, drawstyle="steps-mid",
                         label=f"{name} / {_format_count(ref)} ({s.machine})")
        for c in changes:
            s = next(t for t in series if t.machine == c.machine)
            ax2.axvline(s.points[c.index].commit_index - 0.5, color="0.4", ls=":", lw=1)
        ax2.set_ylabel("counter / first value")
        ax2.legend(fontsize=7, loc="best")
        ax2.grid(alpha=0.3)
    n = len(commits)
    step = max(1, math.ceil(n / 30))
    ticks = list(range(0, n, step))
    axes[-1].xaxis.set_major_locator(FixedLocator(ticks))
    axes[-1].xaxis.set_minor_locator(NullLocator())
    axes[-1].set_xticklabels([commits[i][0][:7] for i in ticks], rotation=60, fontsize=7,
                             family="monospace")
    axes[-1].set_xlim(-0.5, n - 0.5)
    axes[-1].set_xlabel("commit (commit date order)")
    buf = io.BytesIO()
    fig.savefig(buf, format="png", dpi=80)
    return base64.b64encode(buf.getvalue()).decode("ascii")


def _machines_summary(runs):
    out = {}
    for r in runs:
        m = out.setdefault(r.label, {"runs": 0, "commits": set(), "cpu": r.machine.get(
            "cpu_model"), "cores": r.machine.get("num_cpus"), "builds": set(),
            "loads": []})
        m["runs"] += 1
        m["commits"].add(r.sha)
        m["builds"].add(str(r.build.get("library_build_type")))
        la = r.machine.get("load_avg")
        if isinstance(la, list) and la:
            m["loads"].append(float(la[0]))
    return out


def _table(headers, rows):
    esc = html.escape
    head = "".join(f"<th>{esc(h)}</th>" for h in headers)
    body = "".join("<tr>" + "".join(f"<td>{c}</td>" for c in row) + "</tr>" for row in rows)
    return f"<table><thead><tr>{head}</tr></thead><tbody>{body}</tbody></table>"


def write_html(out, runs, notes, commits, series, *, metric="real_time",
               machine=None, params=None, title="hrbench benchmark history", repo="."):
    """Write the static page; return the steps and counter changes it lists.

    Parameters
    ----------
    out : path-like
        The HTML file to write (:func:`~hrbench_analysis.output.write_file`: a regular
        file replaced whole, a symbolic link's target written, a device written
        through; OutputError if the write fails, the previous page kept).
    runs, notes : as returned by `load_history` (runs already filtered by machine).
    commits, series : as returned by `get_series`.
    metric : str, optional
        The time shown.
    machine : str, optional
        The machine the page is restricted to, if any.
    params : dict, optional
        The step rule's parameters, shown on the page.
    repo : path-like, optional
        The git repository of the commits, to list those between two measured ones.

    Returns
    -------
    steps : list of StepRange
    changes : list of CounterChange
    """
    esc = html.escape
    params = params or {}
    steps = get_step_ranges(series, repo)
    changes = get_counter_changes(series)
    machines = _machines_summary(runs)

    def commit_cell(ci):
        sha, date, subject = commits[ci]
        return (f"<code title='{esc(sha)}'>{esc(sha[:10])}</code> "
                f"{esc(date.date().isoformat())} {esc(subject[:60])}")

    parts = [f"<!DOCTYPE html><html><head><meta charset='utf-8'><title>{esc(title)}</title>",
             "<style>body{font-family:sans-serif;max-width:1100px;margin:1em auto;"
             "padding:0 1em}table{border-collapse:collapse;font-size:90%;margin:.5em 0}"
             "td,th{border:1px solid #bbb;padding:2px 6px;text-align:left}"
             ".note{background:#fff4d6;border-left:4px solid #e0a800;padding:.4em .8em}"
             "img{max-width:100%}.slower{color:#b00}.faster{color:#070}"
             "h2{margin-top:1.5em}</style></head><body>",
             f"<h1>{esc(title)}</h1>",
             f"<p>{len(runs)} runs, {len(commits)} commits, "
             f"{len({s.benchmark for s in series})} benchmarks, {esc(metric)}: median of the "
             "repetitions, min..max as a band. Generated "
             f"{dt.datetime.now(dt.UTC).strftime('%Y-%m-%d %H:%M UTC')}.</p>"]
    if machine is not None:
        parts.append(f"<p class='note'>Only machine <b>{esc(machine)}</b> is shown.</p>")
    if len(machines) > 1:
        parts.append(
            f"<p class='note'>This history holds runs of {len(machines)} machines: "
            + ", ".join(f"<b>{esc(k)}</b> ({v['runs']} runs)" for k, v in machines.items())
            + ". Each machine is its own series: times of different machines are never "
            "averaged or joined, and steps are detected per machine.</p>")
    for note in notes:
        parts.append(f"<p class='note'>{esc(note)}</p>")
    rows = [(esc(k), esc(str(v["cpu"] or "?")), esc(str(v["cores"] or "?")), v["runs"],
             len(v["commits"]), esc(", ".join(sorted(v["builds"]))),
             esc(f"{min(v['loads']):.2f}..{max(v['loads']):.2f}") if v["loads"] else "?")
            for k, v in machines.items()]
    parts.append("<h2>Machines</h2>")
    parts.append(_table(["machine", "CPU model", "cores", "runs", "commits",
                         "library build", "load avg (1 min) at start"], rows))
    parts.append("<h2 id='steps'>Detected steps</h2>")
    rule = (f"Piecewise-constant fit of the log medians, penalty "
            f"{params.get('penalty', DEFAULT_PENALTY)} &sigma;&sup2; ln n per step, "
            f"&sigma; the robust noise (at least {params.get('min_noise', DEFAULT_MIN_NOISE)}"
            f"), at least {params.get('min_points', DEFAULT_MIN_POINTS)} points on each "
            f"side, steps under {params.get('min_change', DEFAULT_MIN_CHANGE):.1%} merged. "
            "A step is credited to the commits after the last point at the old level up to "
            "the first at the new one; those not measured are listed.")
    parts.append(f"<p>{rule}</p>")
    if steps:
        rows = []
        for r in steps:
            s, st = r.series, r.step
            cls = "slower" if st.ratio > 1 else "faster"
            where = commit_cell(s.points[st.index].commit_index)
            if not (r.commits is not None and not r.unmeasured):
                where += f"<br>{esc(describe_range(r, commits))}"
            rows.append((f"<a href='#b{series.index(s)}'>{esc(s.benchmark)}</a>",
                         esc(s.machine), where,
                         f"{esc(format_time(st.before))} &rarr; {esc(format_time(st.after))}",
                         f"<span class='{cls}'>{st.ratio:.3f} ({st.ratio - 1:+.1%})</span>"))
        parts.append(_table(["benchmark", "machine", "commits", "before → after", "ratio"],
                            rows))
    else:
        parts.append("<p>No step detected.</p>")
    parts.append("<h2 id='counters'>Counter changes (algorithm changes)</h2>")
    if changes:
        rows = []
        for c in changes:
            s = next(t for t in series if t.benchmark == c.benchmark and t.machine == c.machine)
            rows.append((esc(c.benchmark), esc(c.machine),
                         commit_cell(s.points[c.index].commit_index), esc(c.counter),
                         f"{_format_count(c.before)} &rarr; {_format_count(c.after)}"))
        parts.append(_table(["benchmark", "machine", "commit", "counter", "before → after"],
                            rows))
    else:
        parts.append("<p>No exact counter changed between commits.</p>")
    by_bench = {}
    for s in series:
        by_bench.setdefault(s.benchmark, []).append(s)
    parts.append("<h2>Benchmarks</h2>")
    for bench, ss in by_bench.items():
        bench_changes = [c for c in changes if c.benchmark == bench]
        png = _figure_png(bench, ss, commits, bench_changes)
        anchor = series.index(ss[0])
        parts.append(f"<h3 id='b{anchor}'>{esc(bench)}</h3>")
        parts.append(f"<img alt='{esc(bench)}' src='data:image/png;base64,{png}'>")
        for s in ss:
            last = s.points[-1]
            const = {k: v for k, v in last.counters.items()
                     if not any(c.counter == k and c.machine == s.machine
                                for c in bench_changes)}
            text = ", ".join(f"{esc(k)}={_format_count(v)}" for k, v in sorted(const.items()))
            parts.append(f"<p><b>{esc(s.machine)}</b>: {len(s.points)} commits, last "
                         f"median {esc(format_time(last.median))}"
                         + (f"; unchanged exact counters: {text}" if text else "") + "</p>")
    parts.append("<h2>Commits</h2>")
    rows = []
    for ci, (sha, date, subject) in enumerate(commits):
        ms = sorted({r.label for r in runs if r.sha == sha})
        rows.append((ci, f"<code>{esc(sha)}</code>", esc(date.isoformat()), esc(subject),
                     esc(", ".join(ms))))
    parts.append(_table(["#", "commit", "date", "subject", "machines"], rows))
    parts.append("</body></html>\n")
    out = Path(out)
    out.parent.mkdir(parents=True, exist_ok=True)
    write_file(out, "\n".join(parts))  # a symlink's target, a device written through
    return steps, changes


# ---------------------------------------------------------------------------------------
# The command line.


def _parser(prog):
    parser = argparse.ArgumentParser(
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
    mes.add_argument("--workdir", metavar="DIR", default=os.path.join(
        os.environ.get("RUNNER_TEMP") or "/tmp", "hrbench-gates"),
                     help="worktrees and builds, shared with scripts/ci/gates (default "
                          "/tmp/hrbench-gates)")
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
    workdir = os.path.abspath(args.workdir)
    runs_dir = os.path.join(workdir, "history-runs")
    os.makedirs(runs_dir, exist_ok=True)

    def log(message):
        print(f"measure: {message}", file=sys.stderr, flush=True)

    failed, recorded = [], 0
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
            run_benchmarks(build, out, f"the benchmarks of {short}", bench_cmd=args.bench_cmd,
                           bench_filter=args.filter, min_time=args.min_time,
                           repetitions=args.repetitions, env={"HRBENCH_COMMIT": sha})
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


if __name__ == "__main__":
    sys.exit(main())
