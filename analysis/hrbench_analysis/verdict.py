"""Verdicts: does a sweep reproduce, refute, or fail to decide a claimed power law?"""

import math
from dataclasses import dataclass, field

import numpy as np

from .fit import compare_models, exponent_interval, theta_check
from .slopes import local_slopes, window_slopes

__all__ = [
    "VERDICTS",
    "UNFALSIFIABLE",
    "ALTERNATIVE_MARGIN",
    "Alternative",
    "SKIPPED",
    "Assessment",
    "MEASURED",
    "get_verdict",
    "assess_claim",
    "skipped_assessment",
    "expected_text",
]

#: The verdict of a claim whose exponent has no published value (key ``published =
#: false``): the fit and its interval are reported, judged against nothing.
MEASURED = "measured"

#: The verdict of a claim that could not have failed on its points: they lie exactly on
#: a power law (an identity of the counting, which no measurement can refute), or the
#: same test reproduces them tilted to an alternative exponent (:class:`Alternative`).
#: Not counted as reproduced.
UNFALSIFIABLE = "unfalsifiable"

#: The verdicts: the three judgements in order of strength, :data:`UNFALSIFIABLE`, then
#: :data:`MEASURED`.
VERDICTS = ("reproduced", "refuted", "inconclusive", UNFALSIFIABLE, MEASURED)

#: How far outside a claim's band its alternatives lie (dimensionless): a Theta claim
#: ``k +/- tolerance`` is set against ``k - tolerance - margin`` and
#: ``k + tolerance + margin``, an upper bound ``O(x^k)`` against the faster
#: ``k + tolerance + margin``.
ALTERNATIVE_MARGIN = 0.05

#: Largest relative spread of ``y / x^e`` over the regime at which the points count as
#: lying exactly on a power law: rounding of exact counts, not a measurement.
EXACT_SPREAD = 1e-9


@dataclass
class Alternative:
    """The nearest law a claim's test must tell from the claimed one, and what the test
    says of the measured points tilted to it.

    Attributes
    ----------
    exponent : float
        The alternative exponent (dimensionless).
    verdict : str
        The verdict of the same test, with the same regime, windows and bootstrap seed, on
        the points ``y x^(exponent - e)``, ``e`` the fitted exponent: the measured
        points with their scatter and staircase kept, following the alternative law.
        Anything but ``"reproduced"`` means the claim could have failed on points that
        followed the alternative; ``"reproduced"`` that it could not.
    low, high : float
        The tilted points' interval of the exponent.
    """

    exponent: float
    verdict: str
    low: float
    high: float
    #: The alternative as a law of the claim's y (key ``alternative``, e.g.
    #: ``"patches^0.15"``), tilted to by ``y law / x^e``; ``""`` for an exponent of x.
    law: str = ""

    @property
    def text(self):
        """str: e.g. ``"2.2: refuted [2.181, 2.214]"``, ``"y ~ patches^0.15: refuted [...]"``."""
        name = f"y ~ {self.law}" if self.law else f"{self.exponent:g}"
        return f"{name}: {self.verdict} [{self.low:.3f}, {self.high:.3f}]"

#: The mark of a claim that was not measured (the engine cannot run it); not a verdict.
SKIPPED = "skipped"


