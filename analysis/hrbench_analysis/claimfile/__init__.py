"""Published claims as data: loading and checking the claims files.

A claims file (TOML, one per published source) lists claims. Each claim says which
scene family to run, which parameter to sweep over which log-spaced range, which two
quantities to measure, and which power law ``y = Theta(x^k)`` to expect between them.
Adding a claim needs no code: see ``docs/analysis.md`` for the format.

Loading checks a file offline: its syntax, keys, types and formulas. What depends on the
engine is checked against its capabilities before any run starts: the oracle (see
:func:`hrbench_analysis.claimfile.oracle_error`), the names the formulas read (:func:`check_names`),
and the scene family, parameters and options (:func:`hrbench_analysis.claimfile.param_errors`,
:func:`hrbench_analysis.claimfile.missing_capability`).

The work a claims file can ask for is bounded when it is loaded: a file has at most
:data:`MAX_FILE_BYTES` bytes of UTF-8 text, a sweep range at most :data:`MAX_PER_DECADE`
points per decade and :data:`MAX_RANGE_POINTS` points, the claims loaded together at most
:data:`MAX_SWEEP_POINTS` points (ranges times grids, in the larger mode), a mesh file at
most :data:`MAX_MESH_BYTES` bytes, a formula the limits of :mod:`hrbench_analysis.expr`.

Modules
-------
model     a claim as the analysis holds it (:class:`Claim`), sweep ranges, the limits
read      reading a claims file: the TOML text and the claims it lists
validate  the format of a claim's keys, the checks of its tables and selectors
checks    a claim against the engine's capabilities, before any run
"""

from .checks import (
    REFERENCE_ORACLES,
    STATISTICS_COMMANDS,
    check_names,
    missing_capability,
    oracle_error,
    param_errors,
    param_range_text,
    resolve_oracle,
)
from .model import (
    DEFAULT_ORACLE,
    KIND_PREFIX,
    KINDS,
    MAX_ABS_EXPONENT,
    MAX_DEPTH_LIMIT,
    MAX_FILE_BYTES,
    MAX_MESH_BYTES,
    MAX_PARAMS,
    MAX_PER_DECADE,
    MAX_RANGE_POINTS,
    MAX_SWEEP_POINTS,
    MODES,
    PUBLISHED_KINDS,
    RESERVED_OPTIONS,
    Claim,
    ClaimJudgement,
    ClaimMeasure,
    ClaimOrigin,
    ClaimRun,
    ClaimsFileError,
    Plateaus,
    SweepRange,
    range_problem,
    sweep_points,
)
from .read import load_claims, load_claims_dir

__all__ = [
    "Claim",
    "ClaimOrigin",
    "ClaimRun",
    "ClaimMeasure",
    "ClaimJudgement",
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
    "DEFAULT_ORACLE",
    "KIND_PREFIX",
    "KINDS",
    "PUBLISHED_KINDS",
    "REFERENCE_ORACLES",
    "STATISTICS_COMMANDS",
    "resolve_oracle",
    "oracle_error",
    "param_errors",
    "param_range_text",
    "missing_capability",
]
