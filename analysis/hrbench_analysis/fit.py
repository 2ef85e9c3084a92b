"""Fitting power laws to counts: exponents, intervals, local slopes, Theta checks, models.

All functions take plain arrays of positive numbers ``x`` and ``y`` (any unit; the
exponent is dimensionless) and return named result objects.
"""

import math
from dataclasses import dataclass, field

import numpy as np

__all__ = [
    "PowerLawFit",
    "LocalSlopes",
    "WindowSlopes",
    "ExponentInterval",
    "ThetaCheck",
    "ModelComparison",
    "DEFAULT_MODELS",
    "DEFAULT_SEED",
    "fit_power_law",
    "local_slopes",
    "window_slopes",
    "octave_window_slopes",
    "point_window_slopes",
    "plateau_ends",
    "exponent_interval",
    "theta_check",
    "compare_models",
    "steps_block_length",
]

#: Seed of the bootstrap generator, fixed so that intervals are the same on every run.
DEFAULT_SEED = 20030101

#: Competing models ``c * x^a * (log x)^b``, as (name, a, b): the growth models from
#: ``1`` to ``x^3`` and their reciprocals, so that a quantity that falls (an error
#: against the cost that buys it) meets the same shapes as one that grows. The set is
#: closed under ``y -> 1/y``: ranking ``1/y`` picks the reciprocal of the model ranked
#: for ``y``, with the same AIC differences.
DEFAULT_MODELS = (
    ("x^-3", -3.0, 0),
    ("1/(x^2 log x)", -2.0, -1),
    ("x^-2", -2.0, 0),
    ("x^-1.5", -1.5, 0),
    ("1/(x log x)", -1.0, -1),
    ("x^-1", -1.0, 0),
    ("x^-0.5", -0.5, 0),
    ("1/log x", 0.0, -1),
    ("1", 0.0, 0),
    ("log x", 0.0, 1),
    ("x^0.5", 0.5, 0),
    ("x", 1.0, 0),
    ("x log x", 1.0, 1),
    ("x^1.5", 1.5, 0),
    ("x^2", 2.0, 0),
    ("x^2 log x", 2.0, 1),
    ("x^3", 3.0, 0),
)


def _xy_iv(x, y, min_points=3):
    x = np.asarray(x, dtype=float).ravel()
    y = np.asarray(y, dtype=float).ravel()
    if x.shape != y.shape:
        raise ValueError(f"`x` and `y` must have the same length, got {x.size} and {y.size}")
    if not (np.all(np.isfinite(x)) and np.all(np.isfinite(y))):
        raise ValueError("`x` and `y` must be finite")
    if np.any(x <= 0) or np.any(y <= 0):
        raise ValueError("`x` and `y` must be positive (they are fitted in log space)")
    if x.size < min_points:
        raise ValueError(f"need at least {min_points} points, got {x.size}")
    if np.unique(x).size < 2:
        raise ValueError("`x` must take at least two distinct values")
    order = np.argsort(x, kind="stable")
    return x[order], y[order]


@dataclass
class PowerLawFit:
    """Least-squares fit of ``log10 y = log10 c + k log10 x``.

    Attributes
    ----------
    exponent : float
        Fitted exponent ``k`` (dimensionless).
    prefactor : float
        Fitted ``c`` (unit of y per unit of x^k).
    low, high : float
        Bootstrap confidence interval of the exponent (dimensionless).
    confidence : float
        Confidence level of the interval, e.g. 0.95.
    rms : float
        Root mean square of the residuals of log10 y (decades).
    n : int
        Number of points fitted.
    decades : float
        Span of x, ``log10(max x / min x)`` (decades).
    block : int
        Block length of the residual bootstrap (points; 1 is the plain residual bootstrap).
    n_boot : int
        Number of bootstrap resamples.
    seed : int
        Seed of the bootstrap generator.
    """

    exponent: float
    prefactor: float
    low: float
    high: float
    confidence: float
    rms: float
    n: int
    decades: float
    block: int
    n_boot: int
    seed: int


def steps_block_length(x):
    """Points per factor 2 of x: the block length that keeps one binary step together.

    Parameters
    ----------
    x : array_like
        Positive values.

    Returns
    -------
    block : int
        At least 1.
    """
    x = np.asarray(x, dtype=float)
    decades = math.log10(x.max() / x.min()) if x.size > 1 else 0.0
    if decades <= 0:
        return 1
    return max(1, int(round(x.size * math.log10(2.0) / decades)))


