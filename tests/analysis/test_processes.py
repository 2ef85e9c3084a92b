"""Engine processes and the results cache under a hostile engine or environment.

Every engine process runs in its own process group, which is killed when the engine
exits, times out, prints too much, or the analysis receives SIGINT or SIGTERM; leases
cannot outlive their process; only the engine's own verdicts are cached.
"""

import json
import os
import shutil
import signal
import sqlite3
import subprocess
import sys
import time
from pathlib import Path

import pytest

from hrbench_analysis.bench.builds import (
    BENCH_LIMIT_FACTOR,
    BENCH_TIMEOUT,
    BuildError,
    bench_limit,
    run_benchmarks,
)
from hrbench_analysis.engine import (
    OUTPUT_EXCEEDED,
    TIMED_OUT,
    process,
    run_argv,
    run_engine,
)
from hrbench_analysis.reproduce import main
from hrbench_analysis.store import ACQUIRED, BUSY, ResultStore
from hrbench_analysis.store_points import PointKey, is_verdict
from hrbench_analysis.sweep import run_points
from hrbench_analysis.sweep_plan import expand_claim

ROOT = Path(__file__).resolve().parents[2]
ARGV = ("parallel", {"l": 8.0, "d": 1.0}, 0.5, "garmann")


def pids_of(path):
    """The pids a fake engine wrote (its own and its child's), once it wrote them."""
    return [int(p) for p in path.read_text().split()] if path.exists() else []


def running(pid):
    """Whether `pid` is a live process (a zombie awaiting its reaper is not)."""
    try:
        with open(f"/proc/{pid}/stat", "rb") as fh:
            return fh.read().rsplit(b")", 1)[1].split()[0] != b"Z"
    except (OSError, IndexError):
        return False


def assert_all_ended(pids, within=5.0):
    deadline = time.monotonic() + within
    while any(running(p) for p in pids) and time.monotonic() < deadline:
        time.sleep(0.05)
    assert not [p for p in pids if running(p)], "engine processes survived"


# --- One engine run ----------------------------------------------------------------------


def test_a_child_that_keeps_stdout_open_is_ended_not_waited_for(fake_hrbench, tmp_path,
                                                                 monkeypatch):
    pids = tmp_path / "pids"
    monkeypatch.setenv("FAKE_HRBENCH_CHILD", "leave")   # the child sleeps 600 s
    monkeypatch.setenv("FAKE_HRBENCH_PIDS", str(pids))
    start = time.monotonic()
    run = run_engine(run_argv(fake_hrbench, *ARGV))
    assert time.monotonic() - start < 10
    assert run.exit_code == 0 and not run.stopped
    assert json.loads(run.stdout)["links"] > 0
    (both,) = [pids_of(pids)]
    assert len(both) == 2
    assert_all_ended(both)


def test_a_hung_engine_is_ended_with_its_children_at_its_timeout(fake_hrbench, tmp_path,
                                                                monkeypatch):
    pids = tmp_path / "pids"
    monkeypatch.setenv("FAKE_HRBENCH_CHILD", "hang")
    monkeypatch.setenv("FAKE_HRBENCH_PIDS", str(pids))
    start = time.monotonic()
    run = run_engine(run_argv(fake_hrbench, *ARGV), timeout=1)
    assert 1 <= time.monotonic() - start < 10
    assert run.stopped == TIMED_OUT and run.exit_code == -signal.SIGKILL
    assert run.message.startswith("did not finish within 1 s")
    assert_all_ended(pids_of(pids))


def test_output_beyond_the_bound_ends_the_run_unread(fake_hrbench, monkeypatch):
    monkeypatch.setattr(process, "OUTPUT_LIMIT", 2**20)
    monkeypatch.setenv("FAKE_HRBENCH_FLOOD", str(8 * 2**20))
    run = run_engine(run_argv(fake_hrbench, *ARGV))
    assert run.stopped == OUTPUT_EXCEEDED and run.exit_code == -signal.SIGKILL
    assert len(run.stdout) <= 2**20
    assert "printed more than 1 MiB on standard output" in run.message


def test_an_engine_that_prints_too_much_breaks_the_contract(tmp_path, data_dir,
                                                           fake_hrbench, monkeypatch, capsys):
    monkeypatch.setattr(process, "OUTPUT_LIMIT", 2**16)
    monkeypatch.setenv("FAKE_HRBENCH_FLOOD", str(2**20))
    code = main(["--claims", str(data_dir / "small_claims.toml"), "--hrbench",
                 str(fake_hrbench), "--results", str(tmp_path), "--no-pictures",
                 "--jobs", "2"])
    err = capsys.readouterr().err
    assert code == 2
    (line,) = [x for x in err.splitlines() if x.startswith("error: ")]
    assert "breaks the engine contract in 11 of 11 runs" in line
    assert "printed more than 0.0625 MiB on standard output" in line
    with sqlite3.connect(tmp_path / "hrbench.sqlite") as con:   # none of it is final
        assert con.execute("SELECT COUNT(*) FROM points WHERE ok = 1").fetchone()[0] == 0


