"""The benchmark and regression tooling: Google Benchmark files, timing comparisons, the
CI gates' builds and counts, and the benchmark history over commits.

Modules
-------
gbench        read, check and merge Google Benchmark JSON files (standard library only)
benchcompare  ``hrbench-compare``: the timing comparison of two benchmark runs
cmdtiming     ``hrbench-compare commands``: two shell commands timed in interleaved rounds
builds        a commit built in its git worktree and its benchmarks run (the CI gates,
              ``hrbench-history measure``)
history       ``hrbench-history``: benchmark runs over commits, steps, the page
machine       the machine a benchmark runs on (its CPU model)
baseline      the exact count baseline: the engine's counters of canonical runs, diffed
check_baseline, compare_bench, merge_bench
              the command lines of ``tools/*.py``, which run them from a checkout

The standard library suffices for all but benchcompare, cmdtiming and history (numpy,
scipy), so that the count gate and the merge run with any Python 3.11.
"""
