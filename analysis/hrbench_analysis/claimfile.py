"""Published claims as data: loading and checking the claims files.

A claims file (TOML, one per published source) lists claims. Each claim says which
scene family to run, which parameter to sweep over which log-spaced range, which two
quantities to measure, and which power law ``y = Theta(x^k)`` to expect between them.
Adding a claim needs no code: see ``docs/analysis.md`` for the format.

Loading checks a file offline: its syntax, keys, types and formulas. What depends on the
engine is checked against its capabilities before any run starts: the oracle (see
:func:`hrbench_analysis.engine.oracle_error`), the names the formulas read (:func:`check_names`),
and the scene family, parameters and options (:func:`hrbench_analysis.engine.param_errors`,
:func:`hrbench_analysis.engine.missing_capability`).

The work a claims file can ask for is bounded when it is loaded: a file has at most
:data:`MAX_FILE_BYTES` bytes of UTF-8 text, a sweep range at most :data:`MAX_PER_DECADE`
points per decade and :data:`MAX_RANGE_POINTS` points, the claims loaded together at most
:data:`MAX_SWEEP_POINTS` points (ranges times grids, in the larger mode), a mesh file at
most :data:`MAX_MESH_BYTES` bytes, a formula the limits of :mod:`hrbench_analysis.expr`.
"""

import hashlib
import math
import re
import tomllib
from dataclasses import dataclass, field
from pathlib import Path

from .engine import DEFAULT_ORACLE, KIND_PREFIX, MESH_SCENE
from .errors import AnalysisError, InputFileError, open_bounded, read_bounded
from .expr import Expression, ExpressionError
from .lemmas import STATISTICS, claim_statistics
from .loader import TIMES, environment_names

__all__ = [
    "Claim",
    "Plateaus",
    "SweepRange",
    "ClaimsFileError",
    "load_claims",
    "load_claims_dir",
    "check_names",
    "range_problem",
    "MODES",
    "RESERVED_OPTIONS",
    "MAX_FILE_BYTES",
    "MAX_PER_DECADE",
    "MAX_RANGE_POINTS",
    "MAX_SWEEP_POINTS",
    "MAX_MESH_BYTES",
    "MAX_DEPTH_LIMIT",
    "MAX_ABS_EXPONENT",
    "sweep_points",
    "MAX_PARAMS",
]

#: Sweep modes a claim may give ranges for.
MODES = ("quick", "full")

#: Engine options a claim may not set through ``options``: they have claim keys of their
#: own (``eps``, ``oracle``, ``min_area``, ``max_depth``) or are set by the sweep itself.
RESERVED_OPTIONS = ("eps", "oracle", "min_area", "max_depth", "count_only", "json", "out",
                    "scene_file", "mesh", "help", "version")

#: Largest claims file, in bytes.
MAX_FILE_BYTES = 1 << 20
#: Most points per decade of a sweep range.
MAX_PER_DECADE = 1000
#: Most points of one sweep range (both ends included).
MAX_RANGE_POINTS = 10_000
#: Most points of all the claims loaded together (each claim's range times its grid, in
#: the mode with more): what one sweep may plan before its first run. The package's claims
#: have about 3,100 in the full mode; a point takes about 1 KiB while planned.
MAX_SWEEP_POINTS = 100_000
#: Largest mesh file a claim loads (hashed for the cache key): the engine's default
#: ``--max-input`` of 256 MiB.
MAX_MESH_BYTES = 256 << 20
#: Largest ``max_depth`` of a claim: more levels than double precision resolves.
MAX_DEPTH_LIMIT = 1024
#: Largest magnitude of a claim's expected exponent, and largest tolerance.
MAX_ABS_EXPONENT = 100
#: Most scene parameters of one claim.
MAX_PARAMS = 64

_OPTION_NAME = re.compile(r"[a-z][a-z0-9_]*\Z")
_PARAM_NAME = re.compile(r"[A-Za-z_][A-Za-z0-9_]*\Z")
_OPTION_TEXT = re.compile(r"[A-Za-z0-9_.:/+][A-Za-z0-9_.:/+=-]*\Z")


class ClaimsFileError(AnalysisError, ValueError):
    """A claims file that cannot be read or does not follow the format.

    Attributes
    ----------
    path : str
        The file.
    line : int or None
        1-based line of the problem, when known.
    claim_id : str or None
        The claim the problem belongs to, when known.
    key : str or None
        The offending key, when known.
    """

    def __init__(self, path, message, line=None, claim_id=None, key=None):
        self.path = str(path)
        self.line = line
        self.claim_id = claim_id
        self.key = key
        where = f"{self.path}:{line}" if line else self.path
        prefix = f"claim {claim_id!r}: " if claim_id else ""
        super().__init__(f"{where}: {prefix}{message}")


