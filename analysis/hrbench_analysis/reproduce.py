"""Reproduce the published complexity claims: ``python -m hrbench_analysis.reproduce``.

Runs the sweeps of every claim (reusing cached points), fits the exponents, draws the
figures, and writes ``report.md``, ``report.html`` and ``claims.json`` to the results
directory. The command ``hrbench-reproduce`` is :func:`main`; ``hrbench-sweep``
(:func:`sweep_main`) runs the same sweeps and writes their points as CSV instead.

The engine is ``--engine CMD`` (split into words like a shell), ``--hrbench PATH`` (one
executable), ``$HRBENCH_ENGINE``, ``build/hrbench`` under the current directory or
``hrbench`` on the ``PATH``, the first that is given (:func:`default_engine`); any
executable that keeps the engine contract of ``docs/engine-contract.md`` will do. The
options of both commands are :mod:`hrbench_analysis.reproduce_options`'s.

Before any run, the claims are checked against the engine's capabilities
(``hrbench capabilities --json``, see :mod:`hrbench_analysis.engine`). A claim whose oracle the
engine does not list, whose scene parameters the family lacks or has out of their range
(the swept values included), or whose formulas read a name no run provides, is an error.
A claim that needs a scene family, option or option value the engine lacks, or an oracle
the engine lists only for scenes of another dimension, is skipped (reported, not
failed), so that an older engine still judges the claims it can run.

Exit codes (:data:`EXIT_CODES`): 0 when every claim came out as expected (no claim that
is expected to hold is refuted); 1 when one that is expected to hold is refuted; 2 for
bad input or environment: usage errors, unreadable or malformed claims files, bad
formulas, absurd ranges, parameters out of the family's range, claims the engine can
never run, an engine that cannot be run, lists no capabilities or refuses runs as input
errors (its exit code 2), and a results cache that is not ours or is corrupt; 70 for an
internal error of the analysis (a bug: one line naming it, its traceback with
``--debug``); 74 when an output
cannot be written (a full disk: the previous report stays as it was); 130 when
interrupted (SIGINT), 143 when terminated (SIGTERM): finished points stay cached and the
engine runs under way end with their child processes. Every error but a bug is one line
on standard error. See ``docs/analysis.md``.
"""

import contextlib
import csv
import datetime
import difflib
import io
import os
import platform
import sys
import time
from dataclasses import dataclass

import matplotlib
import numpy as np

from . import __version__, errors
from .claimfile import (
    ClaimsFileError,
    check_names,
    load_claims,
    load_claims_dir,
    missing_capability,
    oracle_error,
    param_errors,
    resolve_oracle,
)
from .engine import (
    INPUT_ERROR,
    NOT_STARTED,
    EngineError,
    RunSpec,
    engine_text,
    engine_version,
    format_number,
    get_capabilities,
    interrupt_exit_code,
    write_links,
)
from .errors import OUTPUT_ERROR, AnalysisError, OutputError, one_line, run_main
from .explorer import write_explorer
from .loader import SCHEMA_VERSION, ResultFormatError, read_links_csv
from .output import refuse_inputs, staged, write_file, write_stdout
from .report import ClaimOutcome, get_claims_table, get_figures, print_claims_table, write_report
from .reproduce_options import ENGINE_ENV, _reproduce_parser, _sweep_parser, default_engine
from .scene_identity import reference_engine, scene_mismatch
from .schedulers import open_scheduler
from .solution import solution_figures
from .stages import Stage
from .store import ResultStore
from .summary import tally_lines
from .sweep import UNREADABLE_RECORD, ClaimData, get_claim_data, run_points
from .sweep_plan import expand_claim
from .verdict import assess_claim, skipped_assessment

__all__ = ["main", "sweep_main", "default_engine", "check_claims", "engine_refusals",
           "EXIT_CODES", "AS_EXPECTED", "REFUTED", "USAGE_ERROR", "INTERNAL_ERROR",
           "OUTPUT_ERROR", "INTERRUPTED", "TERMINATED", "ENGINE_ENV"]
# default_engine and ENGINE_ENV live in reproduce_options; they are named here too, as
# how the commands find their engine.

#: The refinement drawn as a link tiling: scene, parameters, eps, oracle.
TILING = ("parallel", {"l": 16.0, "d": 1.0}, 0.3, "garmann")

