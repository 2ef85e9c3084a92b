#!/usr/bin/env python3
"""A stand-in for the hrbench command line, for the analysis tests only.

It implements just enough of ``hrbench run parallel ... --json``, ``hrbench links``,
``hrbench capabilities --json`` and ``hrbench --version`` to exercise the sweep runner:
the refinement of two parallel segments with the garmann oracle, counted exactly as
docs/conventions.md defines. Of the further engine options it knows ``--method``
(reported back, counts unchanged) and ``--threads`` (ignored). Its capabilities are its
own: the 2D family ``parallel`` (which it runs) and the 3D family ``box3d`` (listed only),
the oracles ``garmann`` (2D and 3D) and ``hanrahan`` (2D only), and the counters its
records hold. Standard library only. Environment variables steer the tests:

FAKE_HRBENCH_DELAY            seconds to sleep before each run
FAKE_HRBENCH_LOG              file to which every run or links command appends its
                              arguments as one line, as soon as it starts
FAKE_HRBENCH_FAIL_BELOW_EPS   exit with code 3 (limit reached) when eps is below this
FAKE_HRBENCH_REFUSE_BELOW_EPS exit with code 2 (input error) when eps is below this
FAKE_HRBENCH_REPORT_METHOD    report this method instead of the one asked for
FAKE_HRBENCH_CAPABILITIES     "missing": no capabilities command (like hrbench 0.2);
                              "garbage": it prints text that is not JSON
FAKE_HRBENCH_MEMORY_BELOW_EPS exit with code 3 and the engine's memory-budget message
                              when eps is below this (as under the default budget, 90%
                              of the memory free at that moment)
FAKE_HRBENCH_CHILD            "hang": a run starts a child that sleeps holding standard
                              output open, then hangs itself; "leave": it starts that
                              child and finishes normally, leaving the child behind
FAKE_HRBENCH_PIDS             file to which a run appends its pid and its child's
FAKE_HRBENCH_FLOOD            bytes a run prints on standard output before its record
FAKE_HRBENCH_SCENE_SHA256     report this scene_sha256 in run records; "canonical": the
                              digest of the plates' corners as docs/scene-format.md states
"""

import hashlib
import json
import math
import os
import subprocess
import sys
import time

VERSION = "hrbench-fake 0.0.1"


def refine(l, d, eps, offset=0.0, l2=None, links_out=None):
    l2 = l if l2 is None else l2
    sys.setrecursionlimit(100000)
    children = {}
    count = {"nodes": 2, "links": 0, "calls": 0, "max_depth": 0}
    npd = {0: 2}
    lpd = {}

    def mid(e):
        t = 0.5 * (e[1] + e[2])
        return (t, 0.0) if e[0] == 0 else (offset + l2 - t, d)

    def kids(e):
        c = children.get(e)
        if c is None:
            m = 0.5 * (e[1] + e[2])
            c = ((e[0], e[1], m, e[3] + 1), (e[0], m, e[2], e[3] + 1))
            children[e] = c
            count["nodes"] += 2
            npd[e[3] + 1] = npd.get(e[3] + 1, 0) + 2
            count["max_depth"] = max(count["max_depth"], e[3] + 1)
        return c

    def project(i, j):
        count["calls"] += 1
        ai, aj = i[2] - i[1], j[2] - j[1]
        pi, pj = mid(i), mid(j)
        r = math.hypot(pi[0] - pj[0], pi[1] - pj[1])
        if max(ai, aj) <= eps * r:
            count["links"] += 1
            lpd[i[3] + j[3]] = lpd.get(i[3] + j[3], 0) + 1
            if links_out is not None:
                links_out.append((i, j))
            return
        if ai >= aj:
            a, b = kids(i)
            project(a, j)
            project(b, j)
        else:
            a, b = kids(j)
            project(i, a)
            project(i, b)

    start = time.perf_counter()
    project((0, 0.0, float(l), 0), (1, 0.0, float(l2), 0))
    seconds = time.perf_counter() - start
    def hist(h):
        return [h.get(k, 0) for k in range(max(h) + 1)] if h else []

    return {
        "nodes": count["nodes"], "leaves": count["nodes"] - len(children),
        "links": count["links"], "oracle_calls": count["calls"],
        "max_depth": count["max_depth"], "forced_links": 0, "culled_pairs": 0,
        "root_pairs": 1, "nodes_per_depth": hist(npd), "links_per_depth": hist(lpd),
        "seconds": seconds,
    }


