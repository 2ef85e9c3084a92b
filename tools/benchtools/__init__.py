"""The count baseline of hrbench: running the engine and diffing exact counters.

Modules
-------
baseline
    The deterministic count baseline: running the engine and diffing counters.

Its command-line entry point is the thin script ``tools/check_baseline.py``. Reading
Google Benchmark JSON and the timing comparison live in the analysis package
(``hrbench_analysis.bench.gbench``, ``hrbench_analysis.bench.benchcompare``: ``hrbench-compare``),
which ``tools/merge_bench.py`` and ``tools/compare_bench.py`` run from the checkout.
"""