@dataclass(frozen=True)
class SweepRange:
    """A log-spaced range of the swept parameter.

    Attributes
    ----------
    start, stop : float
        First and last value (in the parameter's unit; either may be the larger).
    per_decade : float
        Points per decade (factor 10) of the parameter.
    binary_digits : int or None
        If given, round every value to this many significant binary digits instead of
        5 decimal ones, so that it and its halves are exact in double precision (what
        ``--method translation`` needs of a plate length).
    """

    start: float
    stop: float
    per_decade: float
    binary_digits: object = None

    def __post_init__(self):
        problem = range_problem(self.start, self.stop, self.per_decade)
        if problem is not None:
            raise ValueError(problem)

    @property
    def decades(self):
        """float: decades (factors 10) between `start` and `stop`."""
        return _decades(self.start, self.stop)

    @property
    def max_points(self):
        """int: how many values :meth:`values` gives at most (rounding may merge some),
        computed without generating them."""
        return _range_points(self.start, self.stop, self.per_decade)

    def values(self):
        """The swept values, log-spaced from `start` to `stop` inclusive.

        Returns
        -------
        values : list of float
            Rounded to 5 significant digits (or `binary_digits` significant bits), so
            that they print and cache identically on every run.
        """
        sign = 1.0 if self.stop > self.start else -1.0
        decades = self.decades
        n = int(math.floor(decades * self.per_decade + 1e-9)) + 1
        raw = [_log_step(self.start, sign * i / self.per_decade) for i in range(n)]
        if abs(math.log10(raw[-1] / self.stop)) > 1e-9:
            raw.append(self.stop)
        out = []
        for v in raw:
            if self.binary_digits is None:
                v = float(f"{v:.5g}")
            else:
                mantissa, exponent = math.frexp(v)
                scale = 2 ** int(self.binary_digits)
                v = math.ldexp(round(mantissa * scale) / scale, exponent)
            if not out or v != out[-1]:
                out.append(v)
        return out


def _log_step(start, exponent):
    # start * 10**exponent; through logarithms where 10**exponent leaves float64.
    if abs(exponent) < 300:
        return start * 10 ** exponent
    return 10 ** (math.log10(start) + exponent)


def _decades(start, stop):
    # |log10(stop / start)|, without overflow for ranges such as 1e-300 .. 1e300.
    ratio = stop / start
    if 0 < ratio < math.inf:
        return abs(math.log10(ratio))
    return abs(math.log10(stop) - math.log10(start))


def range_problem(start, stop, per_decade):
    """Why a log-spaced range is not allowed, or ``None``.

    Parameters
    ----------
    start, stop : float
        Ends of the range: finite, positive, different.
    per_decade : float
        Points per decade: finite, positive, at most :data:`MAX_PER_DECADE`.

    Returns
    -------
    problem : str or None
        E.g. ``"per_decade must be at most 1000, got 1000000000"``, or a range of more
        than :data:`MAX_RANGE_POINTS` points.
    """
    for name, value in (("from", start), ("to", stop), ("per_decade", per_decade)):
        if not (_is_number(value) and value > 0):
            return f"{name!r} must be a finite number > 0, got {value!r}"
    if start == stop:
        return "'from' and 'to' must differ"
    if per_decade > MAX_PER_DECADE:
        return f"'per_decade' must be at most {MAX_PER_DECADE}, got {per_decade!r}"
    points = _range_points(start, stop, per_decade)
    if points > MAX_RANGE_POINTS + 1:
        return (f"the range has {points - 1} points ({_decades(start, stop):.3g} decades at "
                f"{per_decade:g} per decade); at most {MAX_RANGE_POINTS} are allowed")
    return None


def _range_points(start, stop, per_decade):
    # Values of a range at most: the log-spaced steps, both ends included.
    return math.floor(_decades(start, stop) * per_decade + 1e-9) + 2


def sweep_points(claim):
    """The points a claim's sweep may plan: in the mode with more, its range's values
    (at most) times the combinations of its grid.

    Parameters
    ----------
    claim : Claim

    Returns
    -------
    points : int
    """
    combinations = math.prod(len(values) for values in claim.grid.values())
    return combinations * max(r.max_points for r in claim.ranges.values())


def _check_total(claims, path):
    # Refuse claims that together plan more than MAX_SWEEP_POINTS points.
    total = sum(sweep_points(c) for c in claims)
    if total > MAX_SWEEP_POINTS:
        largest = max(claims, key=sweep_points)
        raise ClaimsFileError(path, f"the claims plan {total} points in all (ranges times "
                              f"grids; claim {largest.id!r} alone {sweep_points(largest)}); "
                              f"at most {MAX_SWEEP_POINTS} are allowed in one sweep",
                              line=largest.line, claim_id=largest.id)


@dataclass
class Plateaus:
    """Which point of each plateau of a staircase a claim fits (key ``plateaus``).

    Attributes
    ----------
    of : Expression
        The quantity that steps, a formula over the fields of a run (e.g. ``N``).
    keep : str
        ``"last"`` (the point just before it steps, in sweep order) or ``"first"`` (just
        after).
    min_octaves : float
        Shortest plateau kept, in octaves of the swept parameter.
    """

    of: Expression
    keep: str
    min_octaves: float