#: Exit code when every claim came out as expected.
AS_EXPECTED = 0
#: Exit code when a claim expected to hold was refuted.
REFUTED = 1
#: Exit code for bad input or environment: usage errors, malformed claims files, bad
#: formulas or ranges, parameters out of range, claims the engine can never run, an
#: engine that cannot be run or refuses runs as input errors, an unusable cache. Every
#: :class:`~hrbench_analysis.errors.AnalysisError` ends the command with it.
USAGE_ERROR = errors.INPUT_ERROR
#: Exit code for an internal error of the analysis, a bug (``EX_SOFTWARE`` of
#: sysexits.h): one line naming it; its traceback with ``--debug``.
INTERNAL_ERROR = errors.INTERNAL_ERROR
#: Exit code when interrupted (Ctrl-C, SIGINT); finished points stay in the cache, and
#: every engine run under way is ended with its child processes.
INTERRUPTED = errors.INTERRUPTED
#: Exit code when terminated (SIGTERM), with the same effects as an interrupt.
TERMINATED = 143

#: Every exit code of the command and its meaning.
EXIT_CODES = {
    AS_EXPECTED: "every claim came out as expected",
    REFUTED: "a claim expected to hold was refuted",
    USAGE_ERROR: "bad input or environment",
    INTERNAL_ERROR: "internal error of the analysis (a bug)",
    OUTPUT_ERROR: "an output could not be written (the previous one is kept)",
    INTERRUPTED: "interrupted",
    TERMINATED: "terminated",
}


def check_claims(claims, mode, capabilities):
    """Check claims against an engine's capabilities, before any run.

    Parameters
    ----------
    claims : list of Claim
    mode : {"quick", "full"}
        Whose options to check.
    capabilities : Capabilities

    Returns
    -------
    errors : list of str
        One line per problem that means the engine can never run a claim: an oracle it
        does not list (:func:`~hrbench_analysis.claimfile.oracle_error`), a scene parameter the
        family lacks or a value (fixed or swept, in either mode) out of its range
        (:func:`~hrbench_analysis.claimfile.param_errors`), or a formula name no run provides
        (:func:`~hrbench_analysis.claimfile.check_names`; checked for the claims not skipped),
        or a scene family the hrbench of this release lacks (:func:`unknown_family`).
        Each line names the file, the line and the claim.
    skipped : dict of str to str
        Claim id to the reason the engine cannot run it now
        (:func:`~hrbench_analysis.claimfile.missing_capability`), in claim order.
    """
    errors, skipped = [], {}
    for c in claims:
        # A selector ("@default", "@kind=...") is checked as the oracle it names.
        name, message = resolve_oracle(c, capabilities)
        if message is None:
            c = c.with_oracle(name)
            message = oracle_error(c, capabilities)
        if message is not None:
            errors.append(f"{c.path}:{c.line}: claim {c.id!r}: {message}")
            continue
        problems = param_errors(c, capabilities)
        if problems:
            errors.extend(problems)
            continue
        reason = missing_capability(c, mode, capabilities)
        if reason is not None and capabilities.family(c.scene) is None:
            message = unknown_family(c.scene, capabilities)
            if (capabilities.engine, capabilities.version) == ("hrbench", __version__):
                # The hrbench of this release has every family its claims may name, so
                # the name is a typo; an older hrbench or another engine may lack it.
                errors.append(f"{c.path}:{c.line}: claim {c.id!r}: {message}")
                continue
            reason = message
        if reason is not None:
            skipped[c.id] = reason
            continue
        try:
            check_names(c, capabilities.scalar_counters,
                        capabilities.family(c.scene).param_names)
        except ClaimsFileError as exc:
            errors.append(str(exc))
    return errors, skipped


def unknown_family(name, capabilities):
    """The message for a scene family the engine lacks, with the nearest names it has.

    ``"engine lacks scene 'paralel' (did you mean 'parallel'?)"``. An outside engine
    may lack a family on purpose, and its claim is skipped; for hrbench itself the same
    message is an error for the hrbench of this release, which offers every family.
    """
    close = difflib.get_close_matches(name, capabilities.family_names, n=2)
    hint = f" (did you mean {' or '.join(map(repr, close))}?)" if close else ""
    return f"engine lacks scene {name!r}{hint}"


