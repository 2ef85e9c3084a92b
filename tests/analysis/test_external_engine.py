"""The minimal external engine (examples/external_engine/engine.py, pure Python): its
counts follow docs/conventions.md, equal hrbench's, and the analysis judges claims on it
through the engine contract alone (``--engine CMD``)."""

import csv
import io
import json
import subprocess
import sys
from pathlib import Path

import pytest

from hrbench_analysis.engine import parse_capabilities
from hrbench_analysis.reproduce import main, sweep_main

ROOT = Path(__file__).resolve().parents[2]
HRBENCH = ROOT / "build" / "hrbench"
ENGINE_DIR = ROOT / "examples" / "external_engine"
# The command exactly as the documentation gives it, run from the repository root.
ENGINE = "python3 examples/external_engine/engine.py"
needs_hrbench = pytest.mark.skipif(not HRBENCH.exists(), reason="build/hrbench not built")

COUNTERS = ("nodes", "leaves", "links", "oracle_calls", "max_depth", "forced_links",
            "culled_pairs", "root_pairs", "nodes_per_depth", "links_per_depth")


def external(*args, check=True):
    proc = subprocess.run([sys.executable, str(ENGINE_DIR / "engine.py"), *args],
                          capture_output=True, text=True)
    if check:
        assert proc.returncode == 0, proc.stderr
    return proc


def counts(record):
    return {k: record[k] for k in COUNTERS}


def test_worked_example_by_hand():
    # docs/conventions.md: parallel l=1 d=1, eps 0.5; two links accepted with equality.
    record = json.loads(external("run", "parallel", "l=1", "d=1", "--eps", "0.5",
                                 "--json").stdout)
    assert counts(record) == {"nodes": 6, "leaves": 4, "links": 4, "oracle_calls": 7,
                              "max_depth": 1, "forced_links": 0, "culled_pairs": 0,
                              "root_pairs": 1, "nodes_per_depth": [2, 4],
                              "links_per_depth": [0, 0, 4]}
    assert record["params"] == {"l": 1.0, "d": 1.0, "offset": 0.0, "l2": 1.0}


def test_worked_example_at_scale():
    record = json.loads(external("run", "parallel", "l=64", "d=1", "--eps", "0.25",
                                 "--count-only", "--json").stdout)
    assert (record["nodes"], record["leaves"], record["links"], record["oracle_calls"],
            record["max_depth"]) == (1022, 512, 5092, 10183, 8)
    assert record["links_per_depth"] == [0, 0, 0, 0, 0, 0, 20, 0, 76, 0, 188, 0, 412, 0,
                                         860, 0, 3536]


def test_recursion_limits_force_links():
    # --max-depth 0: the roots are the only elements; the one call links by force.
    record = json.loads(external("run", "parallel", "l=4", "d=1", "--eps", "0.1",
                                 "--max-depth", "0", "--json").stdout)
    assert (record["links"], record["forced_links"], record["oracle_calls"],
            record["nodes"]) == (1, 1, 1, 2)
    # --min-area 1 on l=2: the halves (length 1) are not shorter than 1 and split again
    # where rejected; the quarters (0.5) are, so no element is shorter than 0.5.
    record = json.loads(external("run", "parallel", "l=2", "d=0.1", "--eps", "0.01",
                                 "--min-area", "1", "--json").stdout)
    assert record["max_depth"] == 2 and record["forced_links"] > 0
    assert record["oracle_calls"] == 2 * record["links"] - 1


@needs_hrbench
@pytest.mark.parametrize("args", [
    ["l=8", "d=1", "--eps", "0.02"],
    ["l=8", "d=1", "offset=2.5", "l2=3", "--eps", "0.1"],
    ["l=1.9", "d=0.3", "--eps", "0.05", "--min-area", "0.01"],
    ["l=5", "d=1", "--eps", "0.05", "--max-depth", "6"],
    ["l=0.7", "d=0.013", "offset=-0.2", "--eps", "0.3"],
])
def test_counts_equal_hrbench(args):
    mine = json.loads(external("run", "parallel", *args, "--count-only", "--json").stdout)
    ref = json.loads(subprocess.run([str(HRBENCH), "run", "parallel", *args, "--count-only",
                                     "--json"], capture_output=True, text=True,
                                    check=True).stdout)
    assert counts(mine) == counts(ref)
    assert mine["params"] == ref["params"]


