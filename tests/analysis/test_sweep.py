import json
import os
import signal
import sqlite3
import subprocess
import sys
import time
from pathlib import Path

import pytest

from hrbench_analysis.claimfile import load_claims, load_claims_dir, resolve_oracle
from hrbench_analysis.engine import (
    CapabilitiesError,
    engine_version,
    get_capabilities,
    parse_capabilities,
)
from hrbench_analysis.reproduce import check_claims
from hrbench_analysis.reproduce_options import CLAIMS_DIR
from hrbench_analysis.store import ResultStore
from hrbench_analysis.sweep import get_claim_data, run_points
from hrbench_analysis.sweep_plan import DEFAULT_SWEEP_EXCLUDES, expand_claim, sweep_excludes

ROOT = Path(__file__).resolve().parents[2]


def claim_points(data_dir, fake, name="small_claims.toml"):
    (claim,) = load_claims(data_dir / name)
    return claim, expand_claim(claim, "quick", fake, engine_version(fake))


def test_expand_claim_builds_the_command_line(data_dir, fake_hrbench):
    claim, points = claim_points(data_dir, fake_hrbench)
    assert len(points) == 11
    assert points[0].argv[1:] == ("run", "parallel", "d=1", "l=8", "--eps", "1",
                                  "--oracle", "garmann", "--count-only", "--json")
    assert points[-1].key.eps == 0.01
    assert points[0].key.version == "hrbench-fake 0.0.1"
    assert len({p.key.text() for p in points}) == len(points)


def test_sweep_stores_points_and_rerun_reuses_them(tmp_path, data_dir, fake_hrbench,
                                                   monkeypatch):
    log = tmp_path / "runs.log"
    monkeypatch.setenv("FAKE_HRBENCH_LOG", str(log))
    claim, points = claim_points(data_dir, fake_hrbench)
    with ResultStore(tmp_path / "cache.sqlite") as store:
        first = run_points(points, store, jobs=2, progress=None)
        assert first == {"total": 11, "cached": 0, "ran": 11, "failed": 0}
        second = run_points(points, store, jobs=2, progress=None)
        assert second == {"total": 11, "cached": 11, "ran": 0, "failed": 0}
        data = get_claim_data(claim, points, store)
    assert len(log.read_text().splitlines()) == 11
    assert data.x.size == 11 and not data.failures
    # The fake engine counts exactly, as docs/conventions.md defines (its worked example,
    # l=64, is in test_cli_json.py).
    assert data.y[0] == 30  # l=8, d=1, eps=1: two trees of depth 3


def test_failed_points_are_recorded_with_exit_code_and_message(tmp_path, data_dir,
                                                              fake_hrbench, monkeypatch):
    monkeypatch.setenv("FAKE_HRBENCH_FAIL_BELOW_EPS", "0.05")
    claim, points = claim_points(data_dir, fake_hrbench)
    with ResultStore(tmp_path / "cache.sqlite") as store:
        summary = run_points(points, store, jobs=2, progress=None)
        assert summary["failed"] == 4
        data = get_claim_data(claim, points, store)
        # Exit code 3 is deterministic: a rerun keeps the failure instead of retrying.
        assert run_points(points, store, jobs=2, progress=None)["ran"] == 0
    assert data.x.size == 7
    assert [f["exit_code"] for f in data.failures] == [3, 3, 3, 3]
    assert all("depth safety cap" in f["stderr"] for f in data.failures)
    assert all("--eps" in f["command"] for f in data.failures)


def test_crash_without_message_is_recorded_and_retried(tmp_path, data_dir):
    crash = tmp_path / "crash"
    crash.write_text(f"#!{sys.executable}\nimport sys\n"
                     "if sys.argv[1:] == ['--version']: print('crash 1'); sys.exit(0)\n"
                     "sys.exit(139)\n")
    crash.chmod(0o755)
    claim, points = claim_points(data_dir, crash)
    with ResultStore(tmp_path / "cache.sqlite") as store:
        assert run_points(points[:2], store, jobs=1, progress=None)["failed"] == 2
        stored = store.get(points[0].key)
        assert stored.exit_code == 139 and "no message" in stored.stderr
        assert run_points(points[:2], store, jobs=1, progress=None)["ran"] == 2


def test_progress_bar_is_plain_text(tmp_path, data_dir, fake_hrbench):
    import io
    claim, points = claim_points(data_dir, fake_hrbench)
    stream = io.StringIO()
    with ResultStore(tmp_path / "cache.sqlite") as store:
        run_points(points[:3], store, jobs=2, progress=stream)
    last = stream.getvalue().strip().splitlines()[-1]
    assert "3/3 points" in last and "0 failed" in last