def test_a_point_past_its_timeout_fails_and_runs_again_next_time(tmp_path, data_dir,
                                                                   fake_hrbench, monkeypatch):
    from hrbench_analysis.claimfile import load_claims

    (claim,) = load_claims(data_dir / "small_claims.toml")
    points = expand_claim(claim, "quick", fake_hrbench, "v")[:2]
    monkeypatch.setenv("FAKE_HRBENCH_CHILD", "hang")
    with ResultStore(tmp_path / "c.sqlite") as store:
        start = time.monotonic()
        summary = run_points(points, store, jobs=2, progress=None, timeout=0.5)
        assert time.monotonic() - start < 10 and summary["failed"] == 2
        failure = store.get(points[0].key)
        assert failure.exit_code == -signal.SIGKILL and not failure.final
        assert failure.stderr.startswith("did not finish within 0.5 s")
        monkeypatch.delenv("FAKE_HRBENCH_CHILD")
        assert run_points(points, store, jobs=2, progress=None, timeout=60)["ran"] == 2
        assert all(store.get(p.key).ok for p in points)


def test_run_timeout_must_be_a_positive_number(capsys):
    try:
        code = main(["--run-timeout", "0"])
    except SystemExit as exc:   # argparse's usage error
        code = exc.code
    assert code == 2 and "--run-timeout" in capsys.readouterr().err


# --- Interrupts ----------------------------------------------------------------------------


@pytest.mark.parametrize("signum, code, scheduler", [
    (signal.SIGINT, 130, "local"), (signal.SIGTERM, 143, "local"),
    (signal.SIGINT, 130, "dask")])
def test_a_signal_to_the_analysis_alone_ends_hung_runs_and_their_children(
        signum, code, scheduler, tmp_path, data_dir, fake_hrbench):
    if scheduler == "dask":
        pytest.importorskip("distributed")
    pids = tmp_path / "pids"
    env = dict(os.environ, FAKE_HRBENCH_CHILD="hang", FAKE_HRBENCH_PIDS=str(pids),
               PYTHONPATH=str(ROOT / "analysis"))
    argv = [sys.executable, "-m", "hrbench_analysis.reproduce", "--claims",
            str(data_dir / "small_claims.toml"), "--hrbench", str(fake_hrbench),
            "--results", str(tmp_path / "results"), "--jobs", "2", "--no-pictures",
            "--scheduler", scheduler]
    # With SIGINT at its default even where the tests run as a background job (which
    # ignores it, and so would the analysis, as it must).
    proc = subprocess.Popen(argv, env=env, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                            text=True,
                            preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL))
    try:
        deadline = time.monotonic() + 60
        while len(pids_of(pids)) < 4 and time.monotonic() < deadline:   # 2 engines, 2 children
            time.sleep(0.05)
        started = pids_of(pids)
        assert len(started) == 4, proc.stderr.read() if proc.poll() is not None else ""
        sent = time.monotonic()
        proc.send_signal(signum)          # to the analysis alone, not to its process group
        _, err = proc.communicate(timeout=20)
    finally:
        proc.kill()
    # Closing a Dask LocalCluster takes a few seconds of its own.
    assert time.monotonic() - sent < (5 if scheduler == "local" else 10)
    assert proc.returncode == code, err
    assert "Traceback" not in err and "interrupted" in err
    assert_all_ended(started)
    with sqlite3.connect(tmp_path / "results" / "hrbench.sqlite") as con:
        assert con.execute("SELECT COUNT(*) FROM leases").fetchone()[0] == 0
        assert con.execute("SELECT COUNT(*) FROM points").fetchone()[0] == 0


def test_a_hung_benchmark_command_is_ended_with_its_children(tmp_path):
    pids = tmp_path / "pids"
    command = f"sleep 60 & echo $$ $! > {pids}; wait"
    start = time.monotonic()
    with pytest.raises(BuildError, match="did not finish within 1 s"):
        run_benchmarks(str(tmp_path), str(tmp_path / "bench.json"), "the gate's benchmarks",
                       bench_cmd=command, timeout=1)
    assert time.monotonic() - start < 5
    assert_all_ended(pids_of(pids))


