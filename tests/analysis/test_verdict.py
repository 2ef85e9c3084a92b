import numpy as np
import pytest

from hrbench_analysis.verdict import UNFALSIFIABLE, get_verdict


def step_counts(decades=3.0, per_decade=12):
    inv_eps = np.logspace(0, decades, int(decades * per_decade) + 1)
    return inv_eps, 2.0 ** (np.floor(np.log2(inv_eps)) + 8)


def test_step_function_data_is_reproduced():
    x, y = step_counts()
    a = get_verdict(x, y, 1.0, 0.1)
    assert a.verdict == "reproduced", a.reason
    assert a.settled and a.theta.holds


def test_false_claim_is_refuted():
    x, y = step_counts()
    a = get_verdict(x, y ** 2, 1.0, 0.1)
    assert a.verdict == "refuted", a.reason
    assert "excludes" in a.reason
    assert a.fit.low > 1.1


def test_too_short_sweep_is_inconclusive():
    x, y = step_counts(decades=0.8)
    a = get_verdict(x, y, 1.0, 0.1)
    assert a.verdict == "inconclusive"
    assert "too few decades" in a.reason


def test_too_few_points_is_inconclusive():
    x = np.array([1.0, 10.0, 100.0, 1000.0])
    a = get_verdict(x, x, 1.0, 0.1)
    assert a.verdict == "inconclusive"
    assert "too few points" in a.reason


def test_regime_limits_the_points_judged():
    x, y = step_counts()
    a = get_verdict(x, y, 1.0, 0.1, x_min=100)
    assert a.n_regime == int(np.sum(x >= 100))
    assert a.verdict == "inconclusive" and "too few" in a.reason


def test_unsettled_slope_is_inconclusive():
    # A crossover: y ~ x^2 at first, then ~ x; the global fit lies between the two.
    x = np.logspace(0, 3, 37)
    y = x ** 2 / (1 + x / 30)
    a = get_verdict(x, y, 1.5, 0.2)
    assert a.verdict == "inconclusive"
    assert "not settled" in a.reason


def test_verdict_validates_its_inputs():
    with pytest.raises(ValueError, match="tolerance"):
        get_verdict([1, 2, 3], [1, 2, 3], 1.0, 0.0)
    with pytest.raises(ValueError, match="positive"):
        get_verdict([1, 2, 3], [1, 0, 3], 1.0, 0.1)


def test_upper_bound_holds_below_it_and_fails_above():
    # y = k, judged against x = k log k: the exponent is about 0.87, under the bound
    # O(k log k) (exponent 1), so the upper bound is reproduced where Theta is not.
    k = np.logspace(np.log10(64), np.log10(16384), 25)
    x = k * np.log(k)
    theta = get_verdict(x, k, 1.0, 0.05)
    upper = get_verdict(x, k, 1.0, 0.05, bound="upper")
    assert theta.verdict != "reproduced"
    assert upper.verdict == "reproduced", upper.reason
    assert "the bound" in upper.reason
    # y = k^2 grows faster than k log k: refuted.
    above = get_verdict(x, k ** 2, 1.0, 0.15, bound="upper")
    assert above.verdict == "refuted", above.reason
    # y = x on the bound, with a scatter of 1%: reproduced, and k^1.2 refuted on the
    # same points tilted to it.
    on = get_verdict(x, 3 * x * wobble(x.size), 1.0, 0.15, bound="upper")
    assert on.verdict == "reproduced" and on.can_fail
    assert [(a.exponent, a.verdict) for a in on.alternatives] == [(1.2, "refuted")]
    # Exactly on the bound, the points are an identity: unfalsifiable, not reproduced.
    exact = get_verdict(x, 3 * x, 1.0, 0.15, bound="upper")
    assert exact.verdict == UNFALSIFIABLE and exact.exact
    assert "could not have failed" in exact.reason


def wobble(n, size=0.01):
    # A deterministic multiplicative scatter of about `size`, so that synthetic points
    # are a measurement and not an identity.
    return 1 + size * np.cos(2.3 * np.arange(n))


def test_alternatives_are_the_nearest_laws_outside_the_band():
    x = np.geomspace(10, 1e5, 30)
    a = get_verdict(x, x ** 2 * wobble(x.size), 2.0, 0.1)
    assert a.verdict == "reproduced"
    assert [alt.exponent for alt in a.alternatives] == [1.85, 2.15]
    assert all(alt.verdict == "refuted" for alt in a.alternatives) and a.can_fail
    # Tilting moves the interval by the tilt, nothing else (the same bootstrap samples).
    shift = 2.15 - a.fit.exponent
    assert a.alternatives[1].low == pytest.approx(a.interval.low + shift, abs=1e-9)
    assert "refutes the alternative exponents 1.85 and 2.15" in a.refutes_text


def test_alternatives_tilted_from_a_staircase_are_not_reproduced():
    # A binary staircase over 3 decades: the interval [0.929, 1.084] excludes 0.85 and
    # 1.15, and the same points tilted to either are not reproduced: the claim could fail.
    x, y = step_counts()
    a = get_verdict(x, y, 1.0, 0.1)
    assert a.verdict == "reproduced" and a.can_fail
    assert [alt.verdict for alt in a.alternatives] == ["inconclusive", "inconclusive"]
    assert a.refutes_text.startswith("refutes the alternative exponents 0.85 and 1.15 "
                                     "(outside the interval [0.929, 1.084])")


def test_no_alternatives_without_a_fit():
    a = get_verdict([1, 2, 3], [1, 2, 3], 1.0, 0.1)
    assert a.verdict == "inconclusive" and a.alternatives == [] and a.can_fail is None


def test_unknown_bound_is_refused():
    x = np.logspace(0, 3, 20)
    with pytest.raises(ValueError, match="bound"):
        get_verdict(x, x, 1.0, 0.1, bound="lower")


def test_an_alternative_law_is_judged_on_the_points_tilted_to_it():
    # y = k log k (with a scatter of counts) for k from 1e4 to 1e8: O(x), x = k log k,
    # with 1 + 0.03 holds, and the same points tilted to the law k^1.15 (exponent about
    # 1.15 / (1 + 1 / ln k) against x) grow faster than the bound.
    k = np.geomspace(1e4, 1e8, 20)
    x, y = k * np.log(k), 11.5 * k * np.log(k) * wobble(k.size)
    a = get_verdict(x, y, 1.0, 0.03, bound="upper", laws=[("patches ** 1.15", k ** 1.15)])
    assert a.verdict == "reproduced" and a.can_fail
    law = a.alternatives[-1]
    assert law.law == "patches ** 1.15" and np.isnan(law.exponent)
    assert law.verdict == "refuted" and law.low > 1.03
    assert "y ~ patches ** 1.15: refuted" in a.refutes_text
    # Points that follow the law itself are refuted by the claim's own test.
    b = get_verdict(x, k ** 1.15, 1.0, 0.03, bound="upper")
    assert b.verdict == "refuted", b.reason
    # Given in another order than x's, the law's values follow their points.
    order = np.arange(k.size)[::-1]
    c = get_verdict(x[order], y[order], 1.0, 0.03, bound="upper",
                    laws=[("patches ** 1.15", (k ** 1.15)[order])])
    assert c.alternatives[-1].low == pytest.approx(law.low)