@dataclass
class Claim:
    """One published statement, turned into a measurement.

    Attributes
    ----------
    id : str
        Short unique name, e.g. ``"C4"``.
    statement : str
        The statement as written in the source, e.g. ``"L = Theta(N^2)"``.
    source : str
        Citation of the source.
    source_key : str
        Short key of the source (the claims file's name by default).
    description : str
        One or two sentences for a reader who has not seen the paper.
    scene : str
        Scene family of ``hrbench run``, or ``"mesh"`` for a mesh file (`mesh`).
    params : dict of str to float
        Fixed scene parameters (scene units).
    oracle : str
        Oracle name (not checked offline: the engine lists its oracles).
    sweep_param : str
        ``"eps"``, ``"min_area"`` or the name of a scene parameter.
    eps : float or None
        Fixed oracle threshold when `sweep_param` is a scene parameter (dimensionless).
    ranges : dict of str to SweepRange
        Range of the swept parameter per mode (``"quick"``, ``"full"``).
    grid : dict of str to tuple of float
        Scene parameters that take each of a list of values (``sweep.grid``): the sweep
        runs the range once for every combination of them.
    x, y : Expression
        Measured quantities (formulas over the fields of a run).
    x_label, y_label : str
        Axis labels with units, for plots.
    expected_exponent : float
        The exponent ``k`` of ``y = Theta(x^k)`` (dimensionless).
    tolerance : float
        How far the measured exponent may lie from `expected_exponent` (dimensionless).
    x_min, x_max : float or None
        The asymptotic regime: only points with ``x_min <= x <= x_max`` count.
    expected_to_hold : bool
        Whether the claim is expected to hold for this measurement.
    min_points : int
        Fewest points in the regime for a verdict.
    min_decades : float
        Fewest decades of ``x`` spanned by the regime for a verdict.
    window_decades : float
        Width of the sliding windows (decades of ``x``) that judge whether the slope settled.
    theta_band : float
        Largest ``max/min`` of ``y / x^k`` over the regime that counts as bounded.
    step_octaves : int
        Period of the counts' staircase in octaves of x: 1 for binary splits, 2 where a
        split quarters an element (quadtree subdivision).
    min_area : float or None
        ``--min-area`` passed to every run (scene units).
    max_depth : int or None
        ``--max-depth`` passed to every run (levels).
    options : dict of str to (str, int or float)
        Further engine options passed to every run, e.g. ``{"visibility": "fraction"}``
        for ``--visibility fraction`` (a ``_`` in a name becomes ``-``).
    mode_options : dict of str to dict
        Options per mode (``"quick"``, ``"full"``) that add to or override `options`.
    chart : str or None
        Name of the report chart the claim is drawn in; claims with the same name share
        one chart. By default claims share a chart when they measure the same x and y.
    path : str
        The claims file.
    line : int
        Line of the claim in the file.
    key_lines : dict of str to int
        Line of the keys ``x``, ``y``, ``eps``, ``params.<name>`` and of the sweep ranges
        (``sweep.quick``, ...), for the messages of the checks against the engine.
    range_keys : dict of str to str
        Mode to the key its range was given by (``"sweep.quick"`` or ``"sweep.range"``).
    mesh : str or None
        The mesh file a claim with scene ``"mesh"`` loads (``--mesh``), resolved against
        the claims file's folder.
    mesh_sha256 : str or None
        SHA-256 of the mesh file's bytes (hex), part of every run's cache key, so that a
        changed file is never answered from runs of the old one.
    command : str
        The engine command every point runs: ``"run"`` (count the hierarchy, the default)
        or ``"solve"`` (also solve its radiosity, so that formulas may read the solve's
        measures, :data:`hrbench_analysis.loader.SOLVE_MEASURES`).
    plateaus : Plateaus or None
        Fit one point per plateau of a staircase instead of every point (key
        ``plateaus``).
    published : bool
        Whether `expected_exponent` is a published value. ``False`` for a measurement
        without one: the exponent in the file is then this project's hypothesis, and the
        verdict is ``"measured"`` (the fit and its interval, judged against nothing).
    """

    id: str
    statement: str
    source: str
    source_key: str
    description: str
    scene: str
    params: dict
    oracle: str
    sweep_param: str
    ranges: dict
    eps: object
    x: Expression
    y: Expression
    x_label: str
    y_label: str
    expected_exponent: float
    tolerance: float
    x_min: object = None
    x_max: object = None
    expected_to_hold: bool = True
    min_points: int = 8
    min_decades: float = 1.5
    window_decades: float = 1.0
    theta_band: float = 10.0
    step_octaves: int = 1
    min_area: object = None
    max_depth: object = None
    options: dict = field(default_factory=dict)
    mode_options: dict = field(default_factory=dict)
    chart: object = None
    grid: dict = field(default_factory=dict)
    path: str = ""
    line: int = 0
    key_lines: dict = field(default_factory=dict)
    range_keys: dict = field(default_factory=dict)
    mesh: object = None
    mesh_sha256: object = None
    command: str = "run"
    published: bool = True
    plateaus: object = None

    def key_line(self, key):
        """The line of `key` in the claims file (the claim's line when unknown)."""
        return self.key_lines.get(key) or self.line

    def range_for(self, mode):
        """The sweep range for `mode`, falling back to the other mode's range."""
        if mode in self.ranges:
            return self.ranges[mode]
        return next(iter(self.ranges.values()))

    @property
    def statistics(self):
        """frozenset of str: the hierarchy statistics its formulas read
        (:data:`hrbench_analysis.lemmas.STATISTICS`); each point then also measures its links."""
        return claim_statistics(self)

    @property
    def timed(self):
        """bool: whether its x or y reads a time (:data:`hrbench_analysis.loader.TIMES`),
        so that its points, exponent and verdict change from run to run."""
        return any(name in TIMES for name in self.x.names | self.y.names)

    def options_for(self, mode):
        """The engine options of `mode`: `options` updated by ``mode_options[mode]``.

        Parameters
        ----------
        mode : {"quick", "full"}

        Returns
        -------
        options : dict of str to (str, int or float)
            Sorted by name.
        """
        merged = dict(self.options)
        merged.update(self.mode_options.get(mode, {}))
        return dict(sorted(merged.items()))


