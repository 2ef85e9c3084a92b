"""Sweeps: run the ``hrbench run`` invocations of claims in parallel, read their points back.

Every run is looked up in the :class:`~hrbench_analysis.store.ResultStore` first; only missing
points are run, on a pool of worker threads (each runs one ``hrbench`` process: one point,
or the missing points of a count-only eps or min_area sweep together, ``hrbench run
--sweep``), and each finished point is committed to the store as soon as it finishes. Before a point
runs, the sweep takes its lease in the store, so that sweeps sharing one cache run each
point once: a point another sweep is running is skipped and its result read when it is
stored. The command lines and the processes themselves are :mod:`hrbench_analysis.engine`'s;
which points a claim needs is :mod:`hrbench_analysis.sweep_plan`'s (:func:`expand_claim`).
"""

import math
import os
import sys
import time
from collections import deque
from concurrent.futures import FIRST_COMPLETED, wait
from dataclasses import dataclass, field

import numpy as np

from .claimfile import ClaimsFileError
from .engine import OUTPUT_EXCEEDED, format_number, run_engine
from .lemmas import measure, statistics_env, stored_statistics
from .loader import ResultFormatError, parse_run_json, run_environment
from .schedulers import LOCAL, open_scheduler
from .slopes import plateau_ends
from .stages import EVERY_SECONDS
from .store import ACQUIRED, DONE, StoreError
from .store_leases import LEASE_RENEW
from .store_points import StoredPoint
from .sweep_plan import expand_claim

__all__ = [
    "ClaimData",
    # Planned in sweep_plan; named here too, where the sweep's functions are documented.
    "expand_claim",
    "run_points",
    "order_by_cost",
    "MAX_ATTEMPTS",
    "WORKER_LOST",
    "get_claim_data",
    "POLL_SECONDS",
    "UNREADABLE_RECORD",
]

#: Seconds between two looks at the points another sweep is running.
POLL_SECONDS = 0.2
#: The longest wait on running points before the sweep renews its leases
#: (:data:`~hrbench_analysis.store_leases.LEASE_RENEW`) or prints its progress line.
WAKE_SECONDS = min(LEASE_RENEW, EVERY_SECONDS / 3)

#: Runs of a point whose worker is lost (a killed Dask worker) before it is stored as
#: failed.
MAX_ATTEMPTS = 3
#: The exit code stored for a point whose worker was lost :data:`MAX_ATTEMPTS` times (no
#: engine ever exits with it; the next sweep runs the point again).
WORKER_LOST = -1000

#: How the message of a point whose run succeeded but printed a record the analysis cannot
#: read (:class:`~hrbench_analysis.loader.ResultFormatError`) starts; such a point is not
#: cached as final, and the command line reports it as an error of the engine.
UNREADABLE_RECORD = "unreadable output: "


def _execute(point, timeout=None, tag=None):
    # Run one point in a worker thread; the caller stores the result.
    run = run_engine(point.argv, timeout, tag)
    ok = run.exit_code == 0
    last = run.message
    if run.stopped == OUTPUT_EXCEEDED:
        last = f"{UNREADABLE_RECORD}{last}"
    elif ok:
        try:
            result = parse_run_json(run.stdout)
        except ResultFormatError as exc:
            ok, last = False, f"{UNREADABLE_RECORD}{exc}"
        else:
            last = _options_mismatch(result, point.key.options)
            ok = not last
    elif not last:
        last = f"exited with code {run.exit_code} and no message"
    code, seconds, statistics = run.exit_code, run.wall_seconds, None
    if ok and point.statistics is not None:
        # Dump the links, measure the hierarchy statistics, store them beside the record.
        found = measure(point.statistics, result.counters.get("links"), timeout, tag)
        seconds += found.wall_seconds
        if found.statistics is None:
            ok, last, code = False, found.message, found.exit_code
        else:
            statistics = stored_statistics(found.statistics)
    return StoredPoint(point.key, ok, code, "" if ok else last, run.stdout, seconds,
                       statistics=statistics)