def test_killed_sweep_resumes_without_lost_or_duplicated_points(tmp_path, data_dir,
                                                                fake_hrbench):
    results = tmp_path / "results"
    log = tmp_path / "runs.log"
    env = dict(os.environ, FAKE_HRBENCH_DELAY="0.25", FAKE_HRBENCH_LOG=str(log),
               PYTHONPATH=str(ROOT))
    argv = [sys.executable, "-m", "hrbench_analysis.reproduce", "--claims",
            str(data_dir / "small_claims.toml"), "--hrbench", str(fake_hrbench),
            "--results", str(results), "--jobs", "2", "--no-tiling"]
    db = results / "hrbench.sqlite"

    # Start the sweep, and kill it once a few points are stored.
    proc = subprocess.Popen(argv, env=env, cwd=ROOT, stdout=subprocess.DEVNULL,
                            stderr=subprocess.DEVNULL, start_new_session=True)
    try:
        deadline = time.time() + 30
        stored = 0
        while time.time() < deadline and stored < 4:
            time.sleep(0.05)
            if db.exists():
                try:
                    with sqlite3.connect(db) as con:
                        stored = con.execute("SELECT COUNT(*) FROM points").fetchone()[0]
                except sqlite3.OperationalError:
                    pass
    finally:
        os.killpg(proc.pid, signal.SIGKILL)
        proc.wait()
    assert proc.returncode == -signal.SIGKILL
    # SIGKILL cannot be caught: the engine runs under way, each in a process group of
    # its own, finish by themselves (each logs its start), and their results are lost.
    settled, size = time.time(), -1
    while time.time() - settled < 1.0:
        time.sleep(0.05)
        if log.stat().st_size != size:
            settled, size = time.time(), log.stat().st_size
    with sqlite3.connect(db) as con:
        before = con.execute("SELECT COUNT(*) FROM points").fetchone()[0]
    assert 4 <= before < 11, "the kill must land in the middle of the sweep"

    # Resume: only the missing points run, and each point is stored exactly once.
    runs_before = len(log.read_text().splitlines())
    resumed = subprocess.run(argv, env=dict(env, FAKE_HRBENCH_DELAY="0"), cwd=ROOT,
                             capture_output=True, text=True, timeout=120)
    assert resumed.returncode == 0, resumed.stderr
    with sqlite3.connect(db) as con:
        rows = con.execute("SELECT key, ok FROM points").fetchall()
    assert len(rows) == 11 and len({k for k, _ in rows}) == 11
    assert all(ok for _, ok in rows)
    runs_after = len(log.read_text().splitlines())
    assert runs_after - runs_before == 11 - before
    context = json.loads((results / "claims.json").read_text())["context"]
    assert context["points"].startswith(f"11 ({before} cached, {11 - before} run")


def test_expand_claim_runs_the_range_for_every_grid_value(tmp_path, data_dir, fake_hrbench):
    text = (data_dir / "small_claims.toml").read_text().replace(
        "params = { l = 8, d = 1 }", "params = { d = 1 }\nsweep.grid = { l = [8, 32] }")
    (tmp_path / "grid.toml").write_text(text)
    claim, points = claim_points(tmp_path, fake_hrbench, "grid.toml")
    assert len(points) == 22
    assert [dict(p.key.params)["l"] for p in points] == [8.0] * 11 + [32.0] * 11
    assert points[11].argv[1:5] == ("run", "parallel", "d=1", "l=32")
    assert len({p.key.text() for p in points}) == 22
    # A swept recursion limit goes to --min-area and into the key.
    (tmp_path / "area.toml").write_text((data_dir / "small_claims.toml").read_text().replace(
        'sweep.param = "eps"', 'sweep.param = "min_area"\neps = 0.5'))
    claim, points = claim_points(tmp_path, fake_hrbench, "area.toml")
    assert [p.key.min_area for p in points][:2] == [1.0, 0.63096]
    assert "--min-area" in points[1].argv and "0.63096" in points[1].argv


MIN_AREA_CLAIM = """
[source]
key = "test"
citation = "hrbench test data"

[[claim]]
id = "T-corner"
statement = "N grows as the recursion limit falls"
description = "Touching perpendicular plates swept over --min-area."
scene = "perpendicular"
params = { l = 1, gap = 0 }
eps = 0.05
sweep.param = "min_area"
sweep.range = { from = 0.001, to = 0.000000001, per_decade = 2 }
x = "1 / min_area"
y = "N"
x_label = "1/A0"
y_label = "N"
expected_exponent = 0
tolerance = 0.5
min_decades = 1
"""

