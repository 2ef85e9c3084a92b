"""A stand-in for `hrbench run ... --json --count-only` in the tests of
tools/check_baseline.py: counters computed from the arguments.

Environment: FAKE_HRBENCH_SHIFT="counter=delta" adds delta to one counter (or to
one histogram entry, "links_per_depth.2=delta") of every run whose arguments
contain FAKE_HRBENCH_MATCH (default: every run); FAKE_HRBENCH_FAIL=1 fails like
the engine does on bad input.
"""

import json
import os
import sys

args = sys.argv[1:]
if os.environ.get("FAKE_HRBENCH_FAIL"):
    print("hrbench: error: scene parallel: parameter l=-1 is out of range (> 0)", file=sys.stderr)
    sys.exit(2)
eps = float(args[args.index("--eps") + 1])
leaves = 2 ** max(1, round(1 / eps).bit_length())
counts = {
    "nodes": 2 * leaves - 2, "leaves": leaves, "links": 5 * leaves, "oracle_calls": 10 * leaves - 1,
    "max_depth": leaves.bit_length() - 2, "forced_links": 0, "culled_pairs": 0, "root_pairs": 1,
    "nodes_per_depth": [2, 4, 8], "links_per_depth": [0, 0, 5 * leaves],
}
shift = os.environ.get("FAKE_HRBENCH_SHIFT")
if shift and os.environ.get("FAKE_HRBENCH_MATCH", "") in " ".join(args):
    name, delta = shift.split("=")
    if "." in name:
        name, depth = name.split(".")
        histogram = counts[name] + [0] * (int(depth) + 1 - len(counts[name]))
        histogram[int(depth)] += int(delta)
        counts[name] = histogram
    else:
        counts[name] += int(delta)
print(json.dumps(dict(counts, schema_version=1, version="0.0-test", seconds=0.001)))
