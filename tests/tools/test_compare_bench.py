"""Tests of tools/compare_bench.py, hrbench-compare and hrbench_analysis.bench.benchcompare on
synthetic runs."""

import json
import math
import os
import random

import numpy as np
import pytest

from conftest import DATA
from hrbench_analysis.bench import compare_bench
from hrbench_analysis.bench.benchcompare import (
    FASTER,
    INCONCLUSIVE,
    NO_CHANGE,
    REGRESSION,
    SLOWER,
    get_comparison_report,
    get_geomean,
    get_overall_verdict,
    get_timing_comparison,
    min_pvalue,
)
from hrbench_analysis.bench.gbench import InputError, get_repetition_times, load_benchmark_file

HEADLINE = "BM_Headline/garmann_count/threads:1/real_time"
SWEEP = "BM_EpsSweep/garmann_count/inv_eps:64/real_time"
TRANSLATION = "BM_TranslationEpsSweep/inv_eps:1024"


def data(name):
    return os.path.join(DATA, name)


def noisy(level, noise, n, seed):
    """_n_ times around _level_, each off by up to +-_noise_ (relative, uniform)."""
    rng = random.Random(seed)
    return [level * (1 + rng.uniform(-noise, noise)) for _ in range(n)]


class TestTimingComparison:
    def test_clear_slowdown_is_a_regression(self):
        r = get_timing_comparison([100, 101, 99, 100.5, 102], [120, 119, 121, 122, 118])
        assert r.verdict == REGRESSION and r.regression
        assert r.change == pytest.approx(120 / 100.5 - 1)
        assert r.pvalue == pytest.approx(2 / 252)  # two-sided: every new time above
        assert (r.n_baseline, r.n_new) == (5, 5)
        assert r.ci_low > 1.05 and r.ci_low <= 1 + r.change <= r.ci_high

    def test_significant_slowdown_under_the_threshold_is_slower_not_a_regression(self):
        r = get_timing_comparison([100, 100.5, 99.5, 100, 100.2], [103, 103.2, 102.8, 103, 103.1])
        assert r.pvalue <= 0.05
        assert r.verdict == SLOWER and not r.regression

    def test_large_but_noisy_change_is_inconclusive(self):
        r = get_timing_comparison([100, 150, 90, 160, 95], [110, 100, 170, 92, 155])
        assert r.change > 0.05 and r.pvalue > 0.05
        assert r.noise > 0.05 and r.ci_high > 1.05
        assert r.verdict == INCONCLUSIVE and not r.regression

    def test_speedup_is_faster(self):
        r = get_timing_comparison([100, 101, 99, 100.5, 99.5], [80, 81, 79, 80.5, 79.5])
        assert r.change == pytest.approx(-0.20)
        assert r.verdict == FASTER

    def test_too_few_repetitions_are_inconclusive_however_large_the_change(self):
        for base, new in (([100], [200]), ([100, 101, 99], [200, 201, 199])):
            r = get_timing_comparison(base, new)
            assert r.verdict == INCONCLUSIVE
            assert (r.ci_low, r.ci_high, r.noise) == (0, math.inf, math.inf)

    def test_threshold_and_alpha_are_honoured(self):
        base, new = [100, 101, 99, 100.5, 102], [120, 119, 121, 122, 118]
        assert get_timing_comparison(base, new, threshold=0.25).verdict == SLOWER
        # 5 a side cannot reach alpha 0.001 (smallest p 2/252): blind, not a pass.
        assert get_timing_comparison(base, new, alpha=0.001).verdict == INCONCLUSIVE

    @pytest.mark.parametrize("kwargs, message", [
        ({"baseline": []}, "`baseline`"),
        ({"new": [1, float("nan")]}, "`new`"),
        ({"new": [1, 0]}, "`new`"),
        ({"threshold": -0.1}, "`threshold`"),
        ({"alpha": 1.5}, "`alpha`"),
        ({"new": [1, 2, 3], "paired": True}, "one time per round"),
    ])
    def test_invalid_input_names_the_argument(self, kwargs, message):
        args = {"baseline": [1, 2], "new": [1, 2], "threshold": 0.05, "alpha": 0.05, **kwargs}
        with pytest.raises(ValueError, match=message):
            get_timing_comparison(**args)

    def test_smallest_p_value_of_the_exact_test(self):
        assert min_pvalue(3, 3) == pytest.approx(0.1)
        assert min_pvalue(5, 5) == pytest.approx(2 / 252)
        assert min_pvalue(2, 2) > 0.05
        assert min_pvalue(5, 5, paired=True) == pytest.approx(1 / 16)
        assert min_pvalue(10, 10, paired=True) == pytest.approx(2 / 1024)


