"""Hierarchy statistics (hrbench_analysis.lemmas): hand-computed values, real runs, the cache.

The definitions are in docs/lemmas.md. The tests that run ``build/hrbench`` are skipped
when it is not built.
"""

import json
import math
import sqlite3
import subprocess
from pathlib import Path

import numpy as np
import pytest

import hrbench_analysis.sweep as sweep
from hrbench_analysis.claimfile import check_names, load_claims, missing_capability, param_errors
from hrbench_analysis.engine import engine_version, get_capabilities, save_argv
from hrbench_analysis.lemmas import (
    STATISTICS,
    STATISTICS_MODE,
    STATISTICS_VERSION,
    LinkDumpError,
    StatisticsJob,
    element_statistics,
    hierarchy_statistics,
    is_lemma,
    measure,
    read_link_dump,
    read_scene_segments,
    stored_statistics,
)
from hrbench_analysis.loader import parse_run_json, read_links_csv
from hrbench_analysis.reproduce_options import CLAIMS_DIR
from hrbench_analysis.store import ResultStore, StoreError
from hrbench_analysis.store_points import StoredPoint
from hrbench_analysis.store_schema import STORE_SCHEMA_VERSION
from hrbench_analysis.sweep import get_claim_data, run_points
from hrbench_analysis.sweep_plan import expand_claim

ROOT = Path(__file__).resolve().parents[2]
HRBENCH = ROOT / "build" / "hrbench"
needs_engine = pytest.mark.skipif(not HRBENCH.exists(), reason="build/hrbench not built")

HEADER = "root_i,elem_i,t0_i,t1_i,depth_i,root_j,elem_j,t0_j,t1_j,depth_j\n"


def plates(l, d):
    # The root segments of `parallel l d`: P (0,0)->(l,0), Q (l,d)->(0,d).
    return np.array([[0.0, 0.0], [l, d]]), np.array([[l, 0.0], [0.0, d]])


def write_dump(path, rows):
    path.write_text(HEADER + "".join(",".join(map(str, row)) + "\n" for row in rows))
    return path


# The worked example of docs/conventions.md: parallel l=1 d=1 --eps 0.5. P0 = [0, 0.5],
# P1 = [0.5, 1] on P; Q0 = [0, 0.5] (x from 1 to 0.5), Q1 = [0.5, 1] (x from 0.5 to 0).
WORKED = [(0, 2, 0, 0.5, 1, 1, 4, 0, 0.5, 1), (0, 2, 0, 0.5, 1, 1, 5, 0.5, 1, 1),
          (0, 3, 0.5, 1, 1, 1, 4, 0, 0.5, 1), (0, 3, 0.5, 1, 1, 1, 5, 0.5, 1, 1)]


def test_worked_example_by_hand(tmp_path):
    links = read_link_dump(write_dump(tmp_path / "links.csv", WORKED))
    stats = element_statistics(links, *plates(1.0, 1.0))
    far = math.sqrt(1.25)  # centres 0.5 apart along the plates, 1 across
    el, st = stats.elements, stats.stretches
    # Every element has two partners of size 0.5, one opposite (r = 1), one beside.
    assert len(el) == 4
    assert el.partners.tolist() == [2, 2, 2, 2]
    assert np.allclose(el.r_min, 1.0) and np.allclose(el.r_max, far)
    assert np.allclose(el.span, 1.0) and np.allclose(el.extent, 1.0)
    # Stretches: P0's foot on Q lies at t = 0.75, the centre of Q1: Q1 is at it, Q0 before
    # it, so P0 has two stretches of one partner; P1's foot, t = 0.25, is Q0's centre, so
    # both its partners lie at or after it. The same for Q0 and Q1 on P.
    per_element = {(int(r), float(t0)): [] for r, t0 in zip(el.root, el.t0, strict=True)}
    for r, t0, side, n in zip(st.root, st.t0, st.side, st.partners, strict=True):
        per_element[(int(r), float(t0))].append((int(side), int(n)))
    assert per_element == {(0, 0.0): [(-1, 1), (1, 1)], (0, 0.5): [(1, 2)],
                           (1, 0.0): [(-1, 1), (1, 1)], (1, 0.5): [(1, 2)]}
    values = hierarchy_statistics(stats)
    assert list(values) == list(STATISTICS)
    assert values["leaf_min_size"] == 0.5
    assert values["partners_max"] == 2 and values["partners_mean"] == 2.0
    assert values["partners_min"] == 2
    assert values["span_per_size_max"] == 2.0 and values["span_per_size_mean"] == 2.0
    assert values["span_lower_min"] == pytest.approx(1.0 / (far - 1.0))
    assert values["span_upper_max"] == pytest.approx(1.0 / (far + 1.0))
    assert values["both_sides_upper_max"] == pytest.approx(1.0 / (far + 1.0))
    assert values["span_violations"] == values["both_sides_violations"] == 0
    assert values["extent_violations"] == 0
    assert values["elements"] == 4 and values["stretches"] == 6


