"""Property tests (Hypothesis): the parser, the claims loader, the fit and the store.

Each property runs a moderate number of examples with a deadline per example, so that a
hang (a Python big-integer power, a regular expression gone exponential) fails the test
instead of stalling it; the deadlines are generous because the work is microseconds and
CI machines are shared. No example database is written (``database=None``).
"""

import json
import math
import tempfile
from pathlib import Path

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from hrbench_analysis.claimfile import MAX_RANGE_POINTS, ClaimsFileError, load_claims
from hrbench_analysis.expr import FUNCTIONS, Expression, ExpressionError
from hrbench_analysis.powerlaw import fit_power_law
from hrbench_analysis.store import ResultStore
from hrbench_analysis.store_points import PointKey, StoredPoint

DATA = Path(__file__).resolve().parent / "data"


def quick(max_examples, deadline_ms=2000):
    """Settings of one property: few enough examples to stay fast, a deadline each."""
    return settings(max_examples=max_examples, deadline=deadline_ms, database=None,
                    suppress_health_check=[HealthCheck.too_slow])


@pytest.fixture(scope="module")
def scratch():
    """A directory for the files of one module's examples."""
    with tempfile.TemporaryDirectory() as directory:
        yield Path(directory)


# --- The expression parser -----------------------------------------------------------------

_FORMULA_ALPHABET = "NLxeps_0123456789.eE+-*/() ,**logsqrtabx\t\n'\"[]:;=<>!%&|^~@"


@quick(300)
@given(st.one_of(st.text(max_size=300), st.text(alphabet=_FORMULA_ALPHABET, max_size=300)))
def test_parser_raises_only_its_own_error_on_any_text(text):
    try:
        expr = Expression(text)
    except ExpressionError:
        return
    value = expr(dict.fromkeys(expr.names, 3.0))
    assert isinstance(value, float)


def _formulas():
    leaves = st.one_of(st.sampled_from(["N", "L", "eps", "g"]),
                       st.integers(0, 10**6).map(str),
                       st.floats(0, 1e300, allow_nan=False, allow_infinity=False).map(repr))

    def extend(inner):
        return st.one_of(
            st.tuples(inner, st.sampled_from(["+", "-", "*", "/", "**"]), inner).map(
                lambda t: f"({t[0]} {t[1]} {t[2]})"),
            st.tuples(st.sampled_from(sorted(FUNCTIONS)), inner).map(lambda t: f"{t[0]}({t[1]})"),
            inner.map(lambda s: f"-{s}"))

    return st.recursive(leaves, extend, max_leaves=40)


@quick(300)
@given(_formulas(), st.floats(allow_nan=True, allow_infinity=True), st.integers(0, 10**18))
def test_any_formula_evaluates_quickly_to_a_float(text, value, count):
    try:
        expr = Expression(text)
    except ExpressionError as exc:          # only the documented size limits
        assert "too long" in str(exc) or "too large" in str(exc) or "nested" in str(exc)
        return
    env = {"N": count, "L": count, "eps": value, "g": value}
    assert isinstance(expr(env), float)


# --- The claims loader ----------------------------------------------------------------------


def _load(scratch, data):
    path = scratch / "claims.toml"
    path.write_bytes(data)
    try:
        claims = load_claims(path)
    except ClaimsFileError as exc:
        assert str(exc).startswith(str(path))
        return None
    for claim in claims:                     # bounded work for whatever loads
        for mode in ("quick", "full"):
            assert len(claim.range_for(mode).values()) <= MAX_RANGE_POINTS
    return claims


@quick(200)
@given(st.binary(max_size=2000))
def test_loader_raises_only_its_own_error_on_any_bytes(scratch, data):
    _load(scratch, data)


@quick(200)
@given(st.binary(max_size=200), st.integers(0, 600))
def test_loader_on_a_valid_file_with_bytes_spliced_in(scratch, junk, at):
    text = (DATA / "small_claims.toml").read_bytes()
    _load(scratch, text[:at] + junk + text[at:])


def _toml(value):
    # A TOML value: strings as JSON strings, numbers, booleans, arrays, inline tables.
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, str):
        return json.dumps(value, ensure_ascii=False)
    if isinstance(value, int):
        return str(value)
    if isinstance(value, float):
        return "nan" if math.isnan(value) else {math.inf: "inf", -math.inf: "-inf"}.get(
            value, repr(value))
    if isinstance(value, list):
        return "[" + ", ".join(_toml(v) for v in value) + "]"
    return "{ " + ", ".join(f"{json.dumps(k)} = {_toml(v)}" for k, v in value.items()) + " }"


_SCALARS = st.one_of(
    st.booleans(), st.integers(-2**63, 2**63 - 1), st.floats(), st.text(max_size=30),
    st.sampled_from(["parallel", "eps", "l", "N", "1/eps", "N**N**N", "quick", "translation"]),
    st.sampled_from([0, 1, 3, 1000, 1001, 1e-300, 1e300, 5e-324, -1.0, 0.5, 1e9]))
