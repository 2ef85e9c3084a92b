"""Sweeps: expand claims into ``hrbench run`` invocations and run them in parallel.

Every run is looked up in the :class:`~analysis.store.ResultStore` first; only missing
points are run, on a pool of worker threads (each runs one ``hrbench`` process), and
each finished point is committed to the store as soon as it finishes.
"""

import os
import re
import subprocess
import sys
import time
from concurrent.futures import ThreadPoolExecutor, as_completed
from dataclasses import dataclass, field

import numpy as np

from .loader import ResultFormatError, parse_run_json, run_environment
from .store import PointKey, StoredPoint

__all__ = [
    "SweepError",
    "SweepPoint",
    "ClaimData",
    "EngineCapabilities",
    "engine_version",
    "engine_capabilities",
    "missing_capability",
    "option_argv",
    "expand_claim",
    "run_points",
    "get_claim_data",
    "format_number",
    "run_links",
]


class SweepError(RuntimeError):
    """The engine cannot be run at all (missing, not executable, no version)."""


def format_number(value):
    """Format a parameter value for the command line: up to 10 significant digits, or
    as many as it takes to give back exactly the same double."""
    value = float(value)
    text = f"{value:.10g}"
    return text if float(text) == value else repr(value)


@dataclass(frozen=True)
class SweepPoint:
    """One run of a sweep.

    Attributes
    ----------
    key : PointKey
        Cache key of the run.
    value : float
        Value of the swept parameter.
    argv : tuple of str
        Command line (the engine path first).
    """

    key: PointKey
    value: float
    argv: tuple


def engine_version(hrbench):
    """The version string of an ``hrbench`` executable.

    Parameters
    ----------
    hrbench : str or path-like
        Path of the executable.

    Returns
    -------
    version : str
        First line of ``hrbench --version``.

    Raises
    ------
    SweepError
        If the executable is missing or ``--version`` fails.
    """
    hrbench = os.fspath(hrbench)
    if not os.path.isfile(hrbench) or not os.access(hrbench, os.X_OK):
        raise SweepError(f"engine not found or not executable: {hrbench} "
                         "(build it first, or pass --hrbench PATH)")
    try:
        proc = subprocess.run([hrbench, "--version"], capture_output=True, text=True,
                              timeout=60)
    except OSError as exc:
        raise SweepError(f"cannot run {hrbench}: {exc}") from None
    lines = proc.stdout.strip().splitlines()
    if proc.returncode != 0 or not lines:
        raise SweepError(f"{hrbench} --version failed with exit code {proc.returncode}")
    return lines[0].strip()


@dataclass(frozen=True)
class EngineCapabilities:
    """What an engine offers, as listed by ``hrbench scenes`` and ``hrbench --help``.

    Attributes
    ----------
    scenes : frozenset of str or None
        Scene families (``None`` if the engine does not list them).
    options : frozenset of str or None
        Command-line options without the leading ``--``, e.g. ``"visibility"`` (``None``
        if the engine has no readable ``--help``).
    """

    scenes: object = None
    options: object = None


def _listing(argv):
    # Standard output of a listing command, or None when it fails.
    try:
        proc = subprocess.run(argv, capture_output=True, text=True, timeout=60)
    except (OSError, subprocess.TimeoutExpired):
        return None
    return proc.stdout if proc.returncode == 0 and proc.stdout.strip() else None


def engine_capabilities(hrbench):
    """The scene families and options an ``hrbench`` executable offers.

    Parameters
    ----------
    hrbench : str or path-like
        Path of the executable.

    Returns
    -------
    capabilities : EngineCapabilities
        A field is ``None`` when the engine cannot list it; claims are then not skipped
        for it.
    """
    hrbench = os.fspath(hrbench)
    scenes = options = None
    text = _listing([hrbench, "scenes"])
    if text is not None:
        # One family per unindented line, "name: description"; parameters are indented.
        scenes = frozenset(m.group(1) for m in
                           re.finditer(r"^([A-Za-z_][\w-]*):", text, flags=re.MULTILINE))
    text = _listing([hrbench, "--help"])
    if text is not None:
        options = frozenset(re.findall(r"(?<![\w-])--([a-z][a-z0-9-]*)", text))
    return EngineCapabilities(scenes=scenes or None, options=options or None)


def missing_capability(claim, mode, capabilities):
    """Why the engine cannot run a claim, or ``None`` if it can.

    Parameters
    ----------
    claim : Claim
    mode : {"quick", "full"}
    capabilities : EngineCapabilities

    Returns
    -------
    reason : str or None
        E.g. ``"engine lacks scene 'parallel3d'"`` or ``"engine lacks option
        --visibility"``.
    """
    if capabilities.scenes is not None and claim.scene not in capabilities.scenes:
        return f"engine lacks scene {claim.scene!r}"
    if capabilities.options is not None:
        lacking = [f"--{name.replace('_', '-')}" for name in claim.options_for(mode)
                   if name.replace("_", "-") not in capabilities.options]
        if lacking:
            return f"engine lacks option{'s' if len(lacking) > 1 else ''} {', '.join(lacking)}"
    return None