_CLAIM_KEYS = {
    "id", "statement", "source", "description", "scene", "params", "oracle", "sweep",
    "x", "y", "x_label", "y_label", "expected_exponent", "tolerance", "regime",
    "expected_to_hold", "min_points", "min_decades", "window_decades", "theta_band",
    "min_area", "max_depth", "eps", "options", "chart", "step_octaves", "mesh", "command",
    "published", "plateaus", *MODES,
}
#: The engine commands a claim's points may run (key ``command``).
COMMANDS = ("run", "solve")
_REQUIRED = ("id", "statement", "scene", "params", "sweep", "x", "y",
             "expected_exponent", "tolerance")
_SWEEP_KEYS = {"param", "quick", "full", "range", "grid"}
_PLATEAU_KEYS = {"of", "keep", "min_octaves"}
#: Most scene parameters in ``sweep.grid``, and most values each takes.
MAX_GRID_PARAMS = 2
MAX_GRID_VALUES = 32
_RANGE_KEYS = {"from", "to", "per_decade"}
_RANGE_OPTIONAL = {"binary_digits"}
_REGIME_KEYS = {"x_min", "x_max"}
_SOURCE_KEYS = {"key", "citation"}
_MODE_KEYS = {"options"}


class _Locator:
    """Find the line of a claim, or of a key inside a claim, in the raw TOML text."""

    def __init__(self, text):
        self.lines = text.splitlines()
        self.headers = [n + 1 for n, line in enumerate(self.lines)
                        if re.match(r"\s*\[\[\s*claim\s*\]\]", line)]

    def claim_line(self, index):
        return self.headers[index] if index < len(self.headers) else None

    def source_line(self, key):
        # The line of `key` in the [source] table (or of source.key), else None.
        stop = self.headers[0] - 1 if self.headers else len(self.lines)
        for n in range(stop):
            if re.match(rf"\s*(source\s*\.\s*)?{re.escape(key)}\s*=", self.lines[n]):
                return n + 1
        return None

    def key_line(self, index, key):
        start = self.claim_line(index)
        if start is None:
            return None
        stop = self.headers[index + 1] - 1 if index + 1 < len(self.headers) else len(self.lines)
        parts = key.split(".")
        last = re.escape(parts[-1])
        parent = re.escape(".".join(parts[:-1])) if len(parts) > 1 else None
        patterns = [
            rf"\s*{re.escape(key)}\s*=",                      # dotted key: sweep.param =
            *([rf"\s*{parent}\s*=.*\b{last}\s*="] if parent else []),  # full.options = { k =
            rf"\s*\[\s*claim\.{re.escape(key)}\s*\]",          # table header: [claim.sweep]
            rf"\s*{last}\s*=",                                 # key inside a sub-table
            rf".*\b{last}\s*=",                                # key inside an inline table
        ]
        for pattern in patterns:
            for n in range(start - 1, stop):
                if re.match(pattern, self.lines[n]):
                    return n + 1
        return start


def _is_number(value):
    return isinstance(value, (int, float)) and not isinstance(value, bool) and math.isfinite(value)


def load_claims(path):
    """Read and check one claims file.

    Parameters
    ----------
    path : str or path-like
        A TOML claims file (format in ``docs/analysis.md``).

    Returns
    -------
    claims : list of Claim
        In file order.

    Raises
    ------
    ClaimsFileError
        If the file cannot be read, is larger than :data:`MAX_FILE_BYTES`, is not UTF-8
        text or not valid TOML (the message gives the line and column), or a claim misses
        a required key, has an unknown key, a value of the wrong type or out of its
        bounds, or a formula that does not parse. The message names the file, the line,
        the claim id and the key. No other exception comes out of arbitrary file content.
    """
    path = Path(path)
    text = _read_text(path)
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        match = re.search(r"line (\d+)", str(exc))
        line = int(match.group(1)) if match else None
        raise ClaimsFileError(path, f"not valid TOML: {exc}", line=line) from None
    except RecursionError:
        raise ClaimsFileError(path, "not valid TOML: arrays or tables nested too "
                              "deeply") from None
    loc = _Locator(text)

    unknown = set(data) - {"source", "claim"}
    if unknown:
        raise ClaimsFileError(path, f"unknown top-level key(s) {', '.join(sorted(unknown))}; "
                              "allowed: source, claim")
    source = data.get("source", {})
    if not isinstance(source, dict):
        raise ClaimsFileError(path, "[source] must be a table with 'key' and 'citation'")
    for key in sorted(source):
        line = loc.source_line(key)
        if key not in _SOURCE_KEYS:
            raise ClaimsFileError(path, f"unknown key 'source.{key}'; allowed: "
                                  f"{', '.join(sorted(_SOURCE_KEYS))}", line=line,
                                  key=f"source.{key}")
        if not (isinstance(source[key], str) and source[key].strip()):
            raise ClaimsFileError(path, f"key 'source.{key}' must be a non-empty string, "
                                  f"got {source[key]!r}", line=line, key=f"source.{key}")
    source_key = source.get("key", path.stem)
    citation = source.get("citation", source_key)
    raw_claims = data.get("claim", [])
    if not isinstance(raw_claims, list) or not raw_claims:
        raise ClaimsFileError(path, "no claims: add at least one [[claim]] table")
    claims = []
    seen = {}
    for index, raw in enumerate(raw_claims):
        if not isinstance(raw, dict):
            raise ClaimsFileError(path, f"claim #{index + 1} must be a table ([[claim]]), got "
                                  f"{type(raw).__name__}", line=loc.claim_line(index))
        claim = _parse_claim(raw, index, path, loc, source_key, citation)
        if claim.id in seen:
            raise ClaimsFileError(path, f"duplicate id (first at line {seen[claim.id]})",
                                  line=claim.line, claim_id=claim.id, key="id")
        seen[claim.id] = claim.line
        claims.append(claim)
    _check_total(claims, path)
    return claims


