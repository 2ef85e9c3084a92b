"""Writing the report's files as one set (:func:`write_report`): ``report.md``,
``report.html``, ``claims.json`` and ``plots/*.png``."""

from ..output import folder_lock, write_files
from ..summary import report_order, tally_lines
from .claims_json import claims_json_text
from .figure import render_pngs
from .html_page import html_report
from .markdown_page import markdown_report
from .sections import _contents, _place_figures
from .table import KINDS_NOTE, TIMED_NOTE, claims_table_lines, get_claims_table

__all__ = ["write_report"]


def write_report(outdir, outcomes, context, figures, jobs=1, advance=None):
    """Write ``report.md``, ``report.html``, ``claims.json``, ``summary.txt`` (the claims
    table, the reasons and the tally as the terminal shows them) and ``plots/*.png``.

    The files are written as one set (:func:`~hrbench_analysis.output.write_files`): a
    failed write leaves the previous report as it was, and runs that share `outdir`
    replace their sets one at a time (:func:`~hrbench_analysis.output.folder_lock`), each
    removing the figures of earlier runs that its report does not show.

    Parameters
    ----------
    outdir : pathlib.Path
        Results directory (created if missing).
    outcomes : sequence of ClaimOutcome
    context : dict of str to str
        Facts about the run (mode, engine, version, wall time, ...), shown at the top
        and stored in ``claims.json``.
    figures : sequence of ReportFigure
    jobs : int
        Processes that render the figures (`render_pngs`).
    advance : callable, optional
        Called as each figure (or alternate view) is rendered, for a progress line.

    Returns
    -------
    paths : dict of str to pathlib.Path
        ``{"markdown": ..., "html": ..., "json": ..., "summary": ...}``.

    Raises
    ------
    AnalysisError, OutputError
        If a file cannot be written (:mod:`hrbench_analysis.output`).
    """
    outdir.mkdir(parents=True, exist_ok=True)
    plots = outdir / "plots"
    plots.mkdir(exist_ok=True)
    every = [*figures, *(f.alternate for f in figures if f.alternate is not None)]
    outcomes = report_order(outcomes)
    rows = get_claims_table(outcomes)
    pngs = dict(zip((f.name for f in every), render_pngs(every, jobs, advance), strict=True))

    json_path = outdir / "claims.json"
    json_text = claims_json_text(outcomes, context)
    placed = _place_figures(outcomes, figures)
    contents = _contents(rows, placed)
    note = [KINDS_NOTE, ""] + ([TIMED_NOTE, ""] if any(r["mark"] for r in rows) else [])
    md_path = outdir / "report.md"
    md_text = markdown_report(outcomes, rows, context, placed, contents, note)
    html_path = outdir / "report.html"
    html_text = html_report(outcomes, rows, context, placed, contents, note, pngs)
    # What the terminal shows, kept: the table, the reasons and the tally.
    summary_path = outdir / "summary.txt"
    summary_text = "\n".join([*claims_table_lines(rows), "", *tally_lines(outcomes), ""])

    # The figures first, so that a report never names a figure not yet written.
    files = [*((plots / f"{name}.png", png) for name, png in pngs.items()),
             (json_path, json_text), (summary_path, summary_text), (md_path, md_text),
             (html_path, html_text)]
    with folder_lock(outdir):
        write_files(files)
        for stale in [*plots.glob("chart*.png"), *plots.glob("slopes*.png")]:
            if stale.name not in {f"{name}.png" for name in pngs}:
                # A figure of an earlier run whose claims have changed (another run on
                # the folder may have removed it first).
                stale.unlink(missing_ok=True)
    return {"markdown": md_path, "html": html_path, "json": json_path,
            "summary": summary_path}
