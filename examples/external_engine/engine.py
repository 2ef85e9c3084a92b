#!/usr/bin/env python3
"""A minimal engine for the hrbench analysis, written without hrbench.

It implements the engine contract (docs/engine-contract.md) for one scene family, the
flatland ``parallel`` plates, with the ``garmann`` oracle, following the counting
conventions of docs/conventions.md with its own recursion. It only counts (no link
list), so it offers the commands ``run``, ``scenes`` and ``capabilities``, plus
``--version`` and ``--help``. Standard library only. Run the analysis on it with

    hrbench-reproduce --engine "python3 examples/external_engine/engine.py" \\
        --claims examples/external_engine/claims.toml

Exit codes: 0 success, 2 usage or input error, 3 the safety depth was reached.
"""

import json
import math
import sys
import time

NAME = "pyflat"
VERSION = "0.1.0"
#: Depth at which a rejected pair stops the run without --max-depth or --min-area.
SAFETY_DEPTH = 48

USAGE = """\
usage: engine.py run parallel [l=64] [d=1] [offset=0] [l2=l] --eps E [--oracle garmann]
                 [--min-area A] [--max-depth D] [--count-only] [--json]
       engine.py scenes
       engine.py capabilities --json
       engine.py --version | --help

Counts the hierarchical refinement of two facing parallel segments, P (0,0)->(l,0) and
Q (offset+l2,d)->(offset,d), with the oracle max(A_i, A_j) <= eps * r, as
docs/conventions.md defines it. Exit codes: 0 success, 2 usage or input error,
3 the safety depth was reached."""


class UsageError(Exception):
    """Bad command line or input: one line on standard error, exit code 2."""


class LimitReached(Exception):
    """A limit was reached while counting: one line on standard error, exit code 3."""


# ---------------------------------------------------------------------------------------
# The scene family.

# name, default (None: that of default_from), default_from, low (exclusive or not), doc
PARAMS = (
    ("l", 64.0, None, 0.0, True, "length of P (scene units)"),
    ("d", 1.0, None, 0.0, True, "distance of the plates (scene units)"),
    ("offset", 0.0, None, None, False, "shift of Q along x (scene units)"),
    ("l2", None, "l", 0.0, True, "length of Q (scene units), l by default"),
)


def parallel_patches(params):
    """The root segments of the family, in scene order: P facing +y, Q facing -y."""
    l, d, offset, l2 = params["l"], params["d"], params["offset"], params["l2"]
    return [((0.0, 0.0), (l, 0.0)), ((offset + l2, d), (offset, d))]


# ---------------------------------------------------------------------------------------
# The refinement (docs/conventions.md: the recursion, the oracle, subdivision, limits).


class Element:
    """A segment a -> b of a root patch, with its squared length and children."""

    __slots__ = ("ax", "ay", "bx", "by", "size2", "depth", "children")

    def __init__(self, a, b, depth):
        self.ax, self.ay = a
        self.bx, self.by = b
        dx, dy = self.bx - self.ax, self.by - self.ay
        self.size2 = dx * dx + dy * dy  # A^2, the one formula of the conventions
        self.depth = depth
        self.children = None


class Counts:
    """The counters of one run."""

    def __init__(self, patches):
        self.nodes = patches
        self.links = 0
        self.oracle_calls = 0
        self.forced_links = 0
        self.max_depth = 0
        self.nodes_per_depth = [patches]
        self.links_per_depth = []

    def add_link(self, depth):
        self.links += 1
        while len(self.links_per_depth) <= depth:
            self.links_per_depth.append(0)
        self.links_per_depth[depth] += 1


def children_of(e, counts):
    """The two halves of `e`, created the first time it is split and shared afterwards."""
    if e.children is None:
        mx, my = 0.5 * (e.ax + e.bx), 0.5 * (e.ay + e.by)
        depth = e.depth + 1
        e.children = (Element((e.ax, e.ay), (mx, my), depth),
                      Element((mx, my), (e.bx, e.by), depth))
        counts.nodes += 2
        if depth > counts.max_depth:
            counts.max_depth = depth
            counts.nodes_per_depth.append(0)
        counts.nodes_per_depth[depth] += 2
    return e.children


def acceptable(i, j, eps):
    """garmann in 2D: max(A_i, A_j) <= eps * r, ties acceptable, r between the midpoints."""
    dx = 0.5 * (j.ax + j.bx) - 0.5 * (i.ax + i.bx)
    dy = 0.5 * (j.ay + j.by) - 0.5 * (i.ay + i.by)
    return math.sqrt(max(i.size2, j.size2)) <= eps * math.sqrt(dx * dx + dy * dy)


