"""The format of a claim's keys, and the checks of those that are tables or selectors:
oracle, plateaus, mesh, sweep grid and engine options."""

import hashlib
import math
import re
from pathlib import Path

from ..engine import MESH_SCENE
from ..errors import InputFileError, open_bounded
from ..expr import Expression, ExpressionError
from .model import (
    DEFAULT_ORACLE,
    KIND_PREFIX,
    MAX_MESH_BYTES,
    MODES,
    RESERVED_OPTIONS,
    Plateaus,
    _is_number,
)

_OPTION_NAME = re.compile(r"[a-z][a-z0-9_]*\Z")
_PARAM_NAME = re.compile(r"[A-Za-z_][A-Za-z0-9_]*\Z")
_OPTION_TEXT = re.compile(r"[A-Za-z0-9_.:/+][A-Za-z0-9_.:/+=-]*\Z")

_CLAIM_KEYS = {
    "id", "statement", "source", "description", "scene", "params", "oracle", "sweep",
    "x", "y", "x_label", "y_label", "expected_exponent", "tolerance", "regime",
    "expected_to_hold", "min_points", "min_decades", "window_decades", "theta_band",
    "min_area", "max_depth", "eps", "options", "chart", "step_octaves", "mesh", "command",
    "published", "plateaus", "bound", "kind", "words", "words_at", "quantity",
    "interval_note", "alternative", "increments", *MODES,
}
#: What a claim may state of its power law (key ``bound``): Theta, or an upper bound O.
BOUNDS = ("theta", "upper")
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
#: Keys of the [source] table: its short name, its citation, and the words (with where
#: they stand) that its claims quote unless a claim quotes its own.
_SOURCE_KEYS = {"key", "citation", "words", "words_at"}
_MODE_KEYS = {"options"}


def _oracle_iv(value, fail):
    # A name, "@default", or { kind = WORD }; the two selectors are kept as their text
    # ("@default", "@kind=WORD") until the engine's capabilities resolve them
    # (hrbench_analysis.claimfile.resolve_oracle, before any run).
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