def _option_text(value):
    if isinstance(value, str):
        return value
    if isinstance(value, int):
        return str(value)
    return format_number(value)


def option_argv(options):
    """The command-line form of engine options.

    Parameters
    ----------
    options : dict of str to (str, int or float)
        E.g. ``{"rays_per_side": 4, "visibility": "fraction"}``.

    Returns
    -------
    argv : list of str
        ``["--rays-per-side", "4", "--visibility", "fraction"]``: sorted by name, ``_``
        in a name becomes ``-``, numbers as in :func:`format_number` (integers exactly).
    """
    argv = []
    for name, value in sorted(options.items()):
        argv += [f"--{name.replace('_', '-')}", _option_text(value)]
    return argv


def expand_claim(claim, mode, hrbench, version):
    """The runs a claim needs.

    Parameters
    ----------
    claim : Claim
    mode : {"quick", "full"}
        Which of the claim's ranges to sweep.
    hrbench : str
        Path of the engine.
    version : str
        Engine version, part of every cache key.

    Returns
    -------
    points : list of SweepPoint
        One per value of the swept parameter, in sweep order.
    """
    points = []
    options = claim.options_for(mode)
    key_options = tuple((name, _option_text(v)) for name, v in sorted(options.items()))
    for value in claim.range_for(mode).values():
        params = dict(claim.params)
        if claim.sweep_param == "eps":
            eps = value
        else:
            params[claim.sweep_param] = value
            eps = claim.eps
        key = PointKey(version=version, scene=claim.scene,
                       params=tuple(sorted(params.items())), eps=float(eps),
                       oracle=claim.oracle, min_area=claim.min_area,
                       max_depth=claim.max_depth, mode="count-only", options=key_options)
        argv = [os.fspath(hrbench), "run", claim.scene]
        argv += [f"{k}={format_number(v)}" for k, v in sorted(params.items())]
        argv += ["--eps", format_number(eps), "--oracle", claim.oracle]
        if claim.min_area is not None:
            argv += ["--min-area", format_number(claim.min_area)]
        if claim.max_depth is not None:
            argv += ["--max-depth", str(int(claim.max_depth))]
        argv += option_argv(options)
        argv += ["--count-only", "--json"]
        points.append(SweepPoint(key=key, value=value, argv=tuple(argv)))
    return points


def _execute(point):
    # Run one point in a worker thread; the caller stores the result.
    start = time.perf_counter()
    try:
        proc = subprocess.run(point.argv, capture_output=True, text=True)
        code, out, err = proc.returncode, proc.stdout, proc.stderr
    except OSError as exc:
        code, out, err = 127, "", str(exc)
    wall = time.perf_counter() - start
    lines = [line for line in err.splitlines() if line.strip()]
    last = lines[-1].strip() if lines else ""
    ok = code == 0
    if ok:
        try:
            result = parse_run_json(out)
        except ResultFormatError as exc:
            ok, last = False, f"unreadable output: {exc}"
        else:
            last = _options_mismatch(result, point.key.options)
            ok = not last
    elif not last:
        last = f"exited with code {code} and no message"
    return StoredPoint(point.key, ok, code, "" if ok else last, out, wall)


def _options_mismatch(result, options):
    # An engine that reports a field named like an option (e.g. "method") must report
    # the value asked for; a mismatch means the option was not applied.
    for name, text in options:
        for field_name in (name, name.replace("_", "-")):
            if field_name not in result.extra:
                continue
            got = result.extra[field_name]
            if got is None:
                continue  # the engine says the option does not apply to this run
            if isinstance(got, (int, float)) and not isinstance(got, bool):
                try:
                    same = float(text) == float(got)
                except ValueError:
                    same = False
            else:
                same = str(got) == text
            if not same:
                return (f"the run reports {field_name}={got!r}, but "
                        f"--{name.replace('_', '-')} {text} was asked for")
    return ""


class _Progress:
    """A plain-text progress bar on a stream (rewritten in place on a terminal)."""

    def __init__(self, total, cached, stream, width=30):
        self.total, self.done, self.failed = total, cached, 0
        self.cached = cached
        self.stream, self.width = stream, width
        self.start = time.perf_counter()
        self.tty = stream is not None and hasattr(stream, "isatty") and stream.isatty()
        self.last_print = -1.0

    def update(self, failed=False, final=False):
        if self.stream is None:
            return
        self.failed += bool(failed)
        elapsed = time.perf_counter() - self.start
        frac = self.done / self.total if self.total else 1.0
        if not (self.tty or final or frac - self.last_print >= 0.1):
            return
        if final and not self.tty and self.last_print == frac:
            return
        self.last_print = frac
        bar = "#" * int(round(frac * self.width))
        text = (f"[{bar:<{self.width}}] {self.done}/{self.total} points "
                f"({self.cached} cached, {self.failed} failed) {elapsed:6.1f} s")
        self.stream.write(("\r" + text) if self.tty else (text + "\n"))
        if final and self.tty:
            self.stream.write("\n")
        self.stream.flush()


