"""Reading what the ``hrbench`` command line writes: run records (JSON), link lists and
solutions (CSV).

Every other module of the analysis works on plain numbers and arrays; this is the only
place that knows the field names of the engine's output. Any engine may write the
records (docs/engine-contract.md); their fields are those of the JSON Schema
``schemas/run-record.schema.json``, and :func:`parse_run_json` checks the fields the
analysis reads, naming the first one that is missing or of the wrong type. The names of
the counters are the engine's own (``hrbench capabilities --json``, read by
:mod:`hrbench_analysis.engine`); this module needs only the few it reads by name
(:data:`COUNTERS`). Their meaning is in docs/conventions.md.

Modules
-------
record    run records (``run --json``, ``solve --json``): :func:`parse_run_json`,
          :func:`read_record`
links     link lists (``links --out``): :func:`read_links_csv`
solution  solutions (``solve --out``): :func:`read_solution`
scene     scenes (``save``): :func:`read_scene_segments`, :func:`read_scene_digest`
"""

import importlib

from .record import (
    ALIASES,
    COUNTERS,
    MAX_RECORD_BYTES,
    MEASURES,
    SCHEMA_VERSION,
    SOLVE_MEASURES,
    TIMES,
    ResultFormatError,
    RunResult,
    environment_names,
    parse_run_json,
    read_record,
    run_environment,
)

#: The readers that need numpy, by module: imported when first named, so that the
#: record reader serves the tools that run on the standard library alone
#: (``tools/check_baseline.py``).
_NUMPY_READERS = {
    "links": ("MAX_LINKS_BYTES", "LinkTable", "read_links_csv"),
    "scene": ("read_scene_digest", "read_scene_segments"),
    "solution": ("COLUMNS_2D", "COLUMNS_3D", "Solution", "read_solution"),
}
_MODULE_OF = {name: module for module, names in _NUMPY_READERS.items() for name in names}


def __getattr__(name):
    module = _MODULE_OF.get(name)
    if module is None:
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    value = getattr(importlib.import_module(f".{module}", __name__), name)
    globals()[name] = value
    return value

__all__ = [
    "COUNTERS",
    "MEASURES",
    "SOLVE_MEASURES",
    "TIMES",
    "ALIASES",
    "SCHEMA_VERSION",
    "MAX_RECORD_BYTES",
    "MAX_LINKS_BYTES",
    "RunResult",
    "ResultFormatError",
    "LinkTable",
    "parse_run_json",
    "read_record",
    "read_links_csv",
    "run_environment",
    "environment_names",
    "COLUMNS_2D",
    "COLUMNS_3D",
    "Solution",
    "read_solution",
    "read_scene_segments",
    "read_scene_digest",
]
