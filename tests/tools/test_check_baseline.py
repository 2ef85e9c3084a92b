"""Tests of tools/check_baseline.py (hrbench_analysis.bench.check_baseline) and
hrbench_analysis.bench.baseline, with a fake engine."""

import json
import os

import pytest

from conftest import DATA
from hrbench_analysis.bench import check_baseline
from hrbench_analysis.bench.baseline import (
    CounterChange,
    RunError,
    get_counter_changes,
    get_counter_coverage,
    run_counts,
)

COUNTS = {"nodes": 30, "leaves": 16, "links": 80, "oracle_calls": 159, "max_depth": 3,
          "forced_links": 0, "culled_pairs": 0, "root_pairs": 1,
          "nodes_per_depth": [2, 4, 8], "links_per_depth": [0, 0, 80]}


@pytest.fixture
def baseline(tmp_path, engine):
    """A baseline written by --update from the fake engine, with two runs."""
    path = tmp_path / "counts.json"
    path.write_text(json.dumps({"schema_version": 1, "runs": [
        {"args": ["parallel", "l=64", "d=1", "--eps", "0.25"]},
        {"args": ["room", "--min-area", "0.01", "--eps", "0.1"]},
    ]}))
    assert check_baseline.main(["--hrbench", engine, "--baseline", str(path), "--update"]) == 0
    return str(path)


def check(engine, baseline, monkeypatch=None, **env):
    for key, value in env.items():
        monkeypatch.setenv(key, value)
    return check_baseline.main(["--hrbench", engine, "--baseline", baseline, "--jobs", "1"])


class TestCounterChanges:
    def test_equal_counts_have_no_changes(self):
        assert get_counter_changes(COUNTS, dict(COUNTS)) == []

    def test_changed_scalars_and_histogram_entries(self):
        now = dict(COUNTS, links=88, oracle_calls=175, links_per_depth=[0, 0, 80, 8])
        changes = get_counter_changes(COUNTS, now)
        assert [c.counter for c in changes] == ["links", "oracle_calls", "links_per_depth[3]"]
        assert changes[0].change == 8 and changes[0].relative == pytest.approx(0.1)
        assert (changes[2].baseline, changes[2].current) == (0, 8)  # missing entries are 0

    def test_counters_missing_from_the_baseline_are_not_compared(self):
        assert get_counter_changes({"links": 80}, dict(COUNTS, nodes=1)) == []

    def test_only_the_given_counters_are_compared(self):
        now = dict(COUNTS, links=1, nodes_per_depth=[2])
        assert get_counter_changes(COUNTS, now, counters={"nodes", "leaves"}) == []
        assert [c.counter for c in get_counter_changes(COUNTS, now, counters={"links"})] == [
            "links"]

    def test_counter_that_became_a_scalar_is_shown_whole(self):
        (change,) = get_counter_changes(COUNTS, dict(COUNTS, nodes_per_depth=14))
        assert (change.counter, change.baseline, change.current) == (
            "nodes_per_depth", [2, 4, 8], 14)

    def test_change_of_a_missing_counter_is_undefined(self):
        c = CounterChange("links", 80, None)
        assert c.change is None and c.relative is None


