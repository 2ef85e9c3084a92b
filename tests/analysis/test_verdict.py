import numpy as np
import pytest

from hrbench_analysis.verdict import get_verdict


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
    # y = x exactly on the bound: reproduced.
    assert get_verdict(x, 3 * x, 1.0, 0.15, bound="upper").verdict == "reproduced"


def test_unknown_bound_is_refused():
    x = np.logspace(0, 3, 20)
    with pytest.raises(ValueError, match="bound"):
        get_verdict(x, x, 1.0, 0.1, bound="lower")