@dataclass
class Assessment:
    """Everything measured about one claim, and the verdict drawn from it.

    Attributes
    ----------
    verdict : str
        ``"reproduced"``, ``"refuted"`` or ``"inconclusive"``; :data:`MEASURED` for a
        claim without a published value that was fitted; or :data:`SKIPPED` for a claim
        that was not measured.
    reason : str
        One sentence saying why.
    expected_exponent, tolerance : float
        The claim's k and tolerance (dimensionless).
    x, y : ndarray
        Every measured point, sorted by x.
    in_regime : ndarray of bool
        Which points lie in the asymptotic regime.
    n_regime : int
        Points in the regime.
    decades : float
        Decades of x spanned by the regime's points.
    fit : PowerLawFit or None
        Power-law fit over the regime (None if too few points); its ``low`` and ``high``
        are the statistical (bootstrap) interval only.
    interval : ExponentInterval or None
        The exponent's interval with its systematic part (what the verdict reads).
    local : LocalSlopes or None
        Neighbour-to-neighbour slopes over all points.
    windows : WindowSlopes or None
        Sliding-window exponents over the regime.
    settled : bool or None
        Whether the mean exponent of the sliding windows in the upper half of the regime
        lies within the tolerance of the exponent fitted over the whole regime (None if
        no window fits).
    settle_spread : float
        Distance between that mean and the fitted exponent (dimensionless).
    theta : ThetaCheck or None
        The bounded-ratio check of ``y / x^k`` over the regime.
    models : ModelComparison or None
        Competing models (growing and falling) over the regime.
    alternatives : list of Alternative
        The alternatives of :data:`ALTERNATIVE_MARGIN` and the test's verdict on the
        points tilted to each (empty when no exponent was fitted).
    exact : bool
        Whether the points of the regime lie exactly on a power law
        (:data:`EXACT_SPREAD`): an identity, which no measurement could refute.
    """

    verdict: str
    reason: str
    expected_exponent: float
    tolerance: float
    x: np.ndarray
    y: np.ndarray
    in_regime: np.ndarray
    n_regime: int
    decades: float
    fit: object = None
    interval: object = None
    local: object = None
    windows: object = None
    settled: object = None
    settle_spread: float = math.nan
    theta: object = None
    models: object = None
    alternatives: list = field(default_factory=list)
    exact: bool = False
    notes: list = field(default_factory=list)

    @property
    def can_fail(self):
        """bool or None: whether these points could have failed the claim: they do not
        lie exactly on a power law, and the test reproduces none of the alternatives
        (tilted to an alternative, the same points would not have reproduced the claim);
        ``None`` when no exponent was fitted."""
        if not self.alternatives:
            return None
        return not self.exact and all(a.verdict != "reproduced" for a in self.alternatives)

    @property
    def refutes_text(self):
        """str: which alternatives the measured interval excludes and what the test says
        of the points tilted to each, or why the claim could not have failed, in one
        sentence; ``""`` when no exponent was fitted."""
        if not self.alternatives:
            return ""
        if self.exact:
            return ("could not have failed on these points: they lie exactly on a power "
                    "law (y / x^e varies by less than 1e-9), an identity of the counting")
        i = self.interval
        powers = [a for a in self.alternatives if not a.law]
        out = [a for a in powers if not i.low <= a.exponent <= i.high]
        inside = [a for a in powers if i.low <= a.exponent <= i.high]
        parts = []
        if out:
            parts.append(f"refutes the alternative exponent{'s' if len(out) > 1 else ''} "
                         + " and ".join(f"{a.exponent:g}" for a in out)
                         + f" (outside the interval [{i.low:.3f}, {i.high:.3f}])")
        if inside:
            parts.append("does not refute " + " and ".join(f"{a.exponent:g}" for a in inside)
                         + " (inside the interval)")
        parts.append("the points tilted to " + ", ".join(a.text for a in self.alternatives))
        if not self.can_fail:
            parts.append("so the claim could not have failed on these points")
        return "; ".join(parts)


def _verdict_iv(x, y, expected_exponent, tolerance, min_points, min_decades,
                window_decades, theta_band):
    x = np.asarray(x, dtype=float).ravel()
    y = np.asarray(y, dtype=float).ravel()
    if x.shape != y.shape:
        raise ValueError(f"`x` and `y` must have the same length, got {x.size} and {y.size}")
    if np.any(~np.isfinite(x)) or np.any(x <= 0) or np.any(~np.isfinite(y)) or np.any(y <= 0):
        raise ValueError("`x` and `y` must be finite and positive")
    if not math.isfinite(expected_exponent):
        raise ValueError("`expected_exponent` must be finite")
    for name, value in (("tolerance", tolerance), ("min_decades", min_decades),
                        ("window_decades", window_decades)):
        if not value > 0:
            raise ValueError(f"`{name}` must be positive, got {value}")
    if int(min_points) < 3:
        raise ValueError(f"`min_points` must be at least 3, got {min_points}")
    if not theta_band >= 1:
        raise ValueError(f"`theta_band` must be at least 1, got {theta_band}")
    order = np.argsort(x, kind="stable")
    return x[order], y[order]