def _execute_shared(points, timeout=None, tag=None):
    # Count several points of an eps or min_area sweep with one run (--sweep), one
    # record per point, each stored with its share of the run's wall time. If that run
    # fails or prints what the analysis cannot match to the points, each point runs
    # alone, so that a failure is stored against the point it belongs to.
    shared = points[0].shared
    run = run_engine(shared.argv([getattr(p.key, shared.param) for p in points]), timeout, tag)
    lines = run.stdout.splitlines()
    if run.exit_code == 0 and len(lines) == len(points) and all(
            _record_of(point, line) for point, line in zip(points, lines, strict=True)):
        return [StoredPoint(point.key, True, 0, "", line + "\n", run.wall_seconds / len(points))
                for point, line in zip(points, lines, strict=True)]
    return [_execute(p, timeout, tag) for p in points]


def _record_of(point, line):
    # Whether _line_ is a record of _point_'s run: readable, with its eps, min_area and
    # options.
    try:
        result = parse_run_json(line)
    except ResultFormatError:
        return False
    return (not _options_mismatch(result, point.key.options) and result.eps == point.key.eps
            and result.min_area == point.key.min_area)


def _options_mismatch(result, options):
    # An engine that reports a field named like an option (e.g. "method") must report
    # the value asked for; a mismatch means the option was not applied.
    # Without a counter table the loader files an integer option field (rays_per_side)
    # with the counters, so look in both.
    fields = {**result.counters, **result.extra}
    for name, text in options:
        for field_name in (name, name.replace("_", "-")):
            if field_name not in fields:
                continue
            got = fields[field_name]
            if got is None:
                continue  # the engine says the option does not apply to this run
            if isinstance(got, bool):  # a flag: its key's text is "true"
                same = text == ("true" if got else "false")
            elif isinstance(got, (int, float)):
                try:
                    same = float(text) == float(got)
                except (ValueError, OverflowError):
                    same = False
            else:
                same = str(got) == text
            if not same:
                return (f"the run reports {field_name}={got!r}, but "
                        f"--{name.replace('_', '-')} {text} was asked for")
    return ""


class _Progress:
    """A plain-text progress bar on a stream (rewritten in place on a terminal), naming
    the dearest of the points running (``running`` holds their keys, dearest first)."""

    def __init__(self, total, cached, stream, width=30):
        self.total, self.done, self.failed = total, cached, 0
        self.cached = cached
        self.stream, self.width = stream, width
        self.start = time.perf_counter()
        self.tty = stream is not None and hasattr(stream, "isatty") and stream.isatty()
        self.last_print = -1.0
        self.last_time = self.start
        self.last_width = 0
        self.running = []

    def update(self, failed=False, final=False):
        if self.stream is None:
            return
        self.failed += bool(failed)
        elapsed = time.perf_counter() - self.start
        frac = self.done / self.total if self.total else 1.0
        # Off a terminal, a line per tenth of the points, and one at least every
        # EVERY_SECONDS while points run (a sweep that ends on a long run is not silent).
        if not (self.tty or final or frac - self.last_print >= 0.1
                or elapsed - (self.last_time - self.start) >= EVERY_SECONDS):
            return
        if final and not self.tty and self.last_print == frac:
            return
        self.last_print = frac
        self.last_time = time.perf_counter()
        bar = "#" * int(round(frac * self.width))
        text = (f"[{bar:<{self.width}}] {self.done}/{self.total} points "
                f"({self.cached} cached, {self.failed} failed) {elapsed:6.1f} s")
        if self.running:
            more = len(self.running) - 1
            text += f"; running {_point_text(self.running[0])}" + (f" +{more}" if more else "")
        # On a terminal, blank what is left of a longer previous line.
        pad = " " * max(0, self.last_width - len(text)) if self.tty else ""
        self.last_width = len(text)
        self.stream.write(("\r" + text + pad) if self.tty else (text + "\n"))
        if final and self.tty:
            self.stream.write("\n")
        self.stream.flush()


def _point_text(key):
    # "parallel d=1 l=64 eps=0.0003 garmann": what a reader needs to recognise a run.
    params = " ".join(f"{k}={format_number(v)}" for k, v in key.params)
    return (f"{key.scene}{' ' + params if params else ''} eps={format_number(key.eps)} "
            f"{key.oracle}")


