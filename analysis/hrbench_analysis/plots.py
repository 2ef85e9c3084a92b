"""Plots of sweeps, fits and link tilings. Every function draws on an Axes it is given.

None of these functions creates, shows or saves a figure; the caller owns it (and picks
the backend; the report uses Agg).
"""

from dataclasses import dataclass

import numpy as np
from matplotlib.collections import PatchCollection
from matplotlib.patches import Rectangle

__all__ = [
    "PowerLawSeries",
    "plot_power_law",
    "plot_power_law_comparison",
    "plot_reference_slopes",
    "plot_slopes",
    "plot_ratio",
    "plot_link_tiling",
]


def plot_power_law(ax, x, y, *, in_regime=None, fit=None, label=None, color=None,
                   marker="o"):
    """Draw measured points on log-log axes, with the fitted power law over the regime.

    Parameters
    ----------
    ax : matplotlib.axes.Axes
    x, y : array_like
        Measured points (positive).
    in_regime : array_like of bool, optional
        Points in the asymptotic regime are drawn filled, the others hollow.
    fit : PowerLawFit or ExponentInterval, optional
        Drawn as a line over the regime, labelled with the exponent and its interval.
    label : str, optional
        Legend label of the points.
    color : color, optional
    marker : str, optional

    Returns
    -------
    line : matplotlib.lines.Line2D
        The points (their colour is the series colour).
    """
    x = np.asarray(x, dtype=float)
    y = np.asarray(y, dtype=float)
    mask = np.ones(x.size, dtype=bool) if in_regime is None else np.asarray(in_regime, bool)
    (points,) = ax.plot(x[mask], y[mask], marker, ms=4, ls="none", color=color, label=label)
    color = points.get_color()
    if (~mask).any():
        ax.plot(x[~mask], y[~mask], marker, ms=4, ls="none", mfc="none", color=color,
                label=None if label is None else f"{label} (outside the regime)")
    if fit is not None and mask.any():
        xs = np.geomspace(x[mask].min(), x[mask].max(), 50)
        ax.plot(xs, fit.prefactor * xs ** fit.exponent, "-", lw=1.2, color=color, alpha=0.8,
                label=(f"fit: exponent {fit.exponent:.3f} "
                       f"[{fit.low:.3f}, {fit.high:.3f}]"))
    ax.set_xscale("log")
    ax.set_yscale("log")
    return points


@dataclass
class PowerLawSeries:
    """One measured series for :func:`plot_power_law_comparison`.

    Attributes
    ----------
    x, y : array_like
        Measured points (positive), e.g. elements N and links L (counts).
    label : str
        Legend label.
    in_regime : array_like of bool, optional
        Points in the asymptotic regime (drawn filled; the others hollow).
    fit : PowerLawFit or ExponentInterval, optional
        Fit over the regime, drawn as a line.
    """

    x: object
    y: object
    label: str
    in_regime: object = None
    fit: object = None


def plot_power_law_comparison(ax, series, *, slopes=None, symbol="x", markers="os^Dv",
                              slope_word="claimed"):
    """Draw several measured series on one log-log chart, with reference slopes.

    Used to set measurements side by side, e.g. the links against the elements of a
    refinement with and without an occluder, or the series of one grid sweep.

    Parameters
    ----------
    ax : matplotlib.axes.Axes
    series : sequence of PowerLawSeries
        Drawn in order, each in its own colour and marker.
    slopes : mapping of float to (array_like, array_like), optional
        Exponents of grey reference lines, each with the points (x, y) it is drawn
        through: its prefactor is fitted in log space with the exponent fixed, so the
        line runs through the data it is compared with (see
        :func:`plot_reference_slopes`). Drawn across the x range of all series; the y
        axis keeps to the measured points (with a margin of a factor 3), so a steep line
        does not squash them.
    symbol : str, optional
        Name of the x quantity in the reference lines' labels, e.g. ``"N"``.
    markers : str, optional
        Marker codes, cycled over the series.
    slope_word : str, optional
        What the reference slopes are, in their labels: ``"claimed"`` (published) or
        ``"hypothesised"`` (no published value).

    Returns
    -------
    points : list of matplotlib.lines.Line2D
        The points of each series, in order.
    """
    points = []
    x_left, x_right = np.inf, 0.0
    y_low, y_high = np.inf, 0.0
    for n, s in enumerate(series):
        x = np.asarray(s.x, dtype=float)
        y = np.asarray(s.y, dtype=float)
        if x.size == 0:
            continue
        points.append(plot_power_law(ax, x, y, in_regime=s.in_regime, fit=s.fit,
                                     label=s.label, marker=markers[n % len(markers)],
                                     color=f"C{n % 10}"))
        x_left, x_right = min(x_left, float(x.min())), max(x_right, float(x.max()))
        y_low, y_high = min(y_low, float(y.min())), max(y_high, float(y.max()))
    if slopes and x_right > x_left:
        for n, (slope, (xs, ys)) in enumerate(sorted(slopes.items())):
            plot_reference_slopes(ax, slope, xs, ys, x_min=x_left, x_max=x_right,
                                  symbol=symbol, style=("--", ":", "-.")[n % 3],
                                  word=slope_word)
        ax.set_ylim(y_low / 3, y_high * 3)
    ax.set_xscale("log")
    ax.set_yscale("log")
    return points