def _read_text(path):
    # The file as text: at most MAX_FILE_BYTES bytes of UTF-8.
    try:
        data = read_bounded(path, MAX_FILE_BYTES, "claims file")
    except InputFileError as exc:
        raise ClaimsFileError(exc.path or path, exc.reason
                              + ("; a claims file is a short TOML text"
                                 if "bytes" in exc.reason else "")) from None
    try:
        return data.decode("utf-8")
    except UnicodeDecodeError as exc:
        line = data.count(b"\n", 0, exc.start) + 1
        column = exc.start - (data.rfind(b"\n", 0, exc.start) + 1) + 1
        raise ClaimsFileError(path, f"not UTF-8 text: byte 0x{data[exc.start]:02x} at column "
                              f"{column} cannot be decoded; save the file as UTF-8",
                              line=line) from None


def _parse_claim(raw, index, path, loc, source_key, citation):
    claim_id = raw.get("id") if isinstance(raw.get("id"), str) else None

    def fail(message, key=None):
        line = loc.key_line(index, key) if key else loc.claim_line(index)
        raise ClaimsFileError(path, message, line=line, claim_id=claim_id or f"#{index + 1}",
                              key=key)

    def want(key, kind, value=None):
        value = raw.get(key) if value is None else value
        if kind == "str" and not (isinstance(value, str) and value.strip()):
            fail(f"key {key!r} must be a non-empty string, got {value!r}", key)
        if kind == "num" and not _is_number(value):
            fail(f"key {key!r} must be a finite number, got {value!r}", key)
        if kind == "pos" and not (_is_number(value) and value > 0):
            fail(f"key {key!r} must be a positive number, got {value!r}", key)
        if kind == "bool" and not isinstance(value, bool):
            fail(f"key {key!r} must be true or false, got {value!r}", key)
        if kind == "table" and not isinstance(value, dict):
            fail(f"key {key!r} must be a table, got {value!r}", key)
        return value

    # Check the keys present against the format.
    for key in _REQUIRED:
        if key not in raw:
            fail(f"missing required key {key!r}", None)
    unknown = set(raw) - _CLAIM_KEYS
    if unknown:
        key = sorted(unknown)[0]
        fail(f"unknown key {key!r}; allowed keys: {', '.join(sorted(_CLAIM_KEYS))}", key)

    want("id", "str")
    want("statement", "str")
    want("scene", "str")
    params = want("params", "table")
    mesh, mesh_sha256 = _mesh_iv(raw, path, want, fail)
    if len(params) > MAX_PARAMS:
        fail(f"key 'params' has {len(params)} scene parameters; at most {MAX_PARAMS} are "
             "allowed", "params")
    for name, value in params.items():
        if not _PARAM_NAME.match(name):
            fail(f"scene parameter name {name!r} must be a word of letters, digits and '_'",
                 "params")
        if not _is_number(value):
            fail(f"scene parameter {name!r} must be a number, got {value!r}", f"params.{name}")
    oracle = _oracle_iv(raw.get("oracle", "garmann"), fail)

    # Read the sweep: parameter and per-mode ranges.
    sweep = want("sweep", "table")
    unknown = set(sweep) - _SWEEP_KEYS
    if unknown:
        key = sorted(unknown)[0]
        fail(f"unknown key 'sweep.{key}'; allowed: {', '.join(sorted(_SWEEP_KEYS))}",
             f"sweep.{key}")
    sweep_param = want("sweep.param", "str", sweep.get("param", ""))
    if sweep_param not in ("eps", "min_area") and sweep_param not in params:
        fail(f"sweep.param {sweep_param!r} must be 'eps', 'min_area' or one of the scene "
             f"parameters ({', '.join(sorted(params))})", "sweep.param")
    if sweep_param == "min_area" and "min_area" in raw:
        fail("key 'min_area' is fixed but sweep.param is 'min_area'; drop one of them",
             "min_area")
    grid = _grid_iv(sweep.get("grid", {}), params, sweep_param, fail)
    eps = None
    if sweep_param == "eps":
        if "eps" in raw:
            fail("key 'eps' is fixed but sweep.param is 'eps'; drop one of them", "eps")
    else:
        if "eps" not in raw:
            fail(f"missing key 'eps': the oracle threshold must be fixed when sweep.param is "
                 f"{sweep_param!r}", None)
        eps = float(want("eps", "pos"))
    ranges = {}
    for mode in (*MODES, "range"):
        if mode not in sweep:
            continue
        spec = sweep[mode]
        key = f"sweep.{mode}"
        if not isinstance(spec, dict):
            fail(f"key {key!r} must be a table {{ from = ..., to = ..., per_decade = ... }}", key)
        missing = _RANGE_KEYS - set(spec)
        extra = set(spec) - _RANGE_KEYS - _RANGE_OPTIONAL
        if missing or extra:
            fail(f"key {key!r} needs the keys from, to, per_decade (and optionally "
                 "binary_digits)", key)
        for sub in _RANGE_KEYS:
            want(f"{key}.{sub}", "pos", spec[sub])
        problem = range_problem(spec["from"], spec["to"], spec["per_decade"])
        if problem is not None:
            fail(f"key {key!r}: {problem}", key)
        digits = spec.get("binary_digits")
        if digits is not None and not (isinstance(digits, int) and not isinstance(digits, bool)
                                       and 1 <= digits <= 52):
            fail(f"key '{key}.binary_digits' must be an integer from 1 to 52, got {digits!r}",
                 f"{key}.binary_digits")
        ranges[mode] = SweepRange(float(spec["from"]), float(spec["to"]),
                                  float(spec["per_decade"]), digits)
    range_keys = {mode: f"sweep.{mode}" for mode in ranges}
    if "range" in ranges:
        common = ranges.pop("range")
        del range_keys["range"]
        for mode in MODES:
            ranges.setdefault(mode, common)
            range_keys.setdefault(mode, "sweep.range")
    if not ranges:
        fail("sweep needs a range: 'quick', 'full' or 'range' = { from, to, per_decade }",
             "sweep")

    # Parse the measured quantities (the names they read are checked by check_names).
    exprs = {}
    for key in ("x", "y"):
        want(key, "str")
        try:
            exprs[key] = Expression(raw[key])
        except ExpressionError as exc:
            fail(f"key {key!r}: {exc}", key)

    k = float(want("expected_exponent", "num"))
    if abs(k) > MAX_ABS_EXPONENT:
        fail(f"key 'expected_exponent' must lie within +/-{MAX_ABS_EXPONENT}, got {k:g}",
             "expected_exponent")
    tol = float(want("tolerance", "pos"))
    if tol > MAX_ABS_EXPONENT:
        fail(f"key 'tolerance' must be at most {MAX_ABS_EXPONENT}, got {tol:g}", "tolerance")
    regime = raw.get("regime", {})
    if not isinstance(regime, dict) or set(regime) - _REGIME_KEYS:
        fail("key 'regime' must be a table with optional x_min and x_max", "regime")
    for sub in regime:
        want(f"regime.{sub}", "num", regime[sub])
    defaults = Claim.__dataclass_fields__
    options = {}
    for key, kind in (("min_points", "pos"), ("min_decades", "pos"),
                      ("window_decades", "pos"), ("theta_band", "pos")):
        if key in raw:
            options[key] = want(key, kind)
    if "min_points" in options:
        value = options["min_points"]
        if not (value == int(value) and 3 <= value <= MAX_RANGE_POINTS):
            fail(f"key 'min_points' must be an integer from 3 to {MAX_RANGE_POINTS}, got "
                 f"{value!r}", "min_points")
        options["min_points"] = int(value)
    if "step_octaves" in raw:
        value = raw["step_octaves"]
        if not (isinstance(value, int) and not isinstance(value, bool) and 1 <= value <= 4):
            fail(f"key 'step_octaves' must be an integer from 1 to 4, got {value!r}",
                 "step_octaves")
        options["step_octaves"] = value
    if options.get("theta_band", defaults["theta_band"].default) < 1:
        fail("key 'theta_band' must be at least 1", "theta_band")
    for key in ("min_area", "max_depth"):
        if key in raw:
            want(key, "pos")
    if "max_depth" in raw and not (raw["max_depth"] == int(raw["max_depth"])
                                   and raw["max_depth"] <= MAX_DEPTH_LIMIT):
        fail(f"key 'max_depth' must be an integer from 1 to {MAX_DEPTH_LIMIT}, got "
             f"{raw['max_depth']!r}", "max_depth")
    base_options = _options_iv(raw.get("options", {}), "options", fail)
    mode_options = {}
    for mode in MODES:
        if mode not in raw:
            continue
        table = raw[mode]
        if not isinstance(table, dict):
            fail(f"key {mode!r} must be a table with the key 'options', got {table!r}", mode)
        unknown = set(table) - _MODE_KEYS
        if unknown:
            key = sorted(unknown)[0]
            fail(f"unknown key '{mode}.{key}'; allowed: {', '.join(sorted(_MODE_KEYS))}",
                 f"{mode}.{key}")
        mode_options[mode] = _options_iv(table.get("options", {}), f"{mode}.options", fail)
    expected = want("expected_to_hold", "bool", raw.get("expected_to_hold", True))
    published = want("published", "bool", raw.get("published", True))
    command = want("command", "str", raw.get("command", "run"))
    if command not in COMMANDS:
        fail(f"key 'command' must be one of {', '.join(COMMANDS)}, got {command!r}", "command")
    for key in ("source", "description", "x_label", "y_label", "chart"):
        if key in raw:
            want(key, "str")
    plateaus = None
    if "plateaus" in raw:
        plateaus = _plateaus_iv(want("plateaus", "table"),
                                options.get("step_octaves", 1), fail)

    return Claim(
        id=raw["id"], statement=raw["statement"], source=raw.get("source", citation),
        source_key=source_key, description=raw.get("description", ""),
        scene=raw["scene"], params={k_: float(v) for k_, v in params.items()},
        oracle=oracle, sweep_param=sweep_param, ranges=ranges, eps=eps,
        x=exprs["x"], y=exprs["y"],
        x_label=raw.get("x_label", raw["x"]), y_label=raw.get("y_label", raw["y"]),
        expected_exponent=k, tolerance=tol,
        x_min=regime.get("x_min"), x_max=regime.get("x_max"),
        expected_to_hold=expected, min_area=raw.get("min_area"),
        max_depth=int(raw["max_depth"]) if "max_depth" in raw else None,
        options=base_options, mode_options=mode_options, chart=raw.get("chart"), grid=grid,
        path=str(path), line=loc.claim_line(index) or 0,
        key_lines={key: loc.key_line(index, key)
                   for key in ("x", "y", "eps", *(f"params.{name}" for name in params),
                               *(f"sweep.{mode}" for mode in (*MODES, "range", "grid")
                                 if mode in sweep))},
        range_keys=range_keys, mesh=mesh, mesh_sha256=mesh_sha256, command=command,
        published=published, plateaus=plateaus, **options)


