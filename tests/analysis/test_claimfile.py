from pathlib import Path

import pytest

from hrbench_analysis.claimfile import (
    PUBLISHED_KINDS,
    ClaimsFileError,
    SweepRange,
    check_names,
    load_claims,
    load_claims_dir,
)
from hrbench_analysis.reproduce_options import CLAIMS_DIR


def test_shipped_claims_load_and_cover_c1_to_c4():
    claims = load_claims_dir(CLAIMS_DIR)
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


# --- Hostile files: every problem is a ClaimsFileError naming file, line, claim and key ---


def variant(tmp_path, data_dir, old, new, name="c.toml"):
    text = (data_dir / "small_claims.toml").read_text()
    assert old in text
    path = tmp_path / name
    path.write_text(text.replace(old, new))
    return path


def test_non_utf8_file_names_the_line_and_column(tmp_path):
    path = tmp_path / "latin1.toml"
    path.write_bytes(b'[source]\nkey = "caf\xe9"\n')
    with pytest.raises(ClaimsFileError) as info:
        load_claims(path)
    assert info.value.line == 2
    assert str(info.value) == (f"{path}:2: not UTF-8 text: byte 0xe9 at column 11 cannot be "
                               "decoded; save the file as UTF-8")


def test_unreadable_and_oversized_files(tmp_path):
    with pytest.raises(ClaimsFileError, match="cannot read"):
        load_claims(tmp_path / "missing.toml")
    with pytest.raises(ClaimsFileError, match="the claims file is a directory, not a regular"):
        load_claims(tmp_path)
    big = tmp_path / "big.toml"
    big.write_bytes(b"# " + b"x" * (1 << 20) + b"\n")
    with pytest.raises(ClaimsFileError, match="has 1048579 bytes; at most 1048576 are "
                       "allowed; a claims file is a short TOML text"):
        load_claims(big)


def test_deeply_nested_toml_is_an_error_not_a_crash(tmp_path):
    path = tmp_path / "deep.toml"
    path.write_text("a = " + "[" * 5000 + "]" * 5000 + "\n")
    with pytest.raises(ClaimsFileError, match="not valid TOML"):
        load_claims(path)


def test_a_claim_that_is_not_a_table(tmp_path):
    path = tmp_path / "c.toml"
    path.write_text("claim = [1, 2]\n")
    with pytest.raises(ClaimsFileError, match=r"claim #1 must be a table"):
        load_claims(path)


@pytest.mark.parametrize("new, key, line, match", [
    ("per_decade = 1000000000", "sweep.range", 13,
     "'per_decade' must be at most 1000, got 1000000000"),
    ("per_decade = 5 }\nsweep.quick = { from = 1e-300, to = 1e300, per_decade = 20",
     "sweep.quick", 14, "the range has 12001 points .* at most 10000 are allowed"),
    ("per_decade = 5e-324", None, None, None),
])
def test_absurd_ranges_are_refused_when_loaded(tmp_path, data_dir, new, key, line, match):
    path = variant(tmp_path, data_dir, "per_decade = 5", new)
    if match is None:       # a tiny per_decade is allowed: it gives the two ends only
        (claim,) = load_claims(path)
        assert claim.range_for("quick").values() == [1.0, 0.01]
        return
    with pytest.raises(ClaimsFileError, match=match) as info:
        load_claims(path)
    assert info.value.key == key and info.value.line == line
    assert info.value.claim_id == "T-elements"


def test_range_limits():
    from hrbench_analysis.claimfile import MAX_PER_DECADE, MAX_RANGE_POINTS
    assert len(SweepRange(1.0, 1e-9, MAX_PER_DECADE).values()) == 9001
    assert len(SweepRange(1.0, 10.0 ** (-MAX_RANGE_POINTS / 1000 + 1e-3), 1000).values()) \
        <= MAX_RANGE_POINTS
    with pytest.raises(ValueError, match="at most 10000 are allowed"):
        SweepRange(1.0, 1e-11, MAX_PER_DECADE)
    with pytest.raises(ValueError, match="finite number > 0"):
        SweepRange(1.0, float("inf"), 5)
    with pytest.raises(ValueError, match="must differ"):
        SweepRange(2.0, 2.0, 5)
    # Ends far apart do not overflow the ratio.
    assert len(SweepRange(1e-300, 1e300, 1).values()) == 601


