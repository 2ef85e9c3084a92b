"""A claim as the analysis holds it (:class:`Claim`), its sweep ranges and the limits of
the work a claims file may ask for."""

import math
from dataclasses import dataclass, field, fields, replace

from ..errors import AnalysisError
from ..expr import Expression
from ..lemmas import claim_statistics
from ..loader import TIMES

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

#: What a claim is, by where its law and its quantity come from (key ``kind``):
#: ``stated``, the source's own law in the source's own quantity; ``reading``, the
#: source's law in a quantity hrbench chose where the source does not fix it (the choice
#: is stated in the key ``quantity``); ``derived``, a law of hrbench's own (a derivation,
#: a carry-over to another dimension or scene, or a measurement without a published
#: value). Only the first two are published claims with a verdict against their source.
KINDS = ("stated", "reading", "derived")
#: The kinds of :data:`KINDS` whose exponent is published.
PUBLISHED_KINDS = ("stated", "reading")

#: How a claim names its oracle through the engine's capabilities instead of by name
#: (its key ``oracle``): ``"@default"``, and ``{ kind = "form-factor" }`` kept as
#: ``"@kind=form-factor"`` until :func:`resolve_oracle` names it.
DEFAULT_ORACLE = "@default"
KIND_PREFIX = "@kind="


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


def _is_number(value):
    return isinstance(value, (int, float)) and not isinstance(value, bool) and math.isfinite(value)


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
class ClaimOrigin:
    """Where a claim comes from: its source and its place in the claims file.

    Attributes
    ----------
    statement : str
        The statement as written in the source, e.g. ``"L = Theta(N^2)"``.
    source : str
        Citation of the source.
    source_key : str
        Short key of the source (the claims file's name by default).
    description : str
        One or two sentences for a reader who has not seen the paper.
    path : str
        The claims file.
    line : int
        Line of the claim in the file.
    key_lines : dict of str to int
        Line of the keys ``x``, ``y``, ``eps``, ``params.<name>`` and of the sweep ranges
        (``sweep.quick``, ...), for the messages of the checks against the engine.
    range_keys : dict of str to str
        Mode to the key its range was given by (``"sweep.quick"`` or ``"sweep.range"``).
    kind : str
        One of :data:`KINDS`: ``"stated"``, ``"reading"`` or ``"derived"``.
    words : str
        The source's own words the claim checks, quoted (key ``words``, or the
        ``[source]`` table's), or ``""`` when the file quotes none.
    words_at : str
        Where the words stand in the source: ``"abstract"``, a section, or ``"the usual
        statement"`` for a law the source is known by but does not print in these words.
    quantity : str
        The quantity hrbench fits and why it is the source's (for a ``reading``, the
        choice hrbench made), or ``""``.
    interval_note : str
        Why the measured interval may exclude the expected exponent itself while lying
        within the tolerance (a pre-asymptotic regime, a slowly varying factor), or ``""``.
    """

    statement: str
    source: str
    source_key: str
    kind: str = "stated"
    words: str = ""
    words_at: str = ""
    quantity: str = ""
    interval_note: str = ""
    description: str = ""
    path: str = ""
    line: int = 0
    key_lines: dict = field(default_factory=dict)
    range_keys: dict = field(default_factory=dict)


@dataclass
class ClaimRun:
    """What to run: the scene, the oracle, the swept parameter and the engine's options.

    Attributes
    ----------
    scene : str
        Scene family of ``hrbench run``, or ``"mesh"`` for a mesh file (`mesh`).
    params : dict of str to float
        Fixed scene parameters (scene units).
    oracle : str
        Oracle name (not checked offline: the engine lists its oracles).
    sweep_param : str
        ``"eps"``, ``"min_area"`` or the name of a scene parameter.
    ranges : dict of str to SweepRange
        Range of the swept parameter per mode (``"quick"``, ``"full"``).
    eps : float or None
        Fixed oracle threshold when `sweep_param` is a scene parameter (dimensionless).
    grid : dict of str to tuple of float
        Scene parameters that take each of a list of values (``sweep.grid``): the sweep
        runs the range once for every combination of them.
    min_area : float or None
        ``--min-area`` passed to every run (scene units).
    max_depth : int or None
        ``--max-depth`` passed to every run (levels).
    options : dict of str to (str, int or float)
        Further engine options passed to every run, e.g. ``{"visibility": "fraction"}``
        for ``--visibility fraction`` (a ``_`` in a name becomes ``-``).
    mode_options : dict of str to dict
        Options per mode (``"quick"``, ``"full"``) that add to or override `options`.
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
    """

    scene: str
    params: dict
    oracle: str
    sweep_param: str
    ranges: dict
    eps: object = None
    grid: dict = field(default_factory=dict)
    min_area: object = None
    max_depth: object = None
    options: dict = field(default_factory=dict)
    mode_options: dict = field(default_factory=dict)
    mesh: object = None
    mesh_sha256: object = None
    command: str = "run"