def engine_refusals(claim, data):
    """The error line of a claim whose runs the engine refused, or ``None``.

    A run that exits with the engine's input-error code (2: a value the engine refuses,
    touching patches without a recursion limit, ...) or that could not be started (127)
    is not a measurement that failed but bad input or environment: the command exits
    with code 2 instead of judging the claim. So is a run that succeeded but printed a
    record the analysis cannot read (a field missing or of the wrong type; the engine
    breaks its contract, docs/engine-contract.md), or that printed more than
    :data:`~hrbench_analysis.engine.OUTPUT_LIMIT` bytes. Runs that reached a limit (exit
    code 3), crashed or ran past ``--run-timeout`` stay failed points of the claim.

    Parameters
    ----------
    claim : Claim
    data : ClaimData

    Returns
    -------
    line : str or None
        E.g. ``"x.toml:6: claim 'T': the engine refused 11 of 11 runs as input errors
        (exit code 2), first at eps=1: hrbench: ..."``.
    """
    total = data.x.size + len(data.failures) + data.missing
    unreadable = [f for f in data.failures
                  if f["stderr"].startswith(UNREADABLE_RECORD)]
    if unreadable:
        first = unreadable[0]
        return one_line(f"{claim.path}:{claim.line}: claim {claim.id!r}: the engine's run "
                        f"record breaks the engine contract in {len(unreadable)} of {total} "
                        f"runs, first at {claim.sweep_param}={format_number(first['value'])}: "
                        f"{first['stderr'][len(UNREADABLE_RECORD):]} (command: "
                        f"{first['command']}; see docs/engine-contract.md)")
    refused = [f for f in data.failures if f["exit_code"] in (INPUT_ERROR, NOT_STARTED)]
    if not refused:
        return None
    first = refused[0]
    what = ("could not start the engine for" if first["exit_code"] == NOT_STARTED
            else "the engine refused")
    return one_line(f"{claim.path}:{claim.line}: claim {claim.id!r}: {what} {len(refused)} "
                    f"of {total} runs (exit code {first['exit_code']}), first at "
                    f"{claim.sweep_param}={format_number(first['value'])}: "
                    f"{first['stderr'] or 'no message'} (command: {first['command']})")


def _tiling_iv(capabilities):
    # Raise EngineError if the engine cannot draw the link tiling of TILING.
    scene, _, _, oracle = TILING
    if "links" not in capabilities.command_names:
        raise EngineError("engine lacks the command 'links'")
    if capabilities.family(scene) is None or capabilities.oracle(oracle) is None:
        raise EngineError(f"engine lacks scene {scene!r} or oracle {oracle!r}")


def main(argv=None):
    """Run the command line; return the exit code (see :data:`EXIT_CODES`).

    Any :class:`~hrbench_analysis.errors.AnalysisError` (bad input or environment) becomes one
    line on standard error and exit code 2, an interrupt exit code 130 (143 for SIGTERM),
    and any other exception, a bug, one line and exit code 70 (its traceback with
    ``--debug``): :func:`~hrbench_analysis.errors.run_main`. Usage errors of the options
    exit with code 2 through :class:`SystemExit` (argparse).
    """
    return _guarded("hrbench-reproduce", _main, argv)


def sweep_main(argv=None):
    """Run ``hrbench-sweep``; return its exit code.

    It loads and checks the claims as :func:`main` does, runs their sweeps into the
    results cache, and writes one CSV row per point of every claim the engine can run:
    ``claim, series, param, value, x, y, status`` (``status`` is ``ok``, or why the point
    has no measurement: the engine's exit code and message, or an ``x`` or ``y`` that is
    not positive). Exit codes: 0 when the sweep finished (failed points are rows, not
    errors), 2 for bad input or environment (as :func:`main`), 70 for a bug, 130 when
    interrupted.
    """
    return _guarded("hrbench-sweep", _sweep_main, argv)


def _guarded(prog, body, argv):
    # Run a command's body with the exit codes of EXIT_CODES for errors and interrupts.
    return run_main(prog, body, argv, prefix="error: ",
                    interrupted="\ninterrupted: finished points are kept in the results "
                    "cache; run again to resume")


@dataclass
class _Setup:
    # What both commands prepare before any run: the claims to judge, the engine, its
    # version and capabilities, and the claims it cannot run now (id -> reason).
    claims: list
    engine: object
    version: str
    capabilities: object
    skipped: dict


