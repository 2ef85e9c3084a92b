"""The engine wrapper of the C kernel (examples/c_kernel/engine.py): its capabilities are
what the analysis reads, and its run records, from the kernel built at build/c_kernel,
validate against the run record's schema with the counts of the worked example."""

import json
import subprocess
import sys
from pathlib import Path

import jsonschema
import pytest

from hrbench_analysis.engine import parse_capabilities
from hrbench_analysis.loader import parse_run_json

ROOT = Path(__file__).resolve().parents[2]
KERNEL = ROOT / "build" / "c_kernel"
WRAPPER = ROOT / "examples" / "c_kernel" / "engine.py"
SCHEMA = json.loads((ROOT / "schemas" / "run-record.schema.json").read_text())
needs_kernel = pytest.mark.skipif(not KERNEL.exists(), reason="build/c_kernel not built")


def wrapper(*args):
    return subprocess.run([sys.executable, str(WRAPPER), str(KERNEL), *args],
                          capture_output=True, text=True)


def test_capabilities_are_what_the_analysis_reads():
    proc = wrapper("capabilities", "--json")
    assert proc.returncode == 0, proc.stderr
    caps = parse_capabilities(proc.stdout, "c_kernel")
    assert caps.engine == "c_kernel"
    assert [f["name"] for f in json.loads(proc.stdout)["families"]] == ["parallel"]
    assert wrapper("--version").stdout == "c_kernel 0.1.0\n"


@needs_kernel
def test_the_worked_example_as_a_run_record():
    # docs/probe-c.md: l=1 d=1 eps 0.5, both directions: 8 links at the end, 2 removed by
    # pass 2; 2 calls in pass 1 and 14 in pass 2.
    proc = wrapper("run", "parallel", "l=1", "d=1", "--eps", "0.5", "--oracle", "garmann",
                   "--count-only", "--json")
    assert proc.returncode == 0, proc.stderr
    record = json.loads(proc.stdout)
    jsonschema.Draft202012Validator(SCHEMA).validate(record)
    parse_run_json(proc.stdout)
    assert {k: record[k] for k in ("nodes", "leaves", "links", "oracle_calls",
                                   "last_pass_oracle_calls", "unlinks", "max_depth")} == {
        "nodes": 6, "leaves": 4, "links": 8, "oracle_calls": 16,
        "last_pass_oracle_calls": 14, "unlinks": 2, "max_depth": 1}


@needs_kernel
@pytest.mark.parametrize("args, message", [
    (["--eps", "0"], "--eps must be a finite number > 0, got 0"),
    (["--eps", "0.5", "--oracle", "hanrahan"], "unknown oracle 'hanrahan'"),
    (["--eps", "0.5", "offset=1"], "unknown argument 'offset=1'"),
])
def test_bad_input_is_one_line_and_exit_code_2(args, message):
    proc = wrapper("run", "parallel", *args, "--json")
    assert proc.returncode == 2
    assert proc.stdout == ""
    assert len(proc.stderr.splitlines()) == 1 and message in proc.stderr