def test_violations_are_counted_by_hand(tmp_path):
    # Plates of length 4 at distance 0.5; links chosen by hand to break the bounds (no
    # real refinement makes them). On P: p = [1.75, 2.25] (centre x = 2) and
    # p' = [0, 0.5] (x = 0.25); on Q (x = 4 - t): q1 = t [1.5, 2] (x = 2.25) and
    # q2 = t [0, 0.5] (x = 3.75). Links: (p, q1), (p, q2), (p', q2).
    rows = [(0, 9, 1.75, 2.25, 3, 1, 7, 1.5, 2.0, 3), (0, 9, 1.75, 2.25, 3, 1, 8, 0, 0.5, 3),
            (0, 5, 0, 0.5, 3, 1, 8, 0, 0.5, 3)]
    stats = element_statistics(read_link_dump(write_dump(tmp_path / "l.csv", rows)),
                               *plates(4.0, 0.5))
    near, far, farthest = math.hypot(0.25, 0.5), math.hypot(1.75, 0.5), math.hypot(3.5, 0.5)
    # p's foot on Q is t = 2: q1 (t = 1.75) and q2 (t = 0.25) both lie before it, one
    # stretch with a gap: D = 1 < r_max - r_min = far - near = 1.26, the lower bound
    # breaks. q2's foot on P is t = 3.75: p and p' lie before it, D = 1 < farthest - far
    # = 1.72, broken too. p' and q1 have one partner each and keep the bounds.
    st = stats.stretches
    p = (st.root == 0) & (st.t0 == 1.75)
    assert st.side[p].tolist() == [-1] and st.partners[p].tolist() == [2]
    assert st.r_min[p] == pytest.approx(near) and st.r_max[p] == pytest.approx(far)
    assert st.span[p].tolist() == [1.0] and st.extent[p].tolist() == [2.0]
    assert st.violations("span").tolist() == [False, True, True, False]
    values = hierarchy_statistics(stats)
    assert values["span_violations"] == 2 and values["both_sides_violations"] == 2
    # p and q2 have two partners, p' and q1 one each.
    assert values["partners_max"] == 2 and values["partners_min"] == 1
    assert values["span_lower_min"] == pytest.approx(1.0 / (farthest - far))
    # Extents: p's partners span t 0..2 (2 >= 1.26), q2's span P from 0 to 2.25
    # (2.25 >= 1.72): the hull keeps the lower bound here.
    assert values["extent_violations"] == 0
    assert values["elements"] == values["stretches"] == 4


def test_single_partner_and_no_links(tmp_path):
    stats = element_statistics(read_link_dump(write_dump(tmp_path / "l.csv", WORKED[:1])),
                               *plates(1.0, 1.0))
    values = hierarchy_statistics(stats)
    assert values["span_lower_min"] is None  # no stretch with r_max > r_min
    assert values["partners_max"] == values["partners_min"] == 1
    assert values["span_violations"] == 0
    empty = read_link_dump(write_dump(tmp_path / "e.csv", []))
    values = hierarchy_statistics(element_statistics(empty, *plates(1.0, 1.0)))
    assert values["elements"] == 0 and values["span_violations"] == 0
    assert values["leaf_min_size"] is None and values["partners_max"] is None
    assert values["partners_min"] is None


