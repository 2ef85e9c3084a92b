"""The report's figures drawn from the outcomes (:func:`get_figures`): a chart per pair of
measured quantities, the local exponents and Theta check of each claim, the link tiling."""

import json

import numpy as np
from matplotlib.figure import Figure

from ..engine import option_flag, option_text
from ..plots import (
    PowerLawSeries,
    plot_link_tiling,
    plot_power_law_comparison,
    plot_ratio,
    plot_slopes,
)
from ..summary import distinct_names
from .figure import ReportFigure
from .sections import _scene_text

__all__ = ["get_figures"]


def _options_text(claim, mode):
    # "visibility fraction, rays-per-side 2, triangulate" (as on the command line, without
    # dashes).
    return ", ".join(option_flag(name)[2:] + ("" if value is True else f" {option_text(value)}")
                     for name, value in claim.options_for(mode).items())


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
        judged = getattr(c, "bound", "theta") == "theta"  # an upper bound has no band
        ratio_label = f"{_group(c.y.text)} / {_power(c.x.text, c.expected_exponent)}"
        plot_ratio(ax2, a.x, ratio, in_regime=a.in_regime,
                   band=a.theta.band if a.theta else None,
                   max_band=a.theta.max_band if a.theta and judged else None,
                   x_label=c.x_label, ratio_label=ratio_label)
        ax2.set_title(f"{c.id}: Theta check, {ratio_label}")
        ax2.grid(True, alpha=0.3)
        ax2.legend(fontsize=8)
        caption = ("Left: exponent between neighbouring points (grey; binary subdivision "
                   "makes counts step functions, so these oscillate) and exponent fitted "
                   "over sliding one-decade windows (blue), against the claimed exponent "
                   "and its tolerance (red). Right: the ratio y/x^k (filled in the "
                   "regime, hollow outside it); the claim y = Theta(x^k) holds when it "
                   "stays between two constants. The dashed lines bound the regime's "
                   "ratios: "
                   + (f"the check takes that band as bounded when max/min is at most "
                      f"{c.theta_band:g} and the ratio's trend at most {c.tolerance:g} "
                      "per decade." if judged else
                      "an upper bound O(x^k) is not judged on them."))
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
