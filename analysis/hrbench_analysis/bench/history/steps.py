"""Steps in a benchmark's times over commits (:func:`detect_steps`): an optimal
partition of the series into constant segments, with a penalty per step."""

import math
from dataclasses import dataclass

import numpy as np

# Step rule defaults (see detect_steps).
DEFAULT_PENALTY = 6.0
DEFAULT_MIN_CHANGE = 0.05
DEFAULT_MIN_NOISE = 0.005
DEFAULT_MIN_POINTS = 3


@dataclass(frozen=True)
class Step:
    """A detected step of a series.

    Attributes
    ----------
    index : int
        Position in the series of the first point at the new level.
    before, after : float
        Level of the segment before and after the step: the geometric mean of the
        medians of its points (same unit as the input).
    ratio : float
        ``after / before`` (1.25: 25% slower).
    """

    index: int
    before: float
    after: float
    ratio: float


def _segment_cost(csum, csum2, s, t):
    # Sum of squared deviations from the mean of y[s:t], vectorised over s.
    n = t - s
    total = csum[t] - csum[s]
    return (csum2[t] - csum2[s]) - total * total / n


def _optimal_partition(y, beta, min_points):
    """Breakpoints of the least-squares piecewise-constant fit with penalty beta per step,
    every segment at least min_points long (the caller ensures n >= min_points)."""
    n = y.size
    csum = np.concatenate(([0.0], np.cumsum(y)))
    csum2 = np.concatenate(([0.0], np.cumsum(y * y)))
    best = np.full(n + 1, np.inf)  # no partition ends before min_points
    best[0] = -beta
    last = np.zeros(n + 1, dtype=int)
    for t in range(min_points, n + 1):
        s = np.arange(t - min_points + 1)
        costs = best[:t - min_points + 1] + _segment_cost(csum, csum2, s, t) + beta
        k = int(np.argmin(costs))
        best[t], last[t] = costs[k], k
    breaks = []
    t = n
    while t > 0:
        t = int(last[t])
        if t > 0:
            breaks.append(t)
    return sorted(breaks)


def noise_level(y):
    """Robust noise of a series of log times: MAD of successive differences / sqrt(2).

    Parameters
    ----------
    y : array_like
        The series (natural log of the medians).

    Returns
    -------
    float
        Estimate of the standard deviation of one point, 0 for fewer than 2 points.
        A step moves one difference only, so it barely affects the estimate.
    """
    y = np.asarray(y, dtype=float)
    if y.size < 2:
        return 0.0
    d = np.diff(y)
    return float(1.4826 * np.median(np.abs(d - np.median(d))) / math.sqrt(2))


def detect_steps(values, penalty=DEFAULT_PENALTY, min_change=DEFAULT_MIN_CHANGE,
                 min_noise=DEFAULT_MIN_NOISE, min_points=DEFAULT_MIN_POINTS):
    """Find the points where a positive series steps to a new level.

    Parameters
    ----------
    values : array_like
        Positive values in commit order (the median time of each commit).
    penalty : float, optional
        Cost of one step in units of ``sigma**2 * ln(n)``: larger finds fewer steps.
    min_change : float, optional
        Smallest relative step kept (0.05: a level 5% higher or lower).
    min_noise : float, optional
        Floor of ``sigma`` (in log units, 0.005 is 0.5%), so that an almost noiseless
        series does not turn every wiggle into a step.
    min_points : int, optional
        Fewest points on each side of a step (3). The `min_points` points just before a
        step and those just after must not overlap (each on its own side of it): two
        commits, one outlying commit, or a level only the last two commits reached, are
        not a step.

    Returns
    -------
    list of Step
        In series order.

    Notes
    -----
    The rule, in the spirit of asv's step detection: fit the logs of the values by a
    piecewise-constant function with segments of at least `min_points` points, minimising
    the sum of squared residuals plus ``beta = penalty * sigma**2 * ln(n)`` per step
    (optimal partitioning, exact, O(n^2)), where ``sigma`` is the robust noise of one
    point (`noise_level`, at least `min_noise`). Then a step whose `min_points` points
    on either side overlap is removed (its two segments merged), and so, while the
    smallest step changes the level by less than `min_change`, is that one.
    Levels are the geometric means of the segments' values.

    Examples
    --------
    >>> s = detect_steps([10, 10.1, 9.9, 10, 12.5, 12.4, 12.6, 12.5])
    >>> [(x.index, round(x.ratio, 2)) for x in s]
    [(4, 1.25)]
    """
    v = np.asarray(values, dtype=float)
    if v.ndim != 1 or not np.all(np.isfinite(v)) or np.any(v <= 0):
        raise ValueError("values must be a 1-d array of finite positive numbers")
    if not (penalty >= 0 and min_change >= 0 and min_noise > 0):
        raise ValueError("penalty and min_change must be >= 0, min_noise > 0")
    if not (isinstance(min_points, int) and min_points >= 1):
        raise ValueError("min_points must be an integer >= 1")
    n = v.size
    if n < max(2, 2 * min_points):
        return []
    y = np.log(v)
    sigma = max(noise_level(y), min_noise)
    beta = penalty * sigma * sigma * math.log(n)
    breaks = _optimal_partition(y, beta, min_points)

    def levels(bs):
        edges = [0, *bs, n]
        return [float(np.mean(y[a:b])) for a, b in zip(edges[:-1], edges[1:], strict=True)]

    def separated(b, up):
        # The min_points points on each side of the step do not overlap.
        before, after = y[b - min_points:b], y[b:b + min_points]
        return before.max() < after.min() if up else before.min() > after.max()

    while breaks:
        lv = levels(breaks)
        mixed = [i for i, b in enumerate(breaks) if not separated(b, lv[i + 1] > lv[i])]
        if mixed:
            del breaks[mixed[0]]
            continue
        sizes = [abs(math.expm1(lv[i + 1] - lv[i])) for i in range(len(breaks))]
        i = int(np.argmin(sizes))
        if sizes[i] >= min_change:
            break
        del breaks[i]
    lv = levels(breaks)
    return [Step(b, math.exp(lv[i]), math.exp(lv[i + 1]), math.exp(lv[i + 1] - lv[i]))
            for i, b in enumerate(breaks)]