def usage(message):
    sys.stderr.write(f"hrbench: {message}\n")
    sys.exit(2)


def _param(name, default, low=0.0, low_open=True, default_from=None, doc=""):
    return {"name": name, "default": None if default_from else default,
            "default_from": default_from, "low": low, "high": None, "low_open": low_open,
            "high_open": False, "integer": False, "doc": doc}


def _option(name, value=None, choices=None, commands=("run", "links"), doc=""):
    return {"name": name, "flag": "--" + name.replace("_", "-"), "value": value,
            "choices": list(choices) if choices else None, "commands": list(commands),
            "doc": doc}


def _counter(name, kind="scalar", category="tree", unit="count"):
    return {"name": name, "kind": kind, "category": category, "unit": unit, "doc": name}


CAPABILITIES = {
    "schema_version": 1,
    "engine": "hrbench",
    "version": VERSION.split()[-1],
    "run_schema_version": 1,
    "commands": [{"name": n, "doc": n} for n in ("run", "links", "capabilities")],
    "families": [
        {"name": "parallel", "dimension": 2, "doc": "two facing parallel segments",
         "params": [_param("l", 1.0), _param("d", 1.0),
                    _param("offset", 0.0, low=None, low_open=False),
                    _param("l2", None, default_from="l")]},
        {"name": "box3d", "dimension": 3, "doc": "listed only: the fake cannot run it",
         "params": [_param("l", 1.0), _param("d", 1.0)]},
    ],
    "oracles": [
        {"name": "garmann", "dimensions": [2, 3], "parameters": ["eps"], "doc": "form factor"},
        {"name": "hanrahan", "dimensions": [2], "parameters": ["eps"], "doc": "listed only"},
    ],
    "methods": [{"name": "enumerate", "doc": "recursion"},
                {"name": "translation", "doc": "reported back only"}],
    "options": [
        _option("eps", "E"), _option("oracle", "NAME", ["garmann", "hanrahan"]),
        _option("min_area", "A"), _option("max_depth", "D"),
        _option("count_only", commands=["run"]),
        _option("method", "M", ["enumerate", "translation"], commands=["run"]),
        _option("threads", "N", commands=["run"]), _option("json", commands=["run"]),
        _option("out", "FILE", commands=["links"]),
    ],
    "counters": [_counter(n) for n in ("nodes", "leaves", "links", "oracle_calls",
                                       "max_depth", "forced_links", "culled_pairs",
                                       "root_pairs")]
                + [_counter(n, "histogram") for n in ("nodes_per_depth", "links_per_depth")],
}


def capabilities():
    how = os.environ.get("FAKE_HRBENCH_CAPABILITIES", "")
    if how == "own-oracles":
        # An engine whose oracles have names of its own, listed with their kinds.
        CAPABILITIES["engine"] = "fake-kernel"
        CAPABILITIES["oracles"] = [
            {"name": "area-over-r", "dimensions": [2, 3], "parameters": ["eps"],
             "doc": "a size over a distance", "kind": "geometric", "default": True},
            {"name": "ff-disc", "dimensions": [2], "parameters": ["eps"],
             "doc": "a form-factor estimate", "kind": "form-factor"},
            {"name": "ff-exact", "dimensions": [3], "parameters": ["eps"],
             "doc": "listed only", "kind": "form-factor"},
        ]
        CAPABILITIES["options"][1]["choices"] = ["area-over-r", "ff-disc", "ff-exact"]
    if how == "missing":
        usage("unknown command 'capabilities' (commands: run, links, scenes)")
    if how == "garbage":
        print("commands: run links")
        return 0
    print(json.dumps(CAPABILITIES, indent=1))
    return 0


def misbehave():
    # The hostile engines of FAKE_HRBENCH_CHILD and FAKE_HRBENCH_FLOOD.
    child = os.environ.get("FAKE_HRBENCH_CHILD")
    pids = [os.getpid()]
    if child:
        # The child inherits standard output and keeps it open while it sleeps.
        sleeper = subprocess.Popen([sys.executable, "-c", "import time; time.sleep(600)"])
        pids.append(sleeper.pid)
    if os.environ.get("FAKE_HRBENCH_PIDS"):
        with open(os.environ["FAKE_HRBENCH_PIDS"], "a") as fh:
            fh.write(" ".join(map(str, pids)) + "\n")
    if child == "hang":
        time.sleep(600)
    flood = int(os.environ.get("FAKE_HRBENCH_FLOOD", "0"))
    block = "x" * 65535 + "\n"
    while flood > 0:
        sys.stdout.write(block[:flood])
        flood -= len(block)