def test_reading_errors(tmp_path):
    bad = tmp_path / "bad.csv"
    bad.write_text("root_i,elem_i,area_i,cx_i,cy_i,cz_i,depth_i\n0,1,1,0,0,0,0\n")
    with pytest.raises(LinkDumpError, match="lacks column.*2D scene"):
        read_link_dump(bad)
    with pytest.raises(LinkDumpError, match="need a 2D scene"):
        read_scene_segments(json.dumps({"dimension": 3, "patches": []}))
    with pytest.raises(LinkDumpError, match="unreadable scene"):
        read_scene_segments("not json")
    with pytest.raises(LinkDumpError, match="names root 1, but the scene has 1 patches"):
        element_statistics(read_link_dump(write_dump(tmp_path / "l.csv", WORKED)),
                           np.zeros((1, 2)), np.ones((1, 2)))


def test_lemma_claims_are_marked_and_read_statistics():
    claims = load_claims(CLAIMS_DIR / "garmann2003_lemmas.toml")
    assert len(claims) >= 5
    for claim in claims:
        assert is_lemma(claim) and "lemma" in claim.statement
        assert claim.statistics and claim.statistics <= set(STATISTICS)
    others = load_claims(CLAIMS_DIR / "garmann2003.toml")
    assert not any(c.statistics for c in others) and not any(is_lemma(c) for c in others)


# ---------------------------------------------------------------------------------------
# Real runs.


def real_job(scene, params, eps):
    args = [f"{k}={v:g}" for k, v in sorted(params.items())]
    return StatisticsJob(tuple(save_argv(HRBENCH, scene, params)),
                         (str(HRBENCH), "links", scene, *args, "--eps", f"{eps:g}"))


@needs_engine
@pytest.mark.parametrize("params, eps", [
    ({"l": 8, "d": 1}, 0.05),
    ({"l": 8, "d": 1}, 0.0316),
    ({"l": 8, "d": 0.25, "l2": 6, "offset": 1.5}, 0.1),
])
def test_real_runs_satisfy_the_inequality_on_every_stretch(params, eps, tmp_path):
    found = measure(real_job("parallel", params, eps))
    assert found.exit_code == 0 and found.message == "", found.message
    values = found.statistics
    assert values["span_violations"] == 0
    assert values["span_lower_min"] >= 1 and values["span_upper_max"] <= 1
    # A split element is larger than eps * r >= eps * d, so every leaf is larger than
    # eps d / 2; with aligned plates (l2 = l, offset 0) the leaf opposite is accepted at
    # r = d, so it is at most eps d.
    d = params["d"]
    assert eps * d / 2 < values["leaf_min_size"]
    if "l2" not in params:
        assert values["leaf_min_size"] <= eps * d
    # The same statistics from the loader's reader of the same link list.
    out = tmp_path / "links.csv"
    subprocess.run([*real_job("parallel", params, eps).links_argv, "--out", str(out)],
                   check=True, capture_output=True, timeout=120)
    table = read_links_csv(out)
    links = {"root_i": table.root_i, "t0_i": table.t0_i, "t1_i": table.t1_i,
             "root_j": table.root_j, "t0_j": table.t0_j, "t1_j": table.t1_j}
    a, b = read_scene_segments(subprocess.run(
        [*real_job("parallel", params, eps).save_argv], capture_output=True, text=True,
        check=True, timeout=60).stdout)
    assert hierarchy_statistics(element_statistics(links, a, b)) == values
    assert 1 <= values["partners_min"] <= values["partners_mean"] <= values["partners_max"]
    # Two partners per link: the partners of the elements add up to 2 L.
    assert values["partners_mean"] * values["elements"] == pytest.approx(2 * len(table))


