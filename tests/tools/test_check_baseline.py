"""Tests of tools/check_baseline.py and benchtools.baseline, with a fake engine."""

import json
import os
import stat
import sys

import pytest

import check_baseline
from benchtools.baseline import CounterChange, get_counter_changes
from conftest import DATA

COUNTS = {"nodes": 30, "leaves": 16, "links": 80, "oracle_calls": 159, "max_depth": 3,
          "forced_links": 0, "culled_pairs": 0, "root_pairs": 1,
          "nodes_per_depth": [2, 4, 8], "links_per_depth": [0, 0, 80]}


@pytest.fixture
def engine(tmp_path):
    """An executable that behaves like `hrbench run ... --json` (tests/tools/data)."""
    path = tmp_path / "hrbench"
    path.write_text(f'#!/bin/sh\nexec "{sys.executable}" "{os.path.join(DATA, "fake_hrbench.py")}" '
                    '"$@"\n')
    path.chmod(path.stat().st_mode | stat.S_IXUSR)
    return str(path)


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

    def test_change_of_a_missing_counter_is_undefined(self):
        c = CounterChange("links", 80, None)
        assert c.change is None and c.relative is None


class TestCommandLine:
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
