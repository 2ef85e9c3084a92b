"""Claims measured by ``hrbench solve``: the keys ``command`` and ``published``, the
solve's measures in formulas, and the verdict ``measured``."""

import json
from pathlib import Path

import numpy as np
import pytest

from hrbench_analysis.claimfile import ClaimsFileError, check_names, load_claims
from hrbench_analysis.loader import SOLVE_MEASURES, parse_run_json, run_environment
from hrbench_analysis.reproduce import main
from hrbench_analysis.reproduce_options import CLAIMS_DIR
from hrbench_analysis.sweep import ClaimData
from hrbench_analysis.sweep_plan import expand_claim
from hrbench_analysis.verdict import MEASURED, VERDICTS, assess_claim

ROOT = Path(__file__).resolve().parents[2]
HRBENCH = ROOT / "build" / "hrbench"
needs_engine = pytest.mark.skipif(not HRBENCH.exists(), reason="build/hrbench not built")

SOLVE_CLAIM = """
[source]
key = "test"
citation = "hrbench test data"

[[claim]]
id = "T-error"
statement = "error = Theta(eps)"
scene = "parallel"
params = { l = 4, d = 1 }
command = "solve"
options = { emission = 1, reference = 9 }
sweep.param = "eps"
sweep.range = { from = 0.5, to = 0.05, per_decade = 10 }
x = "1/eps"
y = "reference_error_l2"
expected_exponent = -1
tolerance = 0.2
min_decades = 1
published = false
"""


def write(tmp_path, text, name="c.toml"):
    path = tmp_path / name
    path.write_text(text)
    return path


def test_command_and_published_are_read(tmp_path):
    (claim,) = load_claims(write(tmp_path, SOLVE_CLAIM))
    assert claim.command == "solve" and claim.published is False
    (default,) = load_claims(write(tmp_path, SOLVE_CLAIM.replace('command = "solve"\n', "")
                                   .replace("published = false\n", ""), "d.toml"))
    assert default.command == "run" and default.published is True


@pytest.mark.parametrize("old, new, key, match", [
    ('command = "solve"', 'command = "links"', "command", "must be one of run, solve"),
    ('command = "solve"', "command = 3", "command", "non-empty string"),
    ("published = false", 'published = "no"', "published", "true or false"),
])
def test_bad_command_or_published_names_key_and_line(tmp_path, old, new, key, match):
    path = write(tmp_path, SOLVE_CLAIM.replace(old, new))
    with pytest.raises(ClaimsFileError, match=match) as info:
        load_claims(path)
    assert info.value.key == key
    assert info.value.line == SOLVE_CLAIM.splitlines().index(old) + 1


def test_solve_measures_are_names_of_solve_claims_only(tmp_path):
    (claim,) = load_claims(write(tmp_path, SOLVE_CLAIM))
    check_names(claim, ["nodes", "links"])
    (counting,) = load_claims(write(tmp_path, SOLVE_CLAIM.replace('command = "solve"\n', ""),
                                    "r.toml"))
    with pytest.raises(ClaimsFileError, match=r"unknown name\(s\) reference_error_l2"):
        check_names(counting, ["nodes", "links"])


def test_solve_points_run_solve_and_have_their_own_cache_key(tmp_path):
    (claim,) = load_claims(write(tmp_path, SOLVE_CLAIM))
    points = expand_claim(claim, "quick", "hrbench", "v1")
    assert points[0].argv == ("hrbench", "solve", "parallel", "d=1", "l=4", "--eps", "0.5",
                              "--oracle", "garmann", "--emission", "1", "--reference", "9",
                              "--json")
    assert {p.key.mode for p in points} == {"solve"}
    (counting,) = load_claims(write(tmp_path, SOLVE_CLAIM.replace('command = "solve"\n', "")
                                    .replace("reference_error_l2", "N"), "r.toml"))
    count_keys = {p.key.text() for p in expand_claim(counting, "quick", "hrbench", "v1")}
    assert count_keys.isdisjoint(p.key.text() for p in points)


def test_solve_record_measures_reach_the_formulas():
    record = {"schema_version": 1, "version": "0", "scene": "parallel",
              "params": {"l": 4.0, "d": 1.0}, "eps": 0.1, "oracle": "garmann",
              "nodes": 254, "leaves": 128, "links": 1850, "oracle_calls": 3699,
              "max_depth": 6, "reference_error_l2": 0.0025, "iterations": 15,
              "cpu_seconds_solve": 0.001, "radiosity": [1.0, 2.0]}
    env = run_environment(parse_run_json(json.dumps(record)))
    assert env["reference_error_l2"] == 0.0025 and env["iterations"] == 15
    assert env["cpu_seconds_solve"] == 0.001 and "radiosity" not in env
    assert {"reference_error_l2", "reference_change", "cpu_seconds_reference"} <= set(
        SOLVE_MEASURES)


