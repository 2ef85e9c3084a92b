"""Run records: the JSON object ``hrbench run --json`` (and ``solve --json``) prints, and
the names a claim's formulas read from it."""

import math
from dataclasses import dataclass, field

from ..errors import AnalysisError, parse_json

#: JSON schema version of ``hrbench run --json`` that this module understands.
SCHEMA_VERSION = 1

#: Longest run record read, in bytes: a record holds a few hundred numbers (per-depth
#: histograms of at most a few thousand entries), a few KiB.
MAX_RECORD_BYTES = 16 << 20

#: The counters the analysis itself reads by name, which every run record must hold:
#: ``nodes`` and ``links`` (the aliases ``N`` and ``L``), ``leaves``, ``oracle_calls`` and
#: ``max_depth``. They are not the full list: the engine names all its counters in
#: ``hrbench capabilities --json`` (:attr:`hrbench_analysis.engine.Capabilities.scalar_counters`),
#: and a record is read generically (see :func:`parse_run_json`). Their meaning is in
#: docs/conventions.md.
COUNTERS = ("nodes", "leaves", "links", "oracle_calls", "max_depth")
_REQUIRED = COUNTERS

#: Measured top-level fields of a record that are not in the engine's counter table but
#: that formulas may read like counters: ``patches`` (root patches of the scene, count),
#: ``seconds`` and ``cpu_seconds`` (the refinement's wall and CPU time, s),
#: ``linking_seconds`` (the initial linking's wall time, s) and ``linking_bytes`` (what
#: the initial linking keeps, bytes).
MEASURES = ("patches", "seconds", "cpu_seconds", "linking_seconds", "linking_bytes")

#: Measured fields of an ``hrbench solve --json`` record that the formulas of a claim with
#: ``command = "solve"`` may read (docs/solve.md): the errors against the dense reference
#: (relative, dimensionless) and their two parts, the projection's (the reference's
#: projection onto the leaves against it) and the hierarchy's (the leaves against that
#: projection: the links' own error), the reference's own change on mesh doubling, the
#: links' largest exact form factor and the share of links above eps, the solver's
#: iterations and residual, the powers, and the time of each stage (s).
SOLVE_MEASURES = ("reference_error_max", "reference_error_mean", "reference_error_l2",
                  "projection_error_max", "projection_error_mean", "projection_error_l2",
                  "hierarchy_error_max", "hierarchy_error_mean", "hierarchy_error_l2",
                  "reference_change", "link_form_factor_max", "link_form_factor_above_eps",
                  "iterations", "residual", "emitted_power",
                  "absorbed_power", "seconds_refine", "seconds_coefficients", "seconds_solve",
                  "cpu_seconds_refine", "cpu_seconds_coefficients", "cpu_seconds_solve",
                  "cpu_seconds_reference")

#: The measures that are times (s): they depend on the machine and its load and change
#: from run to run, where counts and the solution's errors do not.
TIMES = ("seconds", "cpu_seconds", "linking_seconds", "seconds_refine",
         "seconds_coefficients", "seconds_solve", "cpu_seconds_refine",
         "cpu_seconds_coefficients", "cpu_seconds_solve", "cpu_seconds_reference")

#: Short names a claim formula may use for counters, as in the published statements.
ALIASES = {"N": "nodes", "L": "links"}

# Top-level fields that RunResult reads by name: what describes the run (never a
# counter, even where it is an integer) and the two histograms it keeps as fields.
_RECORD_FIELDS = ("schema_version", "version", "scene", "params", "eps", "oracle", "mode",
                  "min_area", "max_depth_limit", "nodes_per_depth", "links_per_depth")


class ResultFormatError(AnalysisError, ValueError):
    """Output of ``hrbench run --json`` that cannot be read."""


@dataclass
class RunResult:
    """One run of ``hrbench run --json``.

    Attributes
    ----------
    version : str
        Engine version string.
    scene : str
        Scene family name, e.g. ``"parallel"``.
    params : dict of str to float
        Scene parameters after defaults (lengths in scene units).
    eps : float
        Oracle threshold (dimensionless for ``garmann`` in 2D).
    oracle : str
        Oracle name.
    mode : str
        ``"count-only"`` or ``"store"``.
    min_area : float or None
        Recursion limit on element size (scene units), if any.
    max_depth_limit : int or None
        Recursion limit on depth (levels), if any.
    counters : dict of str to float
        The scalar counters the record holds (see :func:`parse_run_json`), and the
        measures of :data:`MEASURES` (counts; ``seconds`` in s).
    nodes_per_depth : list of int
        Elements per element depth (count).
    links_per_depth : list of int
        Links per link depth ``depth_i + depth_j`` (count).
    extra : dict
        Fields this module does not know, kept for the record.
    """

    version: str
    scene: str
    params: dict
    eps: float
    oracle: str
    mode: str
    min_area: object
    max_depth_limit: object
    counters: dict
    nodes_per_depth: list = field(default_factory=list)
    links_per_depth: list = field(default_factory=list)
    extra: dict = field(default_factory=dict)


