"""The least-squares power law in log space, with its bootstrap interval.

:func:`fit_power_law` fits ``y = c x^k`` to plain arrays of positive numbers ``x`` and ``y``
(any unit; the exponent is dimensionless); :func:`steps_block_length` gives the bootstrap
blocks that keep one binary step together. The check of ``x`` and ``y`` here is the one
every fit of the package shares (:mod:`hrbench_analysis.slopes`,
:mod:`hrbench_analysis.fit`).
"""

import math
from dataclasses import dataclass

import numpy as np

__all__ = [
    "PowerLawFit",
    "DEFAULT_SEED",
    "fit_power_law",
    "steps_block_length",
]

#: Seed of the bootstrap generator, fixed so that intervals are the same on every run.
DEFAULT_SEED = 20030101


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