def _prepare(args, parser):
    # Load the claims, find the engine and check the claims against it. Returns a
    # _Setup, or the exit code after printing the problems (one line each).
    if args.jobs < 1:
        parser.error("--jobs must be at least 1")
    claims = (load_claims_dir(args.claims) if args.claims.is_dir()
              else load_claims(args.claims))
    if args.claim:
        unknown = set(args.claim) - {c.id for c in claims}
        if unknown:
            print(f"error: --claim: unknown id(s) {', '.join(sorted(unknown))}; known: "
                  f"{', '.join(c.id for c in claims)}", file=sys.stderr)
            return USAGE_ERROR
        claims = [c for c in claims if c.id in args.claim]
    engine = args.engine if args.engine is not None else default_engine()
    version = engine_version(engine)
    capabilities = get_capabilities(engine)
    if capabilities.run_schema_version != SCHEMA_VERSION:
        print(f"error: engine {engine_text(engine)} writes run records of schema_version "
              f"{capabilities.run_schema_version}; this analysis reads {SCHEMA_VERSION}",
              file=sys.stderr)
        return USAGE_ERROR

    # Name each claim's oracle as the engine does (a selector such as "@default" or
    # { kind = "form-factor" } resolves against the capabilities), then check the
    # claims against the engine before any run.
    claims = [c.with_oracle(resolve_oracle(c, capabilities)[0] or c.oracle)
              for c in claims]
    errors, skipped = check_claims(claims, args.mode, capabilities)
    for line in errors:
        print(f"error: {one_line(line)}", file=sys.stderr)
    if errors:
        return USAGE_ERROR
    for claim_id, reason in skipped.items():
        print(f"warning: claim {claim_id} skipped: {reason}", file=sys.stderr)
    return _Setup(claims, engine, version, capabilities, skipped)


def _sweep(args, setup):
    # Run the sweeps, reusing the cache (shared with any other sweep running on it).
    # Returns (summary, {claim id: (points, ClaimData)} for the claims not skipped,
    # error lines of claims whose runs the engine refused), or the exit code of an
    # interrupt (INTERRUPTED, TERMINATED).
    try:
        args.results.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise AnalysisError(f"--results {args.results}: cannot create the directory "
                            f"({exc.strerror or exc})") from None
    cache = args.cache if args.cache is not None else args.results / "hrbench.sqlite"
    with ResultStore(cache) as store:
        points = {c.id: expand_claim(c, args.mode, setup.engine, setup.version,
                                     setup.capabilities)
                  for c in setup.claims if c.id not in setup.skipped}
        # The scenes the engine reports (scene_sha256) are checked against hrbench's,
        # unless the engine is that hrbench: each claim's first point as soon as it is
        # stored (first points run first), so that another geometry stops the sweep
        # after a run, then every point after the sweep.
        (reference, same), digests = reference_engine(setup.engine), {}
        check = (None if same or reference is None else
                 _FirstScenes(args.mode, setup.claims, points, store, reference, digests))
        try:
            if check is not None:
                check.cached()
            with open_scheduler(args.scheduler, args.jobs) as scheduler:
                summary = run_points([p for ps in points.values() for p in ps], store,
                                     scheduler=scheduler, timeout=args.run_timeout,
                                     first=() if check is None else check.claims,
                                     on_stored=check)
        except _SceneRefused as exc:
            return None, {}, [str(exc)]
        except KeyboardInterrupt as exc:
            print(f"\ninterrupted: finished points are kept in {store.path}; "
                  "run again to resume", file=sys.stderr)
            return interrupt_exit_code(exc)
        measured, refusals = {}, []
        with contextlib.ExitStack() as stage:
            if not same:
                stage.enter_context(Stage("checking the engine's scenes against hrbench's"))
            _judge_scenes(args, setup, points, store, reference, same, digests, measured,
                          refusals)
        if not same and reference is not None and not refusals:
            print(f"scenes: {_agreeing(digests)}", file=sys.stderr)
    return summary, measured, refusals


class _SceneRefused(Exception):
    # A claim's first point was refined on other patches than hrbench's: its error line.
    pass


class _FirstScenes:
    # Each claim's first point, checked against hrbench's scene once stored: called by
    # run_points with every point it stores (a cached one, by cached(), before).

    def __init__(self, mode, claims, points, store, reference, digests):
        self.mode, self.store, self.reference, self.digests = mode, store, reference, digests
        self.points = {c.id: points[c.id] for c in claims if points.get(c.id)}
        self.claims = {}
        for c in claims:
            if c.id in self.points:
                self.claims.setdefault(self.points[c.id][0].key, []).append(c)

    def cached(self):
        for key in self.claims:
            if self.store.is_final(key):
                self._check(key)

    def __call__(self, stored):
        if stored.key in self.claims and stored.ok:
            self._check(stored.key)

    def _check(self, key):
        for c in self.claims[key]:
            line, _ = scene_mismatch(c, self.mode, self.points[c.id][:1], self.store,
                                     self.reference, self.digests)
            if line is not None:
                raise _SceneRefused(f"{line}; found on the claim's first point, which the "
                                    "sweep ran first, and the sweep stopped there")


