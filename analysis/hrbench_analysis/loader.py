"""Reading what the ``hrbench`` command line writes: run records (JSON) and link lists (CSV).

Every other module of the analysis works on plain numbers and arrays; this is the only
place that knows the field names of the engine's output. Any engine may write the
records (docs/engine-contract.md); their fields are those of the JSON Schema
``schemas/run-record.schema.json``, and :func:`parse_run_json` checks the fields the
analysis reads, naming the first one that is missing or of the wrong type. The names of
the counters are the engine's own (``hrbench capabilities --json``, read by
:mod:`hrbench_analysis.engine`); this module needs only the few it reads by name
(:data:`COUNTERS`). Their meaning is in docs/conventions.md.
"""

import csv
import io
import math
import warnings
from dataclasses import dataclass, field

import numpy as np

from .errors import AnalysisError, InputFileError, parse_json, read_bounded

__all__ = [
    "COUNTERS",
    "MEASURES",
    "SOLVE_MEASURES",
    "TIMES",
    "ALIASES",
    "SCHEMA_VERSION",
    "MAX_RECORD_BYTES",
    "MAX_LINKS_BYTES",
    "RunResult",
    "ResultFormatError",
    "LinkTable",
    "parse_run_json",
    "read_links_csv",
    "run_environment",
    "environment_names",
]

#: JSON schema version of ``hrbench run --json`` that this module understands.
SCHEMA_VERSION = 1

#: Longest run record read, in bytes: a record holds a few hundred numbers (per-depth
#: histograms of at most a few thousand entries), a few KiB.
MAX_RECORD_BYTES = 16 << 20

#: Largest link list read (``hrbench links --out``), in bytes: the figures draw a few
#: thousand links, a sweep point's statistics up to a few hundred thousand (about 80 bytes
#: a link).
MAX_LINKS_BYTES = 1 << 30

#: The counters the analysis itself reads by name, which every run record must hold:
#: ``nodes`` and ``links`` (the aliases ``N`` and ``L``), ``leaves``, ``oracle_calls`` and
#: ``max_depth``. They are not the full list: the engine names all its counters in
#: ``hrbench capabilities --json`` (:attr:`hrbench_analysis.engine.Capabilities.scalar_counters`),
#: and a record is read generically (see :func:`parse_run_json`). Their meaning is in
#: docs/conventions.md.
COUNTERS = ("nodes", "leaves", "links", "oracle_calls", "max_depth")
_REQUIRED = COUNTERS

#: Measured top-level fields of a record that are not in the engine's counter table but
#: that formulas may read like counters: ``patches`` (root patches of the scene, count)
#: and ``seconds`` (refinement wall time, s).
MEASURES = ("patches", "seconds")

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
TIMES = ("seconds", "seconds_refine", "seconds_coefficients", "seconds_solve",
         "cpu_seconds_refine", "cpu_seconds_coefficients", "cpu_seconds_solve",
         "cpu_seconds_reference")

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
    if len(text) > MAX_RECORD_BYTES:
        raise ResultFormatError(f"run output has {len(text)} characters; a run record has "
                                f"at most {MAX_RECORD_BYTES}")
    obj = parse_json(text, "run output", ResultFormatError)
    if not isinstance(obj, dict):
        raise ResultFormatError("run output is not a JSON object")
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


@dataclass
class LinkTable:
    """The links written by ``hrbench links ... --out F.csv``, one array entry per link.

    Attributes
    ----------
    root_i, root_j : ndarray of int
        Root patch indices of the two elements.
    t0_i, t1_i, t0_j, t1_j : ndarray of float
        Element intervals in arc length along the root patch, from its start point
        (scene units).
    depth_i, depth_j : ndarray of int
        Element depths (levels below the root).
    """

    root_i: np.ndarray
    t0_i: np.ndarray
    t1_i: np.ndarray
    depth_i: np.ndarray
    root_j: np.ndarray
    t0_j: np.ndarray
    t1_j: np.ndarray
    depth_j: np.ndarray

    def __len__(self):
        return len(self.root_i)


_LINK_COLUMNS = ("root_i", "elem_i", "t0_i", "t1_i", "depth_i",
                 "root_j", "elem_j", "t0_j", "t1_j", "depth_j")


