"""The results cache: every run of a sweep, kept in an embedded SQLite database.

Each point is keyed by everything that determines its counts: the engine's version,
the scene, its parameters, ``eps``, the oracle, the recursion limits, further engine
options (``--visibility``, ``--method``, ...) and the mode. A
finished point is committed the moment it finishes (WAL journal), so a rerun reuses it
and an interrupted sweep resumes without losing any point. A failed point is stored
too, with its exit code and the last line of its standard error.

The file is checked when it is opened: a file that is not a SQLite database, fails
SQLite's ``quick_check``, or holds tables or an application id that are not this
cache's is refused with a :class:`StoreError` naming the file (the command line exits
with code 2). A cache of an older layout of this analysis is migrated in place.

Several sweeps may share one cache at the same time and share its work: before running
a point a sweep takes a *lease* on it (a row of the table ``leases``, written in a
``BEGIN IMMEDIATE`` transaction), other sweeps skip leased points and read their results
when they are stored. A lease lapses when its owner, a process on the same host, is
gone (or its process id now belongs to a process started after the lease), when its
owner has not renewed it for :data:`LEASE_TIMEOUT` seconds (owners renew every
:data:`LEASE_RENEW` seconds while the point runs), or when it is dated more than
:data:`LEASE_RENEW` seconds ahead of this host's clock; then another sweep takes the
point over. So no lease outlives its process by more than :data:`LEASE_TIMEOUT`.

A point's hierarchy statistics (:mod:`hrbench_analysis.lemmas`), where measured, are kept
beside its record (table ``statistics``), never inside it: the record stays what the
engine printed.

A point's key and record are :mod:`hrbench_analysis.store_points`'s, a lease and its
timing :mod:`hrbench_analysis.store_leases`'s, the database's tables and columns
:mod:`hrbench_analysis.store_schema`'s.
"""

import json
import os
import socket
import sqlite3
import time
import uuid
from contextlib import contextmanager

from .errors import AnalysisError, one_line
from .store_leases import LEASE_RENEW, LEASE_TIMEOUT, Lease, _pid_alive
from .store_points import StoredPoint, _without_version, is_verdict
from .store_schema import (
    _CELL_TYPES,
    _COLUMNS,
    _LEASE_COLUMNS,
    _LEASES,
    _SCHEMA,
    _SQLITE_MAGIC,
    _STATISTICS,
    _STATISTICS_COLUMNS,
    _TABLES,
    APPLICATION_ID,
    LEGACY_STATISTICS_FIELD,
    STORE_SCHEMA_VERSION,
    _options_of,
    _split_record,
    _statistics_of,
)

__all__ = [
    "ResultStore",
    "StoreError",
    "is_verdict",
    "BUSY_TIMEOUT",
    "ACQUIRED",
    "DONE",
    "BUSY",
]

#: Seconds to wait for another process's write transaction before giving up.
BUSY_TIMEOUT = 60.0

#: Results of :meth:`ResultStore.acquire`: the point is this sweep's to run,
ACQUIRED = "acquired"
#: ... it needs no run (final, or stored by another sweep since this one started),
DONE = "done"
#: ... or another live sweep holds its lease.
BUSY = "busy"


class StoreError(AnalysisError):
    """A results cache that cannot be used: not SQLite, corrupt, foreign, unwritable.

    The message is one line naming the file and what to do.
    """