def plot_reference_slopes(ax, slope, x, y, *, x_min, x_max, symbol="x", style="--",
                          word="claimed"):
    """Draw a grey reference line ``y = c x^slope`` through measured points.

    Parameters
    ----------
    ax : matplotlib.axes.Axes
    slope : float
        Exponent of the line (dimensionless).
    x, y : array_like
        Points the line runs through: ``log c`` is the mean of ``log y - slope log x``
        (the least-squares prefactor with the exponent fixed). Without points, nothing
        is drawn.
    x_min, x_max : float
        Ends of the line (unit of x).
    symbol : str, optional
        Name of the x quantity in the legend label, e.g. ``"N"``.
    style : str, optional
        Line style.
    word : str, optional
        The first word of the legend label (``"claimed slope ..."``).
    """
    x = np.asarray(x, dtype=float)
    y = np.asarray(y, dtype=float)
    ok = (x > 0) & (y > 0)
    if not ok.any():
        return
    log_c = float(np.mean(np.log10(y[ok]) - slope * np.log10(x[ok])))
    xs = np.geomspace(x_min, x_max, 20)
    power = "" if slope == 1 else f"^{slope:g}"
    ax.plot(xs, 10 ** log_c * xs ** slope, style, color="0.4", lw=1,
            label=f"{word} slope {slope:g} (proportional to {symbol}{power}), through "
                  "the regime's points")


def plot_slopes(ax, local=None, windows=None, *, expected=None, tolerance=None,
                x_label="x"):
    """Draw local exponents: neighbour slopes and sliding-window fits.

    Parameters
    ----------
    ax : matplotlib.axes.Axes
    local : LocalSlopes, optional
        Neighbour-to-neighbour slopes (small markers; they oscillate with binary steps).
    windows : WindowSlopes, optional
        Exponents fitted over sliding windows (a line; settles when the law holds).
    expected : float, optional
        The claimed exponent, drawn as a horizontal line.
    tolerance : float, optional
        Shades ``expected +/- tolerance``.
    x_label : str, optional
        Label of the x axis, with its unit.
    """
    if local is not None and local.x.size:
        ax.plot(local.x, local.slope, ".", color="0.6", ms=4,
                label="slope between neighbouring points")
    if windows is not None and windows.x.size:
        ax.plot(windows.x, windows.slope, "-o", ms=3, color="C0",
                label=f"fit over a sliding window of {windows.width:g} decade(s)")
    if expected is not None:
        ax.axhline(expected, color="C3", lw=1, label=f"claimed exponent {expected:g}")
        if tolerance:
            ax.axhspan(expected - tolerance, expected + tolerance, color="C3", alpha=0.12,
                       label=f"tolerance +/- {tolerance:g}")
        lo, hi = expected - 4 * (tolerance or 0.25), expected + 4 * (tolerance or 0.25)
        if windows is not None and windows.slope.size:
            lo = min(lo, windows.slope.min() - 0.1)
            hi = max(hi, windows.slope.max() + 0.1)
        if local is not None and local.slope.size:
            # Show the oscillation of neighbour slopes, but not single outliers.
            lo = min(lo, max(np.min(local.slope) - 0.1, expected - 3))
            hi = max(hi, min(np.max(local.slope) + 0.1, expected + 3))
        ax.set_ylim(lo, hi)
    ax.set_xscale("log")
    ax.set_xlabel(x_label)
    ax.set_ylabel("local exponent d log y / d log x (dimensionless)")