def run_points(points, store, jobs=None, progress=sys.stderr, poll=POLL_SECONDS,
               scheduler=None, timeout=None, first=(), on_stored=None):
    """Run every point that the store does not hold yet, in parallel.

    Parameters
    ----------
    points : sequence of SweepPoint
        Duplicates (same key) are run once.
    store : ResultStore
        Cache; each finished point is committed to it at once, by this process, whichever
        scheduler ran it.
    jobs : int, optional
        Number of concurrent runs of the local pool; default ``os.cpu_count()``.
    progress : text stream or None
        Where to draw the progress bar (standard error by default; ``None`` for silence).
    poll : float, optional
        Seconds between two looks at points that another sweep is running.
    scheduler : Scheduler, optional
        Where the runs execute (:func:`hrbench_analysis.schedulers.open_scheduler`): a
        Dask cluster, say. Default: a local pool of `jobs` threads, closed on return. A
        given scheduler is left open, and its ``slots`` replace `jobs`.
    timeout : float, optional
        Seconds each engine run may take (``--run-timeout``; default: no limit). A run
        past it is ended with its child processes and stored as a failure that the next
        sweep runs again.
    first : collection of PointKey, optional
        Points to start before the others, whatever their cost.
    on_stored : callable, optional
        Called with each :class:`StoredPoint` this sweep runs, once it is stored; an
        exception it raises ends the sweep as an interrupt does (no new run starts, the
        runs under way are ended with their children) and propagates.

    Returns
    -------
    summary : dict
        ``{"total": ..., "cached": ..., "ran": ..., "failed": ...}`` (counts of points).
        ``cached`` counts the points this sweep did not run: found in the store, or
        stored meanwhile by another sweep sharing it; ``ran`` and ``failed`` count the
        runs of this sweep.

    Notes
    -----
    The points run dearest first (:func:`order_by_cost`), so that the sweep does not end
    waiting on one long run. Points with the same ``shared`` command line run as one
    engine run (``--sweep``), which starts with the first of them to come up; if
    it fails, its points run one by one. A point is run only after
    :meth:`ResultStore.acquire` gave this sweep its lease, and at most `jobs` (or the
    scheduler's slots) engine runs are under way at a time. A point leased by another
    live sweep waits until that sweep stores it (it is then read back, even if it
    failed) or its lease lapses (the owner died or stopped renewing; then this sweep
    runs it). Leases are renewed every
    :data:`~hrbench_analysis.store_leases.LEASE_RENEW` seconds while their points run, and
    released when the sweep ends, normally or not. A point whose worker was lost (a Dask
    worker killed) is submitted again, up to :data:`MAX_ATTEMPTS` times in all, and then
    stored as failed with exit code :data:`WORKER_LOST`, which the next sweep runs again.
    """
    since = time.time()
    unique = {}
    for point in points:
        unique.setdefault(point.key, point)
    todo = [p for p in unique.values() if not store.is_final(p.key)]
    cached = len(unique) - len(todo)
    bar = _Progress(len(unique), cached, progress)
    ran = failed = 0
    if todo:
        todo = order_by_cost(todo, store.known_seconds())
        todo = [p for p in todo if p.key in first] + [p for p in todo if p.key not in first]
        own = scheduler is None
        if own:
            scheduler = open_scheduler(LOCAL, jobs or os.cpu_count() or 1)
        slots = scheduler.slots
        pending, waiting, running = deque(todo), [], {}
        attempts = {}
        renewed = time.monotonic()
        try:
            while pending or waiting or running:
                while pending and len(running) < slots:
                    # A point with a shared run takes the others of its run along.
                    point = pending.popleft()
                    batch = [point]
                    if point.shared:
                        batch += [p for p in pending if p.shared == point.shared]
                        pending = deque(p for p in pending if p.shared != point.shared)
                    acquired = []
                    for p in batch:
                        state = store.acquire(p.key, since=since)
                        if state == ACQUIRED:
                            acquired.append(p)
                        elif state == DONE:
                            cached += 1
                            bar.cached += 1
                            bar.done += 1
                            bar.update()
                        else:
                            waiting.append(p)
                    if acquired:
                        running[_submit(scheduler, acquired, timeout)] = acquired
                if running:
                    bar.running = [p.key for ps in running.values() for p in ps]
                    finished, _ = wait(running, timeout=poll if waiting else WAKE_SECONDS,
                                       return_when=FIRST_COMPLETED)
                    if not finished:
                        bar.update()  # the elapsed time, while long runs go on
                    for future in finished:
                        batch = running.pop(future)
                        try:
                            results = future.result()
                        except scheduler.lost as exc:
                            first = batch[0].key
                            attempts[first] = attempts.get(first, 1) + 1
                            if attempts[first] <= MAX_ATTEMPTS:
                                running[_submit(scheduler, batch, timeout)] = batch
                                continue
                            results = [StoredPoint(
                                p.key, False, WORKER_LOST,
                                f"the worker running it was lost {MAX_ATTEMPTS} times "
                                f"({type(exc).__name__})", "", 0.0) for p in batch]
                        for result in results:
                            store.put(result)
                            ran += 1
                            failed += not result.ok
                            bar.done += 1
                            bar.running = [p.key for ps in running.values() for p in ps]
                            bar.update(failed=not result.ok)
                            if on_stored is not None:
                                on_stored(result)
                    if running and time.monotonic() - renewed >= LEASE_RENEW:
                        store.renew()
                        renewed = time.monotonic()
                elif waiting:
                    time.sleep(poll)
                # Ask again for the points other sweeps hold: stored, lapsed or still busy.
                pending.extend(waiting)
                waiting.clear()
        except BaseException:
            # Interrupted: start no new run; the finished ones are already stored.
            if own:
                scheduler.close(cancel=True)
            try:
                store.release()
            except StoreError:
                pass  # the leases lapse when this process is gone
            raise
        if own:
            scheduler.close()
        store.release()
    bar.running = []
    bar.update(final=True)
    return {"total": len(unique), "cached": cached, "ran": ran, "failed": failed}