def test_a_benchmark_commands_background_child_does_not_hold_the_caller(tmp_path):
    # The command exits at once and leaves a child holding its standard error for 5 s:
    # the run ends with the command, and the child with its group.
    pids = tmp_path / "pids"
    command = (f"sleep 5 & echo $! > {pids}; echo '{{\"benchmarks\": []}}' "
               "> \"$HRBENCH_BENCH_OUT\"")
    start = time.monotonic()
    seconds = run_benchmarks(str(tmp_path), str(tmp_path / "bench.json"), "the benchmarks",
                             bench_cmd=command)
    assert time.monotonic() - start < 3 and seconds < 3
    assert_all_ended(pids_of(pids))


def test_the_limit_of_a_benchmark_run_is_derived_from_the_first_run():
    assert bench_limit(None) == BENCH_TIMEOUT              # nothing measured yet
    assert bench_limit(20.0) == 20.0 * BENCH_LIMIT_FACTOR  # ten times the base's run
    assert bench_limit(0.5) == 60                          # never below a minute
    assert bench_limit(3600.0) == BENCH_TIMEOUT            # never above the default


# --- A tool that dies ----------------------------------------------------------------------


HANGING_ENGINE = """#!/bin/sh
echo $$ >> "{pids}"
exec sleep 600
"""


