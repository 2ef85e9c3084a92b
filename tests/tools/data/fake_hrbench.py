"""A stand-in for `hrbench run ... --json --count-only` and `hrbench capabilities --json`
in the tests of tools/check_baseline.py: counters computed from the arguments.

Environment: FAKE_HRBENCH_SHIFT="counter=delta" adds delta to one counter (or to
one histogram entry, "links_per_depth.2=delta") of every run whose arguments
contain FAKE_HRBENCH_MATCH (default: every run); FAKE_HRBENCH_FAIL=1 fails like
the engine does on bad input. FAKE_HRBENCH_NEW_COUNTER=name lists one more scalar
counter (7 in every run); FAKE_HRBENCH_DROP_COUNTER=name neither lists nor reports
that counter; FAKE_HRBENCH_CAPABILITIES=missing has no capabilities command (like
hrbench 0.2). FAKE_HRBENCH_LOG names a file to which every run appends its arguments.
"""

import json
import os
import sys

SCALARS = ["nodes", "leaves", "links", "oracle_calls", "max_depth", "forced_links",
           "culled_pairs", "root_pairs"]
HISTOGRAMS = ["nodes_per_depth", "links_per_depth"]


def counter_names():
    """The scalar counters and histograms this engine lists."""
    scalars = SCALARS + [n for n in [os.environ.get("FAKE_HRBENCH_NEW_COUNTER")] if n]
    drop = os.environ.get("FAKE_HRBENCH_DROP_COUNTER")
    return [n for n in scalars if n != drop], [n for n in HISTOGRAMS if n != drop]


def capabilities():
    if os.environ.get("FAKE_HRBENCH_CAPABILITIES") == "missing":
        print("hrbench: error: --json applies to run only", file=sys.stderr)
        return 2
    scalars, histograms = counter_names()
    counters = ([{"name": n, "kind": "scalar", "category": "tree", "unit": "count", "doc": n}
                 for n in scalars]
                + [{"name": n, "kind": "histogram", "category": "tree", "unit": "count",
                    "doc": n} for n in histograms])
    print(json.dumps({
        "schema_version": 1, "engine": "hrbench", "version": "0.0-test",
        "run_schema_version": 1,
        "commands": [{"name": "run", "doc": "count"}, {"name": "capabilities", "doc": "this"}],
        "families": [{"name": "parallel", "dimension": 2, "doc": "any scene goes",
                      "params": []}],
        "oracles": [{"name": "garmann", "dimensions": [2], "parameters": ["eps"], "doc": ""}],
        "methods": [{"name": "enumerate", "doc": ""}],
        "options": [{"name": "eps", "flag": "--eps", "value": "E", "choices": None,
                     "commands": ["run"], "doc": ""}],
        "counters": counters}))
    return 0


def run(args):
    if os.environ.get("FAKE_HRBENCH_LOG"):
        with open(os.environ["FAKE_HRBENCH_LOG"], "a") as fh:
            fh.write(" ".join(args) + "\n")
    if os.environ.get("FAKE_HRBENCH_FAIL"):
        print("hrbench: error: scene parallel: parameter l=-1 is out of range (> 0)",
              file=sys.stderr)
        return 2
    eps = float(args[args.index("--eps") + 1])
    leaves = 2 ** max(1, round(1 / eps).bit_length())
    counts = {
        "nodes": 2 * leaves - 2, "leaves": leaves, "links": 5 * leaves,
        "oracle_calls": 10 * leaves - 1, "max_depth": leaves.bit_length() - 2,
        "forced_links": 0, "culled_pairs": 0, "root_pairs": 1,
        "nodes_per_depth": [2, 4, 8], "links_per_depth": [0, 0, 5 * leaves],
    }
    scalars, histograms = counter_names()
    counts = {n: counts.get(n, 7) for n in scalars + histograms}
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
    return 0


if __name__ == "__main__":
    argv = sys.argv[1:]
    sys.exit(capabilities() if argv == ["capabilities", "--json"] else run(argv[1:]))