def _submit(scheduler, batch, timeout):
    # One engine run for a batch of points: the point's own, or their shared run. The
    # future gives a list of StoredPoint either way.
    if len(batch) > 1:
        return scheduler.executor.submit(_execute_shared, batch, timeout, scheduler.tag)
    return scheduler.executor.submit(_execute_list, batch[0], timeout, scheduler.tag)


def _execute_list(point, timeout=None, tag=None):
    return [_execute(point, timeout, tag)]


def order_by_cost(points, known_seconds):
    """The points, dearest first.

    The cost model: a point that ran before (under any engine version, found in
    `known_seconds` by :meth:`~hrbench_analysis.store_points.PointKey.run_text`) costs
    what it took then; these come first, longest first. The others keep the reverse of
    their sweep order, since a sweep runs from cheap to dear (eps falling, the geometry
    growing), so that each sweep's dearest points start first and the cheap ones fill
    the tail.

    Parameters
    ----------
    points : sequence of SweepPoint
    known_seconds : dict of str to float
        From :meth:`hrbench_analysis.store.ResultStore.known_seconds`.

    Returns
    -------
    ordered : list of SweepPoint
    """
    known = [p for p in points if p.key.run_text() in known_seconds]
    known.sort(key=lambda p: -known_seconds[p.key.run_text()])
    unknown = [p for p in reversed(points) if p.key.run_text() not in known_seconds]
    return known + unknown


@dataclass
class ClaimData:
    """The measured points of one claim, read back from the store.

    Attributes
    ----------
    value : ndarray
        Swept parameter of every successful point (its unit).
    x, y : ndarray
        Measured quantities of every successful point, sorted by `x`.
    series : ndarray of str
        The grid values of every successful point (``SweepPoint.series``), in the order
        of `x`.
    failures : list of dict
        Failed points: ``{"value", "exit_code", "stderr", "command"}``.
    missing : int
        Points not in the store (the sweep did not reach them).
    engine_seconds : float
        Sum of the refinement times reported by the engine (s).
    alternative : ndarray or None
        The claim's alternative law of y (key ``alternative``) at every successful
        point, in the order of `x`; ``None`` without one.
    fitted : ndarray of bool or None
        Which points the fit reads, in the order of `x`: for a claim with the key
        ``plateaus``, one per plateau (:func:`hrbench_analysis.slopes.plateau_ends`); ``None``
        for every point.

    With the key ``increments`` the points are the increments of the measured ones
    (:func:`octave_increments`), and so are `value` and `alternative`.
    """

    value: np.ndarray
    x: np.ndarray
    y: np.ndarray
    series: np.ndarray = field(default_factory=lambda: np.zeros(0, dtype=object))
    failures: list = field(default_factory=list)
    missing: int = 0
    engine_seconds: float = 0.0
    fitted: object = None
    alternative: object = None