class TestNoiseSignificanceAndGeomean:
    """The verdicts the CI gate rests on, both for independent repetitions (U test) and
    for paired rounds (signed-rank test)."""

    @pytest.mark.parametrize("paired", [False, True])
    @pytest.mark.parametrize("seed", range(5))
    def test_thirty_percent_noise_against_ten_percent_is_inconclusive(self, paired, seed):
        base, new = noisy(10e6, 0.3, 10, seed), noisy(10e6, 0.3, 10, seed + 100)
        r = get_timing_comparison(base, new, threshold=0.10, paired=paired)
        assert r.noise > 0.10
        # Resolved only where the interval itself rules out a slowdown beyond 10%.
        assert r.verdict == INCONCLUSIVE or (r.ci_high <= 1.10 and not r.regression)
        if r.ci_high > 1.10:
            assert r.verdict == INCONCLUSIVE

    @pytest.mark.parametrize("paired", [False, True])
    def test_symmetric_thirty_percent_noise_is_inconclusive(self, paired):
        # The same ten times in another order: no change at all, but 30% noise.
        base = noisy(10e6, 0.3, 10, 1)
        new = base[3:] + base[:3]
        r = get_timing_comparison(base, new, threshold=0.10, paired=paired)
        assert r.verdict == INCONCLUSIVE
        assert r.ci_low < 0.9 and r.ci_high > 1.1

    @pytest.mark.parametrize("paired", [False, True])
    def test_a_2x_slowdown_with_little_noise_is_slower_with_p_below_alpha(self, paired):
        base, new = noisy(10e6, 0.01, 10, 3), noisy(20e6, 0.01, 10, 4)
        r = get_timing_comparison(base, new, threshold=0.10, alpha=0.05, paired=paired)
        assert r.verdict == REGRESSION
        assert r.pvalue < 0.05
        # Every new time above every baseline one (U = 100), every round slower (the
        # signed-rank statistic min(R+, R-) = 0, exact p = 2 / 2**10).
        assert r.statistic == (0 if paired else 100)
        if paired:
            assert r.pvalue == pytest.approx(min_pvalue(10, 10, paired=True))
        assert r.change == pytest.approx(1.0, abs=0.03)
        assert 1.9 < r.ci_low <= r.ci_high < 2.1 and r.noise < 0.02

    @pytest.mark.parametrize("paired", [False, True])
    def test_equal_samples_are_no_significant_change(self, paired):
        times = noisy(10e6, 0.01, 10, 5)
        r = get_timing_comparison(times, list(times), threshold=0.10, paired=paired)
        assert r.verdict == NO_CHANGE
        assert r.change == 0 and r.pvalue == 1
        assert r.ci_low <= 1 <= r.ci_high

    @pytest.mark.parametrize("paired", [False, True])
    def test_the_interval_excludes_1_exactly_when_significant(self, paired):
        rng = np.random.default_rng(11)
        for _ in range(30):
            n = int(rng.integers(6, 15))
            base = np.exp(rng.normal(0, 0.05, n))
            new = np.exp(rng.normal(rng.normal(0, 0.05), 0.05, n))
            r = get_timing_comparison(base, new, alpha=0.05, paired=paired)
            assert (r.pvalue <= 0.05) == (not r.ci_low <= 1 <= r.ci_high), r

    def test_geomean_is_the_geometric_mean_of_the_ratios(self):
        base = {"a": [100.0] * 6, "b": [400.0] * 6}
        new = {"a": [200.0] * 6, "b": [200.0] * 6}  # x2 and x0.5
        comparisons, _, _ = get_comparison_report(base, new)
        g_base, g_new, change = get_geomean(comparisons)
        assert g_base == pytest.approx(200.0) and g_new == pytest.approx(200.0)
        assert change == pytest.approx(0.0, abs=1e-12)
        new["b"] = [800.0] * 6                   # x2 and x2
        comparisons, _, _ = get_comparison_report(base, new)
        assert get_geomean(comparisons)[2] == pytest.approx(1.0)

    def test_overall_verdict(self):
        def c(base, new):
            return get_timing_comparison(base, new, threshold=0.10, paired=True)
        same = c([100] * 6, [100] * 6)
        blind = c([100] * 5, [100] * 5)
        slower = c([100] * 6, [150] * 6)
        assert get_overall_verdict([same]) == "PASS"
        assert get_overall_verdict([same, blind]) == "INCONCLUSIVE"
        assert get_overall_verdict([blind, slower]) == "FAIL"


