"""Reproduce the published complexity claims: ``python -m analysis.reproduce``.

Runs the sweeps of every claim (reusing cached points), fits the exponents, draws the
figures, and writes ``report.md``, ``report.html`` and ``claims.json`` to the results
directory. Claims whose scene family or engine options the engine does not list are
skipped (reported, not failed). Exit code 0 when no claim that is expected to hold is refuted, 1 when one is,
2 for usage errors, malformed claims files or an engine that cannot be run, 130 when
interrupted (finished points stay cached). See ``docs/analysis.md``.
"""

import argparse
import datetime
import os
import platform
import sys
import time
from pathlib import Path

import matplotlib
import numpy as np

from .claimfile import ClaimsFileError, load_claims, load_claims_dir
from .loader import ResultFormatError, read_links_csv
from .report import ClaimOutcome, get_claims_table, get_figures, print_claims_table, write_report
from .store import ResultStore
from .sweep import (ClaimData, SweepError, engine_capabilities, engine_version, expand_claim,
                    get_claim_data, missing_capability, run_links, run_points)
from .verdict import assess_claim, skipped_assessment

ROOT = Path(__file__).resolve().parent.parent

#: The refinement drawn as a link tiling: scene, parameters, eps.
TILING = ("parallel", {"l": 16.0, "d": 1.0}, 0.3)

USAGE_ERROR = 2
REFUTED = 1


def _parser():
    p = argparse.ArgumentParser(
        prog="python -m analysis.reproduce",
        description="Sweep the hrbench engine, fit exponents and judge the published claims.")
    mode = p.add_mutually_exclusive_group()
    mode.add_argument("--quick", dest="mode", action="store_const", const="quick",
                      help="short sweeps, a few minutes on two cores (default)")
    mode.add_argument("--full", dest="mode", action="store_const", const="full",
                      help="longer sweeps over more decades")
    p.add_argument("--jobs", type=int, default=os.cpu_count() or 1, metavar="N",
                   help="concurrent engine runs (default: number of cores, %(default)s)")
    p.add_argument("--results", type=Path, default=ROOT / "results", metavar="DIR",
                   help="results directory: cache, report, plots (default: results/)")
    p.add_argument("--hrbench", type=Path, default=ROOT / "build" / "hrbench",
                   metavar="PATH", help="the engine executable (default: build/hrbench)")
    p.add_argument("--claims", type=Path, default=ROOT / "analysis" / "claims",
                   metavar="PATH", help="a claims file, or a directory of *.toml claims "
                   "files (default: analysis/claims/)")
    p.add_argument("--claim", action="append", default=[], metavar="ID",
                   help="judge only this claim (repeatable)")
    p.add_argument("--no-tiling", action="store_true",
                   help="skip the link tiling figure (needs 'hrbench links')")
    p.set_defaults(mode="quick")
    return p


def main(argv=None):
    """Run the command line; return the exit code."""
    parser = _parser()
    args = parser.parse_args(argv)
    if args.jobs < 1:
        parser.error("--jobs must be at least 1")
    start = time.perf_counter()

    # Load the claims and check the engine.
    try:
        claims = (load_claims_dir(args.claims) if args.claims.is_dir()
                  else load_claims(args.claims))
    except ClaimsFileError as exc:
        print(f"error: {exc}", file=sys.stderr)
        return USAGE_ERROR
    if args.claim:
        unknown = set(args.claim) - {c.id for c in claims}
        if unknown:
            print(f"error: --claim: unknown id(s) {', '.join(sorted(unknown))}; known: "
                  f"{', '.join(c.id for c in claims)}", file=sys.stderr)
            return USAGE_ERROR
        claims = [c for c in claims if c.id in args.claim]
    try:
        version = engine_version(args.hrbench)
    except SweepError as exc:
        print(f"error: {exc}", file=sys.stderr)
        return USAGE_ERROR

    # Skip the claims that need a scene family or an option the engine does not offer.
    capabilities = engine_capabilities(args.hrbench)
    skipped = {}
    for c in claims:
        reason = missing_capability(c, args.mode, capabilities)
        if reason is not None:
            skipped[c.id] = reason
            print(f"warning: claim {c.id} skipped: {reason}", file=sys.stderr)

    # Run the sweeps, reusing the cache.
    args.results.mkdir(parents=True, exist_ok=True)
    with ResultStore(args.results / "hrbench.sqlite") as store:
        points = {c.id: expand_claim(c, args.mode, args.hrbench, version) for c in claims
                  if c.id not in skipped}
        try:
            summary = run_points([p for ps in points.values() for p in ps], store,
                                 jobs=args.jobs)
        except KeyboardInterrupt:
            print(f"\ninterrupted: finished points are kept in {store.path}; "
                  "run again to resume", file=sys.stderr)
            return 130
        outcomes = []
        for c in claims:
            if c.id in skipped:
                empty = np.zeros(0)
                data = ClaimData(value=empty, x=empty, y=empty)
                outcomes.append(ClaimOutcome(c, data, skipped_assessment(c, skipped[c.id]),
                                             args.mode))
                continue
            data = get_claim_data(c, points[c.id], store)
            outcomes.append(ClaimOutcome(c, data, assess_claim(c, data), args.mode))

    # Draw the link tiling of one small refinement.
    links, links_title = None, ""
    if not args.no_tiling:
        scene, params, eps = TILING
        name = "-".join(f"{k}{v:g}" for k, v in params.items())
        csv_path = args.results / f"links-{scene}-{name}-eps{eps:g}.csv"
        try:
            run_links(args.hrbench, scene, params, eps, csv_path)
            links = read_links_csv(csv_path)
            links_title = (f"{scene} " + " ".join(f"{k}={v:g}" for k, v in params.items())
                           + f", eps={eps:g}, oracle garmann: {len(links)} links")
        except (SweepError, ResultFormatError, OSError) as exc:
            print(f"warning: no link tiling: {exc}", file=sys.stderr)

    # Write the report and print the table.
    wall = time.perf_counter() - start
    context = {
        "date": datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%d %H:%M UTC"),
        "mode": args.mode,
        "engine": str(args.hrbench),
        "engine version": version,
        "host": f"{platform.node()} ({os.cpu_count()} cores, {args.jobs} jobs)",
        "points": (f"{summary['total']} ({summary['cached']} cached, {summary['ran']} run, "
                   f"{summary['failed']} failed)"),
        "claims skipped": (", ".join(f"{k} ({v})" for k, v in skipped.items())
                           if skipped else "none"),
        "sweep and fit wall time": f"{wall:.1f} s",
        "python": (f"{platform.python_version()}, numpy {np.__version__}, "
                   f"matplotlib {matplotlib.__version__}"),
    }
    figures = get_figures(outcomes, links, links_title)
    paths = write_report(args.results, outcomes, context, figures)
    print_claims_table(get_claims_table(outcomes))
    print(f"\nreport: {paths['markdown']}, {paths['html']}, {paths['json']} "
          f"({wall:.1f} s)")
    refuted = [o.claim.id for o in outcomes
               if o.claim.expected_to_hold and o.assessment.verdict == "refuted"]
    if refuted:
        print(f"refuted although expected to hold: {', '.join(refuted)}", file=sys.stderr)
        return REFUTED
    return 0


if __name__ == "__main__":
    sys.exit(main())
