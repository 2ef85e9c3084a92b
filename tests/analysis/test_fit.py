import numpy as np
import pytest

from analysis.fit import (
    compare_models,
    fit_power_law,
    local_slopes,
    steps_block_length,
    theta_check,
    window_slopes,
)


def noisy_power_law(k, c=3.0, sigma=0.05, n=40, decades=3.0, seed=1):
    rng = np.random.default_rng(seed)
    x = np.logspace(0, decades, n)
    y = c * x ** k * np.exp(rng.normal(0, sigma, n))
    return x, y


@pytest.mark.parametrize("k", [0.5, 1.0, 2.0, 3.0])
def test_fit_recovers_known_exponent_and_interval_covers_it(k):
    x, y = noisy_power_law(k)
    fit = fit_power_law(x, y)
    assert fit.exponent == pytest.approx(k, abs=0.03)
    assert fit.low < k < fit.high
    # The noise is not trivial: the interval has a width and the residuals are not zero.
    assert fit.high - fit.low > 0.005
    assert fit.rms > 0.005
    assert fit.n == 40 and fit.decades == pytest.approx(3.0)


def test_interval_coverage_is_close_to_nominal():
    # Over many synthetic data sets, the 95% interval should cover the truth most times.
    covered = 0
    for seed in range(60):
        x, y = noisy_power_law(1.5, seed=seed, n=25)
        fit = fit_power_law(x, y, n_boot=400)
        covered += fit.low <= 1.5 <= fit.high
    assert covered >= 50


def test_fit_is_exact_without_noise_and_reproducible():
    x = np.logspace(0, 2, 11)
    fit = fit_power_law(x, 2.5 * x ** 1.7)
    assert fit.exponent == pytest.approx(1.7, abs=1e-12)
    assert fit.prefactor == pytest.approx(2.5, rel=1e-12)
    a = fit_power_law(*noisy_power_law(1.0), block=3)
    b = fit_power_law(*noisy_power_law(1.0), block=3)
    assert (a.low, a.high) == (b.low, b.high)


def test_input_validation_names_the_argument():
    with pytest.raises(ValueError, match="positive"):
        fit_power_law([1, 2, 3], [1, -2, 3])
    with pytest.raises(ValueError, match="same length"):
        fit_power_law([1, 2, 3], [1, 2])
    with pytest.raises(ValueError, match="block"):
        fit_power_law([1, 2, 3], [1, 2, 3], block=0)
    with pytest.raises(ValueError, match="distinct"):
        fit_power_law([2, 2, 2], [1, 2, 3])


def step_counts(decades=3.0, per_decade=12):
    # N of binary trees: doubles each time 1/eps crosses a power of 2, as in docs/conventions.md.
    inv_eps = np.logspace(0, decades, int(decades * per_decade) + 1)
    n = 2.0 ** (np.floor(np.log2(inv_eps)) + 8)
    return inv_eps, n


def test_local_slopes_oscillate_on_steps_but_windows_settle():
    x, y = step_counts()
    local = local_slopes(x, y)
    assert local.slope.max() > 2 and local.slope.min() == 0
    windows = window_slopes(x, y, width=1.0)
    assert windows.slope.size > 10
    assert np.all(np.abs(windows.slope - 1) < 0.12)


def test_local_slopes_merge_equal_x():
    local = local_slopes([1, 2, 2, 4], [1, 3, 5, 16])
    assert local.x.size == 2
    assert local.slope[0] == pytest.approx(np.log2(np.sqrt(15)))


def test_theta_check_bounded_band_for_steps_and_unbounded_for_wrong_power():
    x, y = step_counts()
    good = theta_check(x, y, 1.0, max_band=4, tolerance=0.1)
    assert good.holds and good.band <= 2.0 + 1e-9
    bad = theta_check(x, y * np.log(x + 1) ** 2, 1.0, max_band=4, tolerance=0.1)
    assert not bad.holds and bad.band > 4


def test_model_comparison_prefers_the_true_model():
    x = np.logspace(0.5, 4, 30)
    rng = np.random.default_rng(7)
    y = 2 * x ** 2 * np.log(x) * np.exp(rng.normal(0, 0.02, x.size))
    comparison = compare_models(x, y)
    assert comparison.best == "x^2 log x"
    assert comparison.best_power == 2.0
    assert np.min(np.delete(comparison.delta_aic, comparison.names.index("x^2 log x"))) > 10


def test_model_comparison_skips_log_models_below_one():
    comparison = compare_models([0.5, 1, 2, 4], [0.5, 1, 2, 4])
    assert "x log x" in comparison.skipped
    assert comparison.best == "x"


def test_block_length_is_points_per_doubling():
    x = np.logspace(0, 3, 31)  # 10 points per decade: 3 points per factor 2
    assert steps_block_length(x) == 3