def _number(obj, key, where):
    value = obj.get(key)
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise ResultFormatError(f"{where}: field {key!r} must be a number, got "
                                f"{_short(value)}")
    _float_iv(value, f"{where}: field {key!r}")
    return value


def _float_iv(value, where):
    # float(value), or a ResultFormatError for an integer beyond float64.
    try:
        return float(value)
    except OverflowError:
        raise ResultFormatError(f"{where} is too large for float64") from None


def _is_integer(value):
    return isinstance(value, int) and not isinstance(value, bool)


def _counter_names(obj, counters):
    # The names of the scalar counters of a record, in the record's order.
    if counters is None:
        return [k for k, v in obj.items() if k not in _RECORD_FIELDS and _is_integer(v)]
    return [k for k in counters if k in obj]


def _read_counters(obj, counters):
    # The counters and measures of a record, checked.
    out = {}
    for key in _counter_names(obj, counters):
        if obj[key] is not None:
            if not _is_integer(obj[key]):
                raise ResultFormatError(f"run output: counter {key!r} must be an integer, "
                                        f"got {obj[key]!r}")
            if obj[key] < 0 and key in _REQUIRED:
                raise ResultFormatError(f"run output: counter {key!r} must not be negative, "
                                        f"got {obj[key]!r}")
            out[key] = obj[key]
    for key in (*MEASURES, *SOLVE_MEASURES):
        if obj.get(key) is not None:
            out[key] = _number(obj, key, "run output")
    for key in _REQUIRED:
        if key in obj and not _is_integer(obj[key]):
            raise ResultFormatError(f"run output: counter {key!r} must be an integer, got "
                                    f"{_short(obj[key])}")
        if key not in out:
            raise ResultFormatError(f"run output: required counter {key!r} is missing")
    return out


def _short(value):
    # A value for an error message: at most 60 characters of its repr.
    text = repr(value)
    return text if len(text) <= 60 else text[:57] + "..."


def _string_iv(obj, key, required=True):
    # obj[key] as a string; a missing optional field reads as "".
    if key not in obj and not required:
        return ""
    if key not in obj:
        raise ResultFormatError(f"run output: required field {key!r} is missing")
    if not isinstance(obj[key], str):
        raise ResultFormatError(f"run output: field {key!r} must be a string, got "
                                f"{_short(obj[key])}")
    return obj[key]


def _params_iv(obj):
    # The scene parameters: an object of numbers (names as on the command line).
    if "params" not in obj:
        raise ResultFormatError("run output: required field 'params' is missing (an object "
                                "of the scene parameters, {} for none)")
    params = obj["params"]
    if not isinstance(params, dict):
        raise ResultFormatError(f"run output: field 'params' must be an object, got "
                                f"{_short(params)}")
    out = {}
    for name, value in params.items():
        if isinstance(value, bool) or not isinstance(value, (int, float)):
            raise ResultFormatError(f"run output: field 'params.{name}' must be a number, "
                                    f"got {_short(value)}")
        out[name] = _float_iv(value, f"run output: parameter {name!r}")
    return out


def _optional_iv(obj, key, is_kind, kind):
    # obj[key] when it is null, missing (None) or of `kind`.
    value = obj.get(key)
    if value is not None and not is_kind(value):
        raise ResultFormatError(f"run output: field {key!r} must be {kind} or null, got "
                                f"{_short(value)}")
    return value


def _histogram_iv(obj, key):
    # A per-depth histogram: a list of integers >= 0 (missing or null: empty).
    values = obj.get(key)
    if values is None:
        return []
    if not isinstance(values, list) or not all(_is_integer(v) and v >= 0 for v in values):
        raise ResultFormatError(f"run output: field {key!r} must be a list of integers >= 0, "
                                f"got {_short(values)}")
    return list(values)


def _eps_iv(obj):
    # The oracle threshold: a finite number > 0.
    eps = float(_number(obj, "eps", "run output"))
    if not (eps > 0 and math.isfinite(eps)):
        raise ResultFormatError(f"run output: field 'eps' must be a finite number > 0, got "
                                f"{_short(obj['eps'])}")
    return eps


def _is_number(value):
    return isinstance(value, (int, float)) and not isinstance(value, bool)


def read_record(text):
    """The JSON object of one run record (``run --json``, ``solve --json``), its fields
    unchecked: the one place a record's text is parsed (:func:`parse_run_json` checks
    the fields the analysis reads; a solve's figures read its fields by name).

    Raises
    ------
    ResultFormatError
        If the text is longer than :data:`MAX_RECORD_BYTES`, is not strict JSON or not a
        JSON object.
    """
    if len(text) > MAX_RECORD_BYTES:
        raise ResultFormatError(f"run output has {len(text)} characters; a run record has "
                                f"at most {MAX_RECORD_BYTES}")
    obj = parse_json(text, "run output", ResultFormatError)
    if not isinstance(obj, dict):
        raise ResultFormatError("run output is not a JSON object")
    return obj


