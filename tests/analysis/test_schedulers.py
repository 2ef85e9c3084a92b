"""Sweeps on a Dask cluster: the same results as the local pool, a lost worker loses no
point, and a scheduler that cannot be used is one clear line."""

import json
import os
import signal
import threading
import time

import pytest

from hrbench_analysis import schedulers
from hrbench_analysis.claimfile import load_claims
from hrbench_analysis.engine import engine_version
from hrbench_analysis.reproduce import main
from hrbench_analysis.schedulers import SchedulerError, check_scheduler, open_scheduler
from hrbench_analysis.store import ResultStore
from hrbench_analysis.store_points import StoredPoint
from hrbench_analysis.sweep import MAX_ATTEMPTS, WORKER_LOST, order_by_cost, run_points
from hrbench_analysis.sweep_plan import expand_claim

distributed = pytest.importorskip("distributed")
psutil = pytest.importorskip("psutil")


def points_of(data_dir, fake):
    (claim,) = load_claims(data_dir / "small_claims.toml")
    return expand_claim(claim, "quick", fake, engine_version(fake))


def stored(path):
    with ResultStore(path) as store:
        rows = store._db.execute("SELECT key, ok, exit_code, output FROM points ORDER BY key")
        return [(k, ok, code, json.loads(out)) for k, ok, code, out in rows.fetchall()]


@pytest.mark.parametrize("text", ["local", "dask", "tcp://127.0.0.1:8786",
                                  "tcp://scheduler.example.org:8786", "tls://10.0.0.2:8786"])
def test_scheduler_names_and_addresses(text):
    assert check_scheduler(text) == text


@pytest.mark.parametrize("text", ["", "Dask", "127.0.0.1:8786", "tcp://host", "ssh://h:1",
                                  "tcp://h:1; rm -rf /"])
def test_bad_scheduler_is_refused(text):
    with pytest.raises(SchedulerError, match="expected 'local', 'dask' or the address"):
        check_scheduler(text)


def test_unreachable_scheduler_is_one_line_and_exit_2(tmp_path, data_dir, fake_hrbench,
                                                      monkeypatch, capsys):
    monkeypatch.setattr(schedulers, "CONNECT_TIMEOUT", 2)
    with pytest.raises(SchedulerError, match=r"tcp://127.0.0.1:9: no Dask scheduler answers"):
        open_scheduler("tcp://127.0.0.1:9", 1)
    code = main(["--claims", str(data_dir / "small_claims.toml"), "--hrbench",
                 str(fake_hrbench), "--results", str(tmp_path / "r"), "--no-pictures",
                 "--scheduler", "tcp://127.0.0.1:9"])
    err = capsys.readouterr().err
    assert code == 2
    (line,) = [x for x in err.splitlines() if x.startswith("error:")]
    assert "no Dask scheduler answers" in line
    # Nothing ran, nothing is stored as done.
    with ResultStore(tmp_path / "r" / "hrbench.sqlite") as store:
        assert not any(store.is_final(p.key) for p in points_of(data_dir, fake_hrbench))


def test_dask_gives_the_results_of_the_local_pool(tmp_path, data_dir, fake_hrbench, capsys):
    claims = {}
    for name in ("local", "dask"):
        results = tmp_path / name
        assert main(["--claims", str(data_dir / "small_claims.toml"), "--hrbench",
                     str(fake_hrbench), "--results", str(results), "--no-pictures",
                     "--jobs", "2", "--scheduler", name]) == 0
        claims[name] = json.loads((results / "claims.json").read_text())
        assert claims[name]["context"]["scheduler"] == name
    assert claims["dask"]["claims"] == claims["local"]["claims"]
    local, dask = stored(tmp_path / "local" / "hrbench.sqlite"), stored(
        tmp_path / "dask" / "hrbench.sqlite")
    assert [row[:3] for row in dask] == [row[:3] for row in local]
    drop = {"context", "seconds"}  # where and how long: the rest is the engine's answer
    assert ([{k: v for k, v in r.items() if k not in drop} for *_, r in dask]
            == [{k: v for k, v in r.items() if k not in drop} for *_, r in local])