def fit_power_law(x, y, *, confidence=0.95, n_boot=2000, block=1, seed=DEFAULT_SEED):
    """Fit a power law ``y = c x^k`` by least squares in log space, with a bootstrap interval.

    Parameters
    ----------
    x, y : array_like
        Positive values of the same length (any units).
    confidence : float, optional
        Confidence level of the interval (default 0.95).
    n_boot : int, optional
        Number of bootstrap resamples (default 2000).
    block : int, optional
        Length of the residual blocks (points, default 1). Residuals of counts from binary
        trees are correlated over one step of the tree (a factor 2 of the swept parameter);
        blocks of that length (:func:`steps_block_length`) keep the interval honest.
    seed : int, optional
        Seed of the :class:`numpy.random.Generator` (default :data:`DEFAULT_SEED`).

    Returns
    -------
    fit : PowerLawFit

    Notes
    -----
    The interval comes from a *residual* bootstrap, moving-block variant: the points are
    sorted by x, the ordinary least-squares fit gives fitted values and residuals, and
    each resample adds to the fitted values a series of residuals made of randomly chosen
    contiguous blocks of `block` residuals; the slope is refitted, and the interval is the
    percentile interval of the resampled slopes. With ``block=1`` it is the plain residual
    bootstrap.

    Examples
    --------
    >>> import numpy as np
    >>> x = np.logspace(0, 3, 31)
    >>> fit = fit_power_law(x, 3 * x**2)
    >>> round(fit.exponent, 6), round(fit.prefactor, 6)
    (2.0, 3.0)
    """
    x, y = _xy_iv(x, y)
    if not 0 < confidence < 1:
        raise ValueError(f"`confidence` must lie in (0, 1), got {confidence}")
    if int(n_boot) < 10:
        raise ValueError(f"`n_boot` must be at least 10, got {n_boot}")
    block = int(block)
    if block < 1:
        raise ValueError(f"`block` must be a positive integer, got {block}")
    return _fit_power_law(x, y, confidence, int(n_boot), min(block, x.size), seed)