def _oracle_iv(value, fail):
    # A name, "@default", or { kind = WORD }; the two selectors are kept as their text
    # ("@default", "@kind=WORD") until the engine's capabilities resolve them
    # (hrbench_analysis.engine.resolve_oracle, before any run).
    if isinstance(value, dict):
        if set(value) != {"kind"} or not isinstance(value["kind"], str) \
                or not _PARAM_NAME.match(value["kind"].replace("-", "_")):
            fail("key 'oracle' as a table must be { kind = WORD }, the kind of oracle the "
                 f"engine lists in its capabilities (e.g. \"form-factor\"), got {value!r}",
                 "oracle")
        return KIND_PREFIX + value["kind"]
    if not isinstance(value, str) or not value:
        fail(f"key 'oracle' must be a non-empty string (an oracle name or "
             f"\"{DEFAULT_ORACLE}\") or {{ kind = WORD }}, got {value!r}", "oracle")
    if value.startswith("@") and value != DEFAULT_ORACLE:
        fail(f"key 'oracle': {value!r} names no selector; use \"{DEFAULT_ORACLE}\" or "
             "{ kind = WORD }", "oracle")
    return value


def _plateaus_iv(table, step_octaves, fail):
    # Check the key `plateaus`: { of = FORMULA, keep = "last" | "first", min_octaves = X }.
    unknown = set(table) - _PLATEAU_KEYS
    if unknown:
        key = sorted(unknown)[0]
        fail(f"unknown key 'plateaus.{key}'; allowed: {', '.join(sorted(_PLATEAU_KEYS))}",
             f"plateaus.{key}")
    of = table.get("of")
    if not isinstance(of, str):
        fail(f"key 'plateaus.of' must be a formula (a string) naming the quantity that "
             f"steps, such as \"N\", got {of!r}", "plateaus.of")
    try:
        expr = Expression(of)
    except ExpressionError as exc:
        fail(f"key 'plateaus.of': {exc}", "plateaus.of")
    keep = table.get("keep", "last")
    if keep not in ("last", "first"):
        fail(f"key 'plateaus.keep' must be \"last\" or \"first\", got {keep!r}",
             "plateaus.keep")
    # Half a period of the staircase by default: sub-steps of one jump are shorter.
    span = table.get("min_octaves", step_octaves / 2)
    if not (_is_number(span) and 0 <= span <= 64):
        fail(f"key 'plateaus.min_octaves' must be a number from 0 to 64, got {span!r}",
             "plateaus.min_octaves")
    return Plateaus(of=expr, keep=keep, min_octaves=float(span))