class TestReadingGoogleBenchmarkJson:
    def test_repetition_rows_in_nanoseconds_aggregates_skipped(self):
        times = get_repetition_times(load_benchmark_file(data("base.json")))
        assert set(times) == {HEADLINE, SWEEP, TRANSLATION}  # no _mean, _median, BigO
        assert len(times[HEADLINE]) == 5
        assert all(6.2e8 < t < 6.4e8 for t in times[HEADLINE])  # 630 ms in ns
        assert all(7.2e3 < t < 7.4e3 for t in times[TRANSLATION])  # 7.3 us in ns

    def test_cpu_time_can_be_chosen(self):
        f = load_benchmark_file(data("base.json"))
        real = get_repetition_times(f, "real_time")[HEADLINE]
        cpu = get_repetition_times(f, "cpu_time")[HEADLINE]
        assert cpu == pytest.approx([0.98 * t for t in real])

    @pytest.mark.parametrize("name, message", [
        ("missing.json", "cannot read"),
        ("truncated.json", "not valid JSON"),
        ("not_gbench.json", "no 'benchmarks' list"),
        ("future_schema.json", "json_schema_version 99"),
    ])
    def test_bad_files_are_input_errors(self, name, message):
        with pytest.raises(InputError, match=message):
            load_benchmark_file(data(name))

    def test_report_lists_benchmarks_of_one_run_only(self):
        base = get_repetition_times(load_benchmark_file(data("base.json")))
        two = get_repetition_times(load_benchmark_file(data("two_reps.json")))
        comparisons, only_base, only_new = get_comparison_report(base, two)
        assert [c.name for c in comparisons] == [HEADLINE, SWEEP]
        assert only_base == [TRANSLATION] and only_new == []


def write_bench(path, times):
    """A Google Benchmark file with these repetition times (ns) per benchmark."""
    rows = [{"name": name, "run_name": name, "run_type": "iteration", "repetitions": len(ts),
             "repetition_index": k, "iterations": 1, "real_time": t, "cpu_time": t,
             "time_unit": "ns"} for name, ts in times.items() for k, t in enumerate(ts)]
    path.write_text(json.dumps({"context": {}, "benchmarks": rows}))
    return str(path)