def _fit_power_law(x, y, confidence, n_boot, block, seed):
    lx, ly = np.log10(x), np.log10(y)
    dx = lx - lx.mean()
    sxx = float(dx @ dx)
    slope = float(dx @ (ly - ly.mean())) / sxx
    intercept = float(ly.mean() - slope * lx.mean())
    resid = ly - (intercept + slope * lx)
    n = x.size

    # Resample residuals in contiguous blocks and refit the slope for each resample.
    rng = np.random.default_rng(seed)
    n_blocks = -(-n // block)
    starts = rng.integers(0, n - block + 1, size=(n_boot, n_blocks))
    idx = (starts[:, :, None] + np.arange(block)).reshape(n_boot, -1)[:, :n]
    boot = slope + (resid[idx] @ dx) / sxx
    alpha = (1 - confidence) / 2
    low, high = np.quantile(boot, [alpha, 1 - alpha])
    return PowerLawFit(
        exponent=slope, prefactor=10 ** intercept, low=float(low), high=float(high),
        confidence=confidence, rms=float(np.sqrt(np.mean(resid ** 2))), n=n,
        decades=float(lx[-1] - lx[0]), block=block, n_boot=n_boot, seed=seed)


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


@dataclass
class ExponentInterval:
    """An exponent over a regime, with an interval that holds its systematic error too.

    Attributes
    ----------
    exponent : float
        Least-squares exponent over the whole regime (dimensionless).
    low, high : float
        The interval: the union of the statistical interval, the range of the octave
        window exponents, and the upper windows' exponent plus or minus twice the drift.
    fit : PowerLawFit
        The fit over the whole regime; ``fit.low`` and ``fit.high`` are the statistical
        (bootstrap) interval.
    window_octaves : int
        Width of the octave windows (octaves).
    windows : WindowSlopes
        Exponents over the octave windows, from the lowest window to the highest.
    upper : float
        Mean exponent of the upper half of the windows (dimensionless; NaN with fewer
        than 2 windows).
    drift : float
        ``upper`` minus the mean exponent of the lower half of the windows
        (dimensionless; 0 with fewer than 2 windows).
    """

    exponent: float
    low: float
    high: float
    fit: PowerLawFit
    window_octaves: int
    windows: WindowSlopes
    upper: float
    drift: float

    @property
    def prefactor(self):
        """Prefactor c of the fit over the whole regime."""
        return self.fit.prefactor

    @property
    def half_width(self):
        """Largest distance from the exponent to an end of the interval."""
        return max(self.exponent - self.low, self.high - self.exponent)


def exponent_interval(x, y, *, confidence=0.95, n_boot=2000, seed=DEFAULT_SEED,
                      min_octaves=3, step_octaves=1, window_points=None):
    """Fit the exponent of ``y = c x^k`` and bound it, systematic error included.

    Parameters
    ----------
    x, y : array_like
        Positive values (the asymptotic regime only).
    confidence : float, optional
        Confidence level of the statistical part (default 0.95).
    n_boot : int, optional
        Bootstrap resamples of the statistical part (default 2000).
    seed : int, optional
        Bootstrap seed (default :data:`DEFAULT_SEED`).
    min_octaves : int, optional
        Narrowest octave window (default 3, about one decade: three binary steps).
    step_octaves : int, optional
        Period of the staircase in octaves of x (default 1: one binary split per factor
        2; 2 where a split quarters an element, as quadtree subdivision does). Windows
        and bootstrap blocks span whole periods.
    window_points : int, optional
        For a series of one point per period (:func:`plateau_ends`): windows of this
        many consecutive points (:func:`point_window_slopes`) instead of octave windows.

    Returns
    -------
    interval : ExponentInterval

    Notes
    -----
    Counts are deterministic, so a bootstrap only measures their scatter around the
    binary staircase; the error that matters is systematic: the exponent still drifts
    towards its asymptotic value inside the regime. The interval joins three parts:

    1. the moving-block residual bootstrap of the fit over the whole regime (the
       statistical part, :func:`fit_power_law`);
    2. the exponents over every window of ``W = max(min_octaves, floor(octaves / 2))``
       whole octaves, rounded up to whole periods of the staircase
       (:func:`octave_window_slopes`): how far the exponent moves inside the regime;
    3. ``upper +/- 2 |drift|``, with ``upper`` the mean exponent of the upper half of the
       windows and ``drift`` its distance from the mean of the lower half (means, so
       that what is left of the staircase averages out). An exponent still drifting at
       the top of the regime lies beyond every window; this part bounds the rest of its
       way by twice the way it came between the halves, which holds when the correction
       shrinks by at least a third from the lower half to the upper half (a correction
       ``x^-w`` whose halves lie ``t`` decades apart shrinks by ``10^(-w t)``).

    ``low`` and ``high`` are the smallest and largest ends of the three. With no
    complete window (fewer than `min_octaves` octaves) the interval is the bootstrap's.

    Examples
    --------
    >>> import numpy as np
    >>> x = np.logspace(0, 3, 31)
    >>> iv = exponent_interval(x, 3 * x**2)
    >>> round(iv.exponent, 6), round(iv.low, 6), round(iv.high, 6)
    (2.0, 2.0, 2.0)
    """
    x, y = _xy_iv(x, y)
    for name, value in (("min_octaves", min_octaves), ("step_octaves", step_octaves)):
        if int(value) != value or value < 1:
            raise ValueError(f"`{name}` must be a positive integer, got {value}")
    step = int(step_octaves)
    fit = fit_power_law(x, y, confidence=confidence, n_boot=n_boot,
                        block=steps_block_length(x) * step, seed=seed)
    octaves = max(int(min_octaves), math.floor(math.log2(x[-1] / x[0]) / 2))
    octaves = step * -(-octaves // step)
    if window_points is None:
        windows = octave_window_slopes(x, y, octaves)
    else:
        windows = point_window_slopes(x, y, window_points)
    slopes = windows.slope
    low, high, upper, drift = fit.low, fit.high, math.nan, 0.0
    if slopes.size:
        low, high = min(low, float(slopes.min())), max(high, float(slopes.max()))
    if slopes.size >= 2:
        half = slopes.size // 2
        upper = float(slopes[-half:].mean())
        drift = upper - float(slopes[:half].mean())
        low, high = min(low, upper - 2 * abs(drift)), max(high, upper + 2 * abs(drift))
    return ExponentInterval(exponent=fit.exponent, low=float(low), high=float(high),
                            fit=fit, window_octaves=octaves, windows=windows, upper=upper,
                            drift=drift)


@dataclass
class ThetaCheck:
    """Whether ``y / x^k`` stays inside a bounded band: the test of ``y = Theta(x^k)``.

    Attributes
    ----------
    exponent : float
        The exponent k tested (dimensionless).
    ratio : ndarray
        ``y / x^k`` at every point (unit of y per unit of x^k).
    band : float
        ``max(ratio) / min(ratio)`` (dimensionless, at least 1).
    max_band : float
        Largest band that counts as bounded.
    trend : float
        Least-squares slope of log10(ratio) against log10(x) (decades per decade); a flat
        band has a trend near 0.
    tolerance : float
        Largest ``|trend|`` that counts as flat.
    bounded : bool
        ``band <= max_band``.
    flat : bool
        ``|trend| <= tolerance``.
    holds : bool
        ``bounded and flat``.
    """

    exponent: float
    ratio: np.ndarray
    band: float
    max_band: float
    trend: float
    tolerance: float
    bounded: bool
    flat: bool
    holds: bool


def theta_check(x, y, exponent, *, max_band=10.0, tolerance=0.1):
    """Check that ``y / x^k`` stays in a bounded, flat band.

    Parameters
    ----------
    x, y : array_like
        Positive values.
    exponent : float
        The exponent k of the claimed ``y = Theta(x^k)`` (dimensionless).
    max_band : float, optional
        Largest ``max/min`` of the ratio that counts as bounded (default 10).
    tolerance : float, optional
        Largest trend of the log ratio per decade of x that counts as flat (default 0.1).

    Returns
    -------
    check : ThetaCheck

    Notes
    -----
    A finite sweep cannot prove a bound; it can show that the ratio neither grows nor
    shrinks over the decades swept. Its trend is the fitted exponent minus k, seen from
    the side of the ratio; the band adds that the scatter around the trend is bounded,
    which is what carries the verdict when binary steps make local slopes oscillate.
    """
    x, y = _xy_iv(x, y, min_points=2)
    ratio = y / x ** float(exponent)
    lx, lr = np.log10(x), np.log10(ratio)
    dx = lx - lx.mean()
    trend = float(dx @ (lr - lr.mean()) / (dx @ dx))
    band = float(ratio.max() / ratio.min())
    bounded = band <= max_band
    flat = abs(trend) <= tolerance
    return ThetaCheck(exponent=float(exponent), ratio=ratio, band=band, max_band=max_band,
                      trend=trend, tolerance=tolerance, bounded=bounded, flat=flat,
                      holds=bounded and flat)


@dataclass
class ModelComparison:
    """Competing models ``c * f(x)``, each fitted in log space, ranked by AIC.

    Attributes
    ----------
    names : list of str
        Model names, e.g. ``"x^2 log x"``.
    power : ndarray
        Power a of x in each model.
    log_power : ndarray
        Power b of log x in each model.
    rms : ndarray
        RMS of the log10 residuals of each model (decades).
    aic, bic : ndarray
        Akaike and Bayesian information criteria (lower is better).
    delta_aic : ndarray
        AIC minus the best AIC.
    best : str
        Name of the model with the lowest AIC.
    skipped : list of str
        Models not fitted because some ``x <= 1`` (``log x`` must be positive).
    """

    names: list
    power: np.ndarray
    log_power: np.ndarray
    rms: np.ndarray
    aic: np.ndarray
    bic: np.ndarray
    delta_aic: np.ndarray
    best: str
    skipped: list = field(default_factory=list)

    @property
    def best_power(self):
        """Power of x in the best model."""
        return float(self.power[self.names.index(self.best)])


def compare_models(x, y, models=DEFAULT_MODELS):
    """Rank models ``y = c * x^a * (log x)^b`` by AIC.

    Parameters
    ----------
    x, y : array_like
        Positive values.
    models : sequence of (str, float, int), optional
        (name, a, b) triples; default :data:`DEFAULT_MODELS`.

    Returns
    -------
    comparison : ModelComparison

    Notes
    -----
    Each model has one free parameter, ``log c``, fitted as the mean of
    ``log y - log f(x)``. With ``RSS`` the residual sum of squares in log10 space and n
    points, ``AIC = n ln(RSS/n) + 2`` and ``BIC = n ln(RSS/n) + ln n``; since every model has
    one parameter, both rank the models alike, and a difference of AIC above about 10 is
    strong evidence against the worse model.
    """
    x, y = _xy_iv(x, y)
    lx, ly = np.log10(x), np.log10(y)
    n = x.size
    names, power, log_power, rms, skipped = [], [], [], [], []
    for name, a, b in models:
        if b and np.any(x <= 1):
            skipped.append(name)
            continue
        lf = a * lx + (b * np.log10(np.log(x)) if b else 0.0)
        resid = ly - lf
        resid = resid - resid.mean()
        names.append(name)
        power.append(a)
        log_power.append(b)
        rms.append(float(np.sqrt(np.mean(resid ** 2))))
    rms_arr = np.maximum(np.array(rms), 1e-12)  # floor for exact fits (decades)
    rss = n * rms_arr ** 2
    aic = n * np.log(rss / n) + 2
    bic = n * np.log(rss / n) + math.log(n)
    best = int(np.argmin(aic))
    return ModelComparison(names=names, power=np.array(power), log_power=np.array(log_power),
                           rms=np.array(rms), aic=aic, bic=bic, delta_aic=aic - aic[best],
                           best=names[best], skipped=skipped)