@pytest.mark.parametrize("old, new, key, match", [
    ("min_points = 8", "min_points = 2", "min_points", "integer from 3 to 10000"),
    ("min_points = 8", "min_points = 8.5", "min_points", "integer from 3 to 10000"),
    ("expected_exponent = 1", "expected_exponent = 1e300", "expected_exponent",
     r"within \+/-100"),
    ("params = { l = 8, d = 1 }", 'params = { l = 8, "d 2" = 1 }', "params",
     "letters, digits and '_'"),
    ("min_points = 8", "min_points = 8\nmax_depth = 2.5", "max_depth", "must be an integer"),
    ("min_points = 8", 'min_points = 8\nbound = "lower"', "bound", "one of theta, upper"),
])
def test_values_out_of_their_bounds(tmp_path, data_dir, old, new, key, match):
    path = variant(tmp_path, data_dir, old, new)
    with pytest.raises(ClaimsFileError, match=match) as info:
        load_claims(path)
    assert info.value.key == key


def test_bound_is_theta_unless_an_upper_bound_is_stated(tmp_path, data_dir):
    (claim,) = load_claims(data_dir / "small_claims.toml")
    assert claim.bound == "theta" and claim.judge.bound == "theta"
    (upper,) = load_claims(variant(tmp_path, data_dir, "min_points = 8",
                                   'min_points = 8\nbound = "upper"'))
    assert upper.bound == "upper"


def test_key_lines_of_parameters_and_ranges(data_dir):
    (claim,) = load_claims(data_dir / "small_claims.toml")
    assert claim.key_line("params.l") == 11 and claim.key_line("sweep.range") == 13
    assert claim.range_keys == {"quick": "sweep.range", "full": "sweep.range"}


def test_many_parameters_are_refused_before_any_line_search(tmp_path, data_dir):
    import time
    params = ", ".join(f"p{n} = 1" for n in range(20000))
    path = variant(tmp_path, data_dir, "params = { l = 8, d = 1 }", f"params = {{ {params} }}")
    start = time.perf_counter()
    with pytest.raises(ClaimsFileError, match="20000 scene parameters; at most 64"):
        load_claims(path)
    assert time.perf_counter() - start < 5


def test_sweep_grid_and_min_area_sweep(tmp_path, data_dir):
    path = variant(tmp_path, data_dir, "params = { l = 8, d = 1 }",
                   "params = { d = 1 }\nsweep.grid = { l = [16, 64] }")
    (claim,) = load_claims(path)
    assert claim.grid == {"l": (16.0, 64.0)}
    # A grid parameter may not be fixed or swept as well, nor be eps; lists hold numbers.
    for new, match in (("sweep.grid = { d = [1, 2] }", "already fixed in 'params'"),
                       ("sweep.grid = { eps = [1, 2] }", "scene parameters only"),
                       ("sweep.grid = { offset = [] }", "list of 1 to 32 numbers"),
                       ("sweep.grid = { offset = [2, 2] }", "lists a value twice"),
                       ("sweep.grid = 3", "must be a table")):
        bad = variant(tmp_path, data_dir, "params = { l = 8, d = 1 }",
                      f"params = {{ l = 8, d = 1 }}\n{new}")
        with pytest.raises(ClaimsFileError, match=match) as info:
            load_claims(bad)
        assert info.value.key == "sweep.grid"
    # min_area may be swept (with eps fixed), but not fixed at the same time.
    text = (data_dir / "small_claims.toml").read_text().replace(
        'sweep.param = "eps"', 'sweep.param = "min_area"\neps = 0.1')
    path.write_text(text)
    (claim,) = load_claims(path)
    assert claim.sweep_param == "min_area" and claim.eps == 0.1
    path.write_text(text.replace("eps = 0.1", "eps = 0.1\nmin_area = 0.01"))
    with pytest.raises(ClaimsFileError, match="'min_area' is fixed"):
        load_claims(path)


@pytest.mark.parametrize("value, ok", [(2, True), (1, True), (0, False), (5, False),
                                       (1.5, False), ("2", False)])
