"""Reading what the ``hrbench`` command line writes: run records (JSON) and link lists (CSV).

Every other module of the analysis works on plain numbers and arrays; this is the only
place that knows the field names of the engine's output.
"""

import csv
import json
import math
from dataclasses import dataclass, field

import numpy as np

__all__ = [
    "COUNTERS",
    "ALIASES",
    "SCHEMA_VERSION",
    "RunResult",
    "ResultFormatError",
    "LinkTable",
    "parse_run_json",
    "read_links_csv",
    "run_environment",
]

#: JSON schema version of ``hrbench run --json`` that this module understands.
SCHEMA_VERSION = 1

#: Scalar counters of a run, as named in DESIGN section 2 (all exact integers except ``seconds``).
COUNTERS = (
    "nodes",          # every element of every tree, roots included (count)
    "leaves",         # elements without children (count)
    "links",          # element pairs linked by the refinement (count)
    "oracle_calls",   # evaluations of the refinement oracle (count)
    "max_depth",      # deepest element depth reached (levels)
    "forced_links",   # links made by a recursion limit, not by the oracle (count)
    "culled_pairs",   # root pairs that cannot exchange light (count)
    "root_pairs",     # root pairs refined (count)
    "patches",        # root patches of the scene (count)
    "occluded_pairs", # element pairs found wholly occluded by the visibility test (count)
    "visibility_queries",  # visibility tests of element pairs (count)
    "rays",           # rays cast by the visibility tests (count)
    "seconds",        # refinement wall time (s)
)

#: Short names a claim formula may use for counters, as in the published statements.
ALIASES = {"N": "nodes", "L": "links"}

_REQUIRED = ("nodes", "leaves", "links", "oracle_calls", "max_depth")


class ResultFormatError(ValueError):
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
        The scalar counters of :data:`COUNTERS` that the record holds (counts; ``seconds`` in s).
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
        raise ResultFormatError(f"{where}: field {key!r} must be a number, got {value!r}")
    return value


def parse_run_json(text):
    """Parse the JSON object printed by ``hrbench run ... --json``.

    Unknown fields are kept in ``extra`` and otherwise ignored; optional fields
    (``min_area``, ``max_depth_limit``, ``forced_links``, ``culled_pairs``, ``root_pairs``,
    ``patches``, ``occluded_pairs``, ``visibility_queries``, ``rays``, ``seconds``, the
    per-depth histograms) may be missing.

    Parameters
    ----------
    text : str
        The standard output of one run.

    Returns
    -------
    result : RunResult

    Raises
    ------
    ResultFormatError
        If the text is not a JSON object, its ``schema_version`` is not
        :data:`SCHEMA_VERSION`, or a required counter is missing or not a number.
    """
    try:
        obj = json.loads(text)
    except json.JSONDecodeError as exc:
        raise ResultFormatError(f"run output is not JSON: {exc}") from None
    if not isinstance(obj, dict):
        raise ResultFormatError("run output is not a JSON object")
    schema = obj.get("schema_version")
    if schema != SCHEMA_VERSION:
        raise ResultFormatError(
            f"run output has schema_version {schema!r}; this analysis reads {SCHEMA_VERSION}")
    counters = {}
    for key in COUNTERS:
        if key in obj and obj[key] is not None:
            counters[key] = _number(obj, key, "run output")
        elif key in _REQUIRED:
            raise ResultFormatError(f"run output: required counter {key!r} is missing")
    params = obj.get("params") or {}
    if not isinstance(params, dict):
        raise ResultFormatError("run output: field 'params' must be an object")
    known = {"schema_version", "version", "scene", "params", "eps", "oracle", "mode",
             "min_area", "max_depth_limit", "nodes_per_depth", "links_per_depth", *COUNTERS}
    return RunResult(
        version=str(obj.get("version", "")),
        scene=str(obj.get("scene", "")),
        params={k: float(v) for k, v in params.items()
                if isinstance(v, (int, float)) and not isinstance(v, bool)},
        eps=float(_number(obj, "eps", "run output")),
        oracle=str(obj.get("oracle", "")),
        mode=str(obj.get("mode", "")),
        min_area=obj.get("min_area"),
        max_depth_limit=obj.get("max_depth_limit"),
        counters=counters,
        nodes_per_depth=list(obj.get("nodes_per_depth") or []),
        links_per_depth=list(obj.get("links_per_depth") or []),
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
        Every counter of :data:`COUNTERS` the run reported, the aliases of
        :data:`ALIASES` (``N``, ``L``), ``eps``, every scene parameter, and ``g = l / d``
        when the scene has both ``l`` and ``d`` (dimensionless).
    """
    env = {}
    env.update(result.params)
    env.update(result.counters)
    for alias, name in ALIASES.items():
        if name in result.counters:
            env[alias] = result.counters[name]
    env["eps"] = result.eps
    if "l" in result.params and "d" in result.params:
        d = result.params["d"]
        env["g"] = result.params["l"] / d if d != 0 else math.nan
    return env


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
        If a required column is missing.
    """
    with open(path, newline="") as fh:
        reader = csv.reader(fh)
        header = [h.strip() for h in next(reader, [])]
        missing = [c for c in _LINK_COLUMNS if c not in header and c not in ("elem_i", "elem_j")]
        if missing:
            raise ResultFormatError(f"{path}: link list lacks column(s) {', '.join(missing)}")
        rows = [row for row in reader if row]
    col = {name: header.index(name) for name in header}
    data = np.array([[float(row[col[c]]) for c in
                      ("root_i", "t0_i", "t1_i", "depth_i", "root_j", "t0_j", "t1_j", "depth_j")]
                     for row in rows], dtype=float).reshape(-1, 8)
    return LinkTable(
        root_i=data[:, 0].astype(int), t0_i=data[:, 1], t1_i=data[:, 2],
        depth_i=data[:, 3].astype(int), root_j=data[:, 4].astype(int), t0_j=data[:, 5],
        t1_j=data[:, 6], depth_j=data[:, 7].astype(int))