@needs_engine
def test_a_failed_link_dump_is_reported():
    job = StatisticsJob(tuple(save_argv(HRBENCH, "parallel", {"l": 8, "d": 1})),
                        (str(HRBENCH), "links", "parallel", "l=8", "d=1", "--eps", "-1"))
    found = measure(job)
    assert found.statistics is None and found.exit_code == 2
    assert found.message.startswith("hrbench links failed: ")
    found = measure(real_job("parallel", {"l": 8, "d": 1}, 0.5), links=3)
    assert found.statistics is None and found.exit_code == 1
    assert "the link list has" in found.message and "the run counted 3" in found.message


# ---------------------------------------------------------------------------------------
# Sweeps and the cache.

CLAIM = """
[source]
key = "test"
citation = "hrbench test data"

[[claim]]
id = "LEM-test"
statement = "lemma: partners = Theta(eps^-1)"
scene = "parallel"
params = {{ l = 4, d = 1 }}
sweep.param = "eps"
sweep.range = {{ from = 1.0, to = 0.1, per_decade = 4 }}
x = "1/eps"
y = "{y}"
expected_exponent = 1
tolerance = 0.2
"""


def lemma_claim(tmp_path, y="partners_max", name="lemma.toml"):
    path = tmp_path / name
    path.write_text(CLAIM.format(y=y))
    (claim,) = load_claims(path)
    return claim


@needs_engine
def test_sweep_caches_the_statistics_and_reuses_them(tmp_path, monkeypatch):
    claim = lemma_claim(tmp_path)
    version = engine_version(HRBENCH)
    points = expand_claim(claim, "quick", HRBENCH, version)
    assert len(points) == 5
    assert all(p.key.mode == STATISTICS_MODE and p.statistics is not None for p in points)
    assert points[0].statistics.links_argv[1:] == ("links", "parallel", "d=1", "l=4",
                                                   "--eps", "1", "--oracle", "garmann")
    # A claim of the same runs without statistics keeps the plain count-only key.
    plain = expand_claim(lemma_claim(tmp_path, y="L", name="plain.toml"), "quick", HRBENCH,
                         version)
    assert {p.key.mode for p in plain} == {"count-only"}
    assert {p.key.text() for p in plain}.isdisjoint(p.key.text() for p in points)
    with ResultStore(tmp_path / "cache.sqlite") as store:
        # Records without statistics (the plain claim's) are never taken for them.
        assert run_points(plain, store, jobs=2, progress=None)["ran"] == 5
        assert run_points(points, store, jobs=2, progress=None) == {
            "total": 5, "cached": 0, "ran": 5, "failed": 0}
        # The statistics lie beside the record, which stays what the engine printed.
        point = store.get(points[-1].key)
        stored = point.statistics
        assert "hierarchy_statistics" not in json.loads(point.output)
        assert parse_run_json(point.output).counters["links"] == pytest.approx(
            stored["elements"] * stored["partners_mean"] / 2)
        assert stored["version"] == STATISTICS_VERSION
        assert set(STATISTICS) <= set(stored)
        data = get_claim_data(claim, points, store)
        # A rerun measures nothing: the statistics come from the cache.
        monkeypatch.setattr(sweep, "measure", lambda *a, **k: pytest.fail("measured again"))
        assert run_points(points, store, jobs=2, progress=None) == {
            "total": 5, "cached": 5, "ran": 0, "failed": 0}
        again = get_claim_data(claim, points, store)
    assert data.x.size == 5 and not data.failures
    assert np.array_equal(data.y, again.y)
    assert data.y[-1] == stored["partners_max"]  # eps = 0.1, the largest x


def test_a_record_without_statistics_is_a_store_error(tmp_path, data_dir, fake_hrbench):
    claim = lemma_claim(tmp_path)
    points = expand_claim(claim, "quick", fake_hrbench, "v")
    record = (data_dir / "run_parallel_l64_d1_eps0.25.json").read_text()
    with ResultStore(tmp_path / "cache.sqlite") as store:
        store.put(StoredPoint(points[0].key, True, 0, "", record, 0.1))
        with pytest.raises(StoreError, match="without hierarchy statistics"):
            get_claim_data(claim, points[:1], store)


