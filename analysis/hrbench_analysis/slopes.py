"""Local exponents of counts that climb a staircase, and one point per plateau of it.

Slopes of log y against log x between neighbours (:func:`local_slopes`), over sliding
windows of fixed width (:func:`window_slopes`), of whole octaves
(:func:`octave_window_slopes`) or of consecutive points (:func:`point_window_slopes`);
:func:`plateau_ends` keeps the point at one end of each plateau. They take plain arrays of
positive numbers, as :func:`hrbench_analysis.powerlaw.fit_power_law` does.
"""

import math
from dataclasses import dataclass

import numpy as np

from .powerlaw import _xy_iv

__all__ = [
    "LocalSlopes",
    "WindowSlopes",
    "local_slopes",
    "window_slopes",
    "octave_window_slopes",
    "point_window_slopes",
    "plateau_ends",
]


@dataclass
class LocalSlopes:
    """Slopes of log y against log x between neighbouring distinct x.

    Attributes
    ----------
    x : ndarray
        Geometric midpoints of neighbouring x (unit of x).
    slope : ndarray
        ``d log y / d log x`` between the neighbours (dimensionless).
    """

    x: np.ndarray
    slope: np.ndarray


def _merge_duplicates(x, y):
    # Merge points with equal x (geometric mean of their y).
    ux, inverse = np.unique(x, return_inverse=True)
    ly = np.zeros(ux.size)
    np.add.at(ly, inverse, np.log10(y))
    counts = np.bincount(inverse)
    return ux, 10 ** (ly / counts)


def local_slopes(x, y):
    """Local exponents between neighbouring points.

    Parameters
    ----------
    x, y : array_like
        Positive values. Points with equal x are merged first (geometric mean of y).

    Returns
    -------
    slopes : LocalSlopes

    Notes
    -----
    Counts of binary trees are step functions of the swept parameter, so these slopes
    oscillate strongly even when the law holds; use :func:`window_slopes` to judge
    whether the exponent has settled.
    """
    x, y = _xy_iv(x, y, min_points=2)
    ux, uy = _merge_duplicates(x, y)
    lx, ly = np.log10(ux), np.log10(uy)
    return LocalSlopes(x=10 ** ((lx[1:] + lx[:-1]) / 2), slope=np.diff(ly) / np.diff(lx))


@dataclass
class WindowSlopes:
    """Exponents fitted over sliding windows of fixed width in log x.

    Attributes
    ----------
    x : ndarray
        Geometric centre of each window (unit of x).
    slope : ndarray
        Least-squares exponent over the window (dimensionless).
    n : ndarray of int
        Points in each window.
    width : float
        Window width (decades of x).
    """

    x: np.ndarray
    slope: np.ndarray
    n: np.ndarray
    width: float


def _slope(lx, ly):
    # The least-squares slope of ly against lx (at least two distinct lx).
    dx = lx - lx.mean()
    return float(dx @ (ly - ly.mean()) / (dx @ dx))


def window_slopes(x, y, width=1.0, step=0.1):
    """Fit the exponent over sliding windows of `width` decades of x.

    Parameters
    ----------
    x, y : array_like
        Positive values.
    width : float, optional
        Window width in decades of x (default 1). A window of a decade spans more than
        three binary steps (factors of 2), so the steps average out.
    step : float, optional
        Shift between windows in decades (default 0.1).

    Returns
    -------
    windows : WindowSlopes
        Empty arrays if x spans less than `width`. Windows with fewer than 3 points or
        one distinct x are skipped.
    """
    x, y = _xy_iv(x, y, min_points=2)
    if width <= 0 or step <= 0:
        raise ValueError("`width` and `step` must be positive")
    lx, ly = np.log10(x), np.log10(y)
    centres, slopes, counts = [], [], []
    start = lx[0]
    while start + width <= lx[-1] + 1e-9:
        sel = (lx >= start - 1e-9) & (lx <= start + width + 1e-9)
        if sel.sum() >= 3 and np.unique(lx[sel]).size >= 2:
            sx, sy = lx[sel], ly[sel]
            slopes.append(_slope(sx, sy))
            centres.append(10 ** (start + width / 2))
            counts.append(int(sel.sum()))
        start += step
    return WindowSlopes(x=np.array(centres), slope=np.array(slopes),
                        n=np.array(counts, dtype=int), width=float(width))


