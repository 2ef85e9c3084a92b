"""Fitting power laws to counts: exponents, intervals, local slopes, Theta checks, models.

All functions take plain arrays of positive numbers ``x`` and ``y`` (any unit; the
exponent is dimensionless) and return named result objects. Here: the interval of an
exponent with its systematic part (:func:`exponent_interval`), the Theta check and the
ranking of competing models. The least-squares fit (:mod:`hrbench_analysis.powerlaw`) and
the local slopes and plateaus (:mod:`hrbench_analysis.slopes`) that the interval builds on
are exported from here too.
"""

import math
from dataclasses import dataclass, field

import numpy as np

from .powerlaw import DEFAULT_SEED, PowerLawFit, _xy_iv, fit_power_law, steps_block_length
from .slopes import (
    LocalSlopes,
    WindowSlopes,
    local_slopes,
    octave_window_slopes,
    plateau_ends,
    point_window_slopes,
    window_slopes,
)

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
