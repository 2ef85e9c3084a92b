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
"""