def parse_run_json(text, counters=None):
    """Parse the JSON object printed by ``hrbench run ... --json``.

    Counters are read generically: the fields named in `counters` (the engine's counter
    table) when it is given, otherwise every top-level integer field that does not
    describe the run (scene, eps, limits, ...); without the table, integer fields that
    echo an option (``threads``, ``rays_per_side``) count too. The counters of
    :data:`COUNTERS` must be
    there; the measures of :data:`MEASURES`, the per-depth histograms, ``min_area`` and
    ``max_depth_limit`` may be missing. Other fields are kept in ``extra``.

    The fields the analysis reads are checked as ``schemas/run-record.schema.json``
    states them: ``version``, ``scene`` and ``oracle`` are strings, ``params`` an object of
    numbers, ``eps`` a number, the counters of :data:`COUNTERS` integers ``>= 0``; where
    present, ``mode`` is a string, ``min_area`` a number or null, ``max_depth_limit`` an
    integer or null, the histograms lists of integers ``>= 0``. An engine's record that
    breaks one of these rules is refused with a message that names the field.

    Parameters
    ----------
    text : str
        The standard output of one run.
    counters : sequence of str, optional
        Names of the engine's scalar counters
        (:attr:`hrbench_analysis.engine.Capabilities.scalar_counters`), when an engine is at hand.

    Returns
    -------
    result : RunResult

    Raises
    ------
    ResultFormatError
        If the text is longer than :data:`MAX_RECORD_BYTES`, is not strict JSON (``NaN``,
        ``Infinity`` and a key given twice are refused, where Python's reader would take
        them, the last value of a key winning) or not a JSON object, its
        ``schema_version`` is not :data:`SCHEMA_VERSION`, a field above is missing or of
        the wrong type, a counter is not an integer, or a number does not fit in float64.
        The message names the field. No other exception comes out of arbitrary text.
    """
    obj = read_record(text)
    if "schema_version" not in obj:
        raise ResultFormatError("run output: required field 'schema_version' is missing")
    schema = obj["schema_version"]
    if schema != SCHEMA_VERSION or isinstance(schema, bool):
        raise ResultFormatError(f"run output: field 'schema_version' is {_short(schema)}; "
                                f"this analysis reads {SCHEMA_VERSION}")
    values = _read_counters(obj, counters)
    if "eps" not in obj:
        raise ResultFormatError("run output: required field 'eps' is missing")
    known = {*_RECORD_FIELDS, *_counter_names(obj, counters), *MEASURES, *SOLVE_MEASURES}
    return RunResult(
        version=_string_iv(obj, "version"),
        scene=_string_iv(obj, "scene"),
        params=_params_iv(obj),
        eps=_eps_iv(obj),
        oracle=_string_iv(obj, "oracle"),
        mode=_string_iv(obj, "mode", required=False),
        min_area=_optional_iv(obj, "min_area", _is_number, "a number"),
        max_depth_limit=_optional_iv(obj, "max_depth_limit", _is_integer, "an integer"),
        counters=values,
        nodes_per_depth=_histogram_iv(obj, "nodes_per_depth"),
        links_per_depth=_histogram_iv(obj, "links_per_depth"),
        extra={k: v for k, v in obj.items() if k not in known},
    )


def run_environment(result):
    """The names a claim formula may read for one run.

    Parameters
    ----------
    result : RunResult

    Returns
    -------
    env : dict of str to float
        Every counter and measure in ``result.counters``, the aliases of
        :data:`ALIASES` (``N``, ``L``), ``eps``, ``min_area`` (``nan`` without a recursion
        limit), every scene parameter, and ``g = l / d`` when the scene has both ``l``
        and ``d`` (dimensionless).
    """
    env = {}
    env.update(result.params)
    env.update(result.counters)
    for alias, name in ALIASES.items():
        if name in result.counters:
            env[alias] = result.counters[name]
    env["eps"] = result.eps
    env["min_area"] = math.nan if result.min_area is None else float(result.min_area)
    if "l" in result.params and "d" in result.params:
        d = result.params["d"]
        env["g"] = result.params["l"] / d if d != 0 else math.nan
    return env


def environment_names(params, counters, solve=False):
    """The names :func:`run_environment` gives a formula, for a run of known counters.

    Parameters
    ----------
    params : iterable of str
        Names of the scene parameters.
    counters : iterable of str
        Names of the scalar counters (e.g. the engine's
        :attr:`~hrbench_analysis.engine.Capabilities.scalar_counters`).
    solve : bool, optional
        Whether the run is ``hrbench solve``: then :data:`SOLVE_MEASURES` too.

    Returns
    -------
    names : set of str
        `params`, `counters`, :data:`MEASURES`, the aliases of counters in `counters`,
        ``eps``, ``min_area``, ``g`` when there are both ``l`` and ``d``, and for a solve
        :data:`SOLVE_MEASURES`.
    """
    params, counters = set(params), set(counters)
    names = params | counters | set(MEASURES) | {"eps", "min_area"}
    if solve:
        names |= set(SOLVE_MEASURES)
    names |= {alias for alias, name in ALIASES.items() if name in counters}
    if {"l", "d"} <= params:
        names.add("g")
    return names
