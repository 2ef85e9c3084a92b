import numpy as np
import pytest

from hrbench_analysis.fit import compare_models, exponent_interval, theta_check
from hrbench_analysis.powerlaw import fit_power_law, steps_block_length
from hrbench_analysis.slopes import local_slopes, octave_window_slopes, window_slopes


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


def test_model_comparison_names_the_falling_power_law_of_a_decreasing_quantity():
    # An error that falls like the inverse of its cost, with 5% scatter: a set of growth
    # models alone would name the constant the best (RMS 0.9 decade over three decades).
    x = np.logspace(1, 4, 31)
    rng = np.random.default_rng(11)
    y = 0.3 / x * np.exp(rng.normal(0, 0.05, x.size))
    comparison = compare_models(x, y)
    assert comparison.best == "x^-1" and comparison.best_power == -1.0
    rms = dict(zip(comparison.names, comparison.rms, strict=True))
    assert rms["x^-1"] < 0.05 and rms["1"] > 0.8  # decades
    others = np.delete(comparison.delta_aic, comparison.names.index("x^-1"))
    assert np.min(others) > 10
    # The set is closed under y -> 1/y: the reciprocal data ranks the reciprocal models.
    flipped = compare_models(x, 1 / y)
    assert flipped.best == "x"
    assert (dict(zip(flipped.names, flipped.delta_aic, strict=True))["x log x"]
            == pytest.approx(dict(zip(comparison.names, comparison.delta_aic,
                                      strict=True))["1/(x log x)"]))


def test_model_comparison_of_a_growing_quantity_is_unchanged_by_the_falling_models():
    growth = (("1", 0.0, 0), ("log x", 0.0, 1), ("x^0.5", 0.5, 0), ("x", 1.0, 0),
              ("x log x", 1.0, 1), ("x^1.5", 1.5, 0), ("x^2", 2.0, 0),
              ("x^2 log x", 2.0, 1), ("x^3", 3.0, 0))
    x = np.logspace(0.5, 4, 30)
    rng = np.random.default_rng(3)
    y = 5 * x ** 2 * np.exp(rng.normal(0, 0.05, x.size))
    alone, full = compare_models(x, y, models=growth), compare_models(x, y)
    assert alone.best == full.best == "x^2"
    dfull = dict(zip(full.names, full.delta_aic, strict=True))
    for name, delta in zip(alone.names, alone.delta_aic, strict=True):
        assert dfull[name] == pytest.approx(delta, abs=1e-9)
    # The four best, as the report lists them, are still growth models.
    assert {full.names[i] for i in np.argsort(full.delta_aic)[:4]} <= {n for n, _, _ in growth}


def test_model_comparison_skips_log_models_below_one():
    comparison = compare_models([0.5, 1, 2, 4], [0.5, 1, 2, 4])
    assert "x log x" in comparison.skipped
    assert comparison.best == "x"


def test_block_length_is_points_per_doubling():
    x = np.logspace(0, 3, 31)  # 10 points per decade: 3 points per factor 2
    assert steps_block_length(x) == 3


def staircase(rng, drift):
    """Synthetic counts of a binary tree: a power law on a staircase of one octave's period.

    The true exponent k is drawn at random; the points are sampled 5, 10 or 16 per decade
    over 1.7 to 3.5 decades at a random offset, and the staircase (a jump by a factor up to
    2^1.5 once per octave, at a random phase) is what a bootstrap mistakes for noise. With
    `drift`, a correction ``1 + a (x/x0)^-w`` makes the exponent drift towards k across
    the regime, as boundary effects do before the asymptotic regime.
    """
    k = rng.uniform(0.5, 3.0)
    decades, per_decade = rng.uniform(1.7, 3.5), rng.choice([5, 10, 16])
    x0 = 10 ** rng.uniform(0, 3)
    x = x0 * 10 ** (np.arange(int(decades * per_decade) + 1) / per_decade
                    + rng.uniform(0, 1 / per_decade))
    phase = rng.uniform(1, 2)
    step = 2.0 ** (np.ceil(np.log2(x * phase)) - np.log2(x * phase))
    y = x ** k * step ** min(k, 1.5)
    if drift:
        y = y * (1 + rng.uniform(-1, 1) * (x / x0) ** -rng.uniform(0.5, 1.0))
    return x, y, k


@pytest.mark.parametrize("drift", [False, True])
def test_exponent_interval_covers_the_true_exponent_of_staircases(drift):
    rng = np.random.default_rng(20031 + drift)
    trials, covered, bootstrap_covered = 200, 0, 0
    for _ in range(trials):
        x, y, k = staircase(rng, drift)
        iv = exponent_interval(x, y, n_boot=200)
        covered += iv.low <= k <= iv.high
        bootstrap_covered += iv.fit.low <= k <= iv.fit.high
        assert iv.low <= min(iv.fit.low, iv.exponent) and iv.high >= max(iv.fit.high,
                                                                          iv.exponent)
    assert covered >= 0.9 * trials
    # The bootstrap alone is the dishonest interval this one replaces.
    assert bootstrap_covered < covered


def test_octave_windows_hold_whole_octaves_and_see_a_drift():
    x = np.logspace(0, 3, 31)           # 10 points per decade, 9.97 octaves
    w = octave_window_slopes(x, x ** 2, 3)
    assert w.slope == pytest.approx(np.full(w.slope.size, 2.0))
    assert w.width == pytest.approx(3 * np.log10(2))
    # Every window holds the points of [x_s, 8 x_s): 10 log10(8) = 9.03, so 9 or 10 points.
    assert set(w.n.tolist()) <= {9, 10} and w.n.size == 31 - 9 - 1
    # A correction that fades makes the exponents drift towards the asymptotic 1.
    iv = exponent_interval(x, x * (1 + 3 / x), n_boot=200)
    assert iv.windows.slope[0] < iv.windows.slope[-1] < 1
    assert iv.drift > 0 and iv.low <= 1 <= iv.high
    assert iv.high >= iv.upper + 2 * iv.drift
    with pytest.raises(ValueError, match="octaves"):
        octave_window_slopes(x, x, 0)