def project_kernel(i, j, eps, limits, counts):
    """ProjectKernel(i, j): depth first, first child first; i stays on P's side."""
    counts.oracle_calls += 1
    if acceptable(i, j, eps):
        counts.add_link(i.depth + j.depth)
        return
    p = i if i.size2 >= j.size2 else j  # the larger on squares; ties: the first argument
    min_area, max_depth = limits
    if (min_area is not None and math.sqrt(p.size2) < min_area) or p.depth == max_depth:
        counts.add_link(i.depth + j.depth)
        counts.forced_links += 1
        return
    if max_depth is None and p.depth == SAFETY_DEPTH:
        raise LimitReached(f"the safety depth {SAFETY_DEPTH} was reached refining patches "
                           "0 and 1; give --min-area or --max-depth")
    for c in children_of(p, counts):
        if p is i:
            project_kernel(c, j, eps, limits, counts)
        else:
            project_kernel(i, c, eps, limits, counts)


def refine(patches, eps, min_area=None, max_depth=None):
    """Refine every root pair (here: the one pair of the plates, which face each other and
    do not touch, so none is culled); return the counters."""
    sys.setrecursionlimit(max(sys.getrecursionlimit(), 4 * SAFETY_DEPTH + 100))
    roots = [Element(a, b, 0) for a, b in patches]
    counts = Counts(len(roots))
    for n, root_i in enumerate(roots):
        for root_j in roots[n + 1:]:
            project_kernel(root_i, root_j, eps, (min_area, max_depth), counts)
    return counts


# ---------------------------------------------------------------------------------------
# The command line.


def number(text, what):
    try:
        value = float(text)
    except ValueError:
        raise UsageError(f"{what}: {text!r} is not a number") from None
    if not math.isfinite(value):
        raise UsageError(f"{what}: {text!r} is not a finite number")
    return value


def parse_run(args):
    """The scene parameters and options of ``run parallel ...``."""
    if not args or args[0] != "parallel":
        raise UsageError("run: the only scene is 'parallel' (see 'scenes')"
                         if args else "run: missing scene")
    params, options = {}, {}
    flags = ("--count-only", "--json")
    valued = ("--eps", "--oracle", "--min-area", "--max-depth")
    rest = args[1:]
    k = 0
    while k < len(rest):
        word = rest[k]
        if word in flags or word in valued:
            if word in options:
                raise UsageError(f"option {word} given twice")
            if word in flags:
                options[word] = True
                k += 1
                continue
            if k + 1 >= len(rest):
                raise UsageError(f"option {word} needs a value")
            options[word] = rest[k + 1]
            k += 2
        elif "=" in word and not word.startswith("-"):
            name, text = word.split("=", 1)
            if name not in {p[0] for p in PARAMS}:
                raise UsageError(f"scene 'parallel' has no parameter {name!r} "
                                 f"(its parameters: {', '.join(p[0] for p in PARAMS)})")
            if name in params:
                raise UsageError(f"parameter {name} given twice")
            params[name] = number(text, f"parameter {name}")
            k += 1
        else:
            raise UsageError(f"unknown argument {word!r} (see --help)")
    for name, default, default_from, low, low_open, _ in PARAMS:
        if name not in params:
            params[name] = params[default_from] if default_from else default
        if low is not None and (params[name] < low or (low_open and params[name] == low)):
            raise UsageError(f"parameter {name} = {params[name]:g} is out of range: "
                             f"{name} {'>' if low_open else '>='} {low:g}")
    if "--eps" not in options:
        raise UsageError("run: --eps is required")
    eps = number(options["--eps"], "--eps")
    if not eps > 0:
        raise UsageError(f"--eps must be > 0, got {options['--eps']}")
    oracle = options.get("--oracle", "garmann")
    if oracle != "garmann":
        raise UsageError(f"unknown oracle {oracle!r} (oracles: garmann)")
    min_area = None
    if "--min-area" in options:
        min_area = number(options["--min-area"], "--min-area")
        if not min_area > 0:
            raise UsageError(f"--min-area must be > 0, got {options['--min-area']}")
    max_depth = None
    if "--max-depth" in options:
        text = options["--max-depth"]
        if not text.isdigit() or int(text) > SAFETY_DEPTH:
            raise UsageError(f"--max-depth must be an integer from 0 to {SAFETY_DEPTH}, "
                             f"got {text}")
        max_depth = int(text)
    return params, eps, oracle, min_area, max_depth, "--json" in options