def test_error_parts_and_link_form_factors_reach_the_formulas(tmp_path):
    # A claim on the links' own error reads hierarchy_error_l2 (docs/solve.md), and its
    # formulas may combine the parts like any measure.
    (claim,) = load_claims(write(tmp_path, SOLVE_CLAIM.replace(
        'y = "reference_error_l2"',
        'y = "hierarchy_error_l2 / sqrt(projection_error_l2**2 + hierarchy_error_l2**2)"')))
    check_names(claim, ["nodes", "links"])
    record = {"schema_version": 1, "version": "0", "scene": "parallel",
              "params": {"l": 4.0, "d": 1.0}, "eps": 0.05, "oracle": "garmann",
              "nodes": 510, "leaves": 256, "links": 7570, "oracle_calls": 15139,
              "max_depth": 7, "reference_error_l2": 0.00118, "projection_error_l2": 0.00117,
              "hierarchy_error_l2": 0.000134, "hierarchy_error_max": 0.0002,
              "link_form_factor_max": 0.016, "link_form_factor_above_eps": 0.0}
    env = run_environment(parse_run_json(json.dumps(record)))
    assert env["projection_error_l2"] == 0.00117 and env["hierarchy_error_l2"] == 0.000134
    assert env["hierarchy_error_max"] == 0.0002
    assert env["link_form_factor_max"] == 0.016 and env["link_form_factor_above_eps"] == 0
    for part in ("projection", "hierarchy"):
        assert {f"{part}_error_{norm}" for norm in ("max", "mean", "l2")} <= set(SOLVE_MEASURES)


def test_unpublished_claim_is_measured_with_its_interval(tmp_path):
    (claim,) = load_claims(write(tmp_path, SOLVE_CLAIM))
    x = np.geomspace(2, 200, 16)
    scatter = 1 + 0.01 * np.cos(2.3 * np.arange(x.size))
    a = assess_claim(claim, ClaimData(value=1 / x, x=x, y=0.3 * x ** -1.0 * scatter),
                     n_boot=200)
    assert MEASURED in VERDICTS and a.verdict == MEASURED
    assert a.reason.startswith("no published value: measured exponent -1.00")
    assert a.reason.endswith("it would be reproduced")
    # A measurement far from the hypothesis is still a measurement, never "refuted".
    far = assess_claim(claim, ClaimData(value=1 / x, x=x, y=0.3 * x ** -2.0), n_boot=200)
    assert far.verdict == MEASURED and far.reason.endswith("it would be refuted")
    # Too few points for a fit: inconclusive, as for any claim.
    few = assess_claim(claim, ClaimData(value=1 / x[:3], x=x[:3], y=x[:3] ** -1.0))
    assert few.verdict == "inconclusive"


def test_shipped_accuracy_claims_are_solves_without_published_values():
    (path,) = [p for p in CLAIMS_DIR.glob("*.toml") if p.name == "accuracy.toml"]
    claims = load_claims(path)
    assert {c.oracle for c in claims} == {"garmann", "hanrahan", "bf"}
    for c in claims:
        assert c.command == "solve" and not c.published
        assert c.options_for("quick")["reference"] >= 9


@needs_engine
def test_solve_claim_end_to_end(tmp_path, capsys):
    path = write(tmp_path, SOLVE_CLAIM)
    code = main(["--claims", str(path), "--results", str(tmp_path / "out"),
                 "--hrbench", str(HRBENCH), "--no-tiling"])
    assert code == 0
    claims = json.loads((tmp_path / "out" / "claims.json").read_text())
    (c,) = claims["claims"]
    assert c["verdict"] == MEASURED and c["as_expected"] is None
    # Leaves of length ~eps against a reference of 512 elements per plate: first order.
    assert -1.3 < c["measured_exponent"] < -0.7 and c["published"] is False
    assert "no published value" in (tmp_path / "out" / "report.md").read_text()


def test_an_interval_within_the_band_that_excludes_its_exponent_quotes_the_claims_note(
        tmp_path):
    # A fall like x^-1.1 with a scatter of 1%: within -1 +/- 0.2, but not at -1 itself.
    x = np.geomspace(2, 200, 16)
    data = ClaimData(value=1 / x, x=x, y=x ** -1.1 * (1 + 0.01 * np.cos(2.3 * np.arange(16))))
    (silent,) = load_claims(write(tmp_path, SOLVE_CLAIM))
    a = assess_claim(silent, data, n_boot=200)
    assert "the interval excludes -1 itself: the claims file gives no reason" in a.reason
    (noted,) = load_claims(write(tmp_path, SOLVE_CLAIM.replace(
        "published = false", 'published = false\ninterval_note = "a slow factor"'), "n.toml"))
    assert noted.interval_note == "a slow factor"
    assert assess_claim(noted, data, n_boot=200).reason.endswith(
        "the interval excludes -1 itself: a slow factor")
    # At the exponent itself no note is quoted.
    exact = ClaimData(value=1 / x, x=x, y=data.y * x ** 0.1)
    assert "excludes" not in assess_claim(noted, exact, n_boot=200).reason
