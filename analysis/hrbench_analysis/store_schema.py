"""The layout of the results cache's SQLite database: its tables and columns, what each
cell read back must hold, and the id and layout number the file is marked with.
"""

import json
import math

__all__ = ["APPLICATION_ID", "STORE_SCHEMA_VERSION", "LEGACY_STATISTICS_FIELD"]

#: SQLite ``application_id`` of a results cache ("hrbc"). A cache written before the id
#: existed has 0 and is recognised by its tables.
APPLICATION_ID = 0x68726263
#: SQLite ``user_version`` of the current layout: 3 = table ``points`` with ``options``,
#: table ``leases`` and table ``statistics`` (the hierarchy statistics of a point, beside
#: its record). 2 kept the statistics inside the record (:data:`LEGACY_STATISTICS_FIELD`);
#: 0 is a cache written before the layout had a number (``points`` with or without
#: ``options``). Both are migrated when opened.
STORE_SCHEMA_VERSION = 3
#: The field of a run record in which layouts before 3 kept a point's hierarchy
#: statistics; moved to the table ``statistics`` when such a cache is opened.
LEGACY_STATISTICS_FIELD = "hierarchy_statistics"

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
_STATISTICS = """
CREATE TABLE IF NOT EXISTS statistics (
    key TEXT PRIMARY KEY,
    statistics TEXT NOT NULL
)
"""
_COLUMNS = ("key", "version", "scene", "params", "eps", "oracle", "min_area", "max_depth",
            "mode", "ok", "exit_code", "stderr", "output", "wall_seconds", "finished_at",
            "options")
_LEASE_COLUMNS = ("key", "host", "pid", "token", "started_at", "renewed_at")
_STATISTICS_COLUMNS = ("key", "statistics")
#: Tables of a results cache; any other table makes a database foreign.
_TABLES = ("points", "leases", "statistics")


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
    "statistics": lambda v: v is None or isinstance(v, str),
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


def _statistics_of(text):
    # The statistics cell as a dict; a missing cell, or one that is not a JSON object, as
    # None (the point then has no statistics).
    try:
        statistics = json.loads(text)
    except (TypeError, ValueError):
        return None
    return statistics if isinstance(statistics, dict) else None


def _split_record(text):
    # A record of a layout before 3: (the record without its statistics, the statistics
    # as JSON text), or None when it holds none.
    try:
        record = json.loads(text)
    except (TypeError, ValueError):
        return None
    if not isinstance(record, dict) or LEGACY_STATISTICS_FIELD not in record:
        return None
    statistics = record.pop(LEGACY_STATISTICS_FIELD)
    return json.dumps(record), json.dumps(statistics)
