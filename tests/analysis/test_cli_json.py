"""The fields the analysis reads from the engine's output, checked one by one.

The first tests read a record stored in ``data/`` (written by ``hrbench run parallel l=64
d=1 --eps 0.25 --count-only --json``); the others run ``build/hrbench`` when it exists
(the capabilities test needs an engine with ``hrbench capabilities --json``).
"""

import json
import subprocess
from pathlib import Path

import numpy as np
import pytest

from hrbench_analysis.claimfile import load_claims_dir
from hrbench_analysis.engine import engine_version, get_capabilities
from hrbench_analysis.loader import (
    COUNTERS,
    MEASURES,
    SCHEMA_VERSION,
    ResultFormatError,
    parse_run_json,
    read_links_csv,
    run_environment,
)
from hrbench_analysis.reproduce import check_claims
from hrbench_analysis.reproduce_options import CLAIMS_DIR

ROOT = Path(__file__).resolve().parents[2]
HRBENCH = ROOT / "build" / "hrbench"
needs_engine = pytest.mark.skipif(not HRBENCH.exists(), reason="build/hrbench not built")

# docs/conventions.md, worked example: parallel l=64 d=1, garmann, eps=0.25.
REFERENCE = {"nodes": 1022, "leaves": 512, "links": 5092, "oracle_calls": 10183}


def check_reference_record(text):
    raw = json.loads(text)
    assert raw["schema_version"] == 1
    assert isinstance(raw["version"], str) and raw["version"]
    assert raw["scene"] == "parallel"
    assert raw["params"] == {"l": 64.0, "d": 1.0, "offset": 0.0, "l2": 64.0}
    assert raw["eps"] == 0.25
    assert raw["oracle"] == "garmann"
    assert raw["mode"] == "count-only"
    assert raw["min_area"] is None
    assert raw["max_depth_limit"] is None
    for key, value in REFERENCE.items():
        assert raw[key] == value, key
    assert raw["max_depth"] == 8
    assert raw["forced_links"] == 0
    assert raw["culled_pairs"] == 0
    assert raw["root_pairs"] == 1
    assert sum(raw["nodes_per_depth"]) == raw["nodes"]
    assert sum(raw["links_per_depth"]) == raw["links"]
    assert len(raw["nodes_per_depth"]) == raw["max_depth"] + 1
    assert isinstance(raw["seconds"], float) and raw["seconds"] >= 0

    result = parse_run_json(text)
    assert result.counters["nodes"] == 1022 and result.counters["links"] == 5092
    env = run_environment(result)
    assert env["N"] == 1022 and env["L"] == 5092 and env["g"] == 64.0 and env["eps"] == 0.25


def test_stored_reference_record(data_dir):
    check_reference_record((data_dir / "run_parallel_l64_d1_eps0.25.json").read_text())


def test_reader_is_tolerant_but_checks_schema_and_counters(data_dir):
    raw = json.loads((data_dir / "run_parallel_l64_d1_eps0.25.json").read_text())
    raw["some_new_field"] = {"nested": True}
    for key in ("seconds", "forced_links", "links_per_depth", "min_area"):
        raw.pop(key, None)
    result = parse_run_json(json.dumps(raw))
    assert result.extra["some_new_field"] == {"nested": True}
    assert "seconds" not in result.counters
    with pytest.raises(ResultFormatError, match="schema_version"):
        parse_run_json(json.dumps(dict(raw, schema_version=2)))
    with pytest.raises(ResultFormatError, match="'links'"):
        parse_run_json(json.dumps({k: v for k, v in raw.items() if k != "links"}))
    with pytest.raises(ResultFormatError, match="not valid JSON"):
        parse_run_json("hrbench: oops")