class TestCounterCoverage:
    def test_new_and_missing_counters(self):
        entries = [{"args": ["a"], "counts": {"nodes": 1, "links": 2, "old": 3}},
                   {"args": ["b"], "counts": {"nodes": 1, "links": 2}},
                   {"args": ["c"]}]
        coverage = get_counter_coverage(entries, ["links", "nodes", "rays"])
        assert coverage.compared == ("links", "nodes")
        assert coverage.not_in_baseline == ("rays",)
        assert coverage.not_listed == ("old",) and not coverage.ok

    def test_same_counters(self):
        coverage = get_counter_coverage([{"args": [], "counts": COUNTS}], list(COUNTS))
        assert coverage.ok and coverage.compared == tuple(COUNTS)
        assert coverage.not_in_baseline == () and coverage.not_listed == ()

    def test_run_counts_reads_the_listed_counters(self, engine):
        counts, version = run_counts(engine, ["parallel", "--eps", "0.25"], ["links"])
        assert counts == {"links": 40} and version == "0.0-test"
        with pytest.raises(RunError, match="the record lacks counter.s. rays that the engine "
                                           "lists"):
            run_counts(engine, ["parallel", "--eps", "0.25"], ["links", "rays"])

    def test_update_records_every_counter(self, baseline):
        data = json.load(open(baseline))
        assert data["schema_version"] == 1 and data["engine_version"] == "0.0-test"
        assert len(data["runs"]) == 2
        assert data["runs"][0]["counts"]["links"] == 40  # the fake engine's count at eps 0.25
        assert set(data["runs"][0]["counts"]) == set(COUNTS)

    def test_unchanged_engine_passes(self, engine, baseline, capsys):
        assert check(engine, baseline) == 0
        assert "all 2 runs match" in capsys.readouterr().out

    def test_changed_counter_fails_with_a_readable_diff(self, engine, baseline, monkeypatch,
                                                        capsys):
        assert check(engine, baseline, monkeypatch, FAKE_HRBENCH_SHIFT="links=8",
                     FAKE_HRBENCH_MATCH="room") == 1
        out = capsys.readouterr().out
        assert "CHANGED  hrbench run room --min-area 0.01 --eps 0.1 --json --count-only" in out
        assert "parallel" not in out  # only the run that changed
        line = next(line for line in out.splitlines() if line.strip().startswith("links"))
        assert line.split()[:3] == ["links", "80", "88"]
        assert "+8 (+10.000%)" in line
        assert "1 of 2 runs differ" in out

    def test_changed_histogram_entry_is_shown_by_depth(self, engine, baseline, monkeypatch,
                                                       capsys):
        assert check(engine, baseline, monkeypatch, FAKE_HRBENCH_SHIFT="nodes_per_depth.4=16") == 1
        assert "nodes_per_depth[4]: 0 -> 16  +16" in capsys.readouterr().out

    def test_failing_run_is_reported_with_the_engine_error(self, engine, baseline, monkeypatch,
                                                           capsys):
        assert check(engine, baseline, monkeypatch, FAKE_HRBENCH_FAIL="1") == 1
        assert "error: exit code 2: hrbench: error: scene parallel" in capsys.readouterr().out

    def test_update_then_check_accepts_an_intended_change(self, engine, baseline, monkeypatch):
        monkeypatch.setenv("FAKE_HRBENCH_SHIFT", "links=8")
        assert check(engine, baseline) == 1
        assert check_baseline.main(["--hrbench", engine, "--baseline", baseline, "--update"]) == 0
        assert check(engine, baseline) == 0

    def test_run_without_recorded_counts_fails(self, engine, baseline, capsys):
        data = json.load(open(baseline))
        data["runs"].append({"args": ["perpendicular", "--eps", "0.1"]})
        json.dump(data, open(baseline, "w"))
        assert check(engine, baseline) == 1
        assert "no baseline counts recorded" in capsys.readouterr().out

    def test_update_creates_a_missing_file_with_the_default_runs(self, engine, tmp_path):
        path = tmp_path / "new" / "counts.json"
        assert check_baseline.main(["--hrbench", engine, "--baseline", str(path), "--update"]) == 0
        runs = json.load(open(path))["runs"]
        assert len(runs) > 20
        assert {"garmann", "hanrahan"} <= {r["args"][r["args"].index("--oracle") + 1]
                                           for r in runs if "--oracle" in r["args"]}

    def test_missing_engine_is_an_input_error(self, baseline, tmp_path, capsys):
        assert check(str(tmp_path / "nowhere"), baseline) == 2
        assert "not found" in capsys.readouterr().err

    @pytest.mark.parametrize("content", ["{", '{"schema_version": 2, "runs": []}',
                                         '{"schema_version": 1, "runs": [{"no": 1}]}'])
    def test_malformed_baseline_is_an_input_error(self, engine, tmp_path, content, capsys):
        path = tmp_path / "bad.json"
        path.write_text(content)
        assert check(engine, str(path)) == 2
        assert "error:" in capsys.readouterr().err


class TestEngineCounters:
    """The counters come from `hrbench capabilities --json`, not from a list in the tool."""

    def test_new_counter_is_mentioned_once_and_does_not_fail(self, engine, baseline,
                                                             monkeypatch, capsys):
        assert check(engine, baseline, monkeypatch, FAKE_HRBENCH_NEW_COUNTER="rays") == 0
        out = capsys.readouterr().out
        assert out.count("not in baseline") == 1
        assert "not in baseline: rays (listed by the engine, not compared" in out
        assert "all 2 runs match" in out

    def test_update_records_a_new_counter(self, engine, baseline, monkeypatch):
        monkeypatch.setenv("FAKE_HRBENCH_NEW_COUNTER", "rays")
        assert check_baseline.main(["--hrbench", engine, "--baseline", baseline,
                                    "--update"]) == 0
        assert json.load(open(baseline))["runs"][0]["counts"]["rays"] == 7

    @pytest.mark.parametrize("name", ["culled_pairs", "links_per_depth"])
    def test_counter_the_engine_no_longer_lists_fails(self, engine, baseline, monkeypatch,
                                                      capsys, name):
        assert check(engine, baseline, monkeypatch, FAKE_HRBENCH_DROP_COUNTER=name) == 1
        out = capsys.readouterr().out
        assert f"MISSING  counter(s) {name} of " in out and "no longer listed" in out
        assert "CHANGED" not in out  # the other counters still match
        assert "1 counter(s) of" in out and "all 2 runs match" not in out

    def test_engine_without_capabilities_is_an_input_error(self, engine, baseline, monkeypatch,
                                                           capsys, tmp_path):
        log = tmp_path / "runs.log"
        assert check(engine, baseline, monkeypatch, FAKE_HRBENCH_CAPABILITIES="missing",
                     FAKE_HRBENCH_LOG=str(log)) == 2
        (line,) = capsys.readouterr().err.strip().splitlines()
        assert line.startswith(f"check_baseline.py: error: engine {engine} has no usable "
                               "'capabilities --json' command (exit code 2")
        assert not log.exists()  # no run started

    def test_shipped_baseline_counters_are_compared_by_their_own_names(self):
        # tests/baseline/counts.json holds the same counters in every run; the check
        # compares exactly those (whatever else the engine lists).
        path = os.path.join(os.path.dirname(DATA), "..", "baseline", "counts.json")
        runs = json.load(open(path))["runs"]
        names = set(runs[0]["counts"])
        assert all(set(r["counts"]) == names for r in runs)
        coverage = get_counter_coverage(runs, [*sorted(names), "some_new_counter"])
        assert set(coverage.compared) == names and coverage.ok
        assert coverage.not_in_baseline == ("some_new_counter",)