def read_links_csv(path):
    """Read a link list written by ``hrbench links``.

    Parameters
    ----------
    path : str or path-like
        CSV file with header ``root_i,elem_i,t0_i,t1_i,depth_i,root_j,elem_j,t0_j,t1_j,depth_j``
        (extra columns are ignored).

    Returns
    -------
    links : LinkTable

    Raises
    ------
    ResultFormatError
        If the file is not a regular file of at most :data:`MAX_LINKS_BYTES` bytes, is
        not UTF-8, lacks a required column, or a row holds a value that is not what the
        column is: root indices and depths integers ``>= 0``, positions finite numbers
        with ``t0 <= t1``. The message names the file, the line and the column.

    Notes
    -----
    The one reader of link lists (the tilings, the hierarchy statistics of
    :mod:`hrbench_analysis.lemmas`). A link list of a sweep point holds up to a few hundred
    thousand rows: numpy's C reader reads them; only a list it refuses, or whose values
    break a rule, is read again row by row, for the message that names line and column.
    """
    try:
        text = read_bounded(path, MAX_LINKS_BYTES, "link list").decode("utf-8")
    except InputFileError as exc:
        raise ResultFormatError(str(exc)) from None
    except UnicodeDecodeError as exc:
        raise ResultFormatError(f"{path}: link list is not UTF-8 text (byte {exc.start})"
                                ) from None
    try:
        reader = csv.reader(io.StringIO(text, newline=""))
        header = [h.strip() for h in next(reader, [])]
        missing = [c for c in _LINK_COLUMNS if c not in header and c not in ("elem_i", "elem_j")]
        if missing:
            raise ResultFormatError(
                f"{path}: link list lacks column(s) {', '.join(missing)}"
                + (" (positions along a root patch: the link list of a 2D scene)"
                   if any(c.startswith("t") for c in missing) else ""))
        col = {name: header.index(name) for name in _READ_COLUMNS}
        data = _read_fast(text, [col[name] for name in _READ_COLUMNS])
        if data is not None:
            return _link_table(data)
        rows = [_link_row(row, col, path, reader.line_num) for row in reader if row]
    except csv.Error as exc:
        raise ResultFormatError(f"{path}: link list is not CSV: {exc}") from None
    return _link_table(np.array(rows, dtype=float).reshape(-1, len(_READ_COLUMNS)))


def _link_table(data):
    return LinkTable(
        root_i=data[:, 0].astype(int), t0_i=data[:, 1], t1_i=data[:, 2],
        depth_i=data[:, 3].astype(int), root_j=data[:, 4].astype(int), t0_j=data[:, 5],
        t1_j=data[:, 6], depth_j=data[:, 7].astype(int))


# The columns a LinkTable holds, in its order; the integer ones.
_READ_COLUMNS = ("root_i", "t0_i", "t1_i", "depth_i", "root_j", "t0_j", "t1_j", "depth_j")
_INTEGER_COLUMNS = ("root_i", "depth_i", "root_j", "depth_j")


def _read_fast(text, columns):
    # The rows below the header with numpy's C reader, as floats, when every value keeps
    # the rules of _link_row; else None (the rows are then read one by one).
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")  # "input contained no data": no links
            data = np.loadtxt(io.StringIO(text), delimiter=",", skiprows=1, usecols=columns,
                              dtype=np.float64, ndmin=2, comments=None)
    except (ValueError, IndexError):
        return None
    data = data.reshape(-1, len(columns))
    integers = data[:, [_READ_COLUMNS.index(name) for name in _INTEGER_COLUMNS]]
    t0 = data[:, [_READ_COLUMNS.index("t0_i"), _READ_COLUMNS.index("t0_j")]]
    t1 = data[:, [_READ_COLUMNS.index("t1_i"), _READ_COLUMNS.index("t1_j")]]
    if (np.all(np.isfinite(data)) and np.all(integers >= 0) and np.all(integers < 2 ** 53)
            and np.all(integers == np.floor(integers)) and np.all(t0 <= t1)):
        return data
    return None


def _link_row(row, col, path, line):
    # One row of a link list as floats, checked.
    values = []
    for name in _READ_COLUMNS:
        text = row[col[name]].strip() if col[name] < len(row) else ""
        try:
            value = float(text)
        except ValueError:
            value = math.nan
        integer = name in _INTEGER_COLUMNS
        if not (math.isfinite(value) and (not integer or value == int(value) and
                                          0 <= value < 2 ** 53)):
            raise ResultFormatError(
                f"{path}:{line}: link list column {name} must be "
                + ("an integer >= 0" if integer else "a finite number")
                + f", got {text[:40]!r}")
        values.append(value)
    for side in ("i", "j"):
        t0, t1 = values[_READ_COLUMNS.index(f"t0_{side}")], values[
            _READ_COLUMNS.index(f"t1_{side}")]
        if t0 > t1:
            raise ResultFormatError(f"{path}:{line}: link list has t0_{side} {t0!r} > "
                                    f"t1_{side} {t1!r}")
    return values
