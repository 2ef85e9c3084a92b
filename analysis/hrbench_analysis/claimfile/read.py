"""Reading a claims file: the TOML text, its keys and the claims it lists."""

import re
import tomllib
from pathlib import Path

from ..errors import InputFileError, read_bounded
from ..expr import Expression, ExpressionError
from .model import (
    KINDS,
    MAX_ABS_EXPONENT,
    MAX_DEPTH_LIMIT,
    MAX_FILE_BYTES,
    MAX_PARAMS,
    MAX_RANGE_POINTS,
    MODES,
    Claim,
    ClaimJudgement,
    ClaimMeasure,
    ClaimOrigin,
    ClaimRun,
    ClaimsFileError,
    SweepRange,
    _check_total,
    _is_number,
    range_problem,
)
from .validate import (
    _CLAIM_KEYS,
    _MODE_KEYS,
    _PARAM_NAME,
    _RANGE_KEYS,
    _RANGE_OPTIONAL,
    _REGIME_KEYS,
    _REQUIRED,
    _SOURCE_KEYS,
    _SWEEP_KEYS,
    BOUNDS,
    COMMANDS,
    _grid_iv,
    _mesh_iv,
    _options_iv,
    _oracle_iv,
    _plateaus_iv,
)


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
    quoted = {key: source.get(key, "") for key in ("words", "words_at")}
    raw_claims = data.get("claim", [])
    if not isinstance(raw_claims, list) or not raw_claims:
        raise ClaimsFileError(path, "no claims: add at least one [[claim]] table")
    claims = []
    seen = {}
    for index, raw in enumerate(raw_claims):
        if not isinstance(raw, dict):
            raise ClaimsFileError(path, f"claim #{index + 1} must be a table ([[claim]]), got "
                                  f"{type(raw).__name__}", line=loc.claim_line(index))
        claim = _parse_claim(raw, index, path, loc, source_key, citation, quoted)
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


def _parse_claim(raw, index, path, loc, source_key, citation, quoted):
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
    run, sweep, range_keys = _run_iv(raw, path, want, fail)
    judge = _judge_iv(raw, want, fail)
    measure = _measure_iv(raw, judge.step_octaves, want, fail)
    for key in ("source", "description", "words", "words_at", "quantity", "interval_note"):
        if key in raw:
            want(key, "str")
    kind = _kind_iv(raw, want, fail)
    origin = ClaimOrigin(
        statement=raw["statement"], source=raw.get("source", citation), source_key=source_key,
        kind=kind, words=raw.get("words", quoted["words"]),
        words_at=raw.get("words_at", quoted["words_at"]), quantity=raw.get("quantity", ""),
        interval_note=raw.get("interval_note", ""),
        description=raw.get("description", ""), path=str(path),
        line=loc.claim_line(index) or 0,
        key_lines={key: loc.key_line(index, key)
                   for key in ("x", "y", "alternative", "eps",
                               *(f"params.{name}" for name in run.params),
                               *(f"sweep.{mode}" for mode in (*MODES, "range", "grid")
                                 if mode in sweep))},
        range_keys=range_keys)
    return Claim(id=raw["id"], origin=origin, run=run, measure=measure, judge=judge)


def _kind_iv(raw, want, fail):
    # The claim's kind: the key `kind`, else "derived" for the older `published = false`
    # and "stated" otherwise. A reading must say which quantity hrbench chose.
    published = want("published", "bool", raw.get("published", True))
    kind = want("kind", "str", raw.get("kind", "stated" if published else "derived"))
    if kind not in KINDS:
        fail(f"key 'kind' must be one of {', '.join(KINDS)}, got {kind!r}", "kind")
    if "published" in raw and published != (kind != "derived"):
        fail(f"keys 'published = {str(published).lower()}' and 'kind = \"{kind}\"' "
             "disagree: a derived claim is not published; drop 'published'", "published")
    if kind == "reading" and "quantity" not in raw:
        fail("a claim of kind 'reading' needs the key 'quantity': the quantity hrbench "
             "chose for the source's law, and why", "kind")
    return kind


def _run_iv(raw, path, want, fail):
    # What to run: the scene, the oracle, the sweep and the engine's options. Returns the
    # ClaimRun, the table `sweep` and the key each mode's range was given by.
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
    command = want("command", "str", raw.get("command", "run"))
    if command not in COMMANDS:
        fail(f"key 'command' must be one of {', '.join(COMMANDS)}, got {command!r}", "command")
    return ClaimRun(
        scene=raw["scene"], params={k_: float(v) for k_, v in params.items()},
        oracle=oracle, sweep_param=sweep_param, ranges=ranges, eps=eps, grid=grid,
        min_area=raw.get("min_area"),
        max_depth=int(raw["max_depth"]) if "max_depth" in raw else None,
        options=base_options, mode_options=mode_options, mesh=mesh, mesh_sha256=mesh_sha256,
        command=command), sweep, range_keys


def _judge_iv(raw, want, fail):
    # How to judge: the power law expected, the regime and what makes a verdict.
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
    defaults = ClaimJudgement.__dataclass_fields__
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
    expected = want("expected_to_hold", "bool", raw.get("expected_to_hold", True))
    bound = want("bound", "str", raw.get("bound", "theta"))
    if bound not in BOUNDS:
        fail(f"key 'bound' must be one of {', '.join(BOUNDS)}, got {bound!r}", "bound")
    return ClaimJudgement(
        expected_exponent=k, tolerance=tol, bound=bound, x_min=regime.get("x_min"),
        x_max=regime.get("x_max"), expected_to_hold=expected, **options)


def _measure_iv(raw, step_octaves, want, fail):
    # What to measure: x and y (the names they read are checked by check_names), their
    # labels, the chart and the plateaus of a staircase.
    exprs = {}
    for key in ("x", "y", "alternative"):
        if key == "alternative" and key not in raw:
            continue
        want(key, "str")
        try:
            exprs[key] = Expression(raw[key])
        except ExpressionError as exc:
            fail(f"key {key!r}: {exc}", key)

    for key in ("x_label", "y_label", "chart"):
        if key in raw:
            want(key, "str")
    plateaus = None
    if "plateaus" in raw:
        plateaus = _plateaus_iv(want("plateaus", "table"),
                                step_octaves, fail)

    increments = raw.get("increments")
    if increments is not None and not (isinstance(increments, int)
                                       and not isinstance(increments, bool)
                                       and 1 <= increments <= 16):
        fail(f"key 'increments' must be a whole number of octaves from 1 to 16, got "
             f"{increments!r}", "increments")
    if increments is not None and plateaus is not None:
        fail("keys 'increments' and 'plateaus' exclude each other: the increments pair "
             "points octaves apart, the plateaus keep one point a step", "increments")
    return ClaimMeasure(
        x=exprs["x"], y=exprs["y"], x_label=raw.get("x_label", raw["x"]),
        y_label=raw.get("y_label", raw["y"]), chart=raw.get("chart"), plateaus=plateaus,
        alternative=exprs.get("alternative"), increments=increments)


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
