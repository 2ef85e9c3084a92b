"""The run record's JSON Schema (schemas/run-record.schema.json) against real records,
broken records and the analysis's own reader, and how the analysis finds its engine."""

import copy
import json
import os
import stat
import subprocess
import sys
from pathlib import Path

import jsonschema
import pytest

from hrbench_analysis.engine import EngineError, engine_argv, engine_text, find_engine
from hrbench_analysis.loader import ResultFormatError, parse_run_json
from hrbench_analysis.reproduce import ENGINE_ENV, default_engine, main

ROOT = Path(__file__).resolve().parents[2]
HRBENCH = ROOT / "build" / "hrbench"
EXTERNAL = ROOT / "examples" / "external_engine" / "engine.py"
SCHEMA = json.loads((ROOT / "schemas" / "run-record.schema.json").read_text())
needs_engine = pytest.mark.skipif(not HRBENCH.exists(), reason="build/hrbench not built")


def validator():
    jsonschema.Draft202012Validator.check_schema(SCHEMA)
    return jsonschema.Draft202012Validator(SCHEMA)


def hrbench_record(*args):
    out = subprocess.run([str(HRBENCH), "run", *args, "--json"], capture_output=True,
                         text=True, check=True, cwd=ROOT).stdout
    return json.loads(out)


# docs/conventions.md, worked example, as a minimal record: every required field.
MINIMAL = {"schema_version": 1, "version": "0.1", "scene": "parallel",
           "params": {"l": 1, "d": 1}, "eps": 0.5, "oracle": "garmann", "nodes": 6,
           "leaves": 4, "links": 4, "oracle_calls": 7, "max_depth": 1}


def test_the_schema_is_valid_and_requires_what_the_reader_requires():
    v = validator()
    assert v.is_valid(MINIMAL)
    parse_run_json(json.dumps(MINIMAL))
    assert set(SCHEMA["required"]) == set(MINIMAL)
    for key in SCHEMA["required"]:
        assert key in SCHEMA["properties"], key


@needs_engine
@pytest.mark.parametrize("args", [
    ["parallel", "l=8", "d=1", "--eps", "0.3"],                       # 2D, store
    ["parallel", "l=64", "d=1", "--eps", "0.01", "--count-only"],     # 2D, count-only
    ["parallel", "l=64", "d=1", "--eps", "0.01", "--method", "translation", "--count-only"],
    ["parallel3d", "l=1", "w=1", "d=1", "--eps", "0.5", "--count-only"],
    ["cornell", "--eps", "0.5", "--oracle", "hanrahan", "--min-area", "0.05",
     "--visibility", "fraction", "--rays-per-side", "2", "--count-only"],
    ["room", "w=2", "h=1", "--eps", "0.1", "--max-depth", "3", "--subdivision", "binary"],
    ["--mesh", "tests/data/two_plates.obj", "--eps", "0.5", "--count-only"],
    ["--scene-file", "tests/data/parallel_l64_d1.json", "--eps", "0.5"],
    ["parallel", "l=4", "d=1", "--eps", "0.05", "--oracle", "hanrahan", "--link-form-factors"],
])
def test_hrbench_records_validate_and_every_field_is_declared(args):
    record = hrbench_record(*args)
    errors = [e.message for e in validator().iter_errors(record)]
    assert errors == []
    # The schema stays open for other engines, but hrbench's own fields are all in it.
    assert set(record) <= set(SCHEMA["properties"]), set(record) - set(SCHEMA["properties"])
    parse_run_json(json.dumps(record))


@pytest.mark.parametrize("args", [
    ["parallel", "l=8", "d=1", "--eps", "0.1", "--count-only"],
    ["parallel", "l=3", "d=0.5", "offset=1", "l2=2", "--eps", "0.2", "--min-area", "0.05"],
])
def test_the_external_engines_records_validate(args):
    out = subprocess.run([sys.executable, str(EXTERNAL), "run", *args, "--json"],
                         capture_output=True, text=True, check=True).stdout
    record = json.loads(out)
    assert [e.message for e in validator().iter_errors(record)] == []
    assert set(record) <= set(SCHEMA["properties"])
    parse_run_json(out)