def _legacy_store(path, rows):
    # A cache of layout 2, as the analysis wrote it when the statistics lay inside the
    # record: (key text, record text) rows of successful points.
    with ResultStore(path) as store:
        pass
    with sqlite3.connect(path) as con:
        con.execute("DROP TABLE statistics")
        con.execute("PRAGMA user_version = 2")
        for text, record in rows:
            con.execute("INSERT INTO points (key, version, scene, params, eps, oracle, mode, ok, "
                        "exit_code, stderr, output, wall_seconds, finished_at) VALUES "
                        "(?, 'v', 'parallel', '{}', 1, 'garmann', 'm', 1, 0, '', ?, 0.1, 1)",
                        (text, record))
    return store


def test_statistics_are_stored_beside_the_record_and_read_back(tmp_path, data_dir,
                                                              fake_hrbench):
    claim = lemma_claim(tmp_path)
    points = expand_claim(claim, "quick", fake_hrbench, "v")
    record = (data_dir / "run_parallel_l64_d1_eps0.25.json").read_text()
    values = {name: 1.0 + i for i, name in enumerate(STATISTICS)}
    with ResultStore(tmp_path / "cache.sqlite") as store:
        store.put(StoredPoint(points[0].key, True, 0, "", record, 0.1,
                              statistics=stored_statistics(values)))
        got = store.get(points[0].key)
        data = get_claim_data(claim, points[:1], store)
        # A rerun stored without statistics leaves none behind.
        store.put(StoredPoint(points[0].key, False, 1, "boom", "", 0.1))
        assert store.get(points[0].key).statistics is None
    assert got.output == record
    assert got.statistics == {"version": STATISTICS_VERSION, **values}
    assert data.y.tolist() == [values["partners_max"]]


def test_an_old_cache_with_statistics_inside_records_is_read(tmp_path, data_dir, fake_hrbench):
    claim = lemma_claim(tmp_path)
    points = expand_claim(claim, "quick", fake_hrbench, "v")
    record = json.loads((data_dir / "run_parallel_l64_d1_eps0.25.json").read_text())
    values = {name: 2.0 + i for i, name in enumerate(STATISTICS)}
    inside = json.dumps({**record, "hierarchy_statistics": stored_statistics(values)})
    path = tmp_path / "old.sqlite"
    _legacy_store(path, [(points[0].key.text(), inside),
                         (points[1].key.text(), json.dumps(record))])
    with ResultStore(path) as store:
        moved, plain = store.get(points[0].key), store.get(points[1].key)
        data = get_claim_data(claim, points[:1], store)
    assert json.loads(moved.output) == record
    assert moved.statistics == {"version": STATISTICS_VERSION, **values}
    assert plain.statistics is None and json.loads(plain.output) == record
    assert data.y.tolist() == [values["partners_max"]]
    with sqlite3.connect(path) as con:
        assert con.execute("PRAGMA user_version").fetchone()[0] == STORE_SCHEMA_VERSION


def test_names_are_checked_where_the_statistics_exist(tmp_path, fake_hrbench):
    caps = get_capabilities(fake_hrbench)
    claim = lemma_claim(tmp_path)
    check_names(claim, caps.scalar_counters, ("l", "d"))  # a known name
    # The fake engine has no 'save' command: the claim is skipped, not failed.
    assert "lacks the command(s) save" in missing_capability(claim, "quick", caps)
    assert param_errors(claim, caps) == []
    # --method translation makes no link list; a 3D scene has none of segments.
    text = CLAIM.format(y="partners_max") + 'full.options = { method = "translation" }\n'
    (tmp_path / "m.toml").write_text(text)
    (claim,) = load_claims(tmp_path / "m.toml")
    (error,) = param_errors(claim, caps)
    assert error.endswith("claim 'LEM-test': key 'y': hierarchy statistic(s) partners_max "
                          "need the link list, which 'hrbench links' does not make with "
                          "--method translation")
    text = CLAIM.format(y="partners_max").replace("parallel", "box3d").replace(
        "l = 4, d = 1", "")
    (tmp_path / "b.toml").write_text(text)
    (claim,) = load_claims(tmp_path / "b.toml")
    (error,) = param_errors(claim, caps)
    assert "are measured on the link list of a 2D scene; scene 'box3d' is 3D" in error
