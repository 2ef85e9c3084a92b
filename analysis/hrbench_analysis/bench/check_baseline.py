"""Check the exact counters of the engine against tests/baseline/counts.json
(``tools/check_baseline.py``, standard library only).

usage: check_baseline.py [--hrbench PATH] [--baseline PATH] [--jobs N] [--update]

Reads the engine's counters from `hrbench capabilities --json`, runs every entry of
the baseline file as `hrbench run ARGS --json --count-only` and compares exactly the
counters the baseline holds (scalars exactly, per-depth histograms entry by entry).
On a difference it prints, for each run that changed, the counters, their old and
new values and the change. A counter the engine lists but the baseline lacks is
mentioned once ("not in baseline") and does not fail; a counter of the baseline that
the engine no longer lists fails. With --update it rewrites the file from the current
engine instead, with every counter the engine lists (to add a run, append
{"args": [...]} to the file and update); a missing file is created with the default
runs.

Exit codes: 0 every run matches (or the file was written); 1 a run differs or
failed, or a baseline counter is no longer listed; 2 usage or input error (no
engine, an engine without `capabilities --json`, a baseline that is unreadable, not a
regular file of at most 64 MiB or malformed); 70 internal error (a bug; its traceback
with --debug); 74 the report or the updated file could not be written.
See docs/ci.md.
"""

import concurrent.futures
import json
import os
import sys

from ..engine import EngineError, get_capabilities
from ..errors import OneLineParser, run_main
from ..output import write_file
from .baseline import (
    DEFAULT_RUNS,
    RunDiff,
    RunError,
    get_counter_changes,
    get_counter_coverage,
    load_baseline,
    make_baseline,
    print_baseline_report,
    run_counts,
)

#: The checkout this module is in: the default engine and baseline are its own.
_ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.dirname(
    os.path.abspath(__file__)))))

PROG = "check_baseline.py"


def _parse_args(argv):
    parser = OneLineParser(
        prog=PROG,
        description="Check (or --update) the exact count baseline of the hrbench engine.")
    parser.add_argument("--hrbench", default=os.path.join(_ROOT, "build", "hrbench"),
                        help="engine executable (default build/hrbench)")
    parser.add_argument("--baseline",
                        default=os.path.join(_ROOT, "tests", "baseline", "counts.json"),
                        help="baseline file (default tests/baseline/counts.json)")
    parser.add_argument("--jobs", type=int, default=os.cpu_count() or 1,
                        help="engine runs in parallel (default: number of cores)")
    parser.add_argument("--update", action="store_true",
                        help="rewrite the baseline from the current engine")
    parser.add_argument("--debug", action="store_true",
                        help="print the traceback of an internal error (exit code 70)")
    args = parser.parse_args(argv)
    if args.jobs < 1:
        parser.error("--jobs must be at least 1")
    return args


def _run_all(hrbench, runs, counters, jobs):
    """Counters (or the RunError) of every run, in order."""
    def one(args):
        try:
            return run_counts(hrbench, args, counters)
        except RunError as e:
            return e
    with concurrent.futures.ThreadPoolExecutor(max_workers=jobs) as pool:
        return list(pool.map(one, runs))


def main(argv=None):
    return run_main(PROG, _check, argv, input_errors=(EngineError,))


def _check(argv):
    args = _parse_args(argv)
    capabilities = get_capabilities(args.hrbench)
    counters = capabilities.scalar_counters + capabilities.histogram_counters

    # Read the runs of the baseline (or the default runs for a new file).
    if args.update and not os.path.exists(args.baseline):
        entries = [{"args": a} for a in DEFAULT_RUNS]
    else:
        entries = load_baseline(args.baseline)["runs"]
    results = _run_all(args.hrbench, [e["args"] for e in entries], counters, args.jobs)

    if args.update:
        failed = [(e, r) for e, r in zip(entries, results, strict=True)
                  if isinstance(r, RunError)]
        for e, r in failed:
            print(f"{PROG}: error: hrbench run {' '.join(e['args'])}: {r}",
                  file=sys.stderr)
        if failed:
            return 1
        version = results[0][1] if results else "unknown"
        data = make_baseline([e["args"] for e in entries], [r[0] for r in results], version)
        os.makedirs(os.path.dirname(os.path.abspath(args.baseline)), exist_ok=True)
        write_file(args.baseline, json.dumps(data, indent=1) + "\n")
        print(f"count baseline: wrote {len(entries)} runs to {args.baseline}")
        return 0

    coverage = get_counter_coverage(entries, counters)
    diffs = []
    for entry, result in zip(entries, results, strict=True):
        if isinstance(result, RunError):
            diffs.append(RunDiff(entry["args"], error=str(result)))
        elif not isinstance(entry.get("counts"), dict):
            diffs.append(RunDiff(entry["args"], error="no baseline counts recorded; run "
                                                      "tools/check_baseline.py --update"))
        else:
            diffs.append(RunDiff(entry["args"], get_counter_changes(
                entry["counts"], result[0], coverage.compared)))
    print_baseline_report(diffs, os.path.relpath(args.baseline), coverage=coverage)
    return 0 if coverage.ok and all(d.ok for d in diffs) else 1


if __name__ == "__main__":
    sys.exit(main())