def main(argv):
    if argv[:1] == ["--version"]:
        print(VERSION)
        return 0
    if argv == ["capabilities", "--json"]:
        return capabilities()
    if len(argv) < 2 or argv[0] not in ("run", "links"):
        usage("expected 'run SCENE', 'links SCENE' or 'capabilities --json'")
    command, scene, rest = argv[0], argv[1], argv[2:]
    if os.environ.get("FAKE_HRBENCH_LOG"):
        with open(os.environ["FAKE_HRBENCH_LOG"], "a") as fh:
            fh.write(" ".join(argv) + "\n")
    if scene != "parallel":
        usage(f"unknown scene '{scene}'")
    params = {"l": 1.0, "d": 1.0, "offset": 0.0}
    opts = {"--eps": None, "--oracle": "garmann", "--out": None, "--min-area": None,
            "--max-depth": None, "--method": "enumerate", "--threads": "1"}
    flags = set()
    i = 0
    while i < len(rest):
        arg = rest[i]
        if arg in opts:
            if i + 1 >= len(rest):
                usage(f"{arg} needs a value")
            opts[arg] = rest[i + 1]
            i += 2
        elif arg in ("--json", "--count-only"):
            flags.add(arg)
            i += 1
        elif "=" in arg:
            k, v = arg.split("=", 1)
            params[k] = float(v)
            i += 1
        else:
            usage(f"unknown argument '{arg}'")
    if opts["--eps"] is None:
        usage("--eps is required")
    eps = float(opts["--eps"])
    params.setdefault("l2", params["l"])
    if os.environ.get("FAKE_HRBENCH_DELAY"):
        time.sleep(float(os.environ["FAKE_HRBENCH_DELAY"]))
    misbehave()
    memory = os.environ.get("FAKE_HRBENCH_MEMORY_BELOW_EPS")
    if memory and eps < float(memory):
        sys.stderr.write("hrbench: error: element trees would exceed the memory budget "
                         "(1048576 elements); raise --max-memory or eps\n")
        return 3
    refuse = os.environ.get("FAKE_HRBENCH_REFUSE_BELOW_EPS")
    if refuse and eps < float(refuse):
        usage(f"the patches touch at eps={eps}; give --min-area or --max-depth")
    below = os.environ.get("FAKE_HRBENCH_FAIL_BELOW_EPS")
    if below and eps < float(below):
        sys.stderr.write(f"hrbench: depth safety cap reached at eps={eps}; use --min-area\n")
        return 3
    links = [] if command == "links" else None
    counters = refine(params["l"], params["d"], eps, params["offset"], params["l2"], links)
    if command == "links":
        with open(opts["--out"], "w") as fh:
            fh.write("root_i,elem_i,t0_i,t1_i,depth_i,root_j,elem_j,t0_j,t1_j,depth_j\n")
            for n, (a, b) in enumerate(links):
                fh.write(f"{a[0]},{n},{a[1]!r},{a[2]!r},{a[3]},{b[0]},{n},{b[1]!r},{b[2]!r},"
                         f"{b[3]}\n")
        return 0
    record = {"schema_version": 1, "version": VERSION, "scene": scene, "params": params,
              "eps": eps, "oracle": opts["--oracle"],
              "mode": "count-only" if "--count-only" in flags else "store",
              "min_area": None, "max_depth_limit": None, "future_field": "ignored",
              "method": os.environ.get("FAKE_HRBENCH_REPORT_METHOD", opts["--method"])}
    record.update(counters)
    digest = os.environ.get("FAKE_HRBENCH_SCENE_SHA256")
    if digest == "canonical":  # P (0,0)->(l,0), Q (offset+l2,d)->(offset,d)
        p, d, o, l2 = params["l"], params["d"], params["offset"], params["l2"]
        text = "".join(" ".join("%.17g" % (x + 0.0) for x in corners) + "\n"
                       for corners in ((0, 0, p, 0), (o + l2, d, o, d)))
        digest = hashlib.sha256(text.encode()).hexdigest()
    if digest:
        record["scene_sha256"] = digest
    print(json.dumps(record))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