def test_a_killed_worker_loses_no_point(tmp_path, data_dir, fake_hrbench, monkeypatch):
    log = tmp_path / "runs.log"
    monkeypatch.setenv("FAKE_HRBENCH_LOG", str(log))
    monkeypatch.setenv("FAKE_HRBENCH_DELAY", "1.0")
    points = points_of(data_dir, fake_hrbench)[:4]
    killed, engines = [], []

    def kill_one_worker():
        # Wait for the first run to start (its line logged), then kill the worker process
        # that runs it; the engine dies with it (the parent-death signal).
        deadline = time.monotonic() + 60
        while time.monotonic() < deadline:
            for proc in psutil.process_iter(["cmdline"]):
                cmd = proc.info["cmdline"] or []
                if (any(str(fake_hrbench) == word for word in cmd) and "run" in cmd
                        and log.exists() and log.read_text()):
                    worker = proc.parent()
                    if worker is not None:
                        killed.append(worker.pid)
                        os.kill(worker.pid, signal.SIGKILL)
                        engines.append(proc)
                        return
            time.sleep(0.05)

    with ResultStore(tmp_path / "cache.sqlite") as store, \
            open_scheduler("dask", 2) as scheduler:
        killer = threading.Thread(target=kill_one_worker)
        killer.start()
        summary = run_points(points, store, scheduler=scheduler, progress=None)
        killer.join()
        assert killed, "no worker was killed"
        engines[0].wait(timeout=10)   # ended with its worker, not left running
        assert summary == {"total": 4, "cached": 0, "ran": 4, "failed": 0}
        assert all(store.get(p.key).ok for p in points)
    # The killed worker's point started twice; each point is stored once.
    started = log.read_text().splitlines()
    assert len(started) == 5 and len(set(started)) == 4
    assert len(stored(tmp_path / "cache.sqlite")) == 4


class _LosingExecutor:
    # Every future fails as if its worker had been lost.
    def __init__(self):
        self.calls = 0

    def submit(self, fn, *args):
        from concurrent.futures import Future
        self.calls += 1
        future = Future()
        future.set_exception(ConnectionError("worker lost"))
        return future

    def shutdown(self, wait=True, cancel_futures=False):
        pass


def test_a_point_whose_worker_is_always_lost_is_stored_failed_and_retried(tmp_path,
                                                                         data_dir,
                                                                         fake_hrbench):
    (point,) = points_of(data_dir, fake_hrbench)[:1]
    executor = _LosingExecutor()
    scheduler = schedulers.Scheduler("test", executor, 1, lost=(ConnectionError,),
                                     closers=[lambda: None])
    with ResultStore(tmp_path / "cache.sqlite") as store:
        summary = run_points([point], store, scheduler=scheduler, progress=None)
        assert executor.calls == MAX_ATTEMPTS
        assert summary["failed"] == 1
        got = store.get(point.key)
        assert got.exit_code == WORKER_LOST and "lost 3 times" in got.stderr
        assert not store.is_final(point.key)  # the next sweep runs it again
        summary = run_points([point], store, jobs=1, progress=None)
        assert summary["ran"] == 1 and store.get(point.key).ok


def test_points_run_dearest_first(tmp_path, data_dir, fake_hrbench):
    points = points_of(data_dir, fake_hrbench)
    # Nothing known: the reverse of the sweep (eps falling: dearest last).
    assert order_by_cost(points, {}) == points[::-1]
    # Known costs first, longest first, whatever the engine version was.
    known = {points[2].key.run_text(): 5.0, points[7].key.run_text(): 9.0}
    ordered = order_by_cost(points, known)
    assert ordered[:2] == [points[7], points[2]]
    assert ordered[2:] == [p for p in points[::-1] if p not in (points[2], points[7])]
    with ResultStore(tmp_path / "c.sqlite") as store:
        store.put(StoredPoint(points[3].key, True, 0, "", "{}", 2.5))
        assert store.known_seconds() == {points[3].key.run_text(): 2.5}


def test_progress_names_a_running_point(tmp_path, data_dir, fake_hrbench, monkeypatch):
    import io
    monkeypatch.setenv("FAKE_HRBENCH_DELAY", "0.3")
    stream = io.StringIO()
    with ResultStore(tmp_path / "cache.sqlite") as store:
        run_points(points_of(data_dir, fake_hrbench)[:6], store, jobs=2, progress=stream)
    lines = stream.getvalue().splitlines()
    assert any("; running parallel d=1 l=8 eps=" in x and " garmann" in x for x in lines)
    assert "running" not in lines[-1]