def run_points(points, store, jobs=None, progress=sys.stderr):
    """Run every point that the store does not hold yet, in parallel.

    Parameters
    ----------
    points : sequence of SweepPoint
        Duplicates (same key) are run once.
    store : ResultStore
        Cache; each finished point is committed to it at once.
    jobs : int, optional
        Number of concurrent runs; default ``os.cpu_count()``.
    progress : text stream or None
        Where to draw the progress bar (standard error by default; ``None`` for silence).

    Returns
    -------
    summary : dict
        ``{"total": ..., "cached": ..., "ran": ..., "failed": ...}`` (counts of points).
    """
    unique = {}
    for point in points:
        unique.setdefault(point.key, point)
    todo = [p for p in unique.values() if not store.is_final(p.key)]
    cached = len(unique) - len(todo)
    bar = _Progress(len(unique), cached, progress)
    failed = 0
    if todo:
        # Start the most expensive runs first (sweeps are listed cheap to dear).
        todo.reverse()
        pool = ThreadPoolExecutor(max_workers=jobs or os.cpu_count() or 1)
        try:
            futures = [pool.submit(_execute, p) for p in todo]
            for future in as_completed(futures):
                result = future.result()
                store.put(result)
                failed += not result.ok
                bar.done += 1
                bar.update(failed=not result.ok)
        except BaseException:
            # Interrupted: start no new run; the finished ones are already stored.
            pool.shutdown(wait=True, cancel_futures=True)
            raise
        pool.shutdown()
    bar.update(final=True)
    return {"total": len(unique), "cached": cached, "ran": len(todo), "failed": failed}


@dataclass
class ClaimData:
    """The measured points of one claim, read back from the store.

    Attributes
    ----------
    value : ndarray
        Swept parameter of every successful point (its unit).
    x, y : ndarray
        Measured quantities of every successful point, sorted by `x`.
    failures : list of dict
        Failed points: ``{"value", "exit_code", "stderr", "command"}``.
    missing : int
        Points not in the store (the sweep did not reach them).
    engine_seconds : float
        Sum of the refinement times reported by the engine (s).
    """

    value: np.ndarray
    x: np.ndarray
    y: np.ndarray
    failures: list = field(default_factory=list)
    missing: int = 0
    engine_seconds: float = 0.0


def get_claim_data(claim, points, store):
    """Read a claim's points from the store and evaluate its x and y formulas.

    Parameters
    ----------
    claim : Claim
    points : sequence of SweepPoint
        The claim's points (from :func:`expand_claim`).
    store : ResultStore

    Returns
    -------
    data : ClaimData
        Points whose x or y is not a finite positive number are dropped (they cannot
        enter a log-log fit) and reported as failures.
    """
    rows, failures, missing, seconds = [], [], 0, 0.0
    for point in points:
        stored = store.get(point.key)
        if stored is None:
            missing += 1
            continue
        if not stored.ok:
            failures.append({"value": point.value, "exit_code": stored.exit_code,
                             "stderr": stored.stderr, "command": " ".join(point.argv[1:])})
            continue
        result = parse_run_json(stored.output)
        env = run_environment(result)
        seconds += result.counters.get("seconds", 0.0)
        x, y = claim.x(env), claim.y(env)
        if not (np.isfinite(x) and np.isfinite(y) and x > 0 and y > 0):
            failures.append({"value": point.value, "exit_code": 0,
                             "stderr": f"x={x!r}, y={y!r} not positive",
                             "command": " ".join(point.argv[1:])})
            continue
        rows.append((x, y, point.value))
    rows.sort()
    arr = np.array(rows, dtype=float).reshape(-1, 3)
    return ClaimData(value=arr[:, 2], x=arr[:, 0], y=arr[:, 1], failures=failures,
                     missing=missing, engine_seconds=seconds)


def run_links(hrbench, scene, params, eps, out, oracle="garmann"):
    """Write the link list of one refinement with ``hrbench links``.

    Parameters
    ----------
    hrbench : str or path-like
        Path of the engine.
    scene : str
        Scene family.
    params : dict of str to float
        Scene parameters (scene units).
    eps : float
        Oracle threshold (dimensionless).
    out : str or path-like
        CSV file to write.
    oracle : str, optional

    Raises
    ------
    SweepError
        If the run fails; the message holds its exit code and last line of standard error.
    """
    argv = [os.fspath(hrbench), "links", scene]
    argv += [f"{k}={format_number(v)}" for k, v in sorted(params.items())]
    argv += ["--eps", format_number(eps), "--oracle", oracle, "--out", os.fspath(out)]
    proc = subprocess.run(argv, capture_output=True, text=True)
    if proc.returncode != 0:
        lines = [line for line in proc.stderr.splitlines() if line.strip()]
        raise SweepError(f"{' '.join(argv[1:])} failed with exit code {proc.returncode}: "
                         f"{lines[-1] if lines else 'no message'}")
