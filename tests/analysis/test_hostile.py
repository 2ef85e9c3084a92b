"""Hostile input: every class ends with its documented exit code and one line on stderr.

0 as expected, 1 refuted although expected to hold, 2 bad input or environment, 70 a bug
of the analysis, 130 interrupted (see docs/analysis.md, "Exit codes").
"""

import json
import sqlite3
from types import SimpleNamespace

import pytest

from hrbench_analysis import reproduce
from hrbench_analysis.claimfile import SweepRange, param_errors
from hrbench_analysis.engine import parse_capabilities
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
    # The stages' progress lines may come first; the error is one line, the last.
    lines = [line for line in err.strip().splitlines() if not line.startswith("[")]
    errors = [line for line in lines if line.startswith("error: ")]
    assert len(errors) == 1 and lines[-1] == errors[0], err
    assert "Traceback" not in err
    return errors[0]


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


def test_a_bug_exits_70_with_one_line_never_1(tmp_path, data_dir, fake_hrbench, capsys,
                                              monkeypatch):
    def broken(*args, **kwargs):
        raise ZeroDivisionError("a bug")
    monkeypatch.setattr(reproduce, "expand_claim", broken)
    code, _, err = reproduce_once(tmp_path, data_dir / "small_claims.toml", fake_hrbench,
                                  capsys)
    assert code == reproduce.INTERNAL_ERROR == 70
    lines = [line for line in err.strip().splitlines() if not line.startswith("[")]
    assert len(lines) == 1 and "Traceback" not in err
    assert lines[0].startswith("hrbench-reproduce: internal error, a bug: ZeroDivisionError: a bug")
    code, _, err = reproduce_once(tmp_path, data_dir / "small_claims.toml", fake_hrbench,
                                  capsys, "--debug")
    assert code == 70 and "Traceback" in err and "ZeroDivisionError: a bug" in err


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
        74: "an output could not be written (the previous one is kept)",
        130: "interrupted",
        143: "terminated",
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


# --- Files that are no files: meshes, FIFOs, devices, sparse giants ----------------------

MESH_CLAIM = '''[source]
key = "test"

[[claim]]
id = "M1"
statement = "N = Theta(eps^-1)"
scene = "mesh"
mesh = "MESH"
params = {}
sweep.param = "eps"
sweep.range = { from = 0.5, to = 0.0005, per_decade = 6 }
x = "1/eps"
y = "N"
expected_exponent = 1
tolerance = 0.2
'''


@pytest.mark.parametrize("kind, match", [
    ("device", "the mesh file is a character device, not a regular file (/dev/zero)"),
    ("FIFO", "the mesh file is a FIFO (named pipe), not a regular file"),
    ("sparse", "the mesh file has 3221225472 bytes; at most 268435456 are allowed"),
    ("NUL", r"key 'mesh' holds a NUL byte: 'a\x00b.obj'"),
])
def test_a_mesh_that_is_no_file_exits_2_within_seconds(tmp_path, fake_hrbench, capsys, run_log,
                                                       kind, match):
    import os
    import time
    if kind == "device":
        name = "/dev/zero"
    elif kind == "FIFO":
        name = "fifo.obj"
        os.mkfifo(tmp_path / name)
    elif kind == "sparse":
        name = "giant.obj"
        with open(tmp_path / name, "wb") as f:
            f.truncate(3 << 30)       # 3 GiB without disk blocks: refused by its size
    else:
        name = "a\\u0000b.obj"        # TOML's escape: a NUL in the path
    claims = tmp_path / "claims.toml"
    claims.write_text(MESH_CLAIM.replace("MESH", name))
    start = time.perf_counter()
    code, _, err = reproduce_once(tmp_path, claims, fake_hrbench, capsys)
    assert code == 2 and time.perf_counter() - start < 10
    line = one_error_line(err)
    assert line.startswith(f"error: {claims}:8: claim 'M1': ") and match in line
    assert not run_log.exists()


def test_a_claims_file_that_is_a_fifo_exits_2_at_once(tmp_path, fake_hrbench, capsys, run_log):
    import os
    fifo = tmp_path / "claims.toml"
    os.mkfifo(fifo)
    code, _, err = reproduce_once(tmp_path, fifo, fake_hrbench, capsys)
    assert code == 2
    assert one_error_line(err) == (f"error: {fifo}: the claims file is a FIFO (named pipe), "
                                   "not a regular file")


# --- Numbers out of range, misspelt keys, sweeps too large to plan ------------------------


