"""The report: claims table, per-claim details, figures, as Markdown, HTML and JSON."""

import base64
import html
import io
import json
import math
import multiprocessing
import os
import signal
import sys
import textwrap
from dataclasses import dataclass

import numpy as np
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure

from .engine import option_argv, option_flag, option_text
from .output import folder_lock, write_files
from .plots import (
    PowerLawSeries,
    plot_link_tiling,
    plot_power_law_comparison,
    plot_ratio,
    plot_slopes,
)
from .summary import (
    GROUPS,
    TIMED_MARK,
    claim_anchors,
    claim_group,
    distinct_names,
    report_order,
    source_label,
    verdict_tally,
)
from .verdict import MEASURED, SKIPPED, expected_text

__all__ = [
    "ClaimOutcome",
    "ReportFigure",
    "get_claims_table",
    "print_claims_table",
    "format_claims_table",
    "TERMINAL_WIDTH",
    "TIMED_NOTE",
    "get_claims_json",
    "get_figures",
    "write_report",
]


@dataclass
class ClaimOutcome:
    """A claim together with its measured points and its assessment.

    Attributes
    ----------
    claim : Claim
    data : ClaimData
    assessment : Assessment
    mode : str
        The sweep mode (``"quick"`` or ``"full"``): which range and options were used.
    dimension : int or None
        Dimension of the claim's scene (2 or 3), when the engine lists it: claims of
        different dimensions never share a chart.
    """

    claim: object
    data: object
    assessment: object
    mode: str = "quick"
    dimension: object = None

    @property
    def agrees(self):
        """Whether the verdict is what the claims file expects.

        ``True`` for a reproduced claim expected to hold and a refuted claim expected
        not to hold, ``False`` for the opposite, ``None`` if inconclusive, skipped or
        measured (nothing published to agree with).
        """
        verdict = self.assessment.verdict
        if verdict in ("inconclusive", SKIPPED, MEASURED):
            return None
        return (verdict == "reproduced") == self.claim.expected_to_hold


@dataclass
class ReportFigure:
    """One figure of the report.

    Attributes
    ----------
    name : str
        File stem of the PNG (``results/plots/<name>.png``).
    title : str
        Heading of the figure in the report.
    caption : str
        What the figure shows, for a reader who has not seen the paper.
    figure : matplotlib.figure.Figure
    claims : tuple of str
        Ids of the claims it illustrates: the report shows it in the section of the
        first of them (empty: in the closing "Figures" section).
    alternate : ReportFigure or None
        Another view of the same thing (the Cornell box with its element mesh drawn),
        shown at a toggle below the figure in the HTML report (``<details>``) and after
        it in the Markdown report; its title is the toggle's label.
    """

    name: str
    title: str
    caption: str
    figure: object
    claims: tuple = ()
    alternate: object = None

    def png(self):
        """The figure as PNG bytes (100 dpi)."""
        # The canvas's own print_png draws once, running the layout engine inside the
        # draw; savefig() first draws without rendering to run it, then again. The bytes
        # are the same (checked on every figure of the report), the CPU time a sixth less.
        buf = io.BytesIO()
        self.figure.set_dpi(100)
        FigureCanvasAgg(self.figure).print_png(buf)
        return buf.getvalue()


def _num(value, digits=3):
    if value is None or (isinstance(value, float) and not math.isfinite(value)):
        return "-"
    return f"{value:.{digits}f}"


def get_claims_table(outcomes):
    """One row per claim, ready to print, in the report's order
    (:func:`~hrbench_analysis.summary.report_order`).

    Parameters
    ----------
    outcomes : sequence of ClaimOutcome

    Returns
    -------
    rows : list of dict
        Keys ``id``, ``anchor`` (of the claim's section), ``mark`` (:data:`TIMED_MARK` for
        a claim that times the CPU, else empty), ``statement``, ``source`` and
        ``source_short`` (who states it, :func:`~hrbench_analysis.summary.source_label`),
        ``citation``, ``group`` (its heading, :data:`~hrbench_analysis.summary.GROUPS`),
        ``expected``, ``measured``, ``interval``, ``verdict``, ``expected_to_hold``,
        ``agrees``, ``reason`` (strings).
    """
    outcomes = report_order(outcomes)
    anchors = claim_anchors([o.claim for o in outcomes])
    rows = []
    for o in outcomes:
        a, c = o.assessment, o.claim
        fit, iv = a.fit, a.interval
        rows.append({
            "id": c.id,
            "anchor": anchors[c.id],
            "mark": TIMED_MARK if c.timed else "",
            "statement": c.statement,
            "source": source_label(c),
            "source_short": source_label(c, short=True),
            "citation": c.source,
            "group": GROUPS[claim_group(c)][1],
            "expected": expected_text(c),
            "measured": _num(fit.exponent) if fit else "-",
            "interval": f"[{_num(iv.low)}, {_num(iv.high)}]" if iv else "-",
            "verdict": a.verdict,
            "expected_to_hold": "yes" if c.expected_to_hold else "no",
            "agrees": {True: "yes", False: "NO", None: "-"}[o.agrees],
            "reason": a.reason,
        })
    return rows


