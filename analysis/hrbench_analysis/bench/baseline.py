"""The deterministic count baseline: exact counters of a canonical set of runs.

The baseline file (``tests/baseline/counts.json``) lists runs of ``hrbench run``
by their arguments, each with the exact counters it produced. Checking runs
every entry again (always ``--json --count-only``) and reports each counter that
changed; updating rewrites the counters on purpose.

The counter names are the engine's: ``hrbench capabilities --json`` lists them (its
``counters`` table, read by :mod:`hrbench_analysis.engine`; their meaning is in
docs/conventions.md). A check compares exactly the counters the baseline holds: a
counter the engine lists but the baseline lacks is mentioned once ("not in
baseline") and does not fail the check; a counter the baseline holds but the engine
no longer lists fails it. Scalars are compared exactly, histograms (lists) entry by
entry.
"""

from dataclasses import dataclass, field

from ..engine import EngineError, run_engine
from ..errors import AnalysisError, read_json
from ..loader.record import ResultFormatError, read_record

__all__ = ["BASELINE_SCHEMA_VERSION", "MAX_BASELINE_BYTES", "DEFAULT_RUNS", "BaselineError",
           "RunError", "CounterChange", "RunDiff",
           "CounterCoverage", "load_baseline", "make_baseline", "run_counts",
           "get_counter_coverage", "get_counter_changes", "print_baseline_report"]

BASELINE_SCHEMA_VERSION = 1
#: Largest baseline file read, in bytes (the default runs' file has about 100 KiB).
MAX_BASELINE_BYTES = 64 << 20


def _runs(oracle, eps_scale):
    """The canonical scenes for one oracle; eps multiplied by _eps_scale_."""
    def eps(value):
        return ["--eps", f"{value * eps_scale:.6g}", "--oracle", oracle]
    return [
        ["perpendicular"] + eps(0.1),
        ["perpendicular"] + eps(0.02),
        ["perpendicular", "l=2", "l2=1", "gap=0.05"] + eps(0.05),
        ["angled", "angle=60"] + eps(0.1),
        ["angled", "angle=135", "gap=0.2"] + eps(0.05),
        ["angled", "angle=30", "l=3"] + eps(0.02),
        ["enclosure", "n=6", "--min-area", "0.01"] + eps(0.1),
        ["enclosure", "n=12", "--min-area", "0.005"] + eps(0.05),
        ["room", "--min-area", "0.01"] + eps(0.1),
        ["room", "w=3", "h=1", "--max-depth", "8"] + eps(0.05),
        ["array", "k=4"] + eps(0.1),
        ["array", "k=8", "d=0.5", "spacing=0.5"] + eps(0.2),
        ["random", "n=10", "seed=1"] + eps(0.1),
        ["random", "n=30", "seed=7", "size=8"] + eps(0.2),
    ]


