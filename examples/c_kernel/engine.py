#!/usr/bin/env python3
"""The engine contract (docs/engine-contract.md) around the C kernel of c_kernel.c.

The analysis runs this script with the kernel's path as its first word and reads the
run records it prints; the kernel does the counting. One family, the flatland
``parallel`` plates (``l``, ``d``), and the kernel's one oracle, ``garmann``:

    hrbench-reproduce --engine "python3 examples/c_kernel/engine.py build/c_kernel" \\
        --claims examples/c_kernel/claims.toml

``links`` in a record is the number of directed links the kernel ends with (one per
direction: twice hrbench's on these plates), ``oracle_calls`` counts the calls of both
passes (``last_pass_oracle_calls`` those of the second), ``unlinks`` the links of the
first pass that the second removed. Exit codes: those of the kernel (0, 2 usage or input error,
3 a limit reached).
"""

import json
import math
import subprocess
import sys
import time

NAME = "c_kernel"
VERSION = "0.1.0"  # change it whenever the kernel's counts change (the cache key)
PARAMS = (("l", 64.0, "length of P (scene units)"), ("d", 1.0, "distance of the plates"))
USAGE = """\
usage: engine.py KERNEL run parallel [l=64] [d=1] --eps E [--oracle garmann] [--count-only] [--json]
       engine.py KERNEL scenes | capabilities --json | --version | --help"""


class UsageError(Exception):
    """Bad command line: one line on standard error, exit code 2."""


def number(text, what):
    try:
        value = float(text)
    except ValueError:
        raise UsageError(f"{what}: {text!r} is not a number") from None
    if not math.isfinite(value) or value <= 0:
        raise UsageError(f"{what} must be a finite number > 0, got {text}")
    return value


def run(kernel, args):
    if not args or args[0] != "parallel":
        raise UsageError("run: the only scene is 'parallel'")
    params = {name: default for name, default, _ in PARAMS}
    eps, oracle, as_json = None, "garmann", False
    words = iter(args[1:])
    for word in words:
        if word in ("--count-only", "--json"):
            as_json |= word == "--json"
        elif word in ("--eps", "--oracle"):
            value = next(words, None)
            if value is None:
                raise UsageError(f"option {word} needs a value")
            if word == "--eps":
                eps = number(value, "--eps")
            elif value != "garmann":
                raise UsageError(f"unknown oracle {value!r} (oracles: garmann)")
        elif word.partition("=")[0] in params:
            name, _, text = word.partition("=")
            params[name] = number(text, f"parameter {name}")
        else:
            raise UsageError(f"unknown argument {word!r} (see --help)")
    if eps is None:
        raise UsageError("run: --eps is required")
    start = time.perf_counter()
    done = subprocess.run([kernel, repr(eps), "parallel", repr(params["l"]), repr(params["d"])],
                          capture_output=True, text=True, check=False)
    seconds = time.perf_counter() - start
    if done.returncode != 0:
        sys.stderr.write(done.stderr)
        return done.returncode
    counts = {name: int(value)
              for name, value in (line.split() for line in done.stdout.splitlines())}
    record = {
        "schema_version": 1, "version": VERSION, "context": {"engine": NAME},
        "scene": "parallel", "params": params, "patches": 2, "dimension": 2, "eps": eps,
        "oracle": oracle, "mode": "count-only", "min_area": None, "max_depth_limit": None,
        "nodes": counts["nodes"], "leaves": counts["nodes"] - (counts["nodes"] - 2) // 2,
        "links": counts["links"], "unlinks": counts["unlinks"],
        "oracle_calls": counts["total_oracle_calls"],
        "last_pass_oracle_calls": counts["oracle_calls"],
        "max_depth": counts["max_depth"], "seconds": seconds,
    }
    print(json.dumps(record) if as_json else "\n".join(f"{k:<14} {v}" for k, v in record.items()))
    return 0


def capabilities():
    def counter(name, unit, doc, category="refinement"):
        return {"name": name, "kind": "scalar", "category": category, "unit": unit, "doc": doc}

    def option(name, value, choices, doc, commands=("run",)):
        return {"name": name, "flag": "--" + name.replace("_", "-"), "value": value,
                "choices": choices, "commands": list(commands), "doc": doc}

    return {
        "schema_version": 1, "engine": NAME, "version": VERSION, "run_schema_version": 1,
        "commands": [{"name": "run", "doc": "refine a scene, print its counters"},
                     {"name": "scenes", "doc": "list the scene family and the oracle"},
                     {"name": "capabilities", "doc": "describe the engine as JSON"}],
        "families": [{"name": "parallel", "dimension": 2, "doc": "two facing parallel segments",
                      "params": [{"name": n, "default": v, "default_from": None, "low": 0.0,
                                  "high": None, "low_open": True, "high_open": False,
                                  "integer": False, "doc": doc} for n, v, doc in PARAMS]}],
        "oracles": [{"name": "garmann", "dimensions": [2], "parameters": ["eps"],
                     "doc": "max(A_i, A_j) <= eps * r"}],
        "methods": [{"name": "enumerate", "doc": "two passes: 4 eps, then every link at eps"}],
        "options": [option("eps", "E", None, "oracle threshold, > 0"),
                    option("oracle", "NAME", ["garmann"], "the oracle"),
                    option("count_only", None, None, "count only (the only mode)"),
                    option("json", None, None, "print one JSON object", ("run", "capabilities"))],
        "counters": [counter("nodes", "elements", "elements, roots included", "tree"),
                     counter("leaves", "elements", "elements without children", "tree"),
                     counter("links", "links", "directed links at the end"),
                     counter("unlinks", "links", "links of pass 1 removed by pass 2"),
                     counter("oracle_calls", "calls", "oracle calls of both passes"),
                     counter("last_pass_oracle_calls", "calls", "oracle calls of pass 2"),
                     counter("max_depth", "levels", "depth of the deepest element", "tree")],
    }


def main(argv):
    if len(argv) < 2:
        raise UsageError("usage: engine.py KERNEL COMMAND ... (see --help)")
    kernel, command, rest = argv[0], argv[1], argv[2:]
    if command in ("--version", "version") and not rest:
        print(f"{NAME} {VERSION}")
    elif command in ("--help", "-h", "help"):
        print(USAGE)
    elif command == "run":
        return run(kernel, rest)
    elif command == "scenes" and not rest:
        print("parallel (2D): two facing parallel segments, P (0,0)->(l,0), Q (l,d)->(0,d)")
        print("oracles: garmann (2D): max(A_i, A_j) <= eps * r")
    elif command == "capabilities" and rest == ["--json"]:
        print(json.dumps(capabilities(), indent=1))
    else:
        raise UsageError(f"unknown command {' '.join(argv[1:])!r} (see --help)")
    return 0


if __name__ == "__main__":
    try:
        sys.exit(main(sys.argv[1:]))
    except UsageError as exc:
        print(f"{NAME}: {exc}", file=sys.stderr)
        sys.exit(2)
