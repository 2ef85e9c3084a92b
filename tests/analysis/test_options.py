"""Engine options in claims, per-mode overrides, exact binary grids, and skipped claims."""

import dataclasses
import json
import math
import sqlite3

import numpy as np
import pytest
from matplotlib.figure import Figure

from hrbench_analysis import __version__
from hrbench_analysis.claimfile import ClaimsFileError, SweepRange, load_claims, missing_capability
from hrbench_analysis.engine import engine_version, format_number, get_capabilities, option_argv
from hrbench_analysis.plots import PowerLawSeries, plot_power_law_comparison, plot_ratio
from hrbench_analysis.reproduce import check_claims, main
from hrbench_analysis.store import ResultStore
from hrbench_analysis.store_points import PointKey, StoredPoint
from hrbench_analysis.sweep import get_claim_data, run_points
from hrbench_analysis.sweep_plan import expand_claim

HEADER = '''[source]
key = "test"
citation = "hrbench test data"

[[claim]]
id = "O1"
statement = "N = Theta(eps^-1)"
scene = "parallel"
params = { l = 8, d = 1 }
sweep.param = "eps"
sweep.range = { from = 1.0, to = 0.01, per_decade = 5 }
x = "1/eps"
y = "N"
expected_exponent = 1
tolerance = 0.15
regime = { x_min = 1 }
'''


def write_claims(tmp_path, extra, header=HEADER):
    path = tmp_path / "claims.toml"
    path.write_text(header + extra)
    return path


def load_one(tmp_path, extra):
    (claim,) = load_claims(write_claims(tmp_path, extra))
    return claim


def test_options_are_read_and_merged_per_mode(tmp_path):
    claim = load_one(tmp_path, 'options = { visibility = "fraction", rays_per_side = 4 }\n'
                               'full.options = { rays_per_side = 8, method = "translation" }\n')
    assert claim.options_for("quick") == {"rays_per_side": 4, "visibility": "fraction"}
    assert claim.options_for("full") == {"method": "translation", "rays_per_side": 8,
                                         "visibility": "fraction"}
    assert load_one(tmp_path, "").options_for("full") == {}


def test_option_names_become_dashed_flags():
    argv = option_argv({"visibility": "fraction", "rays_per_side": 4, "subdivision": "binary",
                        "scale": 0.5})
    assert argv == ["--rays-per-side", "4", "--scale", "0.5", "--subdivision", "binary",
                    "--visibility", "fraction"]


@pytest.mark.parametrize("extra, key, match", [
    ("options = { rays_per_side = false }\n", "options.rays_per_side", "string, an integer"),
    ("options = { rays_per_side = [1, 2] }\n", "options.rays_per_side", "string, an integer"),
    ('options = { visibility = "--all" }\n', "options.visibility", "plain word"),
    ('options = { visibility = "a b" }\n', "options.visibility", "plain word"),
    ("options = { eps = 0.1 }\n", "options.eps", "claim key 'eps'"),
    ("options = { json = 1 }\n", "options.json", "sets it itself"),
    ('options = { Visibility = "none" }\n', "options.Visibility", "lower-case"),
    ("options = { scale = nan }\n", "options.scale", "finite"),
    ('options = "fraction"\n', "options", "table of engine options"),
    ('full.options = { method = 1.5e400 }\n', "full.options.method", "finite"),
    ('full.method = "translation"\n', "full.method", "unknown key 'full.method'"),
])
def test_bad_options_name_the_claim_the_key_and_the_line(tmp_path, extra, key, match):
    with pytest.raises(ClaimsFileError, match=match) as info:
        load_one(tmp_path, extra)
    err = info.value
    assert err.claim_id == "O1" and err.key == key
    assert err.line == HEADER.count("\n") + 1
    assert f"claims.toml:{err.line}: claim 'O1'" in str(err)


def test_options_reach_the_command_line_and_the_cache_key(tmp_path, fake_hrbench):
    version = engine_version(fake_hrbench)
    plain = load_one(tmp_path, "")
    fancy = load_one(tmp_path, 'options = { threads = 2 }\n'
                               'full.options = { method = "translation" }\n')
    plain_points = expand_claim(plain, "full", fake_hrbench, version)
    quick = expand_claim(fancy, "quick", fake_hrbench, version)
    full = expand_claim(fancy, "full", fake_hrbench, version)
    assert quick[0].argv[-4:] == ("--threads", "2", "--count-only", "--json")
    assert full[0].argv[-6:] == ("--method", "translation", "--threads", "2",
                                 "--count-only", "--json")
    assert "--method" not in quick[0].argv
    keys = [{p.key.text() for p in ps} for ps in (plain_points, quick, full)]
    assert not (keys[0] & keys[1]) and not (keys[0] & keys[2]) and not (keys[1] & keys[2])
    assert full[0].key.options == (("method", "translation"), ("threads", "2"))