def get_verdict(x, y, expected_exponent, tolerance, *, x_min=None, x_max=None,
                min_points=8, min_decades=1.5, window_decades=1.0, theta_band=10.0,
                step_octaves=1, one_per_step=False, n_boot=2000, seed=None,
                bound="theta", alternatives=True, laws=()):
    """Judge whether measured points follow ``y = Theta(x^k)``, or ``y = O(x^k)``.

    Parameters
    ----------
    x, y : array_like
        Measured points, positive (any units).
    expected_exponent : float
        The claimed exponent k (dimensionless).
    tolerance : float
        How far the exponent may lie from k (dimensionless).
    x_min, x_max : float, optional
        The asymptotic regime; points outside it are shown but not judged.
    min_points : int, optional
        Fewest points in the regime for a verdict (default 8).
    min_decades : float, optional
        Fewest decades of x in the regime for a verdict (default 1.5).
    window_decades : float, optional
        Width of the sliding windows that judge settling (decades, default 1).
    theta_band : float, optional
        Largest ``max/min`` of ``y / x^k`` over the regime that counts as bounded
        (default 10).
    step_octaves : int, optional
        Period of the counts' staircase in octaves of x (default 1; 2 for quadtree
        subdivision), see :func:`hrbench_analysis.fit.exponent_interval`.
    one_per_step : bool, optional
        Whether the points are one per plateau of a staircase
        (:func:`hrbench_analysis.slopes.plateau_ends`): then the windows, of the interval and
        of the settling check alike, are runs of 3 consecutive points (two periods), and
        no staircase is left for the bootstrap's blocks.
    bound : {"theta", "upper"}, optional
        What the claim states: ``"theta"`` (the default) ``y = Theta(x^k)``, judged on
        both sides; ``"upper"`` only ``y = O(x^k)``, as a paper states a complexity
        bound: any exponent up to ``k + tolerance`` reproduces it.
    n_boot : int, optional
        Bootstrap resamples of the exponent's interval (default 2000).
    seed : int, optional
        Bootstrap seed (default :data:`hrbench_analysis.powerlaw.DEFAULT_SEED`).
    alternatives : bool, optional
        Whether to judge the alternatives too (default True; see below).
    laws : sequence of (str, array_like), optional
        Further alternatives given as laws of y: a name and the law's value at each point
        (in the order of `x`), up to a constant factor, judged on ``y law / x^e``.

    Returns
    -------
    assessment : Assessment

    Notes
    -----
    The verdict is decided in this order:

    1. ``inconclusive`` if the regime holds fewer than `min_points` points, spans fewer
       than `min_decades` decades, or is too short for one window of `window_decades`.
    2. ``inconclusive`` if the exponent has not settled: the exponents fitted over sliding
       windows of `window_decades` (shifted by 0.1 decade) in the upper half of the
       regime average to a value farther than `tolerance` from the fit over the whole
       regime. A window of a decade spans more than three binary steps, and averaging
       windows shifted across a step cancels what is left of the step oscillation, so
       the oscillation of neighbour-to-neighbour slopes does not count as unsettled,
       while a crossover to another exponent does.
    3. ``refuted`` if the interval of the exponent (:func:`hrbench_analysis.fit.exponent_interval`:
       the 95% bootstrap interval joined with the systematic error) lies wholly outside
       ``[k - tolerance, k + tolerance]``.
    4. ``reproduced`` if the interval lies wholly inside that band and ``y / x^k`` stays in
       a bounded, flat band (:func:`hrbench_analysis.fit.theta_check`).
    5. ``inconclusive`` otherwise (the interval straddles the edge of the band, or the
       ratio's band is too wide).

    With ``bound="upper"`` the band is ``(-inf, k + tolerance]`` in steps 3 to 5 and the
    ratio's band is not checked: an upper bound says nothing of how far below it the
    counts grow (``O(k log k)`` holds for counts that grow like ``k``).

    Once an exponent ``e`` is fitted, the same test judges the points tilted to each
    alternative exponent ``a`` of :data:`ALTERNATIVE_MARGIN` (``y x^(a - e)``: the same
    scatter and staircase, another law), so that the report can say which alternatives
    the claim's test refutes, and whether the claim could have failed. A ``reproduced``
    verdict becomes :data:`UNFALSIFIABLE` when the test also reproduces the points tilted
    to an alternative, or when the points lie exactly on a power law. A law of `laws`
    is an alternative that is not a power of x, such as ``k^1.15`` where ``O(k log k)``
    is claimed and x is ``log k``.
    """
    if bound not in ("theta", "upper"):
        raise ValueError(f"bound must be 'theta' or 'upper', not {bound!r}")
    options = dict(x_min=x_min, x_max=x_max, min_points=min_points, min_decades=min_decades,
                   window_decades=window_decades, theta_band=theta_band,
                   step_octaves=step_octaves, one_per_step=one_per_step, n_boot=n_boot,
                   seed=seed, bound=bound)
    order = np.argsort(np.asarray(x, dtype=float).ravel(), kind="stable")
    result = _judge(x, y, expected_exponent, tolerance, **options)
    if not alternatives or result.fit is None:
        return result
    k, tol = float(expected_exponent), float(tolerance)
    shift = tol + ALTERNATIVE_MARGIN
    targets = (k + shift,) if bound == "upper" else (k - shift, k + shift)
    e = result.fit.exponent
    for a in targets:
        tilted = result.y * result.x ** (a - e)
        other = _judge(result.x, tilted, k, tol, **options)
        low, high = ((other.interval.low, other.interval.high) if other.interval
                     else (math.nan, math.nan))
        result.alternatives.append(Alternative(round(a, 12), other.verdict, low, high))
    for law, values in laws:
        shape = np.asarray(values, dtype=float).ravel()[order]
        tilted = result.y * shape / result.x ** e
        other = _judge(result.x, tilted, k, tol, **options)
        low, high = ((other.interval.low, other.interval.high) if other.interval
                     else (math.nan, math.nan))
        result.alternatives.append(Alternative(math.nan, other.verdict, low, high, law))
    ratio = result.y[result.in_regime] / result.x[result.in_regime] ** e
    result.exact = bool(ratio.max() / ratio.min() - 1 <= EXACT_SPREAD)
    if result.verdict == "reproduced" and not result.can_fail:
        result.verdict = UNFALSIFIABLE
        result.reason += f"; but the test {result.refutes_text}"
    return result