_COLUMNS = (("id", "claim"), ("source", "source"), ("statement", "statement"),
            ("expected", "expected k"), ("measured", "measured k"), ("interval", "interval"),
            ("verdict", "verdict"), ("expected_to_hold", "should hold"),
            ("agrees", "as expected"))

#: Columns of the claims table on the terminal.
TERMINAL_WIDTH = 100

# The terminal's columns: (row key, header, widest); the statement, last, takes the rest
# of TERMINAL_WIDTH. The claimed exponent is in the statement and the interval in the
# reasons printed below the table, so neither has a column here.
_TERMINAL = (("claim", "claim", 20), ("source_short", "source", 13), ("measured", "k", 8),
             ("verdict", "verdict", 12), ("agrees", "as expected", 11))

#: The note on the claims that time the CPU, below every claims table that has one.
TIMED_NOTE = (f"{TIMED_MARK} times the CPU: its x or y is a time (s), which depends on the "
              "machine and its load, so its points, exponent and verdict change whenever "
              "they are measured anew (another machine, an empty cache); the other claims "
              "measure counts and errors, which do not.")


def _clip(text, width):
    # The text cut to `width` characters, at a space where one is near, an ellipsis
    # marking the cut.
    if len(text) <= width:
        return text
    cut = text[:width - 1]
    space = cut.rfind(" ")
    return (cut[:space] if space > width // 2 else cut).rstrip() + "…"


def _wrap(text):
    # The text as lines of at most TERMINAL_WIDTH characters, continuation lines
    # indented; words (formulas, paths) are never split.
    return textwrap.wrap(text, TERMINAL_WIDTH, subsequent_indent="    ",
                         break_long_words=False, break_on_hyphens=False)


def format_claims_table(rows):
    """The claims table as lines of aligned plain text, :data:`TERMINAL_WIDTH` wide at most.

    Parameters
    ----------
    rows : list of dict
        From :func:`get_claims_table`.

    Returns
    -------
    lines : list of str
        Header, rule, one line per claim (id with its mark, the first author and year of
        its source, measured exponent, verdict, whether as expected, statement cut to the
        columns left), then a line that says what ``k`` is and :data:`TIMED_NOTE` if a
        claim times the CPU. Cut cells end in an ellipsis; nothing wraps.
    """
    cells = [{**r, "claim": r["id"] + r["mark"]} for r in rows]
    widths = [min(cap, max([len(head), *(len(c[key]) for c in cells)]))
              for key, head, cap in _TERMINAL]
    # The caps leave the statement 26 columns at least.
    rest = TERMINAL_WIDTH - sum(widths) - 2 * len(widths)
    columns = [*(key for key, _, _ in _TERMINAL), "statement"]
    widths.append(rest)

    def line(values):
        return "  ".join(_clip(v, w).ljust(w) for v, w in zip(values, widths,
                                                              strict=True)).rstrip()

    lines = [line([*(head for _, head, _ in _TERMINAL), "statement"]),
             "  ".join("-" * w for w in widths)]
    lines += [line([c[key] for key in columns]) for c in cells]
    lines += _wrap("k: the measured exponent (the claimed one is in the statement, the "
                   "interval in the reasons below)")
    if any(r["mark"] for r in rows):
        lines += _wrap(TIMED_NOTE)
    return lines


def print_claims_table(rows, file=None):
    """Print the claims table (:func:`format_claims_table`), then one reason per claim,
    wrapped to :data:`TERMINAL_WIDTH` columns.

    Parameters
    ----------
    rows : list of dict
        From :func:`get_claims_table`.
    file : text stream, optional
        Default standard output.
    """
    file = sys.stdout if file is None else file
    for text in format_claims_table(rows):
        print(text, file=file)
    print(file=file)
    for r in rows:
        for text in _wrap(f"{r['id']}: {r['verdict']}: {r['reason']}"):
            print(text, file=file)


def get_claims_json(outcomes, mode="quick"):
    """One JSON-ready object per claim.

    Parameters
    ----------
    outcomes : sequence of ClaimOutcome
    mode : {"quick", "full"}, optional
        The sweep mode, to record each claim's swept range.

    Returns
    -------
    objects : list of dict
        ``id``, ``statement``, ``source``, ``expected_exponent``, ``tolerance``,
        ``measured_exponent``, ``interval_low``, ``interval_high``, ``verdict``, ``reason``,
        and the details of the measurement (``null`` where not computed).
    """
    out = []
    for o in outcomes:
        a, c, d = o.assessment, o.claim, o.data
        fit, iv, theta, models = a.fit, a.interval, a.theta, a.models
        obj = {
            "id": c.id,
            "statement": c.statement,
            "source": c.source,
            "source_key": c.source_key,
            "description": c.description,
            "expected_exponent": c.expected_exponent,
            "tolerance": c.tolerance,
            "measured_exponent": fit.exponent if fit else None,
            "interval_low": iv.low if iv else None,
            "interval_high": iv.high if iv else None,
            "interval_parts": ({
                "statistical": {"low": fit.low, "high": fit.high,
                                "confidence": fit.confidence},
                "window_octaves": iv.window_octaves,
                "window_exponents": iv.windows.slope.tolist(),
                "upper_windows_exponent": None if math.isnan(iv.upper) else iv.upper,
                "drift": iv.drift,
            } if iv else None),
            "verdict": a.verdict,
            "reason": a.reason,
            "expected_to_hold": c.expected_to_hold,
            "as_expected": o.agrees,
            "published": c.published,
            "command": c.command,
            "scene": c.scene,
            "mesh": ({"file": os.path.basename(c.mesh), "sha256": c.mesh_sha256}
                     if c.mesh else None),
            "params": c.params,
            "oracle": c.oracle,
            "options": c.options_for(o.mode),
            "eps": c.eps,
            "sweep_param": c.sweep_param,
            "sweep": {"param": c.sweep_param, "from": c.range_for(mode).start,
                      "to": c.range_for(mode).stop,
                      "per_decade": c.range_for(mode).per_decade,
                      "grid": {name: list(values) for name, values in c.grid.items()}},
            "min_area": c.min_area,
            "x": c.x.text,
            "y": c.y.text,
            "regime": {"x_min": c.x_min, "x_max": c.x_max},
            "points": int(a.x.size),
            "points_in_regime": a.n_regime,
            "decades_in_regime": a.decades,
            "failed_points": d.failures,
            "missing_points": d.missing,
            "prefactor": fit.prefactor if fit else None,
            "rms_log10": fit.rms if fit else None,
            "bootstrap": ({"method": "moving-block residual bootstrap", "block": fit.block,
                           "resamples": fit.n_boot, "seed": fit.seed} if fit else None),
            "settled": a.settled,
            "settle_spread": None if math.isnan(a.settle_spread) else a.settle_spread,
            "theta_band": theta.band if theta else None,
            "theta_band_limit": theta.max_band if theta else None,
            "theta_trend_per_decade": theta.trend if theta else None,
            "theta_holds": theta.holds if theta else None,
            "best_model": models.best if models else None,
            "models": ([{"model": n, "delta_aic": float(da), "rms_log10": float(r)}
                        for n, da, r in zip(models.names, models.delta_aic, models.rms,
                                            strict=True)]
                       if models else None),
            "data": {"x": a.x.tolist(), "y": a.y.tolist()},
        }
        out.append(obj)
    return out


def _options_text(claim, mode):
    # "visibility fraction, rays-per-side 2, triangulate" (as on the command line, without
    # dashes).
    return ", ".join(option_flag(name)[2:] + ("" if value is True else f" {option_text(value)}")
                     for name, value in claim.options_for(mode).items())


def _scene_text(claim):
    # The family's name, or the mesh file's.
    return f"mesh {os.path.basename(claim.mesh)}" if claim.mesh else claim.scene


def _series_label(claim, ids, values, mode="quick"):
    fixed = ", ".join(f"{k}={v:g}" for k, v in claim.params.items() if k != claim.sweep_param)
    if claim.eps is not None:
        fixed += f", eps={claim.eps:g}"
    if claim.min_area is not None:
        fixed += f", min_area={claim.min_area:g}"
    for name, grid in claim.grid.items():
        fixed += f", {name} in {{{', '.join(f'{v:g}' for v in grid)}}}"
    options = _options_text(claim, mode)
    if options:
        fixed += f", {options}"
    swept = ""
    if len(values):
        swept = f", {claim.sweep_param} from {values.min():g} to {values.max():g}"
        if claim.sweep_param == "eps":
            swept = f", eps from {values.max():g} down to {values.min():g}"
    return f"{', '.join(ids)}: {_scene_text(claim)} {fixed}{swept}"


def _symbol(text):
    return text.replace(" ", "")


def _group(text):
    # Parenthesise a formula with operators: "L/N" -> "(L/N)", "N" -> "N".
    text = _symbol(text)
    return f"({text})" if any(op in text for op in "+-*/") else text


def _power(text, k):
    return _group(text) if k == 1 else f"{_group(text)}^{k:g}"


def get_figures(outcomes, links=None, links_title=""):
    """Draw the report's figures.

    Parameters
    ----------
    outcomes : sequence of ClaimOutcome
    links : LinkTable, optional
        Links of one refinement, drawn as a tiling of the parameter square.
    links_title : str, optional
        Description of that refinement (scene, parameters, eps).

    Returns
    -------
    figures : list of ReportFigure
        One figure per pair of measured quantities (claims measuring the same x and y
        share a chart, with reference slopes for their exponents; a claim's ``chart``
        name overrides the grouping), one per claim (local exponents and the Theta
        ratio), and the tiling if `links` is given.
    """
    figures = []
    usable = [o for o in outcomes if o.assessment.x.size]

    # Draw one chart per pair of measured quantities (or per chart name) and dimension,
    # claims overlaid; a claim swept over a grid gives one series per grid value.
    groups = {}
    for o in usable:
        key = (o.claim.chart if o.claim.chart is not None
               else (_symbol(o.claim.x.text), _symbol(o.claim.y.text)), o.dimension)
        groups.setdefault(key, []).append(o)
    # File names: distinct for distinct claims, even ids that differ only in case or
    # punctuation (R1 and r1); a chart's named by the JSON list of its ids, which no
    # other list of ids gives.
    chart_names = distinct_names([_id_list(m) for m in groups.values()], "chart")
    slopes_names = distinct_names([o.claim.id for o in usable], "slopes")
    for members in groups.values():
        fig = Figure(figsize=(9, 8), layout="constrained")
        ax = fig.add_subplot()
        same_points = {}
        for o in members:
            key = (o.assessment.x.tobytes(), o.assessment.y.tobytes())
            same_points.setdefault(key, []).append(o)
        series, anchors = [], {}
        for same in same_points.values():
            main = next((o for o in same if o.claim.expected_to_hold), same[0])
            a, d = main.assessment, main.data
            label = _series_label(main.claim, [o.claim.id for o in same], d.value, main.mode)
            groups_of = _point_series(main)
            for n, name in enumerate(dict.fromkeys(groups_of)):
                sel = groups_of == name
                series.append(PowerLawSeries(
                    a.x[sel], a.y[sel], in_regime=a.in_regime[sel],
                    fit=a.interval if n == 0 else None,
                    label=(f"{label}: {name}" if n == 0 and name
                           else f"{main.claim.id}: {name}" if name else label)))
        # A claimed slope is drawn through the points of a claim expected to hold.
        for o in sorted(members, key=lambda o: not o.claim.expected_to_hold):
            a = o.assessment
            anchors.setdefault(o.claim.expected_exponent,
                               (a.x[a.in_regime], a.y[a.in_regime]))
        first = members[0].claim
        published = any(o.claim.published for o in members)
        plot_power_law_comparison(ax, series, slopes=anchors, symbol=_symbol(first.x.text),
                                  slope_word="claimed" if published else "hypothesised")
        ax.set_xlabel(first.x_label)
        ax.set_ylabel(first.y_label)
        ids = ", ".join(o.claim.id for o in members)
        title = f"{_label_name(first.y_label)} against {_label_name(first.x_label)} ({ids})"
        title = title[0].upper() + title[1:]
        ax.set_title(title)
        ax.grid(True, which="major", alpha=0.3)
        # Below the axes, so that the legend covers no point.
        ax.legend(fontsize=8, loc="upper center", bbox_to_anchor=(0.5, -0.1))
        caption = ("Log-log plot; filled markers lie in the asymptotic regime that is "
                   "judged, hollow ones outside it; the solid line is the least-squares fit "
                   f"over the regime, the grey lines the "
                   f"{'claimed' if published else 'hypothesised (nothing is published)'} "
                   "slopes drawn through the regime's points (their prefactor fitted with "
                   "the slope fixed). "
                   + " ".join(f"{o.claim.id}: {o.claim.description}" for o in members))
        figures.append(ReportFigure(chart_names[_id_list(members)], title, caption, fig,
                                    tuple(o.claim.id for o in members)))

    # Draw per claim: local exponents and the bounded-ratio check.
    for o in usable:
        a, c = o.assessment, o.claim
        fig = Figure(figsize=(12, 4.4), layout="constrained")
        ax1, ax2 = fig.subplots(1, 2)
        plot_slopes(ax1, a.local, a.windows, expected=c.expected_exponent,
                    tolerance=c.tolerance, x_label=c.x_label)
        ax1.set_title(f"{c.id}: local exponent of {_symbol(c.y.text)} "
                      f"against {_symbol(c.x.text)}")
        ax1.grid(True, alpha=0.3)
        ax1.legend(fontsize=8)
        ratio = a.y / a.x ** c.expected_exponent
        ratio_label = f"{_group(c.y.text)} / {_power(c.x.text, c.expected_exponent)}"
        plot_ratio(ax2, a.x, ratio, in_regime=a.in_regime,
                   band=a.theta.band if a.theta else None, x_label=c.x_label,
                   ratio_label=ratio_label)
        ax2.set_title(f"{c.id}: Theta check, {ratio_label}")
        ax2.grid(True, alpha=0.3)
        ax2.legend(fontsize=8)
        caption = ("Left: exponent between neighbouring points (grey; binary subdivision "
                   "makes counts step functions, so these oscillate) and exponent fitted "
                   "over sliding one-decade windows (blue), against the claimed exponent "
                   "and its tolerance (red). Right: the ratio y/x^k; the claim "
                   "y = Theta(x^k) holds when it stays between two constants (dashed).")
        figures.append(ReportFigure(slopes_names[c.id],
                                    f"{c.id}: local exponents and Theta check", caption, fig,
                                    (c.id,)))

    # Draw the tiling of the parameter square by the links of one root pair.
    if links is not None and len(links):
        fig = Figure(figsize=(7.5, 6.6), layout="constrained")
        ax = fig.add_subplot()
        coll = plot_link_tiling(ax, links)
        bar = fig.colorbar(coll, ax=ax)
        bar.set_label("link depth depth_i + depth_j (levels)")
        ax.set_title(f"Links of one root pair tile the parameter square\n{links_title}")
        caption = ("Every link (i, j) is drawn as the rectangle I_i x I_j of the two element "
                   "intervals, coloured by depth; together they tile the square of positions "
                   "on the two plates. Where the two positions face each other (here the "
                   "anti-diagonal t_i + t_j = l, since the second plate runs opposite to "
                   "the first) the distance is smallest and so are the rectangles. Halving "
                   "eps halves the smallest elements (N doubles) and also widens the band "
                   "of small rectangles around that line, so at fixed geometry the links "
                   "grow like N^2; growing the plates at fixed eps only lengthens the band, "
                   "so the links grow like N.")
        figures.append(ReportFigure("tiling", "Link tiling of the parameter square",
                                    caption, fig))
    return figures


def _point_series(outcome):
    # The grid value of every point ("l=16"), or "" for a claim without a grid.
    labels = getattr(outcome.data, "series", None)
    if labels is None or len(labels) != outcome.assessment.x.size:
        return np.full(outcome.assessment.x.size, "", dtype=object)
    return np.asarray(labels, dtype=object)


def _label_name(label):
    # "number of elements N (count)" -> "number of elements N"
    return label.split(" (")[0]


def _id_list(outcomes):
    return json.dumps([o.claim.id for o in outcomes])


def _md_text(text):
    # Text that stays text in a Markdown table cell.
    return text.replace("|", "\\|")


def _md_link(text, anchor):
    # A link to an anchor of the report; its text escaped to stay one link in a cell.
    text = "".join("\\" + ch if ch in "\\[]|" else ch for ch in text)
    return f"[{text}](#{anchor})"


def _md_table(rows):
    head = "| " + " | ".join(h for _, h in _COLUMNS) + " |"
    rule = "|" + "|".join("---" for _ in _COLUMNS) + "|"
    body = ["| " + " | ".join(_md_link(r["id"], r["anchor"]) + r["mark"] if k == "id"
                              else _md_text(r[k]) for k, _ in _COLUMNS) + " |"
            for r in rows]
    return "\n".join([head, rule, *body])


# The anchor of each group's section, by its heading.
_GROUP_ANCHORS = {title: f"group-{key}" for key, title in GROUPS}


def _contents(rows, placed):
    # The table of contents: (anchor, title, [(claim id, anchor), ...]) per section.
    members = {}
    for r in rows:
        members.setdefault(r["group"], []).append((r["id"], r["anchor"]))
    entries = [("run", "Run", []), ("claims", "Claims table", [])]
    entries += [(_GROUP_ANCHORS[title], title, members[title])
                for _, title in GROUPS if title in members]
    if placed.get(None):
        entries.append(("figures", "Figures", []))
    return entries


def _html_cell(row, key):
    # A cell of the HTML claims table: the claim links to its section, the verdict is
    # coloured by its class, the source shows its full citation on hover.
    esc = html.escape
    if key == "id":
        return f"<td><a href='#{esc(row['anchor'])}'>{esc(row['id'])}</a>{esc(row['mark'])}</td>"
    if key == "verdict":
        return f"<td class='{esc(row[key])}'>{esc(row[key])}</td>"
    if key == "source":
        return f"<td title='{esc(row['citation'])}'>{esc(row[key])}</td>"
    return f"<td>{esc(row[key])}</td>"


def _context_lines(context):
    return [f"- {k}: {v}" for k, v in context.items()]


def _details(o):
    a, c = o.assessment, o.claim
    options = option_argv(c.options_for(o.mode))
    measured = (f"- what is measured: y = `{c.y.text}` against x = `{c.x.text}`, "
                f"{_scene_text(c)} {', '.join(f'{k}={v:g}' for k, v in c.params.items())}"
                + (f", eps={c.eps:g}" if c.eps is not None else "")
                + (f", min_area={c.min_area:g}" if c.min_area is not None else "")
                + (f", max_depth={c.max_depth}" if c.max_depth is not None else "")
                + f", oracle {c.oracle}"
                + (f", options `{' '.join(options)}`" if options else "")
                + (", each point solved (`hrbench solve`)" if c.command == "solve" else "")
                + f", {c.sweep_param} swept"
                + "".join(f" for each {name} in {{{', '.join(f'{v:g}' for v in values)}}}"
                          for name, values in c.grid.items()))
    statement = f"- statement: `{c.statement}` ({c.source})"
    if not c.published:
        statement += (f"; no published value: the exponent {c.expected_exponent:g} is this "
                      "project's hypothesis, reported as a measurement")
    if a.verdict == SKIPPED:
        return [statement, measured,
                f"- **skipped**: {a.reason}; no point was run"]
    lines = [statement, measured,
             f"- regime: {_regime(c)}; {a.n_regime} of {a.x.size} points, "
             f"{a.decades:.2f} decades",
             f"- verdict: **{a.verdict}** ({a.reason})"]
    if a.fit:
        f = a.fit
        lines.append(f"- fit: y = {f.prefactor:.4g} x^{f.exponent:.4f}, RMS {f.rms:.4f} "
                     f"decades; statistical 95% interval [{f.low:.4f}, {f.high:.4f}] "
                     f"(moving-block residual bootstrap, block {f.block} points, "
                     f"{f.n_boot} resamples, seed {f.seed})")
    if a.interval and a.interval.windows.slope.size:
        iv = a.interval
        lines.append(f"- interval [{iv.low:.4f}, {iv.high:.4f}]: {iv.windows.slope.size} "
                     f"windows of {iv.window_octaves} octaves give exponents "
                     f"{iv.windows.slope.min():.3f} to {iv.windows.slope.max():.3f}; the upper "
                     f"half of them averages {iv.upper:.3f}, {iv.drift:+.3f} from the lower "
                     f"half")
    if a.windows is not None and a.windows.slope.size:
        lines.append(f"- window exponents ({a.windows.width:g} decade): "
                     f"{a.windows.slope.min():.3f} to {a.windows.slope.max():.3f}; their mean over "
                     f"the upper half lies {a.settle_spread:.3f} from the fit (settled: "
                     f"{'yes' if a.settled else 'no'})")
    if a.theta:
        t = a.theta
        lines.append(f"- Theta check: y/x^{t.exponent:g} varies by a factor {t.band:.3f} "
                     f"(bounded if at most {t.max_band:g}), trend {t.trend:+.4f} per decade "
                     f"(flat if within {t.tolerance:g})")
    if a.models:
        m = a.models
        order = np.argsort(m.delta_aic)[:4]
        lines.append("- models by AIC: " + ", ".join(
            f"{m.names[i]} (dAIC {m.delta_aic[i]:.1f})" for i in order))
    for f in o.data.failures:
        lines.append(f"- FAILED point {c.sweep_param}={f['value']:g}: exit code "
                     f"{f['exit_code']}: {f['stderr']} (`hrbench {f['command']}`)")
    return lines


def _regime(c):
    parts = []
    if c.x_min is not None:
        parts.append(f"x >= {c.x_min:g}")
    if c.x_max is not None:
        parts.append(f"x <= {c.x_max:g}")
    return " and ".join(parts) if parts else "all points"


# The figures a forked renderer reads (set by render_pngs before it forks).
_TO_RENDER = ()


def _render(k):
    return _TO_RENDER[k].png()


def render_pngs(figures, jobs=1):
    """The PNG bytes of every figure, rendered on up to `jobs` processes.

    Rendering dominates the report's time (about half a second per figure), and each
    figure renders alone, so forked processes share the work; they inherit the figures
    and send back only the bytes, identical to a serial rendering.

    Parameters
    ----------
    figures : sequence of ReportFigure
    jobs : int
        Processes to use; 1, or a platform without ``fork``, renders here, in order.

    Returns
    -------
    pngs : list of bytes
        In the order of `figures`.
    """
    global _TO_RENDER
    if jobs <= 1 or len(figures) < 2 or "fork" not in multiprocessing.get_all_start_methods():
        return [f.png() for f in figures]
    _TO_RENDER = tuple(figures)
    try:
        with multiprocessing.get_context("fork").Pool(min(jobs, len(figures)),
                                                      initializer=_worker_signals) as pool:
            return pool.map(_render, range(len(figures)), chunksize=1)
    finally:
        _TO_RENDER = ()


def _worker_signals():
    # A forked worker inherits the command's handlers, which end engine runs and raise
    # an interrupt: the pool ends its workers with SIGTERM, and Ctrl-C is the parent's.
    signal.signal(signal.SIGTERM, signal.SIG_DFL)
    signal.signal(signal.SIGINT, signal.SIG_IGN)


def write_report(outdir, outcomes, context, figures, jobs=1):
    """Write ``report.md``, ``report.html``, ``claims.json`` and ``plots/*.png``.

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

    Returns
    -------
    paths : dict of str to pathlib.Path
        ``{"markdown": ..., "html": ..., "json": ...}``.

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
    pngs = dict(zip((f.name for f in every), render_pngs(every, jobs), strict=True))

    # The JSON summary.
    json_path = outdir / "claims.json"
    json_text = json.dumps({"context": context,
                            "claims": get_claims_json(outcomes, context.get("mode", "quick"))},
                           indent=2, default=_jsonable) + "\n"

    # The Markdown report: the tally, the contents, the run, the claims table, one
    # section per group of claims, the figures of no claim.
    placed = _place_figures(outcomes, figures)
    contents = _contents(rows, placed)
    note = [TIMED_NOTE, ""] if any(r["mark"] for r in rows) else []
    md = ["# hrbench: reproduction of published complexity claims", "",
          f"**{verdict_tally(outcomes)}**", "", "## Contents", ""]
    md += [f"- {_md_link(title, anchor)}"
           + (": " + ", ".join(_md_link(*claim) for claim in claims) if claims else "")
           for anchor, title, claims in contents]
    md += ["", '## <a id="run"></a>Run', "", *_context_lines(context), "",
           '## <a id="claims"></a>Claims', "", _md_table(rows), "", *note]
    group = None
    for o, r in zip(outcomes, rows, strict=True):
        if r["group"] != group:
            group = r["group"]
            md += [f'## <a id="{_GROUP_ANCHORS[group]}"></a>{group}', ""]
        md += [f'### <a id="{r["anchor"]}"></a>{o.claim.id}: {o.claim.statement}', "",
               o.claim.description, "", *_details(o), ""]
        for f in placed.get(o.claim.id, []):
            md += [f"#### {f.title}", "", f"![{f.title}](plots/{f.name}.png)", "",
                   f.caption, ""]
    if placed.get(None):
        md += ['## <a id="figures"></a>Figures', ""]
    for f in placed.get(None, []):
        md += [f"### {f.title}", "", f"![{f.title}](plots/{f.name}.png)", "", f.caption, ""]
        if f.alternate is not None:
            a = f.alternate
            md += [f"#### {a.title}", "", f"![{a.title}](plots/{a.name}.png)", ""]
    md_path = outdir / "report.md"

    # The HTML report with the figures embedded.
    esc = html.escape
    parts = ["<!DOCTYPE html><html><head><meta charset='utf-8'>",
             "<title>hrbench claims report</title><style>",
             "body{font-family:sans-serif;max-width:1250px;margin:2em auto;padding:0 1em}",
             "table{border-collapse:collapse}td,th{border:1px solid #bbb;padding:3px 8px}",
             "th{background:#eee}.reproduced{background:#d8f5d8}.refuted{background:#f8d8d8}",
             ".inconclusive{background:#f5efc8}.measured{background:#dce8f5}.skipped{background:#e4e4e4}img{max-width:100%}code{background:#f4f4f4}",
             "</style></head><body>",
             "<h1>hrbench: reproduction of published complexity claims</h1>",
             f"<p><b>{esc(verdict_tally(outcomes))}</b></p>",
             "<nav><h2 id='contents'>Contents</h2><ul>"]
    for anchor, title, claims in contents:
        links = ", ".join(f"<a href='#{esc(a)}'>{esc(cid)}</a>" for cid, a in claims)
        parts.append(f"<li><a href='#{esc(anchor)}'>{esc(title)}</a>"
                     + (f": {links}" if links else "") + "</li>")
    parts.append("</ul></nav><h2 id='run'>Run</h2><ul>")
    parts += [f"<li>{esc(k)}: {esc(str(v))}</li>" for k, v in context.items()]
    parts += ["</ul><h2 id='claims'>Claims</h2><table><tr>"]
    parts += [f"<th>{esc(h)}</th>" for _, h in _COLUMNS]
    parts.append("</tr>")
    for r in rows:
        parts.append(f"<tr>{''.join(_html_cell(r, k) for k, _ in _COLUMNS)}</tr>")
    parts.append("</table>")
    parts += [f"<p>{esc(line)}</p>" for line in note if line]
    def img(f):
        data = base64.b64encode(pngs[f.name]).decode("ascii")
        return f"<img alt='{esc(f.title)}' src='data:image/png;base64,{data}'>"

    def image(f, level):
        toggle = ("" if f.alternate is None else
                  f"<details><summary>{esc(f.alternate.title)}</summary>"
                  f"{img(f.alternate)}</details>")
        return (f"<h{level}>{esc(f.title)}</h{level}>{img(f)}{toggle}"
                f"<p>{esc(f.caption)}</p>")

    group = None
    for o, r in zip(outcomes, rows, strict=True):
        if r["group"] != group:
            group = r["group"]
            parts.append(f"<h2 id='{_GROUP_ANCHORS[group]}'>{esc(group)}</h2>")
        parts.append(f"<h3 id='{esc(r['anchor'])}'>{esc(o.claim.id)}: "
                     f"{esc(o.claim.statement)}</h3>")
        parts.append(f"<p>{esc(o.claim.description)}</p><ul>")
        for line in _details(o):
            text = esc(line[2:]).replace("**", "")
            parts.append(f"<li>{text.replace('`', '')}</li>")
        parts.append("</ul>")
        parts += [image(f, 4) for f in placed.get(o.claim.id, [])]
    if placed.get(None):
        parts.append("<h2 id='figures'>Figures</h2>")
    parts += [image(f, 3) for f in placed.get(None, [])]
    parts.append("</body></html>")
    html_path = outdir / "report.html"

    # The figures first, so that a report never names a figure not yet written.
    files = [*((plots / f"{name}.png", png) for name, png in pngs.items()),
             (json_path, json_text), (md_path, "\n".join(md)), (html_path, "\n".join(parts))]
    with folder_lock(outdir):
        write_files(files)
        for stale in [*plots.glob("chart*.png"), *plots.glob("slopes*.png")]:
            if stale.name not in {f"{name}.png" for name in pngs}:
                # A figure of an earlier run whose claims have changed (another run on
                # the folder may have removed it first).
                stale.unlink(missing_ok=True)
    return {"markdown": md_path, "html": html_path, "json": json_path}


def _place_figures(outcomes, figures):
    # Claim id -> the figures shown in its section (each in the first claim it
    # illustrates that the report lists); None -> the rest, shown at the end.
    listed = [o.claim.id for o in outcomes]
    placed = {}
    for f in figures:
        home = next((cid for cid in listed if cid in f.claims), None)
        placed.setdefault(home, []).append(f)
    return placed


def _jsonable(value):
    if isinstance(value, np.generic):
        return value.item()
    if isinstance(value, np.ndarray):
        return value.tolist()
    raise TypeError(f"not JSON serialisable: {type(value).__name__}")
