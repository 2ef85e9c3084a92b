"""The layout of the results cache's SQLite database: its tables and columns, what each
cell read back must hold, and the id and layout number the file is marked with.
"""

import json
import math

__all__ = ["APPLICATION_ID", "STORE_SCHEMA_VERSION"]

#: SQLite ``application_id`` of a results cache ("hrbc"). A cache written before the id
#: existed has 0 and is recognised by its tables.
APPLICATION_ID = 0x68726263
#: SQLite ``user_version`` of the current layout: 2 = table ``points`` with ``options``
#: and table ``leases``. 0 is a cache written before the layout had a number (``points``
#: with or without ``options``), migrated when opened.
STORE_SCHEMA_VERSION = 2

_SQLITE_MAGIC = b"SQLite format 3\x00"

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
_LEASES = """
CREATE TABLE IF NOT EXISTS leases (
    key TEXT PRIMARY KEY,
    host TEXT NOT NULL,
    pid INTEGER NOT NULL,
    token TEXT NOT NULL,
    started_at REAL NOT NULL,
    renewed_at REAL NOT NULL
)
"""
_COLUMNS = ("key", "version", "scene", "params", "eps", "oracle", "min_area", "max_depth",
            "mode", "ok", "exit_code", "stderr", "output", "wall_seconds", "finished_at",
            "options")
_LEASE_COLUMNS = ("key", "host", "pid", "token", "started_at", "renewed_at")
#: Tables of a results cache; any other table makes a database foreign.
_TABLES = ("points", "leases")


def _is_real(value):
    return isinstance(value, (int, float)) and not isinstance(value, bool) and \
        math.isfinite(value)


#: What each cell of the points table read back must be.
_CELL_TYPES = {
    "key": lambda v: isinstance(v, str),
    "ok": lambda v: v in (0, 1) and isinstance(v, int),
    "exit_code": lambda v: isinstance(v, int) and not isinstance(v, bool),
    "stderr": lambda v: isinstance(v, str),
    "output": lambda v: isinstance(v, str),
    "options": lambda v: v is None or isinstance(v, str),
    "wall_seconds": lambda v: _is_real(v) and v >= 0,
    "finished_at": _is_real,
}


def _options_of(text):
    # The options column as (name, text) pairs; a cell that is not a JSON object as none.
    try:
        options = json.loads(text)
    except (TypeError, ValueError):
        return ()
    return tuple(options.items()) if isinstance(options, dict) else ()