def test_key_without_options_keeps_its_old_text():
    key = PointKey(version="v", scene="parallel", params=(("d", 1.0), ("l", 8.0)), eps=0.5,
                   oracle="garmann")
    assert key.text() == json.dumps({
        "version": "v", "scene": "parallel", "params": {"d": "1.0", "l": "8.0"},
        "eps": "0.5", "oracle": "garmann", "min_area": None, "max_depth": None,
        "mode": "count-only"}, sort_keys=True)
    with_options = PointKey(**{**key.__dict__, "options": (("method", "translation"),)})
    assert with_options.text() != key.text() and '"method": "translation"' in with_options.text()


def test_cache_written_before_options_is_migrated(tmp_path):
    path = tmp_path / "old.sqlite"
    old_columns = ("key TEXT PRIMARY KEY, version TEXT NOT NULL, scene TEXT NOT NULL, "
                   "params TEXT NOT NULL, eps REAL NOT NULL, oracle TEXT NOT NULL, "
                   "min_area REAL, max_depth INTEGER, mode TEXT NOT NULL, ok INTEGER NOT NULL, "
                   "exit_code INTEGER NOT NULL, stderr TEXT NOT NULL, output TEXT NOT NULL, "
                   "wall_seconds REAL NOT NULL, finished_at REAL NOT NULL")
    old = PointKey(version="v", scene="parallel", params=(("l", 8.0),), eps=0.5,
                   oracle="garmann")
    with sqlite3.connect(path) as con:
        con.execute(f"CREATE TABLE points ({old_columns})")
        con.execute("INSERT INTO points VALUES (?,?,?,?,?,?,?,?,?,?,?,?,?,?,?)",
                    (old.text(), "v", "parallel", "{}", 0.5, "garmann", None, None,
                     "count-only", 1, 0, "", "{}", 0.1, 0.0))
    with ResultStore(path) as store:
        assert store.get(old).ok
        new = PointKey(**{**old.__dict__, "options": (("method", "translation"),)})
        assert store.get(new) is None
        store.put(StoredPoint(new, True, 0, "", "{}", 0.1))
        assert store.count() == 2
    with sqlite3.connect(path) as con:
        stored = dict(con.execute("SELECT key, options FROM points").fetchall())
    assert json.loads(stored[new.text()]) == {"method": "translation"}
    assert json.loads(stored[old.text()]) == {}


def test_a_run_that_ignores_an_option_fails(tmp_path, fake_hrbench, monkeypatch):
    claim = load_one(tmp_path, 'options = { method = "translation" }\n')
    points = expand_claim(claim, "quick", fake_hrbench, engine_version(fake_hrbench))[:2]
    monkeypatch.setenv("FAKE_HRBENCH_REPORT_METHOD", "enumerate")
    with ResultStore(tmp_path / "cache.sqlite") as store:
        assert run_points(points, store, jobs=1, progress=None)["failed"] == 2
        data = get_claim_data(claim, points, store)
        assert "method='enumerate'" in data.failures[0]["stderr"]
        monkeypatch.delenv("FAKE_HRBENCH_REPORT_METHOD")
        # Not a deterministic failure of the engine: the next sweep runs it again.
        assert run_points(points, store, jobs=1, progress=None) == {
            "total": 2, "cached": 0, "ran": 2, "failed": 0}


def test_binary_digits_give_exact_lengths_that_print_exactly():
    values = SweepRange(64, 2.0 ** 40, 16, binary_digits=6).values()
    assert values[0] == 64 and values[-1] == 2.0 ** 40
    for v in values:
        mantissa, _ = math.frexp(v)
        assert (mantissa * 64).is_integer()
        assert float(format_number(v)) == v
    ratios = np.diff(np.log10(values))
    assert np.all(ratios > 0) and np.all(np.abs(ratios - 1 / 16) < 0.02)
    assert format_number(0.25) == "0.25" and format_number(1e-6) == "1e-06"


def test_bad_binary_digits_are_named(tmp_path):
    header = HEADER.replace("per_decade = 5 }", "per_decade = 5, binary_digits = 0 }")
    with pytest.raises(ClaimsFileError, match="binary_digits") as info:
        load_claims(write_claims(tmp_path, "", header))
    assert info.value.key == "sweep.range.binary_digits"


def test_missing_scene_or_option_is_a_reason_to_skip(tmp_path, fake_hrbench):
    caps = get_capabilities(fake_hrbench)
    claim = load_one(tmp_path, 'options = { visibility = "fraction" }\n')
    assert missing_capability(claim, "quick", caps) == "engine lacks option --visibility"
    claim.scene = "parallel3d"
    assert missing_capability(claim, "quick", caps) == "engine lacks scene 'parallel3d'"
    assert missing_capability(load_one(tmp_path, ""), "quick", caps) is None


def test_a_misspelt_scene_is_an_error_for_this_hrbench_and_a_hint_for_others(
        tmp_path, fake_hrbench):
    claim = load_one(tmp_path, "")
    claim.scene = "paralel"
    older = get_capabilities(fake_hrbench)   # an hrbench of another release
    errors, skipped = check_claims([claim], "quick", older)
    assert errors == []
    assert skipped == {"O1": "engine lacks scene 'paralel' (did you mean 'parallel'?)"}
    current = dataclasses.replace(older, version=__version__)
    errors, skipped = check_claims([claim], "quick", current)
    assert errors == [f"{claim.path}:{claim.line}: claim 'O1': engine lacks scene "
                      "'paralel' (did you mean 'parallel'?)"] and skipped == {}