@pytest.mark.parametrize("old, new, match", [
    ("min_decades = 1.5", "min_decades = 1.5\nmax_depth = 9223372036854775808",
     ":23: claim 'T-elements': key 'max_depth' must be an integer from 1 to 1024, got "
     "9223372036854775808"),
    ("tolerance = 0.15", "tolerance = 5e307",
     ":19: claim 'T-elements': key 'tolerance' must be at most 100, got 5e+307"),
    ('citation = "hrbench test data"', 'citaton = "hrbench test data"',
     ":4: unknown key 'source.citaton'; allowed: citation, key"),
    ('key = "test"', "key = 5", ":3: key 'source.key' must be a non-empty string, got 5"),
])
def test_numbers_out_of_range_and_misspelt_keys_exit_2(tmp_path, data_dir, fake_hrbench,
                                                       capsys, run_log, old, new, match):
    claims = variant(tmp_path, data_dir, old, new)
    code, _, err = reproduce_once(tmp_path, claims, fake_hrbench, capsys)
    assert code == 2
    assert match in one_error_line(err)
    assert not run_log.exists()


def _claim(i, sweep):
    return (f'[[claim]]\nid = "M{i}"\nstatement = "s"\nscene = "parallel"\n'
            f'params = {{ l = 8 }}\nsweep = {{ {sweep} }}\nx = "1/eps"\ny = "N"\n'
            "expected_exponent = 1\ntolerance = 0.1\n")


# 10,000 points: 9.999 decades at 1000 per decade.
_RANGE = 'param = "eps", range = { from = 1e-5, to = 99770, per_decade = 1000 }'
_GRID = ", ".join(str(v) for v in range(1, 33))


@pytest.mark.parametrize("claims, match", [
    # The largest grid (2 parameters of 32 values) on a 10,000-point range.
    ([_claim(0, f"{_RANGE}, grid = {{ d = [{_GRID}], offset = [{_GRID}] }}")],
     "the claims plan 10240000 points in all (ranges times grids; claim 'M0' alone "
     "10240000); at most 100000 are allowed in one sweep"),
    # 2,500 claims of 10,000 points in one file (within the 1 MiB of a claims file).
    ([_claim(i, _RANGE.replace("d = 1", "")) for i in range(2500)],
     "the claims plan 25000000 points in all (ranges times grids; claim 'M0' alone 10000)"),
])
def test_a_sweep_too_large_to_plan_exits_2_before_any_run(tmp_path, fake_hrbench, capsys,
                                                          run_log, claims, match):
    import time
    path = tmp_path / "claims.toml"
    path.write_text('[source]\nkey = "big"\n\n' + "\n".join(claims))
    start = time.perf_counter()
    code, _, err = reproduce_once(tmp_path, path, fake_hrbench, capsys)
    assert code == 2 and time.perf_counter() - start < 30
    assert one_error_line(err).startswith(f"error: {path}:4: claim 'M0': {match}")
    assert not run_log.exists()


def test_the_shipped_claims_are_well_within_the_sweep_bound():
    from hrbench_analysis.claimfile import MAX_SWEEP_POINTS, load_claims_dir, sweep_points
    from hrbench_analysis.reproduce_options import CLAIMS_DIR
    claims = load_claims_dir(CLAIMS_DIR)
    total = sum(sweep_points(c) for c in claims)
    assert 1000 < total < MAX_SWEEP_POINTS / 10
    for c in claims:   # the bound counts every value a range can give
        assert sweep_points(c) >= max(len(r.values()) for r in c.ranges.values())


# --- Engine output: records, link lists, the cache ----------------------------------------


@pytest.mark.parametrize("text, match", [
    ('{"schema_version": 1, "links": 5, "links": 7}', "key 'links' is given twice"),
    ('{"schema_version": 1, "eps": NaN}', "NaN is not a JSON number"),
    ('{"schema_version": 1, "eps": -Infinity}', "-Infinity is not a JSON number"),
    ('{"schema_version": 1, "pad": "' + "x" * (16 << 20) + '"}', "a run record has at most"),
])
def test_run_records_with_duplicate_keys_nan_or_giant_size_are_refused(text, match):
    from hrbench_analysis.loader import ResultFormatError, parse_run_json
    with pytest.raises(ResultFormatError, match=match):
        parse_run_json(text)


_LINKS = "root_i,elem_i,t0_i,t1_i,depth_i,root_j,elem_j,t0_j,t1_j,depth_j\n"