def _judge(x, y, expected_exponent, tolerance, *, x_min, x_max, min_points, min_decades,
           window_decades, theta_band, step_octaves, one_per_step, n_boot, seed, bound):
    # get_verdict's test alone, without its alternatives.
    x, y = _verdict_iv(x, y, expected_exponent, tolerance, min_points, min_decades,
                       window_decades, theta_band)
    k, tol = float(expected_exponent), float(tolerance)
    sel = np.ones(x.size, dtype=bool)
    if x_min is not None:
        sel &= x >= x_min
    if x_max is not None:
        sel &= x <= x_max
    xr, yr = x[sel], y[sel]
    n = int(sel.sum())
    decades = float(math.log10(xr.max() / xr.min())) if n >= 2 else 0.0
    result = Assessment(verdict="inconclusive", reason="", expected_exponent=k, tolerance=tol,
                        x=x, y=y, in_regime=sel, n_regime=n, decades=decades)
    if np.unique(x).size >= 2:
        result.local = local_slopes(x, y)
    regime = _regime_text(x_min, x_max)

    # Check there is enough data for a verdict.
    if n < int(min_points) or np.unique(xr).size < 3:
        result.reason = (f"too few points: {n} in the regime{regime}, "
                         f"need at least {int(min_points)} (with 3 distinct x)")
        return result
    if decades < min_decades:
        result.reason = (f"too few decades: the regime{regime} spans {decades:.2f} decades "
                         f"of x, need {min_decades:g}")
        return result

    # Fit, check the bounded ratio, compare models and slide windows.
    kwargs = {} if seed is None else {"seed": seed}
    if one_per_step:
        interval = exponent_interval(xr, yr, n_boot=n_boot, window_points=3, **kwargs)
    else:
        interval = exponent_interval(xr, yr, n_boot=n_boot, step_octaves=step_octaves,
                                     **kwargs)
    fit = interval.fit
    result.fit = fit
    result.interval = interval
    result.theta = theta_check(xr, yr, k, max_band=theta_band, tolerance=tol)
    result.models = compare_models(xr, yr)
    # One point per plateau: a window of a decade may hold one or two; settle on the
    # interval's windows of three consecutive plateaus instead.
    windows = interval.windows if one_per_step else window_slopes(xr, yr,
                                                                 width=window_decades)
    result.windows = windows
    if windows.slope.size < (2 if one_per_step else 1):
        result.reason = ((f"too few plateaus: {n} in the regime{regime}, need 4 (two "
                          "windows of 3)") if one_per_step else
                         (f"too few decades: no window of {window_decades:g} decades with "
                          f"3 points fits in the regime{regime}"))
        return result
    mid = 10 ** ((math.log10(xr.min()) + math.log10(xr.max())) / 2)
    upper = windows.x >= mid
    if not upper.any():
        upper = windows.x >= windows.x.max()
    spread = float(abs(np.mean(windows.slope[upper]) - fit.exponent))
    result.settle_spread = spread
    result.settled = spread <= tol
    measured = (f"exponent {fit.exponent:.3f} "
                f"[{interval.low:.3f}, {interval.high:.3f}] over {decades:.1f} decades "
                f"({n} points)")
    if not result.settled:
        result.reason = (f"slope not settled: {window_decades:g}-decade windows in the upper "
                         f"half of the regime give an exponent {spread:.3f} away from the "
                         f"fit over the whole regime, more than the tolerance {tol:g}; "
                         f"{measured}")
        return result
    if bound == "upper":
        if interval.low > k + tol:
            result.verdict = "refuted"
            result.reason = (f"{measured}: the interval lies above {k:g} + {tol:g}, the "
                             f"bound; best model {result.models.best}")
        elif interval.high <= k + tol:
            result.verdict = "reproduced"
            result.reason = f"{measured}: at most {k:g} + {tol:g}, the bound"
        else:
            result.reason = f"{measured}: the interval straddles {k:g} + {tol:g}, the bound"
        return result
    if interval.high < k - tol or interval.low > k + tol:
        result.verdict = "refuted"
        result.reason = (f"{measured}: the interval excludes {k:g} +/- {tol:g}; "
                         f"best model {result.models.best}")
        return result
    inside = k - tol <= interval.low and interval.high <= k + tol
    if inside and result.theta.holds:
        result.verdict = "reproduced"
        result.reason = (f"{measured} within {k:g} +/- {tol:g}; y/x^{k:g} stays within a "
                         f"factor {result.theta.band:.2f}")
        return result
    if not inside:
        result.reason = (f"{measured}: the interval straddles the edge of {k:g} +/- {tol:g}")
    else:
        result.reason = (f"{measured}, but y/x^{k:g} varies by a factor "
                         f"{result.theta.band:.2f} (bounded: at most {theta_band:g}) with "
                         f"trend {result.theta.trend:+.3f} per decade")
    return result