def run(args):
    params, eps, oracle, min_area, max_depth, as_json = parse_run(args)
    start = time.perf_counter()
    counts = refine(parallel_patches(params), eps, min_area, max_depth)
    seconds = time.perf_counter() - start
    leaves = counts.nodes - (counts.nodes - 2) // 2  # every split element has two children
    record = {
        "schema_version": 1, "version": VERSION, "context": {"engine": NAME},
        "scene": "parallel", "params": params, "patches": 2, "dimension": 2, "eps": eps,
        "oracle": oracle, "method": "enumerate", "mode": "count-only",
        "min_area": min_area, "max_depth_limit": max_depth,
        "nodes": counts.nodes, "leaves": leaves, "links": counts.links,
        "oracle_calls": counts.oracle_calls, "max_depth": counts.max_depth,
        "forced_links": counts.forced_links, "culled_pairs": 0, "root_pairs": 1,
        "nodes_per_depth": counts.nodes_per_depth, "links_per_depth": counts.links_per_depth,
        "seconds": seconds,
    }
    if as_json:
        print(json.dumps(record))
    else:
        for key, value in record.items():
            if key not in ("schema_version", "context", "params"):
                print(f"{key:<16} {value}")
    return 0


def capabilities():
    """What the engine offers, in the format of ``hrbench capabilities --json``."""
    def option(name, value=None, choices=None, commands=("run",), doc=""):
        return {"name": name, "flag": "--" + name.replace("_", "-"), "value": value,
                "choices": choices, "commands": list(commands), "doc": doc}

    def counter(name, unit, doc, kind="scalar", category="refinement"):
        return {"name": name, "kind": kind, "category": category, "unit": unit, "doc": doc}

    return {
        "schema_version": 1, "engine": NAME, "version": VERSION, "run_schema_version": 1,
        "commands": [{"name": "run", "doc": "refine a scene, print its counters"},
                     {"name": "scenes", "doc": "list the scene family and the oracle"},
                     {"name": "capabilities", "doc": "describe the engine as JSON"}],
        "families": [{
            "name": "parallel", "dimension": 2, "doc": "two facing parallel segments",
            "params": [{"name": name, "default": default, "default_from": default_from,
                        "low": low, "high": None, "low_open": low_open, "high_open": False,
                        "integer": False, "doc": doc}
                       for name, default, default_from, low, low_open, doc in PARAMS]}],
        "oracles": [{"name": "garmann", "dimensions": [2], "parameters": ["eps"],
                     "doc": "max(A_i, A_j) <= eps * r"}],
        "methods": [{"name": "enumerate", "doc": "the recursion, call by call"}],
        "options": [option("eps", "E", doc="oracle threshold, > 0"),
                    option("oracle", "NAME", ["garmann"], doc="the oracle"),
                    option("min_area", "A", doc="link a pair whose larger element is "
                           "shorter than A"),
                    option("max_depth", "D", doc="link a pair whose larger element has "
                           "depth D"),
                    option("count_only", doc="count only (the only mode)"),
                    option("json", commands=("run", "capabilities"),
                           doc="print one JSON object")],
        "counters": [counter("nodes", "elements", "elements, roots included", category="tree"),
                     counter("leaves", "elements", "elements without children",
                             category="tree"),
                     counter("links", "links", "element pairs linked"),
                     counter("oracle_calls", "calls", "ProjectKernel calls"),
                     counter("max_depth", "levels", "depth of the deepest element",
                             category="tree"),
                     counter("forced_links", "links", "links made by a recursion limit"),
                     counter("culled_pairs", "root pairs", "root pairs never refined"),
                     counter("root_pairs", "root pairs", "unordered root pairs"),
                     counter("nodes_per_depth", "elements", "elements by depth",
                             kind="histogram", category="tree"),
                     counter("links_per_depth", "links", "links by depth_i + depth_j",
                             kind="histogram")],
    }


def scenes():
    print("parallel (2D): two facing parallel segments")
    for name, default, default_from, low, low_open, doc in PARAMS:
        value = f"default {default_from}" if default_from else f"default {default:g}"
        bound = "" if low is None else f", {name} {'>' if low_open else '>='} {low:g}"
        print(f"  {name:<7} {doc} ({value}{bound})")
    print("oracles: garmann (2D): max(A_i, A_j) <= eps * r")
    return 0


def main(argv):
    if argv in (["--version"], ["version"]):
        print(f"{NAME} {VERSION}")
        return 0
    if not argv:
        raise UsageError("missing command (see --help)")
    if argv[0] in ("--help", "-h", "help"):
        print(USAGE)
        return 0
    command, rest = argv[0], argv[1:]
    if command == "run":
        return run(rest)
    if command == "scenes" and not rest:
        return scenes()
    if command == "capabilities" and rest == ["--json"]:
        print(json.dumps(capabilities(), indent=1))
        return 0
    raise UsageError(f"unknown command {' '.join(argv)!r} (see --help)")


if __name__ == "__main__":
    try:
        sys.exit(main(sys.argv[1:]))
    except UsageError as exc:
        print(f"{NAME}: {exc}", file=sys.stderr)
        sys.exit(2)
    except LimitReached as exc:
        print(f"{NAME}: {exc}", file=sys.stderr)
        sys.exit(3)
