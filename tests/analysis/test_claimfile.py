from pathlib import Path

import pytest

from analysis.claimfile import (
    ClaimsFileError,
    SweepRange,
    check_names,
    load_claims,
    load_claims_dir,
)

ROOT = Path(__file__).resolve().parents[2]


def test_shipped_claims_load_and_cover_c1_to_c4():
    claims = load_claims_dir(ROOT / "analysis" / "claims")
    ids = {c.id for c in claims}
    assert {"C1", "C2", "C3", "C4"} <= ids
    by_id = {c.id: c for c in claims}
    assert by_id["C4"].expected_exponent == 2 and by_id["C3"].expected_exponent == 1
    assert by_id["C3"].sweep_param == "l" and by_id["C3"].eps == 0.25
    c4 = by_id["C4"]
    assert c4.sweep_param == "eps" and c4.params["l"] / c4.params["d"] >= 64
    for c in claims:
        assert set(c.ranges) == {"quick", "full"}
        assert c.line > 0 and c.path.endswith(".toml")


def test_small_claims_file(data_dir):
    (claim,) = load_claims(data_dir / "small_claims.toml")
    assert claim.id == "T-elements"
    assert claim.x.text == "1/eps" and claim.y.names == {"N"}
    assert claim.range_for("quick") == claim.range_for("full")
    assert claim.expected_to_hold is True
    assert claim.line == 6


def test_sweep_range_is_log_spaced_and_aligned_to_decades():
    values = SweepRange(1.0, 0.01, 5).values()
    assert len(values) == 11
    assert values[0] == 1.0 and values[5] == 0.1 and values[-1] == 0.01
    assert SweepRange(64, 65536, 10).values()[-1] == 65536


def test_toml_syntax_error_names_file_and_line(data_dir):
    with pytest.raises(ClaimsFileError) as info:
        load_claims(data_dir / "bad_syntax.toml")
    assert info.value.line == 8
    assert "bad_syntax.toml:8" in str(info.value)


def test_missing_key_names_claim_and_key(data_dir):
    with pytest.raises(ClaimsFileError) as info:
        load_claims(data_dir / "missing_key.toml")
    message = str(info.value)
    assert "missing_key.toml:4" in message
    assert "'M1'" in message and "'tolerance'" in message


def test_wrong_type_names_claim_key_and_line(data_dir):
    with pytest.raises(ClaimsFileError) as info:
        load_claims(data_dir / "bad_values.toml")
    err = info.value
    assert err.claim_id == "V-bad" and err.key == "expected_exponent"
    assert err.line == 25
    assert "bad_values.toml:25" in str(err) and "finite number" in str(err)


def test_unsafe_formula_is_rejected_with_its_line(data_dir):
    with pytest.raises(ClaimsFileError) as info:
        load_claims(data_dir / "bad_formula.toml")
    assert info.value.key == "y" and info.value.line == 12


def test_misspelt_key_is_reported(data_dir):
    with pytest.raises(ClaimsFileError) as info:
        load_claims(data_dir / "unknown_key.toml")
    assert info.value.key == "tolerence" and info.value.line == 15
    assert "unknown key 'tolerence'" in str(info.value)


def test_oracle_is_not_checked_offline(tmp_path, data_dir):
    # Which oracles exist is the engine's to say (checked before any run, in reproduce).
    text = (data_dir / "small_claims.toml").read_text().replace(
        'scene = "parallel"', 'scene = "parallel"\noracle = "bf"')
    path = tmp_path / "c.toml"
    path.write_text(text)
    (claim,) = load_claims(path)
    assert claim.oracle == "bf"
    path.write_text(text.replace('oracle = "bf"', "oracle = 3"))
    with pytest.raises(ClaimsFileError, match="'oracle' must be a non-empty string"):
        load_claims(path)


def test_unknown_name_in_formula(tmp_path, data_dir):
    text = (data_dir / "small_claims.toml").read_text().replace('y = "N"', 'y = "N / volume"')
    path = tmp_path / "c.toml"
    path.write_text(text)
    (claim,) = load_claims(path)  # the counters are the engine's: checked against them
    with pytest.raises(ClaimsFileError, match="unknown name.*volume") as info:
        check_names(claim, ["nodes", "links"])
    assert info.value.key == "y" and info.value.line == 15 and info.value.claim_id == "T-elements"
    assert "c.toml:15" in str(info.value)
    check_names(claim, ["nodes", "links", "volume"])


def test_formulas_may_read_counters_measures_aliases_and_family_params(tmp_path, data_dir):
    text = (data_dir / "small_claims.toml").read_text().replace(
        'y = "N"', 'y = "rays * seconds / patches + L + offset + g"')
    path = tmp_path / "c.toml"
    path.write_text(text)
    (claim,) = load_claims(path)
    with pytest.raises(ClaimsFileError, match=r"unknown name\(s\) offset, rays;"):
        check_names(claim, ["nodes", "links"])
    check_names(claim, ["nodes", "links", "rays"], scene_params=["l", "d", "offset"])
    with pytest.raises(ClaimsFileError, match=r"unknown name\(s\) L;"):
        check_names(claim, ["nodes", "rays"], scene_params=["offset"])  # no links, no L


def test_duplicate_ids_across_files(tmp_path, data_dir):
    for name in ("a.toml", "b.toml"):
        (tmp_path / name).write_text((data_dir / "small_claims.toml").read_text())
    with pytest.raises(ClaimsFileError, match="already used"):
        load_claims_dir(tmp_path)
