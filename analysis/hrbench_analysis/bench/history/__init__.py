"""Benchmark history over commits: ``hrbench-history record``, ``measure`` and ``html``.

``record`` stores one Google Benchmark run (a JSON file as ``make bench`` or
``refine_bench --benchmark_out=F.json`` writes it, with repetitions) in a history
directory, together with its commit (hash, commit date, subject), its machine (name,
CPU model, core count, load average at the start) and its build (Google Benchmark's
``library_build_type``, and the engine's version, build type, compiler and flags when
``--hrbench PATH`` is given).

``html`` draws a static, self-contained HTML page of every benchmark's time (median
of the repetitions, min and max as a band) and exact counters over the commits, one
series per machine, in the spirit of asv (https://asv.readthedocs.io): the commits
where the time steps (:func:`detect_steps`) are listed in a table at the top and
marked on the plots, and so are the commits where an exact counter changes (an
algorithm change).

Storage: one JSON file per run, ``DIR/<commit date>-<commit[:12]>-<content[:16]>.json``,
where ``content`` is the SHA-256 of the benchmark file's canonical JSON. Plain files
can be merged by copying (the runs of several CI machines, artifacts), read and
diffed by people, and committed to a branch; a file is published with a hard link
from a temporary name, which never overwrites, so concurrent recorders cannot clobber
each other and a reader never sees half a file. The name makes a second record of the
same run (same content, same commit) a no-op, and the content hash refuses the same
measurement under another commit: one measurement is never two points. See
docs/history.md.

``measure BASE..HEAD`` builds every commit of a range in its own git worktree (the code
of the CI gates, :mod:`hrbench_analysis.bench.builds`), runs its benchmarks and records them,
as asv's ``asv run`` does.

A step is flagged only with at least 3 points on each side, and is credited to the range
of commits between the last point before it and the first after it: the commits of that
range this machine did not measure are listed (git is asked in ``--repo``).

Exit codes of the command: 0 success (also a run that was already recorded), 1
``measure`` could not build or run some commit (the others are recorded), 2 usage or
input error, 74 the page could not be written (the previous page is kept): one line on
standard error for each error.

Modules
-------
steps  step detection in a series (:func:`detect_steps`)
store  recording runs, loading them, their series over commits
page   the HTML page
cli    the command line (``hrbench-history``; ``python -m hrbench_analysis.bench.history``)
"""

from .cli import main
from .page import write_html
from .steps import (
    DEFAULT_MIN_CHANGE,
    DEFAULT_MIN_NOISE,
    DEFAULT_MIN_POINTS,
    DEFAULT_PENALTY,
    Step,
    detect_steps,
)
from .store import (
    HISTORY_FORMAT,
    CounterChange,
    HistoryError,
    Point,
    Run,
    Series,
    get_counter_changes,
    get_series,
    load_history,
    record_run,
)

__all__ = [
    "HistoryError",
    "Step",
    "Run",
    "Point",
    "Series",
    "CounterChange",
    "HISTORY_FORMAT",
    "DEFAULT_PENALTY",
    "DEFAULT_MIN_CHANGE",
    "DEFAULT_MIN_NOISE",
    "DEFAULT_MIN_POINTS",
    "detect_steps",
    "record_run",
    "load_history",
    "get_series",
    "get_counter_changes",
    "write_html",
    "main",
]