class TestCommandLine:
    def test_unchanged_run_passes(self, capsys):
        assert compare_bench.main([data("base.json"), data("same.json")]) == 0
        out = capsys.readouterr().out
        assert "0 of 3 benchmarks significantly slower by more than 5%, 0 inconclusive" in out
        assert out.rstrip().endswith("PASS")

    def test_slowdown_fails_and_names_the_benchmark(self, capsys):
        assert compare_bench.main([data("base.json"), data("slower.json")]) == 1
        lines = capsys.readouterr().out.splitlines()
        verdicts = {line.split()[0]: line.split("  ")[-1].strip() for line in lines
                    if line.startswith("BM_")}
        # +3.4% is significant but within 5%: slower, not a regression.
        assert verdicts == {HEADLINE: "SLOWER", SWEEP: "slower", TRANSLATION: "faster"}
        change = next(line for line in lines if line.startswith(HEADLINE)).split()[5]
        assert 15 < float(change.rstrip("%")) < 25  # the file is 20% slower, 1% noise

    def test_geomean_line(self, capsys):
        assert compare_bench.main([data("base.json"), data("slower.json")]) == 1
        out = capsys.readouterr().out
        line = next(x for x in out.splitlines() if x.startswith("OVERALL_GEOMEAN"))
        base = get_repetition_times(load_benchmark_file(data("base.json")))
        new = get_repetition_times(load_benchmark_file(data("slower.json")))
        ratios = [np.median(new[k]) / np.median(base[k]) for k in base]
        expected = math.prod(ratios) ** (1 / 3) - 1
        assert line.split()[-1] == f"{expected:+.1%}"

    def test_a_looser_threshold_passes_the_same_files(self):
        assert compare_bench.main([data("base.json"), data("slower.json"),
                                   "--threshold", "0.25"]) == 0

    def test_too_few_repetitions_are_inconclusive_exit_3(self, capsys):
        assert compare_bench.main([data("two_reps_base.json"), data("two_reps.json")]) == 3
        out = capsys.readouterr().out
        assert "too few repetitions" in out and out.rstrip().endswith("INCONCLUSIVE")

    def test_noisy_runs_are_inconclusive_exit_3(self, tmp_path, capsys):
        base = write_bench(tmp_path / "b.json", {"BM_K": noisy(1e6, 0.3, 10, 1)})
        new = write_bench(tmp_path / "n.json", {"BM_K": noisy(1e6, 0.3, 10, 2)})
        assert compare_bench.main([base, new, "--threshold", "0.1"]) == 3
        assert "BM_K" in capsys.readouterr().out

    def test_paired_rounds(self, tmp_path, capsys):
        # Load drifts from round to round, the same for both builds: paired, the 5%
        # slowdown stands out; unpaired, the drift hides it.
        drift = [1.0, 1.3, 0.8, 1.2, 0.9, 1.1, 1.25, 0.85]
        base = write_bench(tmp_path / "b.json", {"BM_K": [1e6 * d for d in drift]})
        new = write_bench(tmp_path / "n.json", {"BM_K": [1.05e6 * d for d in drift]})
        assert compare_bench.main([base, new, "--paired", "--threshold", "0.02"]) == 1
        assert "Wilcoxon signed-rank of paired rounds" in capsys.readouterr().out
        assert compare_bench.main([base, new, "--threshold", "0.02"]) == 3
        short = write_bench(tmp_path / "s.json", {"BM_K": [1e6] * 7})
        assert compare_bench.main([base, short, "--paired"]) == 2
        assert "one time per round" in capsys.readouterr().err

    @pytest.mark.parametrize("files", [
        ["missing.json", "base.json"],
        ["base.json", "truncated.json"],
        ["base.json", "aggregates_only.json"],
        ["base.json", "other_names.json"],
        ["future_schema.json", "base.json"],
    ])
    def test_input_errors_exit_2(self, files, capsys):
        assert compare_bench.main([data(f) for f in files]) == 2
        assert "error:" in capsys.readouterr().err

    @pytest.mark.parametrize("extra", [["--threshold", "-1"], ["--alpha", "0"], ["--bogus"]])
    def test_usage_errors_exit_2(self, extra, capsys):
        assert compare_bench.main([data("base.json"), data("same.json"), *extra]) == 2
        assert "Traceback" not in capsys.readouterr().err


class TestPackagedCommands:
    def test_hrbench_compare_is_the_same_command(self, capsys):
        from hrbench_analysis.bench import benchcompare
        assert benchcompare.main([data("base.json"), data("slower.json")]) == 1
        assert "1 of 3 benchmarks significantly slower" in capsys.readouterr().out
        assert benchcompare.main([data("base.json"), data("missing.json")]) == 2
        assert capsys.readouterr().err.startswith(
            f"hrbench-compare: error: {data('missing.json')}: cannot read the benchmark file")

    def test_merge_bench_concatenates_the_suites(self, tmp_path, capsys):
        from hrbench_analysis.bench import merge_bench
        out = tmp_path / "merged.json"
        assert merge_bench.main([str(out), data("base.json"), data("two_reps.json")]) == 0
        merged = load_benchmark_file(out)
        base, two = (load_benchmark_file(data(n)) for n in ("base.json", "two_reps.json"))
        assert merged["benchmarks"] == base["benchmarks"] + two["benchmarks"]
        assert len(merged["context"]["executables"]) == 2
        assert merge_bench.main([str(out), data("missing.json")]) == 2
        assert "merge_bench.py: error: " in capsys.readouterr().err