def test_command_line_of_the_contract():
    assert external("--version").stdout.splitlines()[0] == "pyflat 0.1.0"
    assert external("--help").stdout.startswith("usage:")
    assert "parallel (2D)" in external("scenes").stdout
    caps = parse_capabilities(external("capabilities", "--json").stdout, engine="pyflat")
    assert caps.family_names == ("parallel",) and caps.oracle_names == ("garmann",)
    assert caps.family("parallel").param_names == ("l", "d", "offset", "l2")
    assert {"nodes", "leaves", "links", "oracle_calls", "max_depth"} <= set(
        caps.scalar_counters)


@pytest.mark.parametrize("args, message", [
    (["run", "parallel", "l=1", "d=1"], "--eps is required"),
    (["run", "parallel", "d=0", "--eps", "0.5"], "parameter d = 0 is out of range: d > 0"),
    (["run", "parallel", "w=1", "--eps", "0.5"], "has no parameter 'w'"),
    (["run", "parallel", "--eps", "0"], "--eps must be > 0"),
    (["run", "parallel", "--eps", "nan"], "not a finite number"),
    (["run", "parallel", "--eps", "0.5", "--eps", "0.4"], "given twice"),
    (["run", "parallel", "--eps", "0.5", "--oracle", "hanrahan"], "unknown oracle"),
    (["run", "room", "--eps", "0.5"], "the only scene is 'parallel'"),
    (["links", "parallel"], "unknown command"),
    ([], "missing command"),
])
def test_input_errors_are_one_line_and_exit_code_2(args, message):
    proc = external(*args, check=False)
    assert proc.returncode == 2 and proc.stdout == ""
    lines = proc.stderr.splitlines()
    assert len(lines) == 1 and message in lines[0], proc.stderr


def test_the_analysis_judges_claims_on_the_external_engine(tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(ROOT)
    results = tmp_path / "results"
    code = main(["--engine", ENGINE, "--claims", str(ENGINE_DIR / "claims.toml"),
                 "--results", str(results), "--jobs", "2"])
    out, err = capsys.readouterr()
    assert code == 0, err
    claims = json.loads((results / "claims.json").read_text())
    verdicts = {c["id"]: c["verdict"] for c in claims["claims"]}
    assert verdicts == {"C1-flat8": "reproduced", "C2-flat8": "reproduced"}
    assert "no link tiling: engine lacks the command 'links'" in err
    assert "C1-flat8" in out and "pyflat 0.1.0" in (results / "report.md").read_text()

    # hrbench-sweep reads the same points back from the cache (nothing runs again) and
    # writes them as CSV; x and y are those of the engine's own counts.
    code = sweep_main(["--engine", ENGINE, "--claims", str(ENGINE_DIR / "claims.toml"),
                       "--results", str(results), "--claim", "C2-flat8"])
    out, err = capsys.readouterr()
    assert code == 0, err
    assert "11 points (11 cached, 0 run, 0 failed)" in err
    rows = list(csv.DictReader(io.StringIO(out)))
    assert len(rows) == 11 and {r["claim"] for r in rows} == {"C2-flat8"}
    assert all(r["status"] == "ok" and r["param"] == "eps" for r in rows)
    first = next(r for r in rows if r["value"] == "1")
    record = json.loads(external("run", "parallel", "l=8", "d=1", "--eps", "1",
                                 "--json").stdout)
    assert float(first["y"]) == record["links"] / record["nodes"] and float(first["x"]) == 1


@needs_hrbench
def test_the_sweep_points_equal_hrbenchs(tmp_path, monkeypatch, capsys):
    # The same claim swept on both engines gives the same x and y at every point.
    monkeypatch.chdir(ROOT)
    tables = {}
    for name, engine in (("external", ["--engine", ENGINE]),
                         ("hrbench", ["--hrbench", str(HRBENCH)])):
        assert sweep_main([*engine, "--claims", str(ENGINE_DIR / "claims.toml"),
                           "--results", str(tmp_path / name), "--claim", "C1-flat8"]) == 0
        rows = csv.DictReader(io.StringIO(capsys.readouterr().out))
        tables[name] = [(r["value"], r["x"], r["y"], r["status"]) for r in rows]
    assert tables["external"] == tables["hrbench"] and len(tables["hrbench"]) == 11