def get_claim_data(claim, points, store, counters=None):
    """Read a claim's points from the store and evaluate its x and y formulas.

    Parameters
    ----------
    claim : Claim
    points : sequence of SweepPoint
        The claim's points (from :func:`expand_claim`).
    store : ResultStore
    counters : sequence of str, optional
        Names of the engine's scalar counters (``Capabilities.scalar_counters``), which
        the formulas may read; by default every integer field of a record (see
        :func:`hrbench_analysis.loader.parse_run_json`).

    Returns
    -------
    data : ClaimData
        Points whose x or y is ``nan`` (undefined arithmetic, such as ``log(0)``) or not
        positive are dropped (they cannot enter a log-log fit) and reported as failures.
        Formulas read the hierarchy statistics stored beside a record
        (:mod:`hrbench_analysis.lemmas`) like counters.

    Raises
    ------
    ClaimsFileError
        If x or y overflows float64 (``inf``) for a run: the formula can never give a
        measurement (counts are below 1e19), so it is an error of the claims file,
        naming the file, the line, the claim, the key and the run.
    StoreError
        If a point stored as successful holds a record that cannot be read.
    """
    rows, failures, missing, seconds = [], [], 0, 0.0
    plateaus = getattr(claim, "plateaus", None)
    formulas = [("x", claim.x), ("y", claim.y)]
    if plateaus is not None:
        formulas.append(("plateaus.of", plateaus.of))
    alternative = getattr(claim, "alternative", None)
    if alternative is not None:
        formulas.append(("alternative", alternative))
    for point in points:
        stored = store.get(point.key)
        if stored is None:
            missing += 1
            continue
        command = " ".join(point.argv[1:])
        if not stored.ok:
            failures.append({"value": point.value, "exit_code": stored.exit_code,
                             "stderr": stored.stderr, "command": command})
            continue
        try:
            result = parse_run_json(stored.output, counters=counters)
        except ResultFormatError as exc:
            raise StoreError(f"results cache {store.path} holds an unreadable record for "
                             f"'{command}' ({exc}); remove it (rm {store.path}) to start "
                             "afresh") from None
        env = run_environment(result)
        if claim.statistics:
            statistics = statistics_env(stored.statistics)
            if statistics is None:
                raise StoreError(f"results cache {store.path} holds a record without "
                                 f"hierarchy statistics for '{command}'; remove it (rm "
                                 f"{store.path}) to start afresh")
            env.update(statistics)
        seconds += result.counters.get("seconds", 0.0)
        values = {}
        for key, expr in formulas:
            value = expr(env)
            if math.isinf(value):
                raise ClaimsFileError(
                    claim.path, f"key {key!r}: formula {expr.text!r} overflows float64 "
                    f"({value}) for the run at {claim.sweep_param}="
                    f"{format_number(point.value)}; a formula must stay finite for counts "
                    "(formulas are evaluated in float64)",
                    line=claim.key_line(key), claim_id=claim.id, key=key)
            values[key] = value
        x, y = values["x"], values["y"]
        if not (x > 0 and y > 0):
            failures.append({"value": point.value, "exit_code": 0,
                             "stderr": f"x={x!r}, y={y!r} not positive",
                             "command": command})
            continue
        rows.append((x, y, point.value, point.series, values.get("plateaus.of"),
                     values.get("alternative")))
    if getattr(claim, "increments", None):
        rows, dropped = octave_increments(rows, claim.increments)
        failures += dropped
    kept = {id(row) for row in _plateau_rows(claim, rows)} if plateaus is not None else None
    rows.sort(key=lambda row: row[:3])
    fitted = None if kept is None else np.array([id(row) in kept for row in rows], dtype=bool)
    arr = np.array([row[:3] for row in rows], dtype=float).reshape(-1, 3)
    laws = (None if alternative is None else
            np.array([row[5] for row in rows], dtype=float))
    return ClaimData(value=arr[:, 2], x=arr[:, 0], y=arr[:, 1],
                     series=np.array([row[3] for row in rows], dtype=object),
                     failures=failures, missing=missing, engine_seconds=seconds,
                     fitted=fitted, alternative=laws)