_VALUES = st.recursive(
    _SCALARS,
    lambda inner: st.one_of(
        st.lists(inner, max_size=4),
        st.dictionaries(st.sampled_from(["from", "to", "per_decade", "binary_digits",
                                         "param", "quick", "full", "range", "l", "d",
                                         "options", "method", "x_min", "junk"]),
                        inner, max_size=5)),
    max_leaves=12)
_CLAIM_KEYS = ["id", "statement", "scene", "params", "oracle", "sweep", "x", "y",
               "expected_exponent", "tolerance", "regime", "expected_to_hold", "min_points",
               "min_decades", "window_decades", "theta_band", "min_area", "max_depth", "eps",
               "options", "quick", "full", "chart", "source", "tolerence"]


@quick(150)
@given(st.dictionaries(st.sampled_from(_CLAIM_KEYS), _VALUES, max_size=6),
       st.lists(st.sampled_from(_CLAIM_KEYS), max_size=3))
def test_loader_raises_only_its_own_error_on_any_claim(scratch, changes, dropped):
    claim = {"id": "P", "statement": "s", "scene": "parallel", "params": {"l": 8, "d": 1},
             "sweep": {"param": "eps", "range": {"from": 1.0, "to": 0.01, "per_decade": 5}},
             "x": "1/eps", "y": "N", "expected_exponent": 1, "tolerance": 0.15}
    claim.update(changes)
    for key in dropped:
        claim.pop(key, None)
    text = "[[claim]]\n" + "".join(f"{key} = {_toml(v)}\n" for key, v in claim.items())
    _load(scratch, text.encode("utf-8", "surrogatepass"))


# --- The power-law fit ---------------------------------------------------------------------


@quick(150)
@given(k=st.floats(-5, 5), c=st.floats(1e-3, 1e3), x0=st.floats(1e-3, 1e3),
       decades=st.floats(0.5, 6), n=st.integers(5, 60), block=st.integers(1, 5))
def test_fit_recovers_the_exponent_of_an_exact_power_law(k, c, x0, decades, n, block):
    x = x0 * np.logspace(0, decades, n)
    y = c * x ** k
    fit = fit_power_law(x, y, n_boot=200, block=block)
    assert fit.exponent == pytest.approx(k, abs=1e-8)
    assert fit.low - 1e-8 <= k <= fit.high + 1e-8
    assert fit.prefactor == pytest.approx(c, rel=1e-6)


# --- The store -----------------------------------------------------------------------------

_FINITE = st.floats(allow_nan=False, allow_infinity=False)
_NAMES = st.text(st.characters(min_codepoint=97, max_codepoint=122), min_size=1, max_size=6)


@st.composite
def _stored_points(draw):
    names = draw(st.lists(_NAMES, unique=True, max_size=4))
    key = PointKey(
        version=draw(st.text(max_size=20)), scene=draw(st.text(max_size=20)),
        params=tuple(sorted((name, draw(_FINITE)) for name in names)),
        eps=draw(st.floats(min_value=1e-300, max_value=1e300)),
        oracle=draw(st.text(max_size=10)),
        min_area=draw(st.none() | _FINITE), max_depth=draw(st.none() | st.integers(0, 48)),
        mode=draw(st.sampled_from(["count-only", "store"])),
        options=tuple(sorted(draw(st.dictionaries(_NAMES, st.text(max_size=10),
                                                  max_size=3)).items())))
    return StoredPoint(key, draw(st.booleans()), draw(st.integers(-2**31, 2**31 - 1)),
                       draw(st.text(max_size=100)), draw(st.text(max_size=300)),
                       draw(st.floats(0, 1e6)))


@pytest.fixture(scope="module")
def store(scratch):
    with ResultStore(scratch / "cache.sqlite") as store:
        yield store


@quick(150)
@given(_stored_points())
def test_store_round_trips_points(store, point):
    store.put(point)
    got = store.get(point.key)
    assert got.finished_at is not None
    got.finished_at = None
    assert got == point
    assert point.key.text() in store.keys()


# --- The run records -------------------------------------------------------------------------

_JSON = st.recursive(
    st.none() | st.booleans() | st.integers() | st.floats() | st.text(max_size=10),
    lambda inner: st.lists(inner, max_size=4) | st.dictionaries(
        st.sampled_from(["schema_version", "nodes", "leaves", "links", "oracle_calls",
                         "max_depth", "eps", "params", "l", "seconds", "patches", "x"]),
        inner, max_size=8),
    max_leaves=20)


@quick(200)
@given(st.one_of(st.text(max_size=200), _JSON.map(json.dumps),
                 st.dictionaries(st.sampled_from(["nodes", "leaves", "links", "oracle_calls",
                                                  "max_depth", "eps", "params", "seconds"]),
                                 _JSON).map(lambda d: json.dumps({"schema_version": 1, **d}))))