def octave_window_slopes(x, y, octaves):
    """Fit the exponent over every window of a whole number of octaves of x.

    Parameters
    ----------
    x, y : array_like
        Positive values.
    octaves : int
        Window width: the window starting at a point x_s holds the points with
        ``x_s <= x < x_s * 2**octaves``.

    Returns
    -------
    windows : WindowSlopes
        One window per distinct x that has a complete window above it (``width`` in
        decades); windows with fewer than 3 distinct x are skipped.

    Notes
    -----
    Counts of binary trees repeat their steps once per factor 2 of the swept parameter.
    A window of whole octaves holds whole periods of that staircase, so the steps bias
    every window alike and the spread of the window exponents measures how the exponent
    drifts across the regime rather than where the window cuts a step.
    """
    x, y = _xy_iv(x, y, min_points=2)
    octaves = int(octaves)
    if octaves < 1:
        raise ValueError(f"`octaves` must be a positive integer, got {octaves}")
    lx, ly = np.log2(x), np.log2(y)
    eps = 1e-9  # octaves; points within rounding of an edge belong to the window's start
    centres, slopes, counts = [], [], []
    for start in np.unique(lx):
        if start + octaves > lx[-1] + eps:
            break
        sel = (lx >= start - eps) & (lx < start + octaves - eps)
        if np.unique(lx[sel]).size < 3:
            continue
        sx, sy = lx[sel], ly[sel]
        slopes.append(_slope(sx, sy))
        centres.append(2 ** (start + octaves / 2))
        counts.append(int(sel.sum()))
    return WindowSlopes(x=np.array(centres), slope=np.array(slopes),
                        n=np.array(counts, dtype=int), width=octaves * math.log10(2.0))


def point_window_slopes(x, y, points):
    """Fit the exponent over every run of `points` consecutive points.

    Parameters
    ----------
    x, y : array_like
        Positive values.
    points : int
        Points per window, at least 3.

    Returns
    -------
    windows : WindowSlopes
        One window per run of consecutive points (``width`` the widest run, in decades).

    Notes
    -----
    For a series that holds one point per period of a staircase (:func:`plateau_ends`),
    a window of whole octaves may hold too few points; a window of consecutive points
    spans ``points - 1`` periods.
    """
    x, y = _xy_iv(x, y, min_points=2)
    points = int(points)
    if points < 3:
        raise ValueError(f"`points` must be at least 3, got {points}")
    lx, ly = np.log10(x), np.log10(y)
    centres, slopes, width = [], [], 0.0
    for start in range(x.size - points + 1):
        sx, sy = lx[start:start + points], ly[start:start + points]
        if not (sx != sx[0]).any():
            continue
        slopes.append(_slope(sx, sy))
        centres.append(10 ** ((sx[0] + sx[-1]) / 2))
        width = max(width, float(sx[-1] - sx[0]))
    return WindowSlopes(x=np.array(centres), slope=np.array(slopes),
                        n=np.full(len(slopes), points, dtype=int), width=width)


def plateau_ends(value, level, *, keep="last", min_octaves=1.0):
    """One point per plateau of a staircase: the last before it steps, or the first after.

    Parameters
    ----------
    value : array_like
        The swept parameter of each point, in sweep order (monotone, positive).
    level : array_like
        The quantity that steps (e.g. the number of elements N), in the same order.
    keep : {"last", "first"}, optional
        ``"last"``: the point just before `level` changes (default); ``"first"``: the
        point just after it changed.
    min_octaves : float, optional
        Shortest plateau kept, in octaves of `value` from its first point to its last
        (default 1). Shorter runs of equal `level` are sub-steps of one jump (part of
        the elements split a little before the rest), not periods of the staircase.

    Returns
    -------
    index : ndarray of int
        Indices of the kept points, in sweep order. A plateau cut by an end of the sweep
        keeps no point where that end is the one asked for (``"last"``: the final
        plateau; ``"first"``: the first one), since its step was not seen.

    Notes
    -----
    Where the counts climb a staircase whose pattern repeats once per period, every
    kept point lies at the same phase of its period (up to one step of the sweep's
    grid), so the periodic factor is the same at every kept point and a power law
    fitted through them sees the trend alone.

    Examples
    --------
    >>> plateau_ends([1, 2, 4, 8, 16, 32, 64], [1, 1, 1, 4, 4, 4, 16], min_octaves=1)
    array([2, 5])
    """
    value = np.asarray(value, dtype=float).ravel()
    level = np.asarray(level, dtype=float).ravel()
    if value.shape != level.shape:
        raise ValueError(f"`value` and `level` must have the same length, got {value.size} "
                         f"and {level.size}")
    if np.any(~np.isfinite(value)) or np.any(value <= 0):
        raise ValueError("`value` must be finite and positive")
    if keep not in ("last", "first"):
        raise ValueError(f"`keep` must be 'last' or 'first', got {keep!r}")
    if not min_octaves >= 0:
        raise ValueError(f"`min_octaves` must be at least 0, got {min_octaves}")
    if value.size == 0:
        return np.zeros(0, dtype=int)
    # Start of each run of equal level; run i spans starts[i] .. starts[i+1]-1.
    starts = np.flatnonzero(np.r_[True, level[1:] != level[:-1]])
    ends = np.r_[starts[1:], value.size] - 1
    kept = []
    for i, (first, last) in enumerate(zip(starts, ends, strict=True)):
        if abs(math.log2(value[last] / value[first])) < min_octaves - 1e-9:
            continue
        if keep == "last" and i + 1 < starts.size:
            kept.append(last)
        elif keep == "first" and i > 0:
            kept.append(first)
    return np.array(kept, dtype=int)