def test_claims_the_engine_cannot_run_are_skipped_not_failed(tmp_path, fake_hrbench,
                                                            capsys):
    extra = HEADER.split("[[claim]]", 1)[1]
    path = write_claims(tmp_path, "\n[[claim]]" + extra.replace('"O1"', '"O2"').replace(
        'scene = "parallel"', 'scene = "parallel3d"') + "\n[[claim]]" + extra.replace(
        '"O1"', '"O3"') + 'options = { visibility = "fraction" }\n')
    code = main(["--claims", str(path), "--hrbench", str(fake_hrbench), "--results",
                 str(tmp_path / "results"), "--no-tiling", "--jobs", "2"])
    out, err = capsys.readouterr()
    assert code == 0, err
    assert "O2: skipped: engine lacks scene 'parallel3d'" in out
    assert "O3: skipped: engine lacks option --visibility" in out
    assert "O1: reproduced" in out
    md = (tmp_path / "results" / "report.md").read_text()
    assert "| [O2](#claim-o2) |" in md and "**skipped**: engine lacks scene 'parallel3d'" in md
    claims = json.loads((tmp_path / "results" / "claims.json").read_text())["claims"]
    by_id = {c["id"]: c for c in claims}
    assert by_id["O2"]["verdict"] == "skipped" and by_id["O2"]["as_expected"] is None
    assert by_id["O3"]["options"] == {"visibility": "fraction"}


def test_options_are_shown_in_the_report(tmp_path, fake_hrbench, capsys):
    path = write_claims(tmp_path, 'options = { threads = 2 }\n'
                                  'full.options = { method = "translation" }\n')
    results = tmp_path / "results"
    assert main(["--claims", str(path), "--hrbench", str(fake_hrbench), "--results",
                 str(results), "--no-tiling", "--full"]) == 0
    capsys.readouterr()
    md = (results / "report.md").read_text()
    assert "options `--method translation --threads 2`" in md
    obj = json.loads((results / "claims.json").read_text())["claims"][0]
    assert obj["options"] == {"method": "translation", "threads": 2}


def test_theta_panel_names_the_points_and_the_band_in_its_legend():
    x = np.logspace(1, 4, 12)
    ratio = 2 + 0.3 * np.sin(np.arange(12))
    regime = x > 30
    band = ratio[regime].max() / ratio[regime].min()
    ax = Figure().add_subplot()
    plot_ratio(ax, x, ratio, in_regime=regime, band=band, max_band=10, ratio_label="L / N^2")
    labels = [t.get_text() for t in ax.legend().get_texts()]
    assert labels == ["ratio in the regime", "ratio outside the regime",
                      f"the regime's band (min, max): max/min {band:.2f}, bounded if at "
                      "most 10"]
    # The band's two dashed lines lie at the regime's extreme ratios, one of them named.
    dashed = [line for line in ax.get_lines() if line.get_linestyle() == "--"]
    assert sorted(line.get_ydata()[0] for line in dashed) == pytest.approx(
        [ratio[regime].min(), ratio[regime].max()])
    assert sum(not line.get_label().startswith("_") for line in dashed) == 1
    # Without the check's numbers the band is still named; without points outside the
    # regime, they are not.
    ax = Figure().add_subplot()
    plot_ratio(ax, x, ratio)
    assert [t.get_text() for t in ax.legend().get_texts()] == [
        "ratio in the regime", "the regime's band (min, max)"]


def test_comparison_plot_draws_series_and_reference_slopes():
    fig = Figure()
    ax = fig.add_subplot()
    x = np.logspace(2, 5, 12)
    lines = plot_power_law_comparison(
        ax, [PowerLawSeries(x, 1e-3 * x ** 2, "unoccluded"),
             PowerLawSeries(x[:8], 5e-4 * x[:8] ** 2, "occluded", in_regime=x[:8] > 300),
             PowerLawSeries([], [], "empty")],
        slopes={2: (x, 1e-3 * x ** 2), 1: (x[:3], 7 * x[:3])}, symbol="N")
    assert len(lines) == 2 and ax.get_xscale() == "log" and ax.get_yscale() == "log"
    by_label = {line.get_label(): line for line in ax.get_lines()}
    two = by_label["claimed slope 2 (proportional to N^2), through the regime's points"]
    one = by_label["claimed slope 1 (proportional to N), through the regime's points"]
    # The lines run through the points they were given, over the x range of all series.
    xs, ys = two.get_data()
    assert xs[0] == pytest.approx(x.min()) and xs[-1] == pytest.approx(x.max())
    assert ys == pytest.approx(1e-3 * xs ** 2)
    assert one.get_data()[1] == pytest.approx(7 * one.get_data()[0])
    # No series is hidden from the legend: points outside the regime are named too.
    assert "occluded (outside the regime)" in by_label
    # The y axis keeps to the measured points, not to the steepest reference line.
    assert ax.get_ylim()[1] <= 3 * 1e-3 * x.max() ** 2 * (1 + 1e-9)