def test_step_octaves(tmp_path, data_dir, value, ok):
    path = variant(tmp_path, data_dir, "min_points = 8",
                   f"min_points = 8\nstep_octaves = {value!r}".replace("'", '"'))
    if ok:
        assert load_claims(path)[0].step_octaves == value
    else:
        with pytest.raises(ClaimsFileError, match="integer from 1 to 4"):
            load_claims(path)


def test_every_shipped_claim_carries_its_kind_and_reading():
    # A published claim quotes its source's words and says where they stand and why its
    # quantity is the source's; a reading states the quantity hrbench chose.
    text = {path.name: path.read_text() for path in Path(CLAIMS_DIR).glob("*.toml")}
    for c in load_claims_dir(CLAIMS_DIR):
        own = text[Path(c.path).name].split(f'id = "{c.id}"')[1].split("[[claim]]")[0]
        assert "\nkind = " in own, f"{c.id}: no explicit kind"
        assert c.published == (c.kind in PUBLISHED_KINDS)
        if c.published:
            assert c.words and c.words_at and c.quantity, c.id
    kinds = {c.id: c.kind for c in load_claims_dir(CLAIMS_DIR)}
    # The cases of a reading presented as the source's, each with its kind now.
    assert kinds["HS90-best"] == "reading" and kinds["HS90-best-leaves"] == "stated"
    assert kinds["C1-cornell"] == kinds["C3-cornell"] == "derived"
    assert kinds["HSA-precision-centre-cosine"] == "derived"
    assert all(kinds[f"SAG-{f}-plain"] == "derived"
               for f in ("array", "soup", "enclosure", "array3d", "soup3d", "sphere"))
    # Exact by construction: a measurement, never a verdict on a source.
    assert kinds["HSA-lin-3d"] == "derived"
    # Smits et al. bound the initial linking: the all-links fits are measurements, and
    # each bounding method's linking claims read the abstract's own quantity.
    assert all(kinds[f"SAG-{f}{q}"] == "derived" for f in ("array", "soup", "sphere")
               for q in ("", "-calls"))
    claims = {c.id: c for c in load_claims_dir(CLAIMS_DIR)}
    # O(k) against k; O(k log k) on the increments of the linking per patch, k^1.15 the
    # law its test must refute.
    for f in ("array", "enclosure", "sphere", "soup"):
        for bound, suffix, law, per in (("cluster", "", None, ""),
                                        ("patch", "-patch", "patches ** 0.15", " / patches")):
            for q, y in (("", "linking_links"), ("-calls", "linking_calls")):
                c = claims[f"SAG-{f}-linking{suffix}{q}"]
                assert c.kind == "reading" and c.bound == "upper" and c.y.text == y + per
                assert c.options.get("cluster_bound", "cluster") == bound
                assert (c.alternative.text if c.alternative else None) == law
                assert c.increments == (2 if law else None)
                assert c.expected_exponent == (0 if law else 1)


def test_kind_defaults_and_its_checks(tmp_path, data_dir):
    (claim,) = load_claims(data_dir / "small_claims.toml")
    assert claim.kind == "stated" and claim.published and claim.words == ""
    (old,) = load_claims(variant(tmp_path, data_dir, "min_points = 8",
                                 "min_points = 8\npublished = false"))
    assert old.kind == "derived" and not old.published
    (reading,) = load_claims(variant(tmp_path, data_dir, "min_points = 8",
                                     'min_points = 8\nkind = "reading"\nquantity = "q"'))
    assert reading.kind == "reading" and reading.published and reading.quantity == "q"
    # Words given once in [source] are every claim's, unless a claim quotes its own.
    (quoted,) = load_claims(variant(tmp_path, data_dir, 'citation = "hrbench test data"',
                                    'citation = "hrbench test data"\nwords = "w"\n'
                                    'words_at = "abstract"'))
    assert (quoted.words, quoted.words_at) == ("w", "abstract")
    for new, match in (('kind = "law"', "must be one of stated, reading, derived"),
                       ('kind = "reading"', "needs the key 'quantity'"),
                       ('kind = "stated"\npublished = false', "disagree")):
        with pytest.raises(ClaimsFileError, match=match) as info:
            load_claims(variant(tmp_path, data_dir, "min_points = 8",
                                f"min_points = 8\n{new}"))
        assert info.value.line is not None