def test_run_records_raise_only_their_own_error(text):
    from hrbench_analysis.loader import ResultFormatError, parse_run_json, run_environment
    try:
        result = parse_run_json(text)
    except ResultFormatError:
        return
    env = run_environment(result)
    assert {"N", "L", "eps"} <= set(env)


def _with_duplicate_key(text):
    # The text of a JSON object with its first key given again (the last value winning in
    # Python's reader).
    key = text[1:].split(":", 1)[0]
    return "{" + f"{key}: 0, " + text[1:] if text.startswith('{"') else text


@quick(150)
@given(st.dictionaries(st.sampled_from(["schema_version", "nodes", "leaves", "links",
                                        "oracle_calls", "max_depth", "eps", "version",
                                        "scene", "oracle", "params"]), _JSON, min_size=1)
       .map(lambda d: _with_duplicate_key(json.dumps({"schema_version": 1, **d}))))
def test_a_run_record_with_a_key_given_twice_is_never_read(text):
    from hrbench_analysis.loader import ResultFormatError, parse_run_json
    with pytest.raises(ResultFormatError, match="given twice|is not a JSON number"):
        parse_run_json(text)


# --- Google Benchmark files, count baselines, the claims' [source] ----------------------------

_ROW_KEYS = ["name", "run_name", "run_type", "real_time", "cpu_time", "time_unit",
             "iterations", "error_occurred", "repetitions"]
_GBENCH_VALUES = st.one_of(
    st.none(), st.booleans(), st.integers(-2**70, 2**70), st.floats(),
    st.sampled_from(["iteration", "aggregate", "ns", "us", "ms", "s", "h", "BM_A", "BM_B"]),
    st.text(max_size=8))
_ROWS = st.lists(st.one_of(st.dictionaries(st.sampled_from(_ROW_KEYS), _GBENCH_VALUES,
                                           max_size=7), _GBENCH_VALUES), max_size=6)


@quick(200)
@given(st.one_of(
    st.fixed_dictionaries({"benchmarks": _ROWS},
                          optional={"context": st.dictionaries(
                              st.sampled_from(["json_schema_version", "host_name"]),
                              _GBENCH_VALUES)}).map(json.dumps),   # NaN spelt as Python does
    st.text(max_size=200), _JSON.map(json.dumps)))
def test_benchmark_files_raise_only_their_own_error(scratch, text):
    from hrbench_analysis.bench.gbench import InputError, get_repetition_times, load_benchmark_file
    path = scratch / "bench.json"
    path.write_text(text, encoding="utf-8", errors="surrogatepass")
    try:
        data = load_benchmark_file(path)
        for metric in ("real_time", "cpu_time"):
            times = get_repetition_times(data, metric)
    except InputError as exc:
        assert "Traceback" not in str(exc)
        return
    for values in times.values():      # what is read is usable by the comparison
        assert all(math.isfinite(t) and t >= 0 for t in values)


_BASELINE_RUNS = st.lists(st.one_of(
    st.fixed_dictionaries({"args": st.lists(st.one_of(st.text(max_size=6), st.integers()),
                                            max_size=3)},
                          optional={"counts": st.one_of(_JSON, st.dictionaries(
                              st.sampled_from(["links", "nodes", "links_per_depth"]),
                              st.one_of(st.integers(-5, 2**70), st.lists(st.integers(-1, 9),
                                                                        max_size=3)),
                              max_size=3))}),
    _JSON), max_size=4)


@quick(150)
@given(st.one_of(st.fixed_dictionaries({"schema_version": st.sampled_from([1, 1, 2, "1"]),
                                        "runs": _BASELINE_RUNS}).map(json.dumps),
                 st.text(max_size=100)))
def test_baseline_files_raise_only_their_own_error(scratch, text):
    import os

    from hrbench_analysis.bench.baseline import BaselineError, get_counter_changes, load_baseline
    path = scratch / "counts.json"
    path.write_text(text, encoding="utf-8", errors="surrogatepass")
    try:
        data = load_baseline(os.fspath(path))
    except BaselineError:
        return
    for run in data["runs"]:           # a loaded baseline can be compared with any record
        assert all(isinstance(a, str) for a in run["args"])
        get_counter_changes(run.get("counts") or {}, {"links": 1})


@quick(150)
@given(st.dictionaries(st.sampled_from(["key", "citation", "citaton", "url", "Key"]),
                       _SCALARS, max_size=3))
def test_claims_source_tables_raise_only_their_own_error(scratch, source):
    text = (DATA / "small_claims.toml").read_text()
    head, rest = text.split("[[claim]]", 1)
    table = "[source]\n" + "".join(f"{json.dumps(k)} = {_toml(v)}\n" for k, v in source.items())
    claims = _load(scratch, (table + "\n[[claim]]" + rest).encode("utf-8", "surrogatepass"))
    if claims is not None:             # only the two keys, each a non-empty string
        assert set(source) <= {"key", "citation"}
        assert all(isinstance(v, str) and v.strip() for v in source.values())