def _mesh_iv(raw, path, want, fail):
    # Check the keys `scene = "mesh"` and `mesh = "FILE"` (one without the other is an
    # error); return the mesh file resolved against the claims file's folder and the
    # SHA-256 of its bytes, or (None, None) for a scene family.
    if "mesh" not in raw:
        if raw["scene"] == MESH_SCENE:
            fail(f"scene {MESH_SCENE!r} needs the key 'mesh' naming the mesh file", "scene")
        return None, None
    name = want("mesh", "str")
    if raw["scene"] != MESH_SCENE:
        fail(f"key 'mesh' needs scene = {MESH_SCENE!r}, got scene = {raw['scene']!r}", "mesh")
    if raw["params"]:
        fail("a mesh has no scene parameters: 'params' must be {}", "params")
    if "\0" in name:
        fail(f"key 'mesh' holds a NUL byte: {name!r}", "mesh")
    file = (Path(path).parent / name).resolve()
    digest = hashlib.sha256()
    try:
        # Hashed in blocks: never more than MAX_MESH_BYTES read, nor held at once.
        with open_bounded(file, MAX_MESH_BYTES, "mesh file") as fh:
            while block := fh.read(1 << 20):
                digest.update(block)
                if fh.tell() > MAX_MESH_BYTES:
                    raise InputFileError(file, f"the mesh file has more than "
                                         f"{MAX_MESH_BYTES} bytes")
    except InputFileError as exc:
        fail(f"mesh file {name!r}: {exc.reason} ({file})", "mesh")
    except OSError as exc:
        fail(f"mesh file {name!r} cannot be read ({file}): {exc.strerror or exc}", "mesh")
    return str(file), digest.hexdigest()


