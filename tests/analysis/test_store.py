"""hrbench_analysis.store: the cache is checked when opened, and leases share the work of sweeps."""

import json
import sqlite3
import subprocess
import sys
import threading
import time

import pytest

from hrbench_analysis.store import ACQUIRED, BUSY, DONE, ResultStore, StoreError
from hrbench_analysis.store_points import PointKey, StoredPoint
from hrbench_analysis.store_schema import APPLICATION_ID, STORE_SCHEMA_VERSION


def key(eps=0.5):
    return PointKey(version="v", scene="parallel", params=(("d", 1.0), ("l", 8.0)), eps=eps,
                    oracle="garmann")


def point(eps=0.5, ok=True, exit_code=0):
    return StoredPoint(key(eps), ok, exit_code, "" if ok else "boom", '{"links": 1}', 0.1)


# --- Validation when opened ------------------------------------------------------------


def test_new_cache_is_marked_as_ours(tmp_path):
    path = tmp_path / "c.sqlite"
    with ResultStore(path) as store:
        store.put(point())
    with sqlite3.connect(path) as con:
        assert con.execute("PRAGMA application_id").fetchone()[0] == APPLICATION_ID
        assert con.execute("PRAGMA user_version").fetchone()[0] == STORE_SCHEMA_VERSION
        assert con.execute("PRAGMA journal_mode").fetchone()[0] == "wal"
    with ResultStore(path) as store:       # and opens again
        assert store.get(key()).ok


def test_empty_file_is_a_new_cache(tmp_path):
    path = tmp_path / "c.sqlite"
    path.write_bytes(b"")
    with ResultStore(path) as store:
        assert store.count() == 0


def expect_refused(path, match, remove=True):
    with pytest.raises(StoreError, match=match) as info:
        ResultStore(path)
    message = str(info.value)
    assert "\n" not in message and str(path) in message
    assert ("remove it" in message) == remove
    return message


def test_text_file_is_not_a_sqlite_database(tmp_path):
    path = tmp_path / "c.sqlite"
    path.write_text("results, but as text\n")
    message = expect_refused(path, "is not a SQLite database")
    assert message == (f"results cache {path} is not a SQLite database (it starts with "
                       f"b'results,'); remove it (rm {path}) or pass another --results "
                       "directory")


def test_corrupt_database_is_refused(tmp_path):
    path = tmp_path / "c.sqlite"
    with ResultStore(path) as store:
        for n in range(200):
            store.put(point(eps=1.0 / (n + 1)))
    with sqlite3.connect(path) as con:
        con.execute("PRAGMA wal_checkpoint(TRUNCATE)")
    with open(path, "r+b") as fh:      # scribble over the b-tree pages, keep the header
        size = fh.seek(0, 2)
        for offset in range(4096, size, 4096):
            fh.seek(offset)
            fh.write(b"\x0d\xff\xff\x7f" * 16)
    expect_refused(path, "is corrupt")


def test_database_of_another_program_is_refused(tmp_path):
    path = tmp_path / "users.sqlite"
    with sqlite3.connect(path) as con:
        con.execute("CREATE TABLE users (id INTEGER, name TEXT)")
    expect_refused(path, r"is not a results cache: it holds the table\(s\) users")
    with sqlite3.connect(path) as con:
        con.execute("CREATE TABLE points (key TEXT, value TEXT)")
        con.execute("DROP TABLE users")
    expect_refused(path, "its table 'points' lacks eps, .* has value")
    other = tmp_path / "app.sqlite"
    with sqlite3.connect(other) as con:
        con.execute("PRAGMA application_id = 42")
    expect_refused(other, "belongs to another program .*0x2a")


def test_cache_of_a_newer_layout_is_refused(tmp_path):
    path = tmp_path / "c.sqlite"
    ResultStore(path).close()
    with sqlite3.connect(path) as con:
        con.execute(f"PRAGMA user_version = {STORE_SCHEMA_VERSION + 1}")
    expect_refused(path, "written by a newer analysis")


def test_a_new_cache_opens_once_another_writer_is_done(tmp_path):
    # Another process may hold a new file's write lock as this one switches it to WAL;
    # SQLite refuses that switch at once, outside the busy timeout, so the store waits.
    path = tmp_path / "c.sqlite"
    other = sqlite3.connect(path, isolation_level=None, check_same_thread=False)
    other.execute("BEGIN IMMEDIATE")
    done = threading.Timer(0.3, other.execute, ("COMMIT",))
    done.start()
    try:
        start = time.monotonic()
        ResultStore(path).close()
        assert time.monotonic() - start >= 0.25
    finally:
        done.join()
        other.close()