def _without(key):
    def change(r):
        del r[key]
    return change


def _setting(key, value):
    def change(r):
        r[key] = value
    return change


def _param(value):
    def change(r):
        r["params"]["l"] = value
    return change


# Broken records: each fails the schema, and the reader refuses it naming the field.
BROKEN = [(_without(key), key) for key in sorted(MINIMAL)] + [
    (_setting("schema_version", 2), "schema_version"),
    (_setting("version", 3), "version"),
    (_setting("scene", None), "scene"),
    (_setting("oracle", ["garmann"]), "oracle"),
    (_setting("params", "l=1"), "params"),
    (_param("1"), "params.l"),
    (_param(True), "params.l"),
    (_setting("eps", "0.5"), "eps"),
    (_setting("eps", 0), "eps"),
    (_setting("eps", -0.5), "eps"),
    (_setting("links", 4.5), "links"),
    (_setting("links", -4), "links"),
    (_setting("nodes", "6"), "nodes"),
    (_setting("max_depth", True), "max_depth"),
    (_setting("mode", 1), "mode"),
    (_setting("min_area", "0.1"), "min_area"),
    (_setting("max_depth_limit", 2.5), "max_depth_limit"),
    (_setting("nodes_per_depth", [2, -4]), "nodes_per_depth"),
    (_setting("links_per_depth", "0,0,4"), "links_per_depth"),
    (_setting("seconds", "fast"), "seconds"),
]


@pytest.mark.parametrize("change, field", BROKEN,
                         ids=[f"{field}-{n}" for n, (_, field) in enumerate(BROKEN)])
def test_broken_records_fail_the_schema_and_the_reader_names_the_field(change, field):
    record = copy.deepcopy(MINIMAL)
    change(record)
    assert not validator().is_valid(record)
    with pytest.raises(ResultFormatError) as err:
        parse_run_json(json.dumps(record))
    assert f"'{field}'" in str(err.value) or f"'{field.split('.')[-1]}'" in str(err.value)
    assert "\n" not in str(err.value)


def test_counts_must_be_json_integers():
    # JSON Schema counts 4.0 as an integer; the reader wants the integer the engine
    # counted, written as one (docs/engine-contract.md).
    record = dict(MINIMAL, links=4.0)
    assert validator().is_valid(record)
    with pytest.raises(ResultFormatError, match="counter 'links' must be an integer, got 4.0"):
        parse_run_json(json.dumps(record))


def test_optional_fields_may_be_null_or_missing():
    record = dict(MINIMAL, min_area=None, max_depth_limit=None, nodes_per_depth=None,
                  mode="count-only", seconds=0.5, extra_counter=3)
    assert validator().is_valid(record)
    result = parse_run_json(json.dumps(record))
    assert result.min_area is None and result.nodes_per_depth == []
    assert result.counters["extra_counter"] == 3 and result.counters["seconds"] == 0.5


# --- A run record that breaks the contract ends the analysis with one line ----------------

BREAKER = """\
import json, subprocess, sys
out = subprocess.run([sys.executable, {engine!r}, *sys.argv[1:]], capture_output=True,
                     text=True)
if sys.argv[1:2] == ["run"] and out.returncode == 0:
    record = json.loads(out.stdout)
    {change}
    print(json.dumps(record))
else:
    sys.stdout.write(out.stdout)
    sys.stderr.write(out.stderr)
sys.exit(out.returncode)
"""


