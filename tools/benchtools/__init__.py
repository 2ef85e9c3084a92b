"""Regression gates of hrbench: exact counts and timings.

Modules
-------
gbench
    Reading Google Benchmark JSON files (tolerantly).
compare
    Timing comparison of two benchmark runs with repetitions.
baseline
    The deterministic count baseline: running the engine and diffing counters.

The command-line entry points are the thin scripts ``tools/compare_bench.py``,
``tools/check_baseline.py`` and ``tools/merge_bench.py``.
"""
