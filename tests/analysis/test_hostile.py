"""Hostile input: every class ends with its documented exit code and one line on stderr.

0 as expected, 1 refuted although expected to hold, 2 bad input or environment, 70 a bug
of the analysis, 130 interrupted (see docs/analysis.md, "Exit codes").
"""

import json
import sqlite3
from types import SimpleNamespace

import pytest

from hrbench_analysis import reproduce
from hrbench_analysis.claimfile import SweepRange
from hrbench_analysis.engine import param_errors, parse_capabilities
from hrbench_analysis.reproduce import main


def _param(name, low=0.0, high=None, low_open=True, integer=False):
    return {"name": name, "default": 1.0, "default_from": None, "low": low, "high": high,
            "low_open": low_open, "high_open": False, "integer": integer, "doc": name}


#: A capabilities document with a family of real parameters and one of an integer.
CAPABILITIES = {
    "schema_version": 1, "engine": "hrbench", "version": "0.3.0", "run_schema_version": 1,
    "commands": [{"name": "run", "doc": "count"}],
    "families": [
        {"name": "parallel", "dimension": 2, "doc": "plates",
         "params": [_param("l"), _param("l2")]},
        {"name": "enclosure", "dimension": 2, "doc": "n-gon",
         "params": [_param("n", low=3, high=100000, low_open=False, integer=True)]},
    ],
    "oracles": [{"name": "garmann", "dimensions": [2, 3], "parameters": ["eps"], "doc": "g"}],
    "methods": [], "options": [], "counters": [],
}


@pytest.fixture
def run_log(tmp_path, monkeypatch):
    """The file to which the fake engine appends every run."""
    log = tmp_path / "runs.log"
    monkeypatch.setenv("FAKE_HRBENCH_LOG", str(log))
    return log


def variant(tmp_path, data_dir, old, new):
    path = tmp_path / "claims.toml"
    text = (data_dir / "small_claims.toml").read_text()
    assert old in text
    path.write_text(text.replace(old, new))
    return path


def reproduce_once(tmp_path, claims, engine, capsys, *extra):
    code = main(["--claims", str(claims), "--hrbench", str(engine), "--results",
                 str(tmp_path / "results"), "--no-tiling", "--jobs", "2", *extra])
    out, err = capsys.readouterr()
    return code, out, err


def one_error_line(err):
    lines = [line for line in err.strip().splitlines() if not line.startswith("[")]
    assert len(lines) == 1, err
    assert lines[0].startswith("error: ") and "Traceback" not in err
    return lines[0]


# --- Claims files ------------------------------------------------------------------------


def test_non_utf8_claims_file_exits_2(tmp_path, fake_hrbench, capsys, run_log):
    claims = tmp_path / "claims.toml"
    claims.write_bytes(b'[source]\nkey = "\xff\xfe"\n')
    code, _, err = reproduce_once(tmp_path, claims, fake_hrbench, capsys)
    assert code == 2
    assert one_error_line(err) == (f"error: {claims}:2: not UTF-8 text: byte 0xff at column "
                                   "8 cannot be decoded; save the file as UTF-8")
    assert not run_log.exists()


@pytest.mark.parametrize("old, new, match", [
    ("per_decade = 5", "per_decade = 1000000000",
     ":13: claim 'T-elements': key 'sweep.range': 'per_decade' must be at most 1000"),
    ('x = "1/eps"', 'x = "' + "N+" * 5000 + 'N"',
     ":14: claim 'T-elements': key 'x': formula 'N+N+N+N+"),
    ('x = "1/eps"', 'x = "' + "(" * 300 + "N" + ")" * 300 + '"',
     ":14: claim 'T-elements': key 'x': cannot parse formula"),
])
def test_absurd_ranges_and_formulas_exit_2_before_any_run(tmp_path, data_dir, fake_hrbench,
                                                          capsys, run_log, old, new, match):
    claims = variant(tmp_path, data_dir, old, new)
    code, _, err = reproduce_once(tmp_path, claims, fake_hrbench, capsys)
    assert code == 2
    line = one_error_line(err)
    assert match in line and len(line) < 400
    assert not run_log.exists()


def test_formula_overflowing_float64_exits_2_quickly(tmp_path, data_dir, fake_hrbench, capsys):
    import time
    claims = variant(tmp_path, data_dir, 'x = "1/eps"', 'x = "N**N**N"')
    claims.write_text(claims.read_text().replace("per_decade = 5", "per_decade = 0.5"))
    start = time.perf_counter()
    code, _, err = reproduce_once(tmp_path, claims, fake_hrbench, capsys)
    assert code == 2 and time.perf_counter() - start < 30
    assert one_error_line(err) == (
        f"error: {claims}:14: claim 'T-elements': key 'x': formula 'N**N**N' overflows "
        "float64 (inf) for the run at eps=1; a formula must stay finite for counts (formulas "
        "are evaluated in float64)")