@pytest.mark.parametrize("change, message", [
    ("del record['oracle_calls']", "required counter 'oracle_calls' is missing"),
    ("record['scene'] = 7", "field 'scene' must be a string, got 7"),
    ("record['params']['d'] = 'one'", "field 'params.d' must be a number"),
])
def test_an_engine_that_breaks_the_record_is_an_error_naming_the_field(
        tmp_path, data_dir, capsys, change, message):
    script = tmp_path / "breaker.py"
    script.write_text(BREAKER.format(engine=str(EXTERNAL), change=change))
    code = main(["--claims", str(data_dir / "small_claims.toml"), "--engine",
                 f"{sys.executable} {script}", "--results", str(tmp_path / "r"),
                 "--no-tiling", "--jobs", "2"])
    err = capsys.readouterr().err
    assert code == 2
    lines = [line for line in err.splitlines() if line.startswith("error:")]
    assert len(lines) == 1 and message in lines[0], err
    assert "breaks the engine contract" in lines[0] and "T-elements" in lines[0]


# --- Finding the engine -------------------------------------------------------------------


def test_engine_commands_are_words_and_paths_are_never_split(tmp_path):
    spaced = tmp_path / "my engine"
    assert engine_argv(spaced) == [str(spaced)]
    assert engine_argv(("python3", "e.py")) == ["python3", "e.py"]
    assert engine_text(("python3", "my e.py")) == "python3 'my e.py'"
    assert find_engine(("python3", "anything")) == ["python3", "anything"]
    with pytest.raises(EngineError, match="not found or not executable: no-such-program-x"):
        find_engine(("no-such-program-x", "--flag"))
    with pytest.raises(EngineError, match="not found or not executable"):
        find_engine(spaced)


def _executable(path):
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text("#!/bin/sh\necho fake 1\n")
    path.chmod(path.stat().st_mode | stat.S_IXUSR)
    return path


def test_default_engine_order(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    monkeypatch.setenv("PATH", str(tmp_path / "bin"))
    monkeypatch.delenv(ENGINE_ENV, raising=False)
    with pytest.raises(EngineError, match="no engine: pass --engine CMD, set"):
        default_engine()
    on_path = _executable(tmp_path / "bin" / "hrbench")
    assert default_engine() == on_path
    _executable(tmp_path / "build" / "hrbench")
    assert default_engine() == Path("build") / "hrbench"
    monkeypatch.setenv(ENGINE_ENV, "python3 'my engine.py' --x")
    assert default_engine() == ("python3", "my engine.py", "--x")
    monkeypatch.setenv(ENGINE_ENV, "'unbalanced")
    with pytest.raises(EngineError, match=f"\\${ENGINE_ENV}: cannot split"):
        default_engine()


def test_no_engine_is_one_line_and_exit_code_2(tmp_path, data_dir):
    env = {k: v for k, v in os.environ.items() if k != ENGINE_ENV}
    env["PATH"] = str(tmp_path)  # no hrbench on it
    proc = subprocess.run([sys.executable, "-m", "hrbench_analysis.reproduce", "--claims",
                           str(data_dir / "small_claims.toml")],
                          capture_output=True, text=True, cwd=tmp_path, env=env)
    assert proc.returncode == 2
    assert proc.stderr.strip().splitlines() == [
        f"error: no engine: pass --engine CMD, set ${ENGINE_ENV}, run from a directory that "
        "holds build/hrbench, or put hrbench on the PATH"]
    assert not (tmp_path / "results").exists()


@pytest.mark.parametrize("command", ["hrbench-reproduce", "hrbench-sweep", "hrbench-compare",
                                     "hrbench-history"])
def test_console_scripts_run_from_any_directory(command):
    script = Path(sys.executable).parent / command
    if not script.exists():
        pytest.skip(f"{command} not installed in this environment (pip install -e .)")
    proc = subprocess.run([str(script), "--help"], capture_output=True, text=True, cwd="/")
    assert proc.returncode == 0, proc.stderr
    assert proc.stdout.startswith(f"usage: {command}")