def _agreeing(digests):
    # One line on the scenes compared: how many agreed, or that none was reported.
    agreed = sum(len(d) == 64 for d in digests.values())
    if not digests:
        return ("the engine reports no scene_sha256: its scenes are not checked against "
                "hrbench's (docs/engine-contract.md#scene-identity)")
    return (f"the engine's scene_sha256 agrees with hrbench's for {agreed} scene"
            f"{'' if agreed == 1 else 's'}"
            + (f" ({len(digests) - agreed} not checked: hrbench cannot save them)"
               if agreed < len(digests) else ""))


def _judge_scenes(args, setup, points, store, reference, same, digests, measured, refusals):
    # Read each claim's points; a claim whose runs the engine refused, or whose scenes
    # differ from hrbench's, goes to `refusals`, the others to `measured`.
    for c in setup.claims:
        if c.id in setup.skipped:
            continue
        data = get_claim_data(c, points[c.id], store,
                              setup.capabilities.scalar_counters)
        line = engine_refusals(c, data)
        if line is None and not same:
            line, warnings = scene_mismatch(c, args.mode, points[c.id], store, reference,
                                            digests)
            for warning in warnings:
                print(f"warning: {one_line(warning)}", file=sys.stderr)
        if line is not None:
            refusals.append(line)
            continue
        measured[c.id] = (points[c.id], data)


def _prepare_and_sweep(args, parser):
    """Prepares and runs the sweeps of both commands: (setup, summary, measured), or the
    exit code when preparing fails, the sweep is interrupted or the engine refuses a claim
    (each refusal printed as one line)."""
    setup = _prepare(args, parser)
    if isinstance(setup, int):
        return setup
    swept = _sweep(args, setup)
    if isinstance(swept, int):
        return swept
    summary, measured, refusals = swept
    for line in refusals:
        print(f"error: {line}", file=sys.stderr)
    if refusals:
        return USAGE_ERROR
    return setup, summary, measured


def _sweep_main(argv):
    parser = _sweep_parser()
    args = parser.parse_args(argv)
    refuse_inputs([("--out", args.out)], [("--claims", args.claims), ("--cache", args.cache)])
    ran = _prepare_and_sweep(args, parser)
    if isinstance(ran, int):
        return ran
    setup, summary, measured = ran
    rows = []
    for c in setup.claims:
        if c.id not in measured:
            continue
        points, data = measured[c.id]
        series = {p.value: p.series for p in points}
        for value, x, y, s in zip(data.value, data.x, data.y, data.series, strict=True):
            rows.append((c.id, s, c.sweep_param, format_number(value), repr(float(x)),
                         repr(float(y)), "ok"))
        for f in data.failures:
            status = f"exit code {f['exit_code']}: {f['stderr'] or 'no message'}"
            rows.append((c.id, series.get(f["value"], ""), c.sweep_param,
                         format_number(f["value"]), "", "", one_line(status)))
    text = io.StringIO()
    writer = csv.writer(text, lineterminator="\n")
    writer.writerow(("claim", "series", "param", "value", "x", "y", "status"))
    writer.writerows(rows)
    if args.out is None:
        write_stdout(text.getvalue())
    else:
        write_file(args.out, text.getvalue())
    print(f"{summary['total']} points ({summary['cached']} cached, {summary['ran']} run, "
          f"{summary['failed']} failed)" + (f"; CSV in {args.out}" if args.out else ""),
          file=sys.stderr)
    return AS_EXPECTED