# --- Parameters against the engine's ranges ----------------------------------------------


def stand_in(scene="parallel", params=None, sweep_param="eps", ranges=None, grid=None):
    ranges = ranges or {"quick": SweepRange(1.0, 0.01, 5), "full": SweepRange(1.0, 0.01, 5)}
    return SimpleNamespace(
        scene=scene, params=params or {}, sweep_param=sweep_param, path="c.toml", id="X",
        grid=grid or {},
        range_for=lambda mode: ranges[mode],
        range_keys={"quick": "sweep.quick", "full": "sweep.full"},
        key_line=lambda key: {"params.l": 7, "params.n": 8, "sweep.quick": 9,
                              "sweep.full": 10}.get(key, 5))


@pytest.mark.parametrize("kwargs, errors", [
    ({"params": {"l": 8.0}}, []),
    ({"params": {"l": 0.0}},
     ["c.toml:7: claim 'X': key 'params.l': scene parameter l = 0 is out of range for scene "
      "'parallel': l > 0"]),
    ({"params": {"l": 8.0, "lenght": 3.0}},
     ["c.toml:5: claim 'X': key 'params.lenght': scene 'parallel' has no parameter 'lenght' "
      "(its parameters: l, l2)"]),
    ({"scene": "enclosure", "params": {"n": 2.5}},
     ["c.toml:8: claim 'X': key 'params.n': scene parameter n = 2.5 is out of range for "
      "scene 'enclosure': 3 <= n <= 100000, an integer"]),
    ({"scene": "enclosure", "params": {"n": 8.0}, "sweep_param": "n",
      "ranges": {"quick": SweepRange(4.0, 64.0, 2), "full": SweepRange(64.0, 1e6, 1)}},
     ["c.toml:9: claim 'X': key 'sweep.quick': the sweep gives scene parameter n 1 value(s) "
      "out of range for scene 'enclosure', first 12.649: 3 <= n <= 100000, an integer",
      "c.toml:10: claim 'X': key 'sweep.full': the sweep gives scene parameter n 2 value(s) "
      "out of range for scene 'enclosure', first 640000: 3 <= n <= 100000, an integer"]),
    ({"params": {"l": 8.0}, "grid": {"l2": (4.0, -2.0)}},
     ["c.toml:5: claim 'X': key 'sweep.grid': scene parameter l2 = -2 is out of range for "
      "scene 'parallel': l2 > 0"]),
    ({"params": {"l": 8.0}, "grid": {"w": (4.0,)}},
     ["c.toml:5: claim 'X': key 'sweep.grid': scene 'parallel' has no parameter 'w' "
      "(its parameters: l, l2)"]),
    ({"scene": "room", "params": {"q": -1.0}}, []),   # a family the engine lacks: skipped
])
def test_parameters_are_checked_against_the_declared_ranges(kwargs, errors):
    caps = parse_capabilities(json.dumps(CAPABILITIES))
    assert param_errors(stand_in(**kwargs), caps) == errors


@pytest.mark.parametrize("old, new, line", [
    ("params = { l = 8, d = 1 }", "params = { l = 8, d = -1 }",
     ":11: claim 'T-elements': key 'params.d': scene parameter d = -1 is out of range for "
     "scene 'parallel': d > 0"),
    ("params = { l = 8, d = 1 }", "params = { l = 8, d = 1, lenght = 3 }",
     ":11: claim 'T-elements': key 'params.lenght': scene 'parallel' has no parameter "
     "'lenght' (its parameters: l, d, offset, l2)"),
    ('sweep.param = "eps"\nsweep.range = { from = 1.0, to = 0.01, per_decade = 5 }',
     'eps = 0.5\nsweep.param = "l"\nsweep.range = { from = 8, to = 0.0, per_decade = 5 }',
     ":14: claim 'T-elements': key 'sweep.range.to' must be a positive number, got 0.0"),
])
def test_parameters_out_of_range_exit_2_before_any_run(tmp_path, data_dir, fake_hrbench,
                                                       capsys, run_log, old, new, line):
    claims = variant(tmp_path, data_dir, old, new)
    code, _, err = reproduce_once(tmp_path, claims, fake_hrbench, capsys)
    assert code == 2
    assert one_error_line(err) == f"error: {claims}{line}"
    assert not run_log.exists()