# The runs a new baseline file starts with: garmann and hanrahan on every 2D scene
# family (hanrahan at smaller eps and g = l / d, where its refinement is not trivial),
# one run on two threads, the translation method on the parallel family (once on the
# configuration the two-thread run enumerates, and up to 1.4e14 links) and on
# parallel3d (once on a configuration also enumerated, and at 6.7e18 links), bf on the
# Cornell box (no 2D family emits), binary and quadtree, and the form-factor estimates
# other than the default (--ff-estimate) of hanrahan, 2D and 3D, and of bf.
DEFAULT_RUNS = ([
    ["parallel", "l=64", "d=1", "--eps", "0.25"],
    ["parallel", "l=64", "d=1", "--eps", "0.1"],
    ["parallel", "l=256", "d=1", "--eps", "0.05"],
    ["parallel", "l=16", "d=2", "offset=5", "--eps", "0.1"],
    ["parallel", "l=32", "d=1", "offset=-7.5", "l2=20", "--eps", "0.2"],
    ["parallel", "l=4", "d=1", "--eps", "0.02"],
] + _runs("garmann", 1.0) + [
    ["parallel", "l=16", "d=1", "--eps", "0.01", "--oracle", "hanrahan"],
    ["parallel", "l=4", "d=1", "--eps", "0.004", "--oracle", "hanrahan"],
    ["parallel", "l=16", "d=2", "offset=5", "--eps", "0.01", "--oracle", "hanrahan"],
    ["parallel", "l=8", "d=1", "offset=-2.5", "l2=5", "--eps", "0.01", "--oracle", "hanrahan"],
] + _runs("hanrahan", 0.2) + [
    ["random", "n=100", "seed=3", "size=20", "--eps", "0.05"],
    ["random", "n=100", "seed=3", "size=20", "--eps", "0.01", "--oracle", "hanrahan"],
    ["parallel", "l=64", "d=0.25", "offset=3.5", "--eps", "0.04", "--threads", "2"],
    ["parallel", "l=64", "d=0.25", "offset=3.5", "--eps", "0.04", "--method", "translation"],
    ["parallel", "l=64", "d=1", "--eps", "0.25", "--method", "translation"],
    ["parallel", "l=1024", "d=0.25", "offset=3.5", "--eps", "0.02", "--method", "translation"],
    ["parallel", "l=2147483648", "d=1", "--eps", "0.01", "--method", "translation"],
    ["parallel3d", "l=8", "d=1", "--eps", "0.01"],
    ["parallel3d", "l=8", "d=1", "--eps", "0.01", "--method", "translation"],
    ["parallel3d", "l=8", "d=1", "--eps", "0.01", "--subdivision", "quadtree", "--method",
     "translation"],
    ["parallel3d", "l=1024", "d=1", "--eps", "0.000001", "--method", "translation"],
    ["cornell", "--eps", "0.05", "--min-area", "0.001", "--oracle", "bf"],
    ["cornell", "--eps", "0.02", "--min-area", "0.0005", "--oracle", "bf", "--subdivision",
     "quadtree"],
] + [
    # The form-factor estimates other than the default (clamped-cosine), in 2D and 3D.
    ["parallel", "l=16", "d=1", "--eps", "0.01", "--oracle", "hanrahan", "--ff-estimate", name]
    for name in ("centre-cosine", "solid-angle")
] + [
    ["parallel3d", "l=8", "d=1", "--eps", "0.05", "--oracle", "hanrahan"],
] + [
    ["parallel3d", "l=8", "d=1", "--eps", "0.05", "--oracle", "hanrahan", "--ff-estimate", name]
    for name in ("centre-cosine", "solid-angle")
] + [
    ["cornell", "--eps", "0.05", "--min-area", "0.001", "--oracle", "bf", "--ff-estimate",
     "centre-cosine"],
])


class RunError(Exception):
    """The engine failed on a run, or its output was not the expected JSON."""


class BaselineError(AnalysisError, ValueError):
    """A baseline file that cannot be read or does not follow the format (exit code 2)."""


@dataclass(frozen=True)
class CounterChange:
    """One counter of one run that differs from the baseline.

    Attributes
    ----------
    counter : str
        Counter name, e.g. ``links`` or ``links_per_depth[12]``.
    baseline, current : int or None
        Value in the baseline and now (None where absent).
    """

    counter: str
    baseline: object
    current: object

    @property
    def change(self):
        """Absolute change ``current - baseline`` (None unless both are numbers)."""
        if isinstance(self.baseline, int) and isinstance(self.current, int):
            return self.current - self.baseline
        return None

    @property
    def relative(self):
        """Relative change ``current / baseline - 1`` (None if undefined)."""
        if self.change is None or self.baseline == 0:
            return None
        return self.change / self.baseline


@dataclass
class RunDiff:
    """The outcome of checking one baseline entry.

    Attributes
    ----------
    args : list of str
        Arguments of ``hrbench run`` (without ``--json --count-only``).
    changes : list of CounterChange
        Counters that differ; empty if the run matches.
    error : str or None
        Why the run could not be checked (engine error, missing baseline).
    """

    args: list
    changes: list = field(default_factory=list)
    error: str = None

    @property
    def ok(self):
        return self.error is None and not self.changes


def command_of(args):
    """The command line of a baseline run, as a user would type it."""
    return "hrbench run " + " ".join(args) + " --json --count-only"


def load_baseline(path):
    """Read a baseline file.

    Parameters
    ----------
    path : str or path-like

    Returns
    -------
    dict
        With ``schema_version`` and ``runs``, a list of dicts with ``args`` (list
        of str) and ``counts`` (dict, missing for an entry not yet recorded).

    Raises
    ------
    BaselineError
        If the file is not a regular file of at most :data:`MAX_BASELINE_BYTES` bytes,
        not strict JSON (no ``NaN``, no key given twice), of another schema version, or
        a run's ``args`` is not a list of strings or its ``counts`` not an object of
        integers ``>= 0`` and lists of them.
    """
    data = read_json(path, MAX_BASELINE_BYTES, "baseline", f"baseline {path}", BaselineError)
    if not isinstance(data, dict) or data.get("schema_version") != BASELINE_SCHEMA_VERSION:
        raise BaselineError(f"baseline {path}: schema_version must be "
                            f"{BASELINE_SCHEMA_VERSION}")
    runs = data.get("runs")
    if not isinstance(runs, list):
        raise BaselineError(f"baseline {path}: 'runs' must be a list of objects with 'args'")
    for n, run in enumerate(runs, 1):
        problem = _run_problem(run)
        if problem:
            raise BaselineError(f"baseline {path}: run {n}: {problem}")
    return data


