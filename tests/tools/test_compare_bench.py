"""Tests of tools/compare_bench.py, hrbench-compare and hrbench_analysis.benchcompare on
synthetic runs."""

import math
import os

import pytest

import compare_bench
from conftest import DATA
from hrbench_analysis.benchcompare import (
    get_comparison_report,
    get_timing_comparison,
    min_pvalue,
)
from hrbench_analysis.gbench import InputError, get_repetition_times, load_benchmark_file

HEADLINE = "BM_Headline/garmann_count/threads:1/real_time"
SWEEP = "BM_EpsSweep/garmann_count/inv_eps:64/real_time"
TRANSLATION = "BM_TranslationEpsSweep/inv_eps:1024"


def data(name):
    return os.path.join(DATA, name)


class TestTimingComparison:
    def test_clear_slowdown_is_flagged(self):
        r = get_timing_comparison([100, 101, 99, 100.5, 102], [120, 119, 121, 122, 118])
        assert r.slower
        assert r.change == pytest.approx(120 / 100.5 - 1)
        assert r.pvalue == pytest.approx(1 / 252)  # every new time above every old one
        assert (r.n_baseline, r.n_new) == (5, 5)

    def test_significant_slowdown_under_the_threshold_is_not_flagged(self):
        r = get_timing_comparison([100, 100.5, 99.5, 100, 100.2], [103, 103.2, 102.8, 103, 103.1])
        assert r.pvalue <= 0.05
        assert not r.slower

    def test_large_but_noisy_change_is_not_flagged(self):
        r = get_timing_comparison([100, 150, 90, 160, 95], [110, 100, 170, 92, 155])
        assert r.change > 0.05
        assert r.pvalue > 0.05
        assert not r.slower

    def test_speedup_is_not_flagged(self):
        r = get_timing_comparison([100, 101, 99], [80, 81, 79])
        assert r.change == pytest.approx(-0.20)
        assert not r.slower

    def test_single_repetitions_give_no_p_value(self):
        r = get_timing_comparison([100], [200])
        assert math.isnan(r.pvalue)
        assert not r.slower

    def test_threshold_and_alpha_are_honoured(self):
        base, new = [100, 101, 99, 100, 102], [120, 119, 121, 122, 118]
        assert not get_timing_comparison(base, new, threshold=0.25).slower
        assert not get_timing_comparison(base, new, alpha=0.001).slower

    @pytest.mark.parametrize("kwargs, message", [
        ({"baseline": []}, "`baseline`"),
        ({"new": [1, float("nan")]}, "`new`"),
        ({"threshold": -0.1}, "`threshold`"),
        ({"alpha": 1.5}, "`alpha`"),
    ])
    def test_invalid_input_names_the_argument(self, kwargs, message):
        args = {"baseline": [1, 2], "new": [1, 2], "threshold": 0.05, "alpha": 0.05, **kwargs}
        with pytest.raises(ValueError, match=message):
            get_timing_comparison(**args)

    def test_smallest_p_value_of_the_exact_test(self):
        assert min_pvalue(3, 3) == pytest.approx(0.05)
        assert min_pvalue(5, 5) == pytest.approx(1 / 252)
        assert min_pvalue(2, 2) > 0.05


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


class TestCommandLine:
    def test_unchanged_run_passes(self, capsys):
        assert compare_bench.main([data("base.json"), data("same.json")]) == 0
        out = capsys.readouterr().out
        assert "0 of 3 benchmarks significantly slower" in out

    def test_slowdown_fails_and_names_the_benchmark(self, capsys):
        assert compare_bench.main([data("base.json"), data("slower.json")]) == 1
        lines = capsys.readouterr().out.splitlines()
        verdicts = {line.split()[0]: line.split()[-1] for line in lines if line.startswith("BM_")}
        assert verdicts == {HEADLINE: "SLOWER", SWEEP: "same", TRANSLATION: "faster"}
        change = next(line for line in lines if line.startswith(HEADLINE)).split()[5]
        assert 15 < float(change.rstrip("%")) < 25  # the file is 20% slower, 1% noise

    def test_a_looser_threshold_passes_the_same_files(self):
        assert compare_bench.main([data("base.json"), data("slower.json"),
                                   "--threshold", "0.25"]) == 0

    def test_too_few_repetitions_pass_with_a_note(self, capsys):
        assert compare_bench.main([data("two_reps_base.json"), data("two_reps.json")]) == 0
        assert "too few repetitions" in capsys.readouterr().out

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
    def test_usage_errors_exit_2(self, extra):
        with pytest.raises(SystemExit) as e:
            compare_bench.main([data("base.json"), data("same.json"), *extra])
        assert e.value.code == 2


class TestPackagedCommands:
    def test_hrbench_compare_is_the_same_command(self, capsys):
        from hrbench_analysis import benchcompare
        assert benchcompare.main([data("base.json"), data("slower.json")]) == 1
        assert "1 of 3 benchmarks significantly slower" in capsys.readouterr().out
        assert benchcompare.main([data("base.json"), data("missing.json")]) == 2
        assert capsys.readouterr().err.startswith("hrbench-compare: error: cannot read")

    def test_merge_bench_concatenates_the_suites(self, tmp_path, capsys):
        import merge_bench
        out = tmp_path / "merged.json"
        assert merge_bench.main([str(out), data("base.json"), data("two_reps.json")]) == 0
        merged = load_benchmark_file(out)
        base, two = (load_benchmark_file(data(n)) for n in ("base.json", "two_reps.json"))
        assert merged["benchmarks"] == base["benchmarks"] + two["benchmarks"]
        assert len(merged["context"]["executables"]) == 2
        assert merge_bench.main([str(out), data("missing.json")]) == 2
        assert "merge_bench.py: error: cannot read" in capsys.readouterr().err