def plot_ratio(ax, x, ratio, *, in_regime=None, band=None, max_band=None, x_label="x",
               ratio_label="y / x^k"):
    """Draw the Theta check: the ratio ``y / x^k`` against x.

    Every element is named in the legend: the ratio's points in the regime (filled) and
    outside it (hollow), and the band of the regime's points, two dashed lines at their
    smallest and largest ratio.

    Parameters
    ----------
    ax : matplotlib.axes.Axes
    x, ratio : array_like
        Positive values.
    in_regime : array_like of bool, optional
        Points in the regime are drawn filled, the others hollow.
    band : float, optional
        The band ``max/min`` over the regime, shown in the legend.
    max_band : float, optional
        The widest band that counts as bounded (the check's ``max_band``), shown in the
        legend.
    x_label : str, optional
        Label of the x axis, with its unit.
    ratio_label : str, optional
        The ratio as a formula, e.g. ``"L / N^2"``, for the y axis label.

    Notes
    -----
    The y axis is logarithmic when the ratio spans more than a factor 10, linear otherwise
    (so that a narrow band reads with plain tick labels).
    """
    x = np.asarray(x, dtype=float)
    ratio = np.asarray(ratio, dtype=float)
    mask = np.ones(x.size, dtype=bool) if in_regime is None else np.asarray(in_regime, bool)
    ax.plot(x[mask], ratio[mask], "o", ms=4, color="C2", label="ratio in the regime")
    if (~mask).any():
        ax.plot(x[~mask], ratio[~mask], "o", ms=4, mfc="none", color="C2",
                label="ratio outside the regime")
    if mask.any():
        label = "the regime's band (min, max)"
        if band is not None:
            label += f": max/min {band:.2f}"
        if max_band is not None:
            label += f", bounded if at most {max_band:g}"
        ax.axhline(ratio[mask].max(), color="0.5", lw=0.8, ls="--", label=label)
        ax.axhline(ratio[mask].min(), color="0.5", lw=0.8, ls="--")
    ax.set_xscale("log")
    if ratio.max() > 10 * ratio.min():
        ax.set_yscale("log")
    ax.set_xlabel(x_label)
    ax.set_ylabel(f"{ratio_label} (bounded if Theta holds)")


def plot_link_tiling(ax, links, *, root_pair=(0, 1), cmap="viridis"):
    """Draw the links of one root pair as rectangles tiling the parameter square.

    Each link ``(i, j)`` is the rectangle ``[t0_i, t1_i] x [t0_j, t1_j]``, coloured by its
    depth ``depth_i + depth_j``; the links of a root pair tile ``[0, A_P] x [0, A_Q]``.

    Parameters
    ----------
    ax : matplotlib.axes.Axes
    links : LinkTable
    root_pair : (int, int), optional
        Which pair of roots to draw (default the first two).
    cmap : str or Colormap, optional

    Returns
    -------
    collection : matplotlib.collections.PatchCollection
        Pass it to ``Figure.colorbar`` for a depth scale.
    """
    p, q = root_pair
    sel = (links.root_i == p) & (links.root_j == q)
    swap = (links.root_i == q) & (links.root_j == p)
    x0 = np.concatenate([links.t0_i[sel], links.t0_j[swap]])
    x1 = np.concatenate([links.t1_i[sel], links.t1_j[swap]])
    y0 = np.concatenate([links.t0_j[sel], links.t0_i[swap]])
    y1 = np.concatenate([links.t1_j[sel], links.t1_i[swap]])
    depth = np.concatenate([links.depth_i[sel] + links.depth_j[sel],
                            links.depth_i[swap] + links.depth_j[swap]])
    rects = [Rectangle((a, b), c - a, d - b) for a, b, c, d in zip(x0, y0, x1, y1, strict=True)]
    coll = PatchCollection(rects, cmap=cmap, edgecolor="k", linewidth=0.15)
    coll.set_array(depth.astype(float))
    ax.add_collection(coll)
    if x0.size:
        ax.set_xlim(x0.min(), x1.max())
        ax.set_ylim(y0.min(), y1.max())
    ax.set_aspect("equal")
    ax.set_xlabel(f"position on patch {p}, arc length t_i (scene units)")
    ax.set_ylabel(f"position on patch {q}, arc length t_j (scene units)")
    return coll