@pytest.mark.parametrize("row, match", [
    ("0,1,0,nan,1,1,1,0,1,1", "column t1_i must be a finite number, got 'nan'"),
    ("0,1,0,1,1,1,1,0,inf,1", "column t1_j must be a finite number, got 'inf'"),
    ("0,1,0,1,x,1,1,0,1,1", "column depth_i must be an integer >= 0, got 'x'"),
    ("-1,1,0,1,1,1,1,0,1,1", "column root_i must be an integer >= 0, got '-1'"),
    ("0,1,0,1,1.5,1,1,0,1,1", "column depth_i must be an integer >= 0"),
    ("0,1,2,1,1,1,1,0,1,1", "link list has t0_i 2.0 > t1_i 1.0"),
    ("0,1,0,1", "column depth_i must be an integer >= 0, got ''"),
])
def test_garbage_in_a_link_list_is_a_format_error_naming_line_and_column(tmp_path, row, match):
    from hrbench_analysis.loader import ResultFormatError, read_links_csv
    path = tmp_path / "links.csv"
    path.write_text(_LINKS + "0,1,0,1,1,1,1,0,1,1\n" + row + "\n")
    with pytest.raises(ResultFormatError, match=f"{path}:3: .*{match}"):
        read_links_csv(path)


@pytest.mark.parametrize("row", ["0,1,0,nan,1,1,1,0,1,1", "0,1,0,1,1,1,1,0,-inf,1",
                                 "0.5,1,0,1,1,1,1,0,1,1", "0,1,1,0.5,1,1,1,0,1,1"])
def test_nan_in_an_engines_link_list_fails_the_point_never_the_claim(tmp_path, row):
    # read_link_dump feeds the lemma statistics: a NaN there made every bound look broken
    # and turned a lemma claim "refuted".
    from hrbench_analysis.lemmas import LinkDumpError, read_link_dump
    path = tmp_path / "links.csv"
    path.write_text(_LINKS + "0,1,0,1,1,1,1,0,1,1\n" + row + "\n")
    # The loader's reader (the one reader of link lists) names the line.
    with pytest.raises(LinkDumpError, match=f"{path}:3: link list "):
        read_link_dump(path)


def test_a_clean_link_list_still_reads(tmp_path):
    from hrbench_analysis.lemmas import read_link_dump
    from hrbench_analysis.loader import read_links_csv
    path = tmp_path / "links.csv"
    path.write_text(_LINKS + "0,1,0,0.5,1,1,1,0,1,0\n1,2,0.5,1,1,0,1,0,1,0\n")
    table = read_links_csv(path)
    assert list(table.root_i) == [0, 1] and list(table.t1_i) == [0.5, 1.0]
    assert list(table.depth_i + table.depth_j) == [1, 1]
    assert list(read_link_dump(path)["t0_i"]) == [0.0, 0.5]


@pytest.mark.parametrize("column, value", [("wall_seconds", "'slow'"),
                                           ("output", "x'00'"), ("exit_code", "'three'"),
                                           ("finished_at", "'yesterday'")])
def test_a_wrong_typed_cell_in_the_cache_is_one_line(tmp_path, data_dir, fake_hrbench, capsys,
                                                     column, value):
    claims = data_dir / "small_claims.toml"
    assert reproduce_once(tmp_path, claims, fake_hrbench, capsys)[0] == 0
    cache = tmp_path / "results" / "hrbench.sqlite"
    with sqlite3.connect(cache) as con:
        con.execute(f"UPDATE points SET {column} = {value} WHERE rowid = "
                    "(SELECT MIN(rowid) FROM points)")
    code, _, err = reproduce_once(tmp_path, claims, fake_hrbench, capsys)
    assert code == 2
    line = one_error_line(err)
    assert line.startswith(f"error: results cache {cache} holds a cell of the wrong type: "
                           f"column {column} of point ")


# --- The shared guards --------------------------------------------------------------------


def test_read_bounded_checks_before_reading(tmp_path):
    import os

    from hrbench_analysis.errors import InputFileError, read_bounded
    path = tmp_path / "f"
    path.write_bytes(b"12345")
    assert read_bounded(path, 5) == b"12345"
    with pytest.raises(InputFileError, match="has 5 bytes; at most 4 are allowed"):
        read_bounded(path, 4)
    os.mkfifo(tmp_path / "p")
    with pytest.raises(InputFileError, match="FIFO"):
        read_bounded(tmp_path / "p", 10)    # returns at once: the FIFO is never waited on
    with pytest.raises(InputFileError, match="NUL byte"):
        read_bounded("a\0b", 10)
    with pytest.raises(InputFileError, match="No such file"):
        read_bounded(tmp_path / "missing", 10)


@pytest.mark.parametrize("text, match", [
    ('{"a": 1, "a": 2}', "key 'a' is given twice"), ("[NaN]", "NaN is not a JSON number"),
    ('{"a": {"b": 1, "b": 1}}', "key 'b' is given twice"), ("[" * 100000, "nested too deeply"),
    ("1" * 5000, "is not valid JSON"), (b"\xff", "not UTF-8"),
])
def test_parse_json_is_strict(text, match):
    from hrbench_analysis.errors import InputFileError, parse_json
    with pytest.raises(InputFileError, match=match):
        parse_json(text, "the text")
    assert parse_json('{"a": [1, 2.5, null]}') == {"a": [1, 2.5, None]}