def test_runs_the_engine_refuses_exit_2_instead_of_inconclusive(tmp_path, data_dir,
                                                                fake_hrbench, capsys,
                                                                monkeypatch):
    monkeypatch.setenv("FAKE_HRBENCH_REFUSE_BELOW_EPS", "0.05")
    claims = data_dir / "small_claims.toml"
    code, out, err = reproduce_once(tmp_path, claims, fake_hrbench, capsys)
    assert code == 2 and "reproduced" not in out and "inconclusive" not in out
    assert one_error_line(err) == (
        f"error: {claims}:6: claim 'T-elements': the engine refused 4 of 11 runs (exit code "
        "2), first at eps=0.039811: hrbench: the patches touch at eps=0.039811; give "
        "--min-area or --max-depth (command: run parallel d=1 l=8 --eps 0.039811 --oracle "
        "garmann --count-only --json)")
    assert not (tmp_path / "results" / "claims.json").exists()


# --- The results cache -------------------------------------------------------------------


@pytest.mark.parametrize("content, match", [
    (b"garbage garbage\n", "is not a SQLite database (it starts with b'garbage '); remove it"),
    (None, "is not a results cache: it holds the table(s) users; remove it"),
])
def test_foreign_or_broken_cache_exits_2(tmp_path, data_dir, fake_hrbench, capsys, run_log,
                                         content, match):
    results = tmp_path / "results"
    results.mkdir()
    cache = results / "hrbench.sqlite"
    if content is None:
        with sqlite3.connect(cache) as con:
            con.execute("CREATE TABLE users (id INTEGER)")
    else:
        cache.write_bytes(content)
    code, _, err = reproduce_once(tmp_path, data_dir / "small_claims.toml", fake_hrbench,
                                  capsys)
    assert code == 2
    line = one_error_line(err)
    assert line.startswith(f"error: results cache {cache} ") and match in line
    assert not run_log.exists()


# --- Bugs and interrupts -----------------------------------------------------------------


def test_a_bug_exits_70_with_its_traceback_never_1(tmp_path, data_dir, fake_hrbench, capsys,
                                                   monkeypatch):
    def broken(*args, **kwargs):
        raise ZeroDivisionError("a bug")
    monkeypatch.setattr(reproduce, "expand_claim", broken)
    code, _, err = reproduce_once(tmp_path, data_dir / "small_claims.toml", fake_hrbench,
                                  capsys)
    assert code == reproduce.INTERNAL_ERROR == 70
    assert "Traceback" in err and "ZeroDivisionError: a bug" in err
    assert err.strip().splitlines()[-1].startswith("internal error of the analysis (a bug")


def test_interrupt_exits_130(tmp_path, data_dir, fake_hrbench, capsys, monkeypatch):
    def interrupted(*args, **kwargs):
        raise KeyboardInterrupt
    monkeypatch.setattr(reproduce, "load_claims", interrupted)
    code, _, err = reproduce_once(tmp_path, data_dir / "small_claims.toml", fake_hrbench,
                                  capsys)
    assert code == 130 and "interrupted" in err and "Traceback" not in err


def test_exit_codes_are_listed():
    assert reproduce.EXIT_CODES == {
        0: "every claim came out as expected",
        1: "a claim expected to hold was refuted",
        2: "bad input or environment",
        70: "internal error of the analysis (a bug)",
        130: "interrupted",
    }


def test_an_engine_that_cannot_be_started_is_an_environment_error():
    import numpy as np

    from hrbench_analysis.sweep import ClaimData
    claim = SimpleNamespace(path="c.toml", line=6, id="T", sweep_param="eps")
    data = ClaimData(value=np.zeros(0), x=np.zeros(0), y=np.zeros(0), failures=[
        {"value": 0.5, "exit_code": 127, "stderr": "cannot run build/hrbench: [Errno 2] No "
         "such file or directory", "command": "run parallel --eps 0.5"},
        {"value": 0.25, "exit_code": 3, "stderr": "limit", "command": "run"}])
    assert reproduce.engine_refusals(claim, data) == (
        "c.toml:6: claim 'T': could not start the engine for 1 of 2 runs (exit code 127), "
        "first at eps=0.5: cannot run build/hrbench: [Errno 2] No such file or directory "
        "(command: run parallel --eps 0.5)")
    data.failures.pop(0)
    assert reproduce.engine_refusals(claim, data) is None      # a limit is a failed point