def _main(argv):
    parser = _reproduce_parser()
    args = parser.parse_args(argv)
    start = time.perf_counter()
    ran = _prepare_and_sweep(args, parser)
    if isinstance(ran, int):
        return ran
    setup, summary, measured = ran
    sweep_wall = time.perf_counter() - start
    capabilities, skipped = setup.capabilities, setup.skipped
    outcomes = []
    with Stage(f"fitting {len(setup.claims)} claims", total=len(setup.claims)) as stage:
        for c in setup.claims:
            stage.advance()
            if c.id in skipped:
                empty = np.zeros(0)
                data = ClaimData(value=empty, x=empty, y=empty)
                outcomes.append(ClaimOutcome(c, data, skipped_assessment(c, skipped[c.id]),
                                             args.mode))
                continue
            data = measured[c.id][1]
            family = capabilities.family(c.scene)
            outcomes.append(ClaimOutcome(c, data, assess_claim(c, data), args.mode,
                                         family.dimension if family else None))

    # Draw the link tiling of one small refinement.
    links, links_title = None, ""
    runs_pictures = not (args.no_pictures or args.charts_only)
    if runs_pictures:
        scene, params, eps, oracle = TILING
        name = "-".join(f"{k}{v:g}" for k, v in params.items())
        csv_path = args.results / f"links-{scene}-{name}-eps{eps:g}.csv"
        try:
            _tiling_iv(capabilities)
            with Stage("listing the links of the tiling figure"), \
                    staged(csv_path) as written:  # whole for another run reading it
                write_links(setup.engine, RunSpec.of(scene, params, eps, oracle), written)
                links = read_links_csv(written)
            links_title = (f"{scene} " + " ".join(f"{k}={v:g}" for k, v in params.items())
                           + f", eps={eps:g}, oracle {oracle}: {len(links)} links")
        except (EngineError, ResultFormatError, OSError) as exc:
            print(f"warning: no link tiling: {one_line(exc)}", file=sys.stderr)

    # Draw the figures, solve for the pictures, write the report and print the table.
    context = {
        "date": datetime.datetime.now(datetime.UTC).strftime("%Y-%m-%d %H:%M UTC"),
        "mode": args.mode,
        "engine": engine_text(setup.engine),
        "engine version": setup.version,
        "host": f"{platform.node()} ({os.cpu_count()} cores, {args.jobs} jobs)",
        "scheduler": args.scheduler,
        "points": (f"{summary['total']} ({summary['cached']} cached, {summary['ran']} run, "
                   f"{summary['failed']} failed)"),
        "claims skipped": (", ".join(f"{k} ({v})" for k, v in skipped.items())
                           if skipped else "none"),
        "sweep wall time": f"{sweep_wall:.1f} s (loading the claims and running the sweep)",
        "python": (f"{platform.python_version()}, numpy {np.__version__}, "
                   f"matplotlib {matplotlib.__version__}"),
    }
    figures = []
    if not args.no_pictures:
        with Stage("drawing the charts"):
            figures = get_figures(outcomes, links, links_title)
    if runs_pictures:
        figures += solution_figures(setup.engine, args.results, args.jobs,
                                    warn=lambda line: print(line, file=sys.stderr),
                                    progress=sys.stderr)
    every = len(figures) + sum(f.alternate is not None for f in figures)
    try:
        with Stage(f"rendering {every} figures and writing the report", total=every,
                   beat=False) as stage:  # renders in forked processes: no thread
            paths = write_report(args.results, outcomes, context, figures, args.jobs,
                                 advance=stage.advance)
    except OSError as exc:  # making plots/ or removing an old figure
        raise OutputError(f"--results {args.results}: cannot write the report "
                          f"({exc.strerror or exc}: {exc.filename or ''})") from None
    if runs_pictures:
        try:
            with Stage("writing the explorer page"):
                write_explorer(args.results, setup.engine)
        except (EngineError, ResultFormatError, OSError) as exc:
            print(f"warning: no explorer page: {one_line(exc)}", file=sys.stderr)
    print_claims_table(get_claims_table(outcomes))
    wall = time.perf_counter() - start
    print(f"\nreport: {paths['markdown']}, {paths['html']}, {paths['json']} "
          f"(sweep {sweep_wall:.1f} s, then fits, figures and report "
          f"{wall - sweep_wall:.1f} s: {wall:.1f} s of wall time in all)")
    for line in tally_lines(outcomes):
        print(line)
    # Timed claims never decide the exit code: their verdicts change with the load.
    refuted = [o.claim.id for o in outcomes if not o.claim.timed
               and o.claim.expected_to_hold and o.assessment.verdict == "refuted"]
    if refuted:
        print(f"refuted although expected to hold: {', '.join(refuted)}", file=sys.stderr)
        return REFUTED
    return AS_EXPECTED


if __name__ == "__main__":
    sys.exit(main())