def test_not_a_file_or_not_writable(tmp_path):
    expect_refused(tmp_path, "is not a regular file", remove=False)
    expect_refused(tmp_path / "no" / "such" / "dir.sqlite", "cannot be opened or written",
                   remove=False)


def test_unreadable_record_is_a_store_error(tmp_path, data_dir):
    from hrbench_analysis.claimfile import load_claims
    from hrbench_analysis.sweep import get_claim_data
    from hrbench_analysis.sweep_plan import expand_claim
    (claim,) = load_claims(data_dir / "small_claims.toml")
    points = expand_claim(claim, "quick", "hrbench", "v")[:1]
    with ResultStore(tmp_path / "c.sqlite") as store:
        store.put(StoredPoint(points[0].key, True, 0, "", "not json", 0.1))
        with pytest.raises(StoreError, match="holds an unreadable record"):
            get_claim_data(claim, points, store)


# --- Leases ------------------------------------------------------------------------------


def test_a_lease_makes_other_sweeps_wait_and_put_releases_it(tmp_path):
    path = tmp_path / "c.sqlite"
    with ResultStore(path) as a, ResultStore(path) as b:
        assert a.acquire(key()) == ACQUIRED
        assert a.acquire(key()) == ACQUIRED          # its own lease again
        assert b.acquire(key()) == BUSY              # same process, but a's lease is live
        (lease,) = b.leases()
        assert lease.token == a.token and lease.pid == a.pid
        a.put(point())
        assert b.leases() == []
        assert b.acquire(key()) == DONE


def test_a_failure_stored_meanwhile_is_not_run_twice(tmp_path):
    path = tmp_path / "c.sqlite"
    with ResultStore(path) as a, ResultStore(path) as b:
        since = time.time()
        assert a.acquire(key(), since=since) == ACQUIRED
        a.put(point(ok=False, exit_code=139))         # a crash: retried by a later sweep,
        assert b.acquire(key(), since=since) == DONE  # but not by one running meanwhile
        assert b.acquire(key(), since=time.time() + 1) == ACQUIRED


def test_lease_of_a_dead_process_is_taken_over(tmp_path):
    path = tmp_path / "c.sqlite"
    dead = subprocess.run([sys.executable, "-c", "import os; print(os.getpid())"],
                          capture_output=True, text=True, check=True)
    pid = int(dead.stdout)
    with ResultStore(path) as store:
        store.acquire(key())
        store._db.execute("UPDATE leases SET pid = ?, token = 'dead'", (pid,))
        with ResultStore(path) as other:
            assert other.acquire(key()) == ACQUIRED
            (lease,) = other.leases()
            assert lease.token == other.token


def test_stale_lease_of_another_host_is_taken_over(tmp_path):
    path = tmp_path / "c.sqlite"
    with ResultStore(path) as a, ResultStore(path, lease_timeout=60) as b:
        a.acquire(key())
        a._db.execute("UPDATE leases SET host = 'elsewhere', pid = 1")
        assert b.acquire(key()) == BUSY              # another host: only its age counts
        a._db.execute("UPDATE leases SET renewed_at = renewed_at - 61")
        assert b.acquire(key()) == ACQUIRED


def test_renew_keeps_a_lease_and_close_releases_it(tmp_path):
    path = tmp_path / "c.sqlite"
    a = ResultStore(path)
    a.acquire(key())
    a._db.execute("UPDATE leases SET renewed_at = renewed_at - 1000")
    a.renew()
    with ResultStore(path) as b:
        (lease,) = b.leases()
        assert time.time() - lease.renewed_at < 10
        a.close()
        assert b.leases() == []


def test_old_cache_gains_the_lease_table(tmp_path):
    path = tmp_path / "old.sqlite"
    with ResultStore(path) as store:
        store.put(point())
    with sqlite3.connect(path) as con:            # as the analysis wrote it before leases
        con.execute("DROP TABLE leases")
        con.execute("PRAGMA application_id = 0")
        con.execute("PRAGMA user_version = 0")
    with ResultStore(path) as store:
        assert store.get(key()).ok and store.leases() == []
    with sqlite3.connect(path) as con:
        assert con.execute("PRAGMA application_id").fetchone()[0] == APPLICATION_ID
        rows = con.execute("SELECT options FROM points").fetchall()
    assert [json.loads(r[0]) for r in rows] == [{}]