def test_counters_are_read_generically_or_from_the_engines_table(data_dir):
    raw = json.loads((data_dir / "run_parallel_l64_d1_eps0.25.json").read_text())
    raw.update(rays=12, rays_per_side=None, threads_used=2, max_depth_limit=30)
    generic = parse_run_json(json.dumps(raw))
    assert generic.counters["rays"] == 12 and generic.counters["threads_used"] == 2
    assert generic.counters["patches"] == 2 and generic.counters["seconds"] == raw["seconds"]
    for name in ("eps", "max_depth_limit", "rays_per_side", "schema_version"):
        assert name not in generic.counters, name
    assert generic.max_depth_limit == 30 and generic.extra["rays_per_side"] is None

    table = (*COUNTERS, "rays", "visibility_queries")
    listed = parse_run_json(json.dumps(raw), counters=table)
    assert listed.counters["rays"] == 12 and "visibility_queries" not in listed.counters
    assert "threads_used" not in listed.counters and listed.extra["threads_used"] == 2
    assert listed.counters["patches"] == 2  # the measures are read either way
    assert run_environment(listed)["rays"] == 12
    with pytest.raises(ResultFormatError, match="counter 'rays' must be an integer, got 1.5"):
        parse_run_json(json.dumps(dict(raw, rays=1.5)), counters=table)


@needs_engine
def test_engine_capabilities_describe_its_run_records():
    caps = get_capabilities(HRBENCH)
    assert engine_version(HRBENCH) == f"hrbench {caps.version}"
    assert caps.run_schema_version == SCHEMA_VERSION
    assert set(COUNTERS) <= set(caps.scalar_counters)
    proc = subprocess.run([str(HRBENCH), "run", "parallel", "l=64", "d=1", "--eps", "0.25",
                           "--count-only", "--json"], capture_output=True, text=True,
                          timeout=60)
    assert proc.returncode == 0, proc.stderr
    raw = json.loads(proc.stdout)
    for name in caps.scalar_counters:
        assert isinstance(raw[name], int) and not isinstance(raw[name], bool), name
    for name in caps.histogram_counters:
        assert isinstance(raw[name], list), name
    result = parse_run_json(proc.stdout, counters=caps.scalar_counters)
    # The counters, and the measures: patches, the times and the linking's bytes.
    assert set(result.counters) == {*caps.scalar_counters, *MEASURES}
    # Every shipped claim names an oracle and formula names this engine offers.
    errors, _ = check_claims(load_claims_dir(CLAIMS_DIR), "full", caps)
    assert errors == []


@needs_engine
def test_engine_run_json_fields():
    proc = subprocess.run([str(HRBENCH), "run", "parallel", "l=64", "d=1", "--eps", "0.25",
                           "--count-only", "--json"], capture_output=True, text=True,
                          timeout=60)
    assert proc.returncode == 0, proc.stderr
    check_reference_record(proc.stdout)
    assert json.loads(proc.stdout)["version"] in engine_version(HRBENCH)


@needs_engine
def test_engine_usage_error_exits_2_with_one_line():
    proc = subprocess.run([str(HRBENCH), "run", "parallel", "l=64", "d=1", "--count-only",
                           "--json", "--no-such-flag"], capture_output=True, text=True,
                          timeout=60)
    assert proc.returncode == 2
    assert proc.stderr.strip()


@needs_engine
def test_engine_links_csv_tiles_the_parameter_square(tmp_path):
    out = tmp_path / "links.csv"
    proc = subprocess.run([str(HRBENCH), "links", "parallel", "l=16", "d=1", "--eps", "0.3",
                           "--out", str(out)], capture_output=True, text=True, timeout=60)
    assert proc.returncode == 0, proc.stderr
    header = out.read_text().splitlines()[0].split(",")
    assert header == ["root_i", "elem_i", "t0_i", "t1_i", "depth_i",
                      "root_j", "elem_j", "t0_j", "t1_j", "depth_j"]
    links = read_links_csv(out)
    assert len(links) > 100
    area = np.sum((links.t1_i - links.t0_i) * (links.t1_j - links.t0_j))
    assert area == pytest.approx(16.0 * 16.0, rel=1e-12)
    assert np.all(links.t0_i >= 0) and np.all(links.t1_i <= 16)
    assert np.all(links.depth_i >= 0) and np.all(links.depth_j >= 0)