def _grid_iv(grid, params, sweep_param, fail):
    # Check `sweep.grid`: scene parameters, each with a list of positive values.
    if not isinstance(grid, dict):
        fail(f"key 'sweep.grid' must be a table of scene parameters with lists of values, "
             f"e.g. {{ l = [16, 64, 256] }}, got {grid!r}", "sweep.grid")
    if len(grid) > MAX_GRID_PARAMS:
        fail(f"key 'sweep.grid' has {len(grid)} parameters; at most {MAX_GRID_PARAMS} are "
             "allowed", "sweep.grid")
    out = {}
    for name, values in grid.items():
        key = f"sweep.grid.{name}"
        if not _PARAM_NAME.match(name) or name in ("eps", "min_area"):
            fail(f"{key}: the grid takes scene parameters only, got {name!r}", "sweep.grid")
        if name == sweep_param or name in params:
            fail(f"{key}: scene parameter {name!r} is already "
                 + ("swept" if name == sweep_param else "fixed in 'params'"), "sweep.grid")
        if not (isinstance(values, list) and 1 <= len(values) <= MAX_GRID_VALUES
                and all(_is_number(v) for v in values)):
            fail(f"{key} must be a list of 1 to {MAX_GRID_VALUES} numbers, got {values!r}",
                 "sweep.grid")
        if len(set(values)) != len(values):
            fail(f"{key} lists a value twice: {values!r}", "sweep.grid")
        out[name] = tuple(float(v) for v in values)
    return out


def check_names(claim, counters, scene_params=()):
    """Check that a claim's formulas read only names a run provides.

    A formula may read the scene parameters (the claim's and the family's), ``eps``,
    ``g`` (with ``l`` and ``d``), the engine's scalar counters, the measures
    ``patches`` and ``seconds``, the aliases ``N`` and ``L`` (see
    :func:`hrbench_analysis.loader.run_environment`), and the hierarchy statistics of
    :data:`hrbench_analysis.lemmas.STATISTICS`; a claim with ``command = "solve"`` also
    the solve's measures (:data:`hrbench_analysis.loader.SOLVE_MEASURES`). Any other name
    is a typo: the analysis exits with code 2 before any run.

    Parameters
    ----------
    claim : Claim
    counters : iterable of str
        Names of the engine's scalar counters
        (:attr:`hrbench_analysis.engine.Capabilities.scalar_counters`).
    scene_params : iterable of str, optional
        Parameter names of the claim's scene family (they have defaults, so a run
        reports them even where the claim does not set them).

    Raises
    ------
    ClaimsFileError
        Naming the file, the line, the claim, the key (``x`` or ``y``), the unknown
        names and the known ones.
    """
    known = environment_names({*claim.params, *claim.grid, *scene_params}, counters,
                              solve=claim.command == "solve")
    # The hierarchy statistics (lemmas.py); where they cannot be measured (a 3D
    # scene, --method translation) hrbench_analysis.engine.param_errors says so.
    known |= set(STATISTICS)
    formulas = [("x", claim.x), ("y", claim.y)]
    if claim.plateaus is not None:
        formulas.append(("plateaus.of", claim.plateaus.of))
    for key, expr in formulas:
        unknown = expr.names - known
        if unknown:
            raise ClaimsFileError(
                claim.path, f"key {key!r} reads unknown name(s) {', '.join(sorted(unknown))}; "
                f"known: {', '.join(sorted(known))}",
                line=claim.key_line(key), claim_id=claim.id, key=key)


def _options_iv(options, where, fail):
    # Check a table of engine options; `where` is its key ("options", "full.options").
    if not isinstance(options, dict):
        fail(f"key {where!r} must be a table of engine options, e.g. "
             "{ visibility = \"fraction\" }, "
             f"got {options!r}", where)
    out = {}
    for name, value in options.items():
        key = f"{where}.{name}"
        if not _OPTION_NAME.match(name):
            fail(f"option {name!r} in {where!r}: names are lower-case letters, digits and "
                 "'_' (a '_' becomes '-' on the command line)", key)
        if name in RESERVED_OPTIONS:
            fail(f"option {name!r} in {where!r} is not allowed there: "
                 + (f"use the claim key {name!r}" if name in _CLAIM_KEYS
                    else "the sweep sets it itself"), key)
        if isinstance(value, str):
            if not _OPTION_TEXT.match(value):
                fail(f"option {name!r} in {where!r} must be a plain word such as "
                     f"\"fraction\" (letters, digits, '_', '.', ':', '/', '+', '=', '-', "
                     f"not starting with '-'), got {value!r}", key)
        elif value is True:
            pass  # a switch, such as triangulate = true for --triangulate
        elif isinstance(value, bool) or not isinstance(value, (int, float)):
            fail(f"option {name!r} in {where!r} must be a string, an integer, a number or "
                 f"true (a switch; leave a switch out to turn it off), got {value!r}", key)
        elif not math.isfinite(value):
            fail(f"option {name!r} in {where!r} must be finite, got {value!r}", key)
        out[name] = value
    return out


def load_claims_dir(directory):
    """Read every ``*.toml`` claims file in a directory, in name order.

    Parameters
    ----------
    directory : str or path-like

    Returns
    -------
    claims : list of Claim

    Raises
    ------
    ClaimsFileError
        If a file is malformed, or two files use the same claim id.
    """
    claims = []
    seen = {}
    files = sorted(Path(directory).glob("*.toml"))
    if not files:
        raise ClaimsFileError(directory, "no claims files (*.toml) found")
    for path in files:
        for claim in load_claims(path):
            if claim.id in seen:
                raise ClaimsFileError(path, f"id already used in {seen[claim.id]}",
                                      line=claim.line, claim_id=claim.id, key="id")
            seen[claim.id] = claim.path
            claims.append(claim)
    _check_total(claims, directory)
    return claims