def expected_text(claim):
    """The exponent a claim expects, as its verdicts name it: "2 +/- 0.15", "<= 1 + 0.15"."""
    if getattr(claim, "bound", "theta") == "upper":
        return f"<= {claim.expected_exponent:g} + {claim.tolerance:g}"
    return f"{claim.expected_exponent:g} +/- {claim.tolerance:g}"


def _regime_text(x_min, x_max):
    parts = []
    if x_min is not None:
        parts.append(f"x >= {x_min:g}")
    if x_max is not None:
        parts.append(f"x <= {x_max:g}")
    return f" ({', '.join(parts)})" if parts else ""


def assess_claim(claim, data, n_boot=2000):
    """Judge one claim from its measured points.

    Parameters
    ----------
    claim : Claim
    data : ClaimData
        The claim's points (see :func:`hrbench_analysis.sweep.get_claim_data`).
    n_boot : int, optional
        Bootstrap resamples.

    Returns
    -------
    assessment : Assessment
        As from :func:`get_verdict`; failed points are named in ``notes`` and in the reason.
    """
    # With the key `plateaus` the fit reads one point per plateau (data.fitted).
    fitted = getattr(data, "fitted", None)
    x, y = (data.x, data.y) if fitted is None else (data.x[fitted], data.y[fitted])
    if x.size == 0:
        reason = ("no successful points" if data.x.size == 0 else
                  f"no plateau of {claim.plateaus.of.text} with its step among the "
                  f"{data.x.size} points")
        result = Assessment(verdict="inconclusive", reason=reason,
                            expected_exponent=claim.expected_exponent,
                            tolerance=claim.tolerance, x=x, y=y,
                            in_regime=np.zeros(0, dtype=bool), n_regime=0, decades=0.0)
    else:
        result = get_verdict(
            x, y, claim.expected_exponent, claim.tolerance, x_min=claim.x_min,
            x_max=claim.x_max, min_points=claim.min_points, min_decades=claim.min_decades,
            window_decades=claim.window_decades, theta_band=claim.theta_band,
            step_octaves=claim.step_octaves,
            one_per_step=getattr(claim, "plateaus", None) is not None, n_boot=n_boot,
            bound=getattr(claim, "bound", "theta"), laws=_laws(claim, data, fitted))
    if not getattr(claim, "published", True) and result.interval is not None:
        # Nothing published to judge against: report the fit, and what the hypothesis
        # of the claims file would have been judged.
        i = result.interval
        result.reason = (f"no published value: measured exponent {i.fit.exponent:.3f} "
                         f"[{i.low:.3f}, {i.high:.3f}] over {result.decades:.1f} decades "
                         f"({result.n_regime} points); against the hypothesis "
                         f"{expected_text(claim)} it would be "
                         f"{result.verdict}")
        result.verdict = MEASURED
    i, k, tol = result.interval, claim.expected_exponent, claim.tolerance
    if (i is not None and getattr(claim, "bound", "theta") == "theta"
            and k - tol <= i.low and i.high <= k + tol and not i.low <= k <= i.high):
        # Within the tolerance, but not at the claimed exponent itself: say why.
        why = getattr(claim, "interval_note", "") or "the claims file gives no reason"
        note = f"the interval excludes {claim.expected_exponent:g} itself: {why}"
        result.notes.append(note)
        result.reason += f"; {note}"
    if fitted is not None:
        note = (f"fitted one point per plateau of {claim.plateaus.of.text}, the "
                f"{claim.plateaus.keep} of each: {x.size} of {data.x.size} points")
        result.notes.append(note)
        result.reason += f"; {note}"
    octaves = getattr(claim, "increments", None)
    if octaves:
        note = (f"fitted the increments of {claim.y.text} per e-fold of {claim.x.text}, "
                f"{octaves} octave{'s' if octaves > 1 else ''} of {claim.x.text} apart "
                "(key increments)")
        result.notes.append(note)
        result.reason += f"; {note}"
    if data.failures:
        codes = sorted({f["exit_code"] for f in data.failures})
        note = (f"{len(data.failures)} point(s) failed (exit code "
                f"{', '.join(map(str, codes))}) and are left out")
        result.notes.append(note)
        result.reason += f"; {note}"
    if data.missing:
        note = f"{data.missing} point(s) not run yet"
        result.notes.append(note)
        result.reason += f"; {note}"
    return result


def _laws(claim, data, fitted):
    # The claim's alternative law of y (key `alternative`) at its fitted points, if any.
    law = getattr(claim, "alternative", None)
    values = getattr(data, "alternative", None)
    if law is None or values is None:
        return ()
    return ((law.text, values if fitted is None else values[fitted]),)


def skipped_assessment(claim, reason):
    """The assessment of a claim that was not measured.

    Parameters
    ----------
    claim : Claim
    reason : str
        Why, e.g. ``"engine lacks scene 'parallel3d'"``.

    Returns
    -------
    assessment : Assessment
        Verdict :data:`SKIPPED`, no points.
    """
    empty = np.zeros(0, dtype=float)
    return Assessment(verdict=SKIPPED, reason=reason,
                      expected_exponent=claim.expected_exponent, tolerance=claim.tolerance,
                      x=empty, y=empty.copy(), in_regime=np.zeros(0, dtype=bool),
                      n_regime=0, decades=0.0)