@pytest.mark.skipif(process._prctl is None, reason="no parent-death signal (not Linux)")
@pytest.mark.parametrize("tool", ["reproduce", "check_baseline", "render"])
def test_an_engine_dies_with_the_tool_killed_with_its_group(tool, tmp_path, data_dir):
    # The engine hangs (in `--version`, a run, a solve); the tool and its process group
    # get SIGKILL, as a CI time limit sends it: nothing can end the engine but the
    # kernel's parent-death signal, since the engine runs in a session of its own.
    pids = tmp_path / "pids"
    engine = tmp_path / "hanging-hrbench"
    engine.write_text(HANGING_ENGINE.format(pids=pids))
    engine.chmod(0o755)
    baseline = tmp_path / "counts.json"
    baseline.write_text(json.dumps({"schema_version": 1, "runs": [
        {"args": ["parallel", "l=1024", "d=1", "--eps", "1e-9", "--max-depth", "48"]}]}))
    argv = {
        "reproduce": ["-m", "hrbench_analysis.reproduce", "--claims",
                      str(data_dir / "small_claims.toml"), "--hrbench", str(engine),
                      "--results", str(tmp_path / "results"), "--no-pictures"],
        "check_baseline": [str(ROOT / "tools" / "check_baseline.py"), "--hrbench",
                           str(engine), "--baseline", str(baseline)],
        "render": ["-m", "hrbench_analysis.render", "cornell", "--eps", "0.5", "--hrbench",
                   str(engine), "--out", str(tmp_path / "r.png")],
    }[tool]
    env = dict(os.environ, PYTHONPATH=str(ROOT / "analysis"))
    proc = subprocess.Popen([sys.executable, *argv], env=env, start_new_session=True,
                            stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
    try:
        deadline = time.monotonic() + 60
        while not pids_of(pids) and proc.poll() is None and time.monotonic() < deadline:
            time.sleep(0.05)
        started = pids_of(pids)
        assert started, proc.stderr.read().decode() if proc.poll() is not None else ""
    finally:
        os.killpg(proc.pid, signal.SIGKILL)
        proc.wait()
    assert_all_ended(started)


# --- Leases --------------------------------------------------------------------------------


def key(eps=0.5):
    return PointKey(version="v", scene="parallel", params=(("d", 1.0), ("l", 8.0)), eps=eps,
                    oracle="garmann")


def test_a_lease_dated_in_the_future_does_not_block(tmp_path):
    path = tmp_path / "c.sqlite"
    with ResultStore(path) as a, ResultStore(path) as b:
        a.acquire(key())
        a._db.execute("UPDATE leases SET host = 'elsewhere', pid = 1, "
                      "renewed_at = renewed_at + 10")         # within a renewal: clock skew
        assert b.acquire(key()) == BUSY
        a._db.execute("UPDATE leases SET renewed_at = renewed_at + 86400")
        assert b.acquire(key()) == ACQUIRED
        (lease,) = b.leases()
        assert lease.token == b.token


def test_a_lease_whose_pid_was_reused_by_a_later_process_is_taken_over(tmp_path):
    path = tmp_path / "c.sqlite"
    sleeper = subprocess.Popen([sys.executable, "-c", "import time; time.sleep(60)"])
    try:
        time.sleep(0.1)
        with ResultStore(path) as a, ResultStore(path) as b:
            a.acquire(key())
            a._db.execute("UPDATE leases SET pid = ?, started_at = ?",
                          (sleeper.pid, time.time() + 2))      # it started before the lease
            assert b.acquire(key()) == BUSY
            a._db.execute("UPDATE leases SET started_at = started_at - 3600")
            assert b.acquire(key()) == ACQUIRED               # it started after: not the owner
    finally:
        sleeper.kill()
        sleeper.wait()


def test_a_sweep_runs_a_point_leased_in_the_future(tmp_path, data_dir, fake_hrbench):
    from hrbench_analysis.claimfile import load_claims

    (claim,) = load_claims(data_dir / "small_claims.toml")
    points = expand_claim(claim, "quick", fake_hrbench, "v")
    with ResultStore(tmp_path / "c.sqlite") as store:
        store._db.execute(
            "INSERT INTO leases VALUES (?, 'elsewhere', 1, 'gone', ?, ?)",
            (points[0].key.text(), time.time() + 1e6, time.time() + 1e6))
        start = time.monotonic()
        summary = run_points(points, store, jobs=2, progress=None)
        assert time.monotonic() - start < 30
        assert summary["ran"] == len(points) and summary["failed"] == 0
        assert store.leases() == []


# --- Which failures are cached -------------------------------------------------------------


@pytest.mark.parametrize("code, message, options, cached", [
    (2, "hrbench: error: parallel: d = -1 is out of range: d > 0", (), True),
    (2, "pyflat: unknown scene 'x'", (), True),
    (2, "/usr/bin/python3: can't open file '/e/engine.py': [Errno 2] No such file or "
        "directory", (), False),
    (2, "sh: 0: cannot open engine.sh: No such file", (), False),
    (2, 'Can\'t open perl script "engine.pl": No such file or directory', (), False),
    (2, "", (), False),
    (3, "hrbench: error: depth safety cap reached at eps=0.001; use --min-area", (), True),
    (3, "hrbench: error: element trees would exceed the memory budget (9 elements); "
        "raise --max-memory or eps", (), False),
    (3, "hrbench: error: element trees would exceed the memory budget (9 elements); "
        "raise --max-memory or eps", (("max_memory", "500"),), True),
    (3, "hrbench: error: out of memory; use --count-only or a larger eps",
        (("max_memory", "500"),), False),
    (1, "hrbench: internal error: boom", (), False),
    (126, "permission denied", (), False),
    (127, "cannot run x: not found", (), False),
    (-9, "", (), False),
])
def test_only_the_engines_own_verdicts_are_cached(code, message, options, cached):
    assert is_verdict(code, message, options) is cached


def test_an_engine_script_missing_for_a_moment_is_retried(tmp_path, data_dir, fake_hrbench):
    from hrbench_analysis.claimfile import load_claims

    (claim,) = load_claims(data_dir / "small_claims.toml")
    script = tmp_path / "engine.py"
    points = expand_claim(claim, "quick", [sys.executable, script], "v")
    with ResultStore(tmp_path / "c.sqlite") as store:
        first = run_points(points, store, jobs=2, progress=None)
        assert first["failed"] == len(points)
        failure = store.get(points[0].key)
        assert failure.exit_code == 2 and "can't open file" in failure.stderr
        assert not failure.final
        shutil.copy(fake_hrbench, script)          # the script is back
        second = run_points(points, store, jobs=2, progress=None)
        assert second["ran"] == len(points) and second["failed"] == 0
        records = [json.loads(store.get(p.key).output) for p in points]
    with ResultStore(tmp_path / "clean.sqlite") as store:
        run_points(points, store, jobs=2, progress=None)
        clean = [json.loads(store.get(p.key).output) for p in points]
    drop = ("seconds",)
    assert ([{k: v for k, v in r.items() if k not in drop} for r in records]
            == [{k: v for k, v in r.items() if k not in drop} for r in clean])


def test_a_memory_budget_failure_is_retried_and_the_verdict_recovers(
        tmp_path, data_dir, fake_hrbench, monkeypatch, capsys):
    def reproduce(results):
        code = main(["--claims", str(data_dir / "small_claims.toml"), "--hrbench",
                     str(fake_hrbench), "--results", str(results), "--no-pictures",
                     "--jobs", "2"])
        capsys.readouterr()
        return code, json.loads((results / "claims.json").read_text())["claims"]

    monkeypatch.setenv("FAKE_HRBENCH_MEMORY_BELOW_EPS", "0.2")   # memory short for a moment
    code, low = reproduce(tmp_path / "a")
    assert code == 0 and low[0]["verdict"] == "inconclusive"
    monkeypatch.delenv("FAKE_HRBENCH_MEMORY_BELOW_EPS")
    code, again = reproduce(tmp_path / "a")
    _, clean = reproduce(tmp_path / "b")
    assert again == clean and clean[0]["verdict"] == "reproduced"