HRBENCH = ROOT / "build" / "hrbench"
needs_engine = pytest.mark.skipif(not HRBENCH.exists(), reason="build/hrbench not built")


def logged_engine(tmp_path, fail_shared=False):
    # The real engine behind a script that logs each command line (and, if asked,
    # fails every --sweep run the way a crashing engine would).
    log = tmp_path / "runs.log"
    script = tmp_path / "hrbench"
    fail = 'case "$*" in *--sweep*) exit 70;; esac\n' if fail_shared else ""
    script.write_text(f'#!/bin/sh\necho "$*" >> {log}\n{fail}exec {HRBENCH} "$@"\n')
    script.chmod(0o755)
    return script, log


def records(store, points):
    # Every stored record without what differs from run to run (context, times).
    out = {}
    for p in points:
        stored = store.get(p.key)
        assert stored is not None and stored.ok, stored
        record = json.loads(stored.output)
        for key in ("context", "seconds", "cpu_seconds", "linking_seconds"):
            record.pop(key)
        out[p.key] = record
    return out


EPS_CLAIM = MIN_AREA_CLAIM.replace('eps = 0.05\nsweep.param = "min_area"',
                                   'min_area = 1e-9\nsweep.param = "eps"').replace(
    "from = 0.001, to = 0.000000001, per_decade = 2", "from = 0.5, to = 0.005, per_decade = 6")


@needs_engine
@pytest.mark.parametrize("fail_shared", [False, True])
@pytest.mark.parametrize("text, flag", [(MIN_AREA_CLAIM, "--min-area"), (EPS_CLAIM, "--eps")])
def test_sweep_runs_once_and_stores_what_separate_runs_give(tmp_path, fail_shared, text, flag):
    path = tmp_path / "claims.toml"
    path.write_text(text)
    (claim,) = load_claims(path)
    engine, log = logged_engine(tmp_path, fail_shared)
    version = engine_version(engine)
    shared = expand_claim(claim, "quick", engine, version, get_capabilities(engine))
    alone = expand_claim(claim, "quick", engine, version)
    assert len(shared) == 13 and len({p.shared for p in shared}) == 1
    assert [p.key for p in shared] == [p.key for p in alone]
    assert all(p.shared is None for p in alone)
    identity = shared[0].shared.argv()
    assert flag not in identity and identity[-4:] == [
        "--sweep", claim.sweep_param, "--count-only", "--json"]
    # The run's command line is the points' less the swept flag, with --sweep NAME=VALUES.
    at = shared[0].argv.index(flag)
    assert shared[0].shared.argv([p.value for p in shared[:2]]) == [
        *shared[0].argv[:at], *shared[0].argv[at + 2:-2], "--sweep",
        f"{claim.sweep_param}={shared[0].argv[at + 1]},{shared[1].argv[at + 1]}",
        "--count-only", "--json"]
    with ResultStore(tmp_path / "shared.sqlite") as store:
        log.write_text("")
        summary = run_points(shared, store, jobs=2, progress=None)
        assert summary == {"total": 13, "cached": 0, "ran": 13, "failed": 0}
        runs = log.read_text().splitlines()
        # One run for all 13 points, or, when it fails, that run and one per point.
        assert sum("--sweep" in r for r in runs) == 1
        assert len(runs) == (14 if fail_shared else 1)
        got = records(store, shared)
        assert sum(store.get(p.key).wall_seconds for p in shared) > 0
    with ResultStore(tmp_path / "alone.sqlite") as store:
        run_points(alone, store, jobs=2, progress=None)
        want = records(store, alone)
    assert got == want
    assert len({r["nodes"] for r in got.values()}) > 5  # the swept value changes the counts


@needs_engine
@pytest.mark.parametrize("options", ["{ threads = 2 }", '{ method = "enumerate" }',
                                     "{ clusters = true }"])
def test_sweeps_with_options_a_shared_run_cannot_take_run_point_by_point(tmp_path, options):
    path = tmp_path / "claims.toml"
    path.write_text(EPS_CLAIM.replace("min_area = 1e-9\n",
                                      f"min_area = 1e-9\noptions = {options}\n"))
    (claim,) = load_claims(path)
    points = expand_claim(claim, "quick", HRBENCH, engine_version(HRBENCH),
                          get_capabilities(HRBENCH))
    assert points and all(p.shared is None for p in points)