def _is_count(value):
    return isinstance(value, int) and not isinstance(value, bool) and value >= 0


def _run_problem(run):
    # Why one entry of 'runs' does not follow the format, or None.
    if not isinstance(run, dict):
        return "must be an object with 'args'"
    args = run.get("args")
    if not (isinstance(args, list) and all(isinstance(a, str) and "\0" not in a
                                           for a in args)):
        return "'args' must be a list of strings"
    counts = run.get("counts")
    if counts is None:
        return None
    if not isinstance(counts, dict):
        return "'counts' must be an object of counters"
    for name, value in counts.items():
        if not (_is_count(value) or isinstance(value, list)
                and all(_is_count(v) for v in value)):
            return (f"counter {name!r} must be an integer >= 0 or a list of them, got "
                    f"{str(value)[:40]}")
    return None


def make_baseline(runs, counts, engine_version):
    """Build the content of a baseline file.

    Parameters
    ----------
    runs : list of list of str
        Arguments of each run.
    counts : list of dict
        Counters of each run, as from `run_counts`.
    engine_version : str
        Engine version that produced them.
    """
    return {
        "schema_version": BASELINE_SCHEMA_VERSION,
        "engine_version": engine_version,
        "note": "exact counters of `hrbench run ARGS --json --count-only`; checked by "
                "tools/check_baseline.py, rewritten on purpose by `make baseline`",
        "runs": [{"args": list(a), "counts": c} for a, c in zip(runs, counts, strict=True)],
    }


def run_counts(hrbench, args, counters, timeout=120):
    """Run the engine once and return its counters.

    Parameters
    ----------
    hrbench : str
        Path of the ``hrbench`` executable.
    args : list of str
        Arguments of ``hrbench run``; ``--json --count-only`` are added.
    counters : sequence of str
        Names of the counters to read: the engine's scalar counters and histograms
        (``Capabilities.scalar_counters + Capabilities.histogram_counters``).
    timeout : float, optional
        Seconds before the run is abandoned.

    Returns
    -------
    counts : dict
        Every counter of `counters`, by name.
    version : str
        The engine version it reported.

    Raises
    ------
    RunError
        If the engine exits with an error, prints something else than a JSON object,
        or its record lacks a counter of `counters`.
    """
    try:
        run = run_engine([hrbench, "run", *args, "--json", "--count-only"], timeout=timeout)
    except EngineError as e:
        raise RunError(str(e)) from None
    if run.exit_code != 0:
        raise RunError(f"exit code {run.exit_code}: {run.message or 'no message'}")
    try:
        record = read_record(run.stdout)
    except ResultFormatError as e:
        raise RunError(str(e)) from None
    missing = [name for name in counters if name not in record]
    if missing:
        raise RunError(f"the record lacks counter(s) {', '.join(missing)} that the engine "
                       "lists")
    return {name: record[name] for name in counters}, str(record.get("version", "unknown"))


@dataclass(frozen=True)
class CounterCoverage:
    """Which counters a check compares, and which it cannot.

    Attributes
    ----------
    compared : tuple of str
        Counters in the baseline that the engine lists: compared run by run.
    not_in_baseline : tuple of str
        Counters the engine lists that a baseline entry lacks: mentioned once, not a
        failure (`make baseline` records them).
    not_listed : tuple of str
        Counters in the baseline that the engine no longer lists: a failure.
    """

    compared: tuple
    not_in_baseline: tuple
    not_listed: tuple

    @property
    def ok(self):
        """bool: whether every counter of the baseline is still listed by the engine."""
        return not self.not_listed


def get_counter_coverage(entries, counters):
    """Match the counters of the baseline with those the engine lists.

    Parameters
    ----------
    entries : list of dict
        Runs of the baseline file; those without ``counts`` are ignored.
    counters : sequence of str
        Names of every counter the engine lists (scalars and histograms).

    Returns
    -------
    CounterCoverage
        Names in the order of `counters` (`not_listed` in the baseline's order).
    """
    recorded = [e["counts"] for e in entries if isinstance(e.get("counts"), dict)]
    in_baseline = list(dict.fromkeys(name for counts in recorded for name in counts))
    return CounterCoverage(
        compared=tuple(n for n in counters if n in in_baseline),
        not_in_baseline=tuple(n for n in counters if any(n not in c for c in recorded)),
        not_listed=tuple(n for n in in_baseline if n not in counters))