@dataclass
class ClaimMeasure:
    """What to measure: the two quantities and how they are drawn.

    Attributes
    ----------
    x, y : Expression
        Measured quantities (formulas over the fields of a run).
    x_label, y_label : str
        Axis labels with units, for plots.
    chart : str or None
        Name of the report chart the claim is drawn in; claims with the same name share
        one chart. By default claims share a chart when they measure the same x and y.
    alternative : Expression or None
        A law of y that the claim's test must refute, up to a constant factor (key
        ``alternative``): the measured points tilted to it (``y law / x^e``) are judged
        by the same test (:func:`hrbench_analysis.verdict.get_verdict`).
    plateaus : Plateaus or None
        Fit one point per plateau of a staircase instead of every point (key
        ``plateaus``).
    increments : int or None
        Fit the growth of y per e-fold of x between points this many octaves of x apart
        instead of y (key ``increments``,
        :func:`hrbench_analysis.sweep.octave_increments`): with ``y = count / x``,
        ``count = O(x log x)`` is ``O(1)`` in the increments.
    """

    x: Expression
    y: Expression
    x_label: str
    y_label: str
    chart: object = None
    plateaus: object = None
    alternative: object = None
    increments: object = None


@dataclass
class ClaimJudgement:
    """How to judge the measurement: the power law expected and what makes a verdict.

    Attributes
    ----------
    expected_exponent : float
        The exponent ``k`` of ``y = Theta(x^k)`` (dimensionless), or of ``y = O(x^k)``.
    tolerance : float
        How far the measured exponent may lie from `expected_exponent` (dimensionless).
    bound : {"theta", "upper"}
        What the claim states: ``y = Theta(x^k)``, judged on both sides, or the upper
        bound ``y = O(x^k)`` of a complexity statement, reproduced by any exponent up to
        ``k + tolerance`` (:func:`hrbench_analysis.verdict.get_verdict`).
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
    """

    expected_exponent: float
    tolerance: float
    bound: str = "theta"
    x_min: object = None
    x_max: object = None
    expected_to_hold: bool = True
    min_points: int = 8
    min_decades: float = 1.5
    window_decades: float = 1.0
    theta_band: float = 10.0
    step_octaves: int = 1


#: The parts of a claim, by attribute.
CLAIM_PARTS = {"origin": ClaimOrigin, "run": ClaimRun, "measure": ClaimMeasure,
               "judge": ClaimJudgement}


@dataclass
class Claim:
    """One published statement, turned into a measurement.

    Every attribute of its parts is also an attribute of the claim (``claim.eps`` is
    ``claim.run.eps``).

    Attributes
    ----------
    id : str
        Short unique name, e.g. ``"C4"``.
    origin : ClaimOrigin
        Where it comes from.
    run : ClaimRun
        What to run.
    measure : ClaimMeasure
        What to measure.
    judge : ClaimJudgement
        How to judge it.
    """

    id: str
    origin: ClaimOrigin
    run: ClaimRun
    measure: ClaimMeasure
    judge: ClaimJudgement

    def with_oracle(self, oracle):
        """The same claim with another oracle (a selector resolved to a name)."""
        return replace(self, run=replace(self.run, oracle=oracle))

    def key_line(self, key):
        """The line of `key` in the claims file (the claim's line when unknown)."""
        return self.key_lines.get(key) or self.line

    def range_for(self, mode):
        """The sweep range for `mode`, falling back to the other mode's range."""
        if mode in self.ranges:
            return self.ranges[mode]
        return next(iter(self.ranges.values()))

    @property
    def published(self):
        """bool: whether `expected_exponent` is a published value: the claim's kind is
        ``stated`` or ``reading`` (:data:`PUBLISHED_KINDS`). A ``derived`` claim's exponent
        is this project's hypothesis, and its verdict is ``"measured"`` (the fit and its
        interval, judged against nothing)."""
        return self.kind in PUBLISHED_KINDS

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


def _part_attribute(part, name):
    # A claim's attribute `name` of its part `part`, read and set through the claim.
    def get(claim):
        return getattr(getattr(claim, part), name)

    def set_(claim, value):
        setattr(getattr(claim, part), name, value)

    return property(get, set_, doc=f"``{part}.{name}``")


for _part, _kind in CLAIM_PARTS.items():
    for _field in fields(_kind):
        setattr(Claim, _field.name, _part_attribute(_part, _field.name))