#: How far (octaves) from its place its partner of :func:`octave_increments` may lie: a
#: quarter octave, so that on a sweep of 2 binary digits (``x`` and ``1.5 x`` an octave)
#: ``2^j`` never pairs with ``1.5 * 2^(j + 1)``, across the staircase's phases.
INCREMENT_SLACK_OCTAVES = 0.25


def octave_increments(rows, octaves):
    """The growth of y per e-fold of x over a whole number of octaves, point by point.

    Parameters
    ----------
    rows : list of tuple
        ``(x, y, value, series, plateau, law)`` per measured point; `law` may be ``None``.
    octaves : int
        How far apart the two points of an increment lie (octaves of x).

    Returns
    -------
    rows : list of tuple
        Per point ``i`` of each series whose partner ``j`` exists (the point with
        ``x_j`` nearest ``2^octaves x_i`` in octaves, no farther than
        :data:`INCREMENT_SLACK_OCTAVES`): ``(sqrt(x_i x_j), (y_j - y_i) / ln(x_j / x_i),
        sqrt(value_i value_j), series, None, (law_j - law_i) / ln(x_j / x_i))``.
    dropped : list of dict
        Increments that are not positive (y did not grow between the two points), which
        a log-log fit cannot read, as failures ``{"value", "exit_code", "stderr",
        "command"}``.

    Notes
    -----
    ``y = a ln x + b`` has the increment ``a`` at every x, whatever ``b``. A count
    ``L = a x ln x + b x`` is ``O(x log x)``; with ``y = L / x`` its increments are
    ``O(1)``, and a power law fitted to them separates it from ``L ~ x^(1+p)``
    (increments ``~ x^p``), where the exponent of ``L`` itself against ``x ln x``
    carries the lower-order term ``b x`` as a drift of about ``-b / (a ln^2 x)``.
    Increments over whole octaves, not between neighbours, compare points of the same
    phase of a binary staircase where the sweep holds ``x`` and ``2 x`` (binary digits).

    Examples
    --------
    >>> import math
    >>> rows = [(k, 3 * math.log(k) - 7, k, "", None, None) for k in (8, 12, 16, 24, 32)]
    >>> [(round(x, 3), round(y, 12)) for x, y, *_ in octave_increments(rows, 1)[0]]
    [(11.314, 3.0), (16.971, 3.0), (22.627, 3.0)]
    """
    out, dropped = [], []
    for series in dict.fromkeys(row[3] for row in rows):
        part = sorted((row for row in rows if row[3] == series), key=lambda row: row[0])
        xs = np.log2([row[0] for row in part])
        for i, row in enumerate(part):
            j = int(np.argmin(np.abs(xs - xs[i] - octaves)))
            if abs(xs[j] - xs[i] - octaves) > INCREMENT_SLACK_OCTAVES:
                continue
            other = part[j]
            span = math.log(other[0] / row[0])
            rise = (other[1] - row[1]) / span
            value = math.sqrt(row[2] * other[2])
            if not rise > 0:
                dropped.append({"value": value, "exit_code": 0, "command": "",
                                "stderr": f"the increment of y from x={row[0]:g} to "
                                          f"x={other[0]:g} is not positive ({rise:g})"})
                continue
            law = None if row[5] is None else (other[5] - row[5]) / span
            out.append((math.sqrt(row[0] * other[0]), rise, value, series, None, law))
    return out, dropped


def _plateau_rows(claim, rows):
    # One row per plateau of claim.plateaus.of, series by series, in sweep order (the
    # order of the swept values from the range's 'from' to its 'to', whichever mode).
    spec = claim.plateaus
    falling = any(r.start > r.stop for r in claim.ranges.values())
    kept = []
    for series in dict.fromkeys(row[3] for row in rows):
        part = sorted((row for row in rows if row[3] == series), key=lambda row: row[2],
                      reverse=falling)
        index = plateau_ends([row[2] for row in part], [row[4] for row in part],
                             keep=spec.keep, min_octaves=spec.min_octaves)
        kept += [part[i] for i in index]
    return kept