def get_counter_changes(baseline, current, counters=None):
    """List the counters that differ between two sets of counts.

    Parameters
    ----------
    baseline, current : dict
        Counters as stored in the baseline file and as from `run_counts`.
        Scalars are compared exactly; histograms (lists) entry by entry (a missing
        entry counts as 0). Counters absent from the baseline are not compared.
    counters : collection of str, optional
        Compare only these (e.g. ``CounterCoverage.compared``); default: every counter
        of `baseline`.

    Returns
    -------
    list of CounterChange
        The scalars in the baseline's order, then the histograms by depth.
    """
    names = [n for n in baseline if counters is None or n in counters]
    # A histogram is a list in the baseline; it is compared by depth unless it is now a
    # scalar (then the two values are shown as they are).
    histograms = [n for n in names if isinstance(baseline[n], list)
                  and isinstance(current.get(n), (list, type(None)))]
    changes = [CounterChange(n, baseline[n], current.get(n)) for n in names
               if n not in histograms and baseline[n] != current.get(n)]
    for name in histograms:
        old, new = list(baseline[name]), list(current.get(name) or [])
        for depth in range(max(len(old), len(new))):
            a = old[depth] if depth < len(old) else 0
            b = new[depth] if depth < len(new) else 0
            if a != b:
                changes.append(CounterChange(f"{name}[{depth}]", a, b))
    return changes


def _format_change(c):
    if c.change is None:
        return ""
    text = f"{c.change:+,}"
    if c.relative is not None:
        # Tiny relative changes of huge counters in scientific notation, not +0.000%.
        percent = 100 * c.relative
        text += f" ({percent:+.3f}%)" if abs(percent) >= 1e-3 else f" ({percent:+.2e}%)"
    return text


def print_baseline_report(diffs, baseline_path, file=None, max_histogram_lines=6,
                          coverage=None):
    """Print which runs changed, in which counter and by how much.

    Parameters
    ----------
    diffs : list of RunDiff
        One per baseline entry.
    baseline_path : str
        Shown in the summary.
    file : file-like, optional
        Where to print (default: standard output).
    max_histogram_lines : int, optional
        Histogram entries shown per run before the rest are summarised.
    coverage : CounterCoverage, optional
        Counters the engine lists but the baseline lacks are mentioned once ("not in
        baseline"); counters the engine no longer lists are reported as a failure.
    """
    def out(line=""):
        print(line, file=file)

    if coverage is not None and coverage.not_in_baseline:
        out(f"not in baseline: {', '.join(coverage.not_in_baseline)} (listed by the engine, "
            "not compared; `make baseline` records them)")
    if coverage is not None and coverage.not_listed:
        out(f"MISSING  counter(s) {', '.join(coverage.not_listed)} of {baseline_path} "
            "no longer listed by the engine (hrbench capabilities --json)")
    bad = [d for d in diffs if not d.ok]
    for d in bad:
        out(f"CHANGED  {command_of(d.args)}")
        if d.error:
            out(f"    error: {d.error}")
            continue
        scalars = [c for c in d.changes if "[" not in c.counter]
        histogram = [c for c in d.changes if "[" in c.counter]
        if scalars:
            out(f"    {'counter':<16}{'baseline':>20}{'now':>20}  change")
            for c in scalars:
                out(f"    {c.counter:<16}{c.baseline!s:>20}{c.current!s:>20}  {_format_change(c)}")
        for c in histogram[:max_histogram_lines]:
            out(f"    {c.counter}: {c.baseline} -> {c.current}  {_format_change(c)}")
        if len(histogram) > max_histogram_lines:
            out(f"    ... and {len(histogram) - max_histogram_lines} more histogram entries")
    if bad or (coverage is not None and not coverage.ok):
        out()
        if bad:
            out(f"count baseline: {len(bad)} of {len(diffs)} runs differ from {baseline_path}")
        if coverage is not None and not coverage.ok:
            out(f"count baseline: {len(coverage.not_listed)} counter(s) of {baseline_path} "
                "are no longer listed by the engine")
        out("If the change is intended, rewrite the baseline with `make baseline` "
            "(tools/check_baseline.py --update) and commit it with the change.")
    else:
        out(f"count baseline: all {len(diffs)} runs match {baseline_path}")
