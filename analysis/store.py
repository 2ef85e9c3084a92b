"""The results cache: every run of a sweep, kept in an embedded SQLite database.

Each point is keyed by everything that determines its counts: the engine's version,
the scene, its parameters, ``eps``, the oracle, the recursion limits, further engine
options (``--visibility``, ``--method``, ...) and the mode. A
finished point is committed the moment it finishes (WAL journal), so a rerun reuses it
and an interrupted sweep resumes without losing any point. A failed point is stored
too, with its exit code and the last line of its standard error.
"""

import json
import sqlite3
import time
from dataclasses import dataclass

__all__ = ["PointKey", "StoredPoint", "ResultStore", "CACHED_FAILURES"]

#: Exit codes of ``hrbench`` whose failures are deterministic and therefore cached:
#: 2 (usage or input error) and 3 (a refinement limit was reached). Any other failure
#: (a crash, a signal) is tried again on the next sweep.
CACHED_FAILURES = (2, 3)


@dataclass(frozen=True)
class PointKey:
    """Everything that determines the counts of one run.

    Attributes
    ----------
    version : str
        Engine version (output of ``hrbench --version``).
    scene : str
        Scene family.
    params : tuple of (str, float)
        Scene parameters as requested, sorted by name (scene units).
    eps : float
        Oracle threshold (dimensionless).
    oracle : str
        Oracle name.
    min_area : float or None
        ``--min-area`` (scene units), if given.
    max_depth : int or None
        ``--max-depth`` (levels), if given.
    mode : str
        ``"count-only"`` or ``"store"``.
    options : tuple of (str, str)
        Further engine options as passed on the command line, sorted by name, e.g.
        ``(("method", "translation"),)`` for ``--method translation``.
    """

    version: str
    scene: str
    params: tuple
    eps: float
    oracle: str
    min_area: object = None
    max_depth: object = None
    mode: str = "count-only"
    options: tuple = ()

    def text(self):
        """A canonical string form of the key, used as the database's primary key.

        A key without options has the same text as before options existed, so points
        cached then stay valid.
        """
        obj = {
            "version": self.version, "scene": self.scene,
            "params": {k: repr(float(v)) for k, v in self.params},
            "eps": repr(float(self.eps)), "oracle": self.oracle,
            "min_area": None if self.min_area is None else repr(float(self.min_area)),
            "max_depth": self.max_depth, "mode": self.mode}
        if self.options:
            obj["options"] = {k: str(v) for k, v in self.options}
        return json.dumps(obj, sort_keys=True)


@dataclass
class StoredPoint:
    """One cached run.

    Attributes
    ----------
    key : PointKey
    ok : bool
        Whether the run exited with code 0 and printed a readable record.
    exit_code : int
        Exit code of the run (0 when ok; negative for a signal).
    stderr : str
        Last non-empty line of standard error ("" when ok).
    output : str
        Standard output (the JSON record when ok).
    wall_seconds : float
        Wall time of the whole process (s).
    """

    key: PointKey
    ok: bool
    exit_code: int
    stderr: str
    output: str
    wall_seconds: float


_SCHEMA = """
CREATE TABLE IF NOT EXISTS points (
    key TEXT PRIMARY KEY,
    version TEXT NOT NULL,
    scene TEXT NOT NULL,
    params TEXT NOT NULL,
    eps REAL NOT NULL,
    oracle TEXT NOT NULL,
    min_area REAL,
    max_depth INTEGER,
    mode TEXT NOT NULL,
    ok INTEGER NOT NULL,
    exit_code INTEGER NOT NULL,
    stderr TEXT NOT NULL,
    output TEXT NOT NULL,
    wall_seconds REAL NOT NULL,
    finished_at REAL NOT NULL,
    options TEXT NOT NULL DEFAULT '{}'
)
"""
_COLUMNS = ("key", "version", "scene", "params", "eps", "oracle", "min_area", "max_depth",
            "mode", "ok", "exit_code", "stderr", "output", "wall_seconds", "finished_at",
            "options")


class ResultStore:
    """A SQLite database of finished runs.

    Parameters
    ----------
    path : str or path-like
        Database file, created if missing (e.g. ``results/hrbench.sqlite``).

    Notes
    -----
    The database uses the WAL journal and commits every point on its own, so a process
    killed in the middle of a sweep leaves every finished point behind and no partial
    one. Use it from one thread; the sweep runner writes from its main thread only.
    """

    def __init__(self, path):
        self.path = str(path)
        self._db = sqlite3.connect(self.path, timeout=30.0)
        self._db.execute("PRAGMA journal_mode=WAL")
        self._db.execute("PRAGMA synchronous=NORMAL")
        self._db.execute(_SCHEMA)
        columns = {row[1] for row in self._db.execute("PRAGMA table_info(points)")}
        if "options" not in columns:
            # A cache written before engine options existed: add the column, keep the rows.
            self._db.execute("ALTER TABLE points ADD COLUMN options TEXT NOT NULL DEFAULT '{}'")
        self._db.commit()

    def close(self):
        """Close the database."""
        self._db.close()

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()

    def get(self, key):
        """The cached run for `key`, or ``None``.

        Parameters
        ----------
        key : PointKey

        Returns
        -------
        point : StoredPoint or None
        """
        row = self._db.execute(
            "SELECT ok, exit_code, stderr, output, wall_seconds FROM points WHERE key = ?",
            (key.text(),)).fetchone()
        if row is None:
            return None
        return StoredPoint(key, bool(row[0]), row[1], row[2], row[3], row[4])

    def is_final(self, key):
        """Whether `key` needs no new run: it succeeded, or failed deterministically."""
        point = self.get(key)
        return point is not None and (point.ok or point.exit_code in CACHED_FAILURES)

    def put(self, point):
        """Store a run and commit at once (a rerun of the same key replaces it).

        Parameters
        ----------
        point : StoredPoint
        """
        k = point.key
        self._db.execute(
            f"INSERT OR REPLACE INTO points ({', '.join(_COLUMNS)}) "
            f"VALUES ({', '.join('?' * len(_COLUMNS))})",
            (k.text(), k.version, k.scene, json.dumps(dict(k.params), sort_keys=True),
             float(k.eps), k.oracle, k.min_area, k.max_depth, k.mode, int(point.ok),
             int(point.exit_code), point.stderr, point.output, float(point.wall_seconds),
             time.time(), json.dumps(dict(k.options), sort_keys=True)))
        self._db.commit()

    def count(self):
        """Number of stored runs."""
        return self._db.execute("SELECT COUNT(*) FROM points").fetchone()[0]

    def keys(self):
        """Canonical key strings of every stored run (see :meth:`PointKey.text`)."""
        return [row[0] for row in self._db.execute("SELECT key FROM points")]
