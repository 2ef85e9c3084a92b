"""Reading Google Benchmark JSON output (``--benchmark_out_format=json``).

Standard library only, so that ``tools/merge_bench.py`` runs with any Python 3.11. The
reader is tolerant of what it does not use: unknown fields are ignored, optional fields
may be missing, and the schema version is checked when the file states one
(``context.json_schema_version``; Google Benchmark 1.7 does not write it). It is strict
about what it reads: a regular file of at most :data:`MAX_FILE_BYTES` bytes, strict JSON
(no ``NaN``, no key given twice), times that are finite numbers ``>= 0``.
"""

import math

from ..errors import AnalysisError, read_json

__all__ = ["InputError", "MAX_FILE_BYTES", "load_benchmark_file", "get_repetition_times",
           "merge_benchmark_files", "time_unit", "format_time"]

#: Largest benchmark file read, in bytes: a suite of thousands of benchmarks with 100
#: repetitions each writes a few MiB.
MAX_FILE_BYTES = 256 << 20

# Schema versions of the Google Benchmark JSON format this reader understands.
_SUPPORTED_SCHEMA_VERSIONS = (1,)

# Nanoseconds per unit of Google Benchmark's `time_unit`.
_NS_PER_UNIT = {"ns": 1.0, "us": 1e3, "ms": 1e6, "s": 1e9}


def time_unit(ns):
    """The unit to show a time of `ns` nanoseconds in: ``(name, nanoseconds per unit)``,
    the largest of s, ms, us that `ns` reaches, else ns."""
    for unit, scale in (("s", 1e9), ("ms", 1e6), ("us", 1e3)):
        if ns >= scale:
            return unit, scale
    return "ns", 1.0


def format_time(ns):
    """A time of `ns` nanoseconds in its unit (:func:`time_unit`), 4 significant digits:
    ``"12.79 ms"``."""
    unit, scale = time_unit(ns)
    return f"{ns / scale:.4g} {unit}"


class InputError(AnalysisError, ValueError):
    """An input file is missing, unreadable or not what the tool expects (exit code 2)."""


def load_benchmark_file(path):
    """Read a Google Benchmark JSON file.

    Parameters
    ----------
    path : str or path-like
        File written with ``--benchmark_out=F.json --benchmark_out_format=json``.

    Returns
    -------
    dict
        The parsed file, with a ``benchmarks`` list and a ``context`` dict
        (empty if the file has none).

    Raises
    ------
    InputError
        If the file cannot be read, is not a regular file of at most
        :data:`MAX_FILE_BYTES` bytes, is not strict JSON, has no ``benchmarks`` list or
        states an unsupported schema version.
    """
    data = read_json(path, MAX_FILE_BYTES, "benchmark file", str(path), InputError)
    if not isinstance(data, dict) or not isinstance(data.get("benchmarks"), list):
        raise InputError(f"{path} is not Google Benchmark JSON: no 'benchmarks' list")
    context = data.setdefault("context", {})
    version = context.get("json_schema_version")
    if version is not None and version not in _SUPPORTED_SCHEMA_VERSIONS:
        raise InputError(f"{path}: json_schema_version {version} is not supported "
                         f"(supported: {', '.join(map(str, _SUPPORTED_SCHEMA_VERSIONS))})")
    return data



def iteration_rows(data):
    """The rows of a Google Benchmark JSON report that measure one run each.

    Parameters
    ----------
    data : dict
        The report, with its list ``benchmarks``.

    Yields
    ------
    name, row : object, dict
        The row's ``run_name`` (its ``name`` when it has none; not checked) and the row,
        for every row of ``run_type`` iteration (aggregates such as means are left out)
        without ``error_occurred``.
    """
    for row in data["benchmarks"]:
        if not isinstance(row, dict) or row.get("run_type", "iteration") != "iteration":
            continue
        if row.get("error_occurred"):
            continue
        yield row.get("run_name", row.get("name")), row

def get_repetition_times(data, metric="real_time"):
    """Collect the per-repetition times of every benchmark.

    Parameters
    ----------
    data : dict
        A file as returned by `load_benchmark_file`.
    metric : {'real_time', 'cpu_time'}
        Which time to collect.

    Returns
    -------
    dict of str to list of float
        For each benchmark (its ``run_name``, or ``name``), the times of its
        iteration rows in file order, in nanoseconds per iteration. Aggregate
        rows (mean, median, stddev, BigO, RMS, ...) are skipped.

    Raises
    ------
    InputError
        If a time is not a finite number ``>= 0`` (naming the benchmark), or its
        ``time_unit`` is not one of ns, us, ms, s.
    """
    if metric not in ("real_time", "cpu_time"):
        raise ValueError(f"metric must be 'real_time' or 'cpu_time', not {metric!r}")
    times = {}
    for name, row in iteration_rows(data):
        value = row.get(metric)
        if not isinstance(name, str) or value is None:
            continue
        unit = _NS_PER_UNIT.get(row.get("time_unit", "ns"))
        if unit is None:
            raise InputError(f"benchmark {name}: time_unit {_short(row.get('time_unit'))} is "
                             f"not one of {', '.join(_NS_PER_UNIT)}")
        try:
            ns = float(value) * unit if _is_number(value) else math.nan
        except OverflowError:  # an integer beyond float64
            ns = math.inf
        if not (math.isfinite(ns) and ns >= 0):
            raise InputError(f"benchmark {name}: {metric} {_short(value)} is not a finite "
                             "time >= 0")
        times.setdefault(name, []).append(ns)
    return times


def _is_number(value):
    return isinstance(value, (int, float)) and not isinstance(value, bool)


def _short(value):
    text = repr(value)
    return text if len(text) <= 40 else text[:37] + "..."


def merge_benchmark_files(files):
    """Merge several Google Benchmark JSON files into one.

    Parameters
    ----------
    files : sequence of dict
        Files as returned by `load_benchmark_file`, e.g. one per suite.

    Returns
    -------
    dict
        The context of the first file, with the executables of all of them under
        ``executables``, and the concatenated ``benchmarks``.
    """
    if not files:
        raise ValueError("files must not be empty")
    context = dict(files[0]["context"])
    context["executables"] = [f["context"].get("executable") for f in files]
    benchmarks = [row for f in files for row in f["benchmarks"]]
    return {"context": context, "benchmarks": benchmarks}