class ResultStore:
    """A SQLite database of finished runs, shared safely by concurrent sweeps.

    Parameters
    ----------
    path : str or path-like
        Database file, created if missing (e.g. ``results/hrbench.sqlite``).
    lease_timeout : float, optional
        Seconds after which an unrenewed lease of another sweep lapses (default
        :data:`LEASE_TIMEOUT`).

    Raises
    ------
    StoreError
        If the file is not a SQLite database, is corrupt (``PRAGMA quick_check``), holds
        tables or an application id of something else, was written by a newer layout,
        or cannot be opened or written. The message is one line naming the file.

    Notes
    -----
    The database uses the WAL journal and commits every point on its own, so a process
    killed in the middle of a sweep leaves every finished point behind and no partial
    one. Writes run in ``BEGIN IMMEDIATE`` transactions and wait up to
    :data:`BUSY_TIMEOUT` seconds for another process's. Use one store from one thread;
    the sweep runner writes from its main thread only.
    """

    def __init__(self, path, lease_timeout=LEASE_TIMEOUT):
        self.path = os.fspath(path)
        self.lease_timeout = float(lease_timeout)
        self.host = socket.gethostname()
        self.pid = os.getpid()
        self.token = uuid.uuid4().hex
        self._file_iv()
        try:
            self._db = sqlite3.connect(self.path, timeout=BUSY_TIMEOUT, isolation_level=None)
        except sqlite3.Error as exc:
            raise self._error(exc) from None
        try:
            self._open()
        except BaseException as exc:
            self._db.close()
            if isinstance(exc, sqlite3.Error):
                raise self._error(exc) from None
            raise

    # -- opening and checking -----------------------------------------------------------

    def _fail(self, what, remove=True):
        # A StoreError naming the file, with advice.
        advice = (f"; remove it (rm {self.path}) or pass another --results directory"
                  if remove else "")
        return StoreError(one_line(f"results cache {self.path} {what}{advice}"))

    def _cells_iv(self, text, row, columns):
        # The cells of a points row, or a StoreError naming the first of the wrong type
        # (SQLite keeps any type in any column: a cache edited or written by a foreign
        # program may hold text where a number is due).
        for column, value in zip(columns, row, strict=True):
            if not _CELL_TYPES[column](value):
                raise self._fail(f"holds a cell of the wrong type: column {column} of point "
                                 f"{one_line(text, 80)} is {one_line(repr(value), 40)}")
        return row

    def _error(self, exc):
        # Translate a sqlite3 error into a StoreError with advice.
        message = str(exc)
        lower = message.lower()
        if "not a database" in lower:
            return self._fail(f"is not a SQLite database ({message})")
        if "malformed" in lower or "corrupt" in lower:
            return self._fail(f"is corrupt ({message})")
        if "locked" in lower or "busy" in lower:
            return self._fail(f"is locked by another process for more than {BUSY_TIMEOUT:g} s "
                              f"({message})", remove=False)
        if "unable to open" in lower or "readonly" in lower or "read-only" in lower \
                or "disk i/o" in lower or "full" in lower:
            return self._fail(f"cannot be opened or written ({message}); check the "
                              "permissions and free space of its directory", remove=False)
        return self._fail(f"cannot be used ({message})")

    def _file_iv(self):
        # Refuse what is not a file, or a file that does not start like SQLite.
        if not os.path.exists(self.path):
            return
        if not os.path.isfile(self.path):
            raise self._fail("is not a regular file", remove=False)
        try:
            with open(self.path, "rb") as fh:
                head = fh.read(len(_SQLITE_MAGIC))
        except OSError as exc:
            raise self._fail(f"cannot be read ({exc.strerror or exc})", remove=False) from None
        if head and head != _SQLITE_MAGIC:
            raise self._fail(f"is not a SQLite database (it starts with {head[:8]!r})")

    def _open(self):
        db = self._db
        db.execute(f"PRAGMA busy_timeout = {int(BUSY_TIMEOUT * 1000)}")
        problems = [row[0] for row in db.execute("PRAGMA quick_check")]
        if problems != ["ok"]:
            raise self._fail(f"is corrupt (quick_check: {'; '.join(map(str, problems[:3]))})")
        app = db.execute("PRAGMA application_id").fetchone()[0]
        if app not in (0, APPLICATION_ID):
            raise self._fail(f"belongs to another program (SQLite application_id {app:#x}, "
                             f"a results cache has {APPLICATION_ID:#x})")
        self._use_wal()
        db.execute("PRAGMA synchronous=NORMAL")
        with self._write():
            version = db.execute("PRAGMA user_version").fetchone()[0]
            if version > STORE_SCHEMA_VERSION:
                raise self._fail(f"was written by a newer analysis (layout {version}, this one "
                                 f"reads up to {STORE_SCHEMA_VERSION})")
            tables = {row[0] for row in db.execute(
                "SELECT name FROM sqlite_master WHERE type = 'table' "
                "AND name NOT LIKE 'sqlite%'")}
            foreign = sorted(tables - set(_TABLES))
            if foreign:
                raise self._fail(f"is not a results cache: it holds the table(s) "
                                 f"{', '.join(foreign)}")
            if tables and "points" not in tables:
                raise self._fail("is not a results cache: it has no table 'points'")
            self._columns_iv("points", _COLUMNS, optional=("options",))
            self._columns_iv("leases", _LEASE_COLUMNS)
            self._columns_iv("statistics", _STATISTICS_COLUMNS)
            db.execute(_SCHEMA)
            columns = {row[1] for row in db.execute("PRAGMA table_info(points)")}
            if "options" not in columns:
                # A cache written before engine options existed: add the column, keep the rows.
                db.execute("ALTER TABLE points ADD COLUMN options TEXT NOT NULL DEFAULT '{}'")
            db.execute(_LEASES)
            db.execute(_STATISTICS)
            if version < 3:
                self._move_statistics()
            db.execute(f"PRAGMA application_id = {APPLICATION_ID}")
            db.execute(f"PRAGMA user_version = {STORE_SCHEMA_VERSION}")

    def _use_wal(self):
        # Switching to WAL needs the file to itself, and SQLite answers "locked" at once,
        # without waiting through the busy timeout, while another process opens the same
        # new cache: retry for as long as any other write may wait.
        deadline = time.monotonic() + BUSY_TIMEOUT
        while True:
            try:
                self._db.execute("PRAGMA journal_mode=WAL")
                return
            except sqlite3.OperationalError as exc:
                if "locked" not in str(exc).lower() or time.monotonic() > deadline:
                    raise
                time.sleep(0.01)

    def _move_statistics(self):
        # A cache of a layout before 3 kept a point's hierarchy statistics inside its
        # record: move them beside it, leaving the record as the engine printed it.
        rows = self._db.execute("SELECT key, output FROM points WHERE output LIKE ?",
                                (f'%"{LEGACY_STATISTICS_FIELD}"%',)).fetchall()
        for key, output in rows:
            split = _split_record(output)
            if split is None:
                continue
            record, statistics = split
            self._db.execute("UPDATE points SET output = ? WHERE key = ?", (record, key))
            self._put_statistics(key, statistics)

    def _put_statistics(self, key, statistics):
        # A point's hierarchy statistics (JSON text), beside its record.
        self._db.execute("INSERT OR REPLACE INTO statistics (key, statistics) VALUES (?, ?)",
                         (key, statistics))

    def _columns_iv(self, table, expected, optional=()):
        # A table of ours, if present, must have our columns (extra ones are a foreign
        # layout too, since rows are written with our columns only).
        columns = {row[1] for row in self._db.execute(f"PRAGMA table_info({table})")}
        if not columns:
            return
        missing = sorted(set(expected) - columns - set(optional))
        extra = sorted(columns - set(expected))
        if missing or extra:
            detail = ", ".join(([f"lacks {', '.join(missing)}"] if missing else [])
                               + ([f"has {', '.join(extra)}"] if extra else []))
            raise self._fail(f"is not a results cache: its table {table!r} {detail}")

    @contextmanager
    def _write(self):
        # One write transaction, taken at once (BEGIN IMMEDIATE) so that two sweeps never
        # interleave a read and a write of the same rows.
        self._db.execute("BEGIN IMMEDIATE")
        try:
            yield
        except BaseException:
            try:
                self._db.execute("ROLLBACK")
            except sqlite3.Error:
                pass
            raise
        self._db.execute("COMMIT")

    @contextmanager
    def _guard(self):
        # Report any sqlite3 error of a method as a StoreError.
        try:
            yield
        except sqlite3.Error as exc:
            raise self._error(exc) from None

    # -- life cycle ---------------------------------------------------------------------

    def close(self):
        """Release this store's leases and close the database."""
        try:
            self.release()
        except StoreError:
            pass
        self._db.close()

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()

    # -- points -------------------------------------------------------------------------

    def known_seconds(self):
        """How long each run took that succeeded, under any engine version.

        Returns
        -------
        seconds : dict of str to float
            Wall seconds of the latest successful run of each
            :meth:`~hrbench_analysis.store_points.PointKey.run_text`:
            the sweep's cost model (:func:`hrbench_analysis.sweep.run_points`).
        """
        with self._guard():
            rows = self._db.execute("SELECT key, wall_seconds FROM points WHERE ok = 1 "
                                    "ORDER BY finished_at").fetchall()
        rows = [self._cells_iv(row[0], row, ("key", "wall_seconds")) for row in rows]
        try:
            return {_without_version(key): float(seconds) for key, seconds in rows}
        except (ValueError, AttributeError):  # a key that is not a JSON object
            raise self._fail("holds a point whose key is not a JSON object") from None

    def get(self, key):
        """The cached run for `key`, or ``None``.

        Parameters
        ----------
        key : PointKey

        Returns
        -------
        point : StoredPoint or None
        """
        with self._guard():
            row = self._db.execute(
                "SELECT p.ok, p.exit_code, p.stderr, p.output, p.wall_seconds, "
                "p.finished_at, s.statistics FROM points AS p LEFT JOIN statistics AS s "
                "ON s.key = p.key WHERE p.key = ?", (key.text(),)).fetchone()
        if row is None:
            return None
        row = self._cells_iv(key.text(), row, ("ok", "exit_code", "stderr", "output",
                                                "wall_seconds", "finished_at", "statistics"))
        return StoredPoint(key, bool(row[0]), row[1], row[2], row[3], row[4], row[5],
                           _statistics_of(row[6]))

    def is_final(self, key):
        """Whether `key` needs no new run: it succeeded, or failed deterministically."""
        point = self.get(key)
        return point is not None and point.final

    def put(self, point):
        """Store a run and commit at once (a rerun of the same key replaces it).

        Its statistics, if any, go to the table ``statistics`` beside the record, in the
        same transaction. This store's lease on the point, if any, is released there too.

        Parameters
        ----------
        point : StoredPoint
        """
        k = point.key
        text = k.text()
        with self._guard(), self._write():
            self._db.execute(
                f"INSERT OR REPLACE INTO points ({', '.join(_COLUMNS)}) "
                f"VALUES ({', '.join('?' * len(_COLUMNS))})",
                (text, k.version, k.scene, json.dumps(dict(k.params), sort_keys=True),
                 float(k.eps), k.oracle, k.min_area, k.max_depth, k.mode, int(point.ok),
                 int(point.exit_code), point.stderr, point.output, float(point.wall_seconds),
                 time.time(), json.dumps(dict(k.options), sort_keys=True)))
            if point.statistics is None:
                self._db.execute("DELETE FROM statistics WHERE key = ?", (text,))
            else:
                self._put_statistics(text, json.dumps(point.statistics))
            self._db.execute("DELETE FROM leases WHERE key = ? AND token = ?",
                             (text, self.token))

    def count(self):
        """Number of stored runs."""
        with self._guard():
            return self._db.execute("SELECT COUNT(*) FROM points").fetchone()[0]

    def keys(self):
        """Canonical key strings of every stored run (see
        :meth:`~hrbench_analysis.store_points.PointKey.text`)."""
        with self._guard():
            return [row[0] for row in self._db.execute("SELECT key FROM points")]

    # -- leases -------------------------------------------------------------------------

    def _lease(self, text):
        row = self._db.execute(f"SELECT {', '.join(_LEASE_COLUMNS)} FROM leases WHERE key = ?",
                               (text,)).fetchone()
        return None if row is None else Lease(*row)

    def _settled(self, text, since):
        # Whether the point needs no run by this sweep: final, or stored since `since`.
        row = self._db.execute("SELECT ok, exit_code, stderr, options, finished_at FROM points "
                               "WHERE key = ?", (text,)).fetchone()
        if row is None:
            return False
        ok, code, message, options, finished_at = self._cells_iv(
            text, row, ("ok", "exit_code", "stderr", "options", "finished_at"))
        return bool(ok) or is_verdict(code, message, _options_of(options)) or (
            since is not None and finished_at >= since)

    def _held(self, lease, now):
        # Whether another sweep's lease still counts: renewed within lease_timeout, not
        # dated ahead of this clock by more than a renewal (no live owner renews into
        # the future; such a lease would otherwise hold for as long as it is ahead), and,
        # on this host, owned by a live process that started before the lease.
        if lease is None or lease.token == self.token:
            return False
        if not all(isinstance(t, (int, float)) and not isinstance(t, bool)
                   for t in (lease.started_at, lease.renewed_at)):
            return False  # a row no sweep of this analysis wrote
        if not -LEASE_RENEW <= now - lease.renewed_at <= self.lease_timeout:
            return False
        return not (lease.host == self.host and lease.pid != self.pid
                    and not _pid_alive(lease.pid, lease.started_at))

    def acquire(self, key, since=None):
        """Take the lease on a point before running it.

        Parameters
        ----------
        key : PointKey
        since : float, optional
            Start of the calling sweep (seconds since the epoch): a point stored since
            then, even as a failure that is otherwise retried, needs no second run.

        Returns
        -------
        state : {ACQUIRED, DONE, BUSY}
            :data:`ACQUIRED`: the lease is this store's, run the point and :meth:`put`
            it. :data:`DONE`: the point is final or was stored since `since`.
            :data:`BUSY`: another live sweep holds the lease; ask again later. A lease
            whose owner process on this host is gone, that was not renewed for
            `lease_timeout` seconds or that is dated ahead of this clock by more than
            :data:`LEASE_RENEW` seconds is taken over.
        """
        text = key.text()
        with self._guard():
            # Look first without the write lock: most answers need none.
            now = time.time()
            if self._settled(text, since):
                return DONE
            if self._held(self._lease(text), now):
                return BUSY
            with self._write():
                now = time.time()
                if self._settled(text, since):
                    return DONE
                if self._held(self._lease(text), now):
                    return BUSY
                self._db.execute(
                    f"INSERT OR REPLACE INTO leases ({', '.join(_LEASE_COLUMNS)}) "
                    "VALUES (?, ?, ?, ?, ?, ?)",
                    (text, self.host, self.pid, self.token, now, now))
        return ACQUIRED

    def renew(self):
        """Renew every lease of this store (call it at least every :data:`LEASE_RENEW` s)."""
        with self._guard(), self._write():
            self._db.execute("UPDATE leases SET renewed_at = ? WHERE token = ?",
                             (time.time(), self.token))

    def release(self):
        """Give up every lease of this store (its points were stored or will not run)."""
        with self._guard(), self._write():
            self._db.execute("DELETE FROM leases WHERE token = ?", (self.token,))

    def leases(self):
        """Every lease in the cache, of any sweep.

        Returns
        -------
        leases : list of Lease
        """
        with self._guard():
            return [Lease(*row) for row in self._db.execute(
                f"SELECT {', '.join(_LEASE_COLUMNS)} FROM leases ORDER BY key")]