def _capabilities(sweep_entry, clusters_entry=None):
    # An engine's capabilities listing `run --sweep` (and `--clusters`) as given.
    options = [{"name": "sweep", "flag": "--sweep", "value": "P=V,...", "choices": None,
                "commands": ["run"], "doc": "", **sweep_entry}]
    if clusters_entry is not None:
        options.append({"name": "clusters", "flag": "--clusters", "value": None,
                        "choices": None, "commands": ["run"], "doc": "", **clusters_entry})
    return parse_capabilities(json.dumps({
        "schema_version": 1, "engine": "e", "version": "1", "run_schema_version": 1,
        "commands": [], "families": [], "oracles": [], "methods": [], "options": options,
        "counters": []}))


def test_the_planner_reads_which_options_exclude_sweep_on_either_side_or_its_default():
    # An engine that lists no exclusions is taken to refuse what hrbench refused before
    # it listed them.
    assert sweep_excludes(_capabilities({})) == DEFAULT_SWEEP_EXCLUDES
    assert sweep_excludes(_capabilities({"commands": ["links"]})) is None
    assert sweep_excludes(None) is None
    # Listed on --sweep's entry, or on the other option's: the relation is symmetric.
    assert sweep_excludes(_capabilities({"excludes": []})) == frozenset()
    assert sweep_excludes(_capabilities({"excludes": ["threads"]},
                                        {"excludes": ["sweep"]})) == {"threads", "clusters"}
    with pytest.raises(CapabilitiesError, match="excludes"):
        _capabilities({"excludes": "threads"})


def _exit_code(argv, wait):
    # The engine's exit code, or None if it is still counting after _wait_ seconds (it
    # took the command line: a refusal comes before any counting).
    proc = subprocess.Popen(argv, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE,
                            text=True)
    try:
        proc.wait(timeout=wait)
    except subprocess.TimeoutExpired:
        proc.kill()
        proc.wait()
        return None
    finally:
        proc.stderr.close()
    return proc.returncode


@needs_engine
def test_the_planner_shares_a_run_for_every_shipped_claim_exactly_where_the_engine_takes_it():
    # Every shipped count-only claim over eps or min_area, in both modes: the shared run
    # the planner plans is accepted by the engine (at the series' cheapest value), and
    # where it plans none, the engine refuses that run with exit 2 (a usage error).
    capabilities, version = get_capabilities(HRBENCH), engine_version(HRBENCH)
    # The claims as hrbench-reproduce runs them: oracles named as the engine names them,
    # those it skips left out.
    claims = [c.with_oracle(resolve_oracle(c, capabilities)[0] or c.oracle)
              for c in load_claims_dir(CLAIMS_DIR)]
    shared, alone = set(), set()
    for mode in ("quick", "full"):
        errors, skipped = check_claims(claims, mode, capabilities)
        assert errors == []
        for claim in claims:
            if claim.id in skipped or claim.sweep_param not in ("eps", "min_area") or \
                    claim.statistics or getattr(claim, "command", "run") != "run":
                continue
            points = expand_claim(claim, mode, HRBENCH, version, capabilities)
            first = points[0]
            run = first.shared or first.run.shared(HRBENCH, claim.sweep_param)
            code = _exit_code(run.argv([first.value]), 60 if first.shared is None else 5)
            if first.shared is not None:
                assert all(p.shared is not None for p in points), claim.id
                assert code in (0, None), f"{claim.id} {mode}: refused: {run.argv()}"
                shared.add(claim.id)
            else:
                assert code == 2, f"{claim.id} {mode}: the engine takes {run.argv()}"
                alone.add(claim.id)
    # Both kinds are shipped: clusters and translation claims run point by point.
    assert "SIL-eps" in alone and len(shared) > 10, (shared, alone)


def test_a_flag_echoed_in_the_record_matches_its_key():
    # `options = { clusters = true }` is keyed as the text "true"; the record echoes the
    # flag as JSON true. A record saying false means the flag was not applied.
    from types import SimpleNamespace

    from hrbench_analysis.sweep import _options_mismatch
    record = SimpleNamespace(counters={}, extra={"clusters": True})
    assert _options_mismatch(record, [("clusters", "true")]) == ""
    record.extra["clusters"] = False
    assert "clusters=False" in _options_mismatch(record, [("clusters", "true")])
