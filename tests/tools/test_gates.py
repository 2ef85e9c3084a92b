"""Tests of scripts/ci/gates (the CI gates of action.yml) on fake prebuilt builds.

A fake build is a directory with two executables: `hrbench`, the stand-in engine of
tests/tools/data/fake_hrbench.py (counters can be shifted), and `refine_bench`, a small
sh stand-in written below that writes Google Benchmark JSON with controlled times (a
factor per build, +-2% deterministic noise unless told) and logs each run. The refs are commits
of a throwaway git repository holding tests/baseline/counts.json. Nothing is compiled.
"""

import contextlib
import io
import json
import os
import random
import re
import shutil
import stat
import subprocess
import sys

import pytest

from conftest import DATA, GATES, ROOT, load_gates

SHIM = os.path.join(ROOT, "scripts", "ci", "gates")

BENCHMARKS = {  # name: CPU time in ns
    "BM_EpsSweep/garmann_count/inv_eps:64/real_time": 10.0e6,
    "BM_EpsSweep/garmann_store/inv_eps:64/real_time": 30.0e6,
    "BM_EpsSweep/hanrahan_count/inv_eps:256/real_time": 4.6e6,
    "BM_GeometrySweep/garmann_count/g:256/real_time": 9.0e6,
    "BM_GeometrySweep/hanrahan_store/g:16/real_time": 60.0e6,
}
MAX_ROUNDS = 12

# The stand-in refine_bench, in sh so that a round costs no Python start: it lists the
# benchmarks its filter matches (grep -E), or logs its build's name and copies the
# Google Benchmark JSON prepared for its output file (base-001.json, head-001.json, ...).
FAKE_REFINE_BENCH = """#!/bin/sh
dir="$(dirname "$0")"; filter=.; out=; list=
for a in "$@"; do
  case "$a" in
    --benchmark_filter=*) filter="${a#*=}" ;;
    --benchmark_out=*) out="${a#*=}" ;;
    --benchmark_list_tests=true) list=1 ;;
  esac
done
if [ -n "$list" ]; then grep -E -- "$filter" "$dir/names.txt"; exit 0; fi
if [ -f "$dir/crash" ]; then echo "fake refine_bench: crashed" >&2; exit 3; fi
cat "$dir/name" >> "$dir/../bench.log"
cp "$dir/runs/$(basename "$out")" "$out"
"""


def _fake_runs(directory, name, factor, noise):
    """The JSON of every run: times times _factor_, +-_noise_ (relative, uniform) fixed by
    build and file."""
    directory.mkdir()
    for side in ("base", "head"):
        for r in range(1, MAX_ROUNDS + 1):
            rng = random.Random(f"{name}-{side}-{r}")
            rows = []
            for bench, ns in BENCHMARKS.items():
                t = ns * factor * (1 + rng.uniform(-noise, noise))
                rows.append({"name": bench, "run_name": bench, "run_type": "iteration",
                             "repetitions": 1, "repetition_index": 0, "threads": 1,
                             "iterations": 10, "real_time": 2 * t, "cpu_time": t,
                             "time_unit": "ns"})
            (directory / f"{side}-{r:03d}.json").write_text(json.dumps({
                "context": {"executable": "refine_bench", "num_cpus": 2,
                            "library_build_type": "release"}, "benchmarks": rows}))


RUNS = [{"args": ["parallel", "l=64", "d=1", "--eps", "0.25"]},
        {"args": ["room", "--min-area", "0.01", "--eps", "0.1"]}]


def _executable(path, text):
    path.write_text(text)
    path.chmod(path.stat().st_mode | stat.S_IXUSR)


def make_build(tmp_path, name, factor=1.0, shift=None, crash=False, noise=0.02):
    """A fake build directory: hrbench (counters shifted by _shift_, "links=8") and
    refine_bench (times multiplied by _factor_, +-_noise_ per run)."""
    build = tmp_path / f"build-{name}"
    build.mkdir()
    (build / "name").write_text(name + "\n")
    (build / "names.txt").write_text("\n".join(BENCHMARKS) + "\n")
    if crash:
        (build / "crash").write_text("")
    _fake_runs(build / "runs", name, factor, noise)
    # Each build's executables differ in content, as two real builds' do (the gates
    # compare builds by content); the fakes read their data beside them.
    _executable(build / "refine_bench", FAKE_REFINE_BENCH + f"# build {name}\n")
    env = f"FAKE_HRBENCH_SHIFT={shift} " if shift else ""
    _executable(build / "hrbench", f'#!/bin/sh\n# build {name}\n{env}exec "{sys.executable}" '
                f'"{os.path.join(DATA, "fake_hrbench.py")}" "$@"\n')
    return str(build)


def _git(repo, *args):
    subprocess.run(["git", "-C", str(repo), "-c", "user.name=t", "-c", "user.email=t@t",
                    *args], check=True, capture_output=True)


_BASELINES = {}


def write_baseline(tmp_path, repo, shift=None):
    """tests/baseline/counts.json in _repo_, from the fake engine (shifted or not); written
    once per shift by tools/check_baseline.py --update, then copied."""
    path = repo / "tests" / "baseline" / "counts.json"
    path.parent.mkdir(parents=True, exist_ok=True)
    if shift not in _BASELINES:
        path.write_text(json.dumps({"schema_version": 1, "runs": RUNS}))
        engine = make_build(tmp_path, f"writer-{shift or 'plain'}", shift=shift)
        subprocess.run([sys.executable, os.path.join(ROOT, "tools", "check_baseline.py"),
                        "--hrbench", os.path.join(engine, "hrbench"), "--baseline", str(path),
                        "--update"], check=True, capture_output=True)
        _BASELINES[shift] = path.read_text()
    path.write_text(_BASELINES[shift])


@pytest.fixture
def repo(tmp_path):
    """A git repository with two commits, base and head (a comment-only change)."""
    repo = tmp_path / "repo"
    repo.mkdir()
    _git(repo, "init", "-q", "-b", "main")
    write_baseline(tmp_path, repo)
    (repo / "notes.txt").write_text("base\n")
    _git(repo, "add", "-A")
    _git(repo, "commit", "-q", "-m", "base")
    _git(repo, "tag", "base")
    (repo / "notes.txt").write_text("base\n# a comment\n")
    _git(repo, "commit", "-q", "-am", "head")
    _git(repo, "tag", "head")
    return repo


class Result:
    def __init__(self, returncode, stdout, stderr):
        self.returncode, self.stdout, self.stderr = returncode, stdout, stderr


_GATES = []


def run_gates(tmp_path, repo, base_build, head_build, *extra, env=None, base="base",
              head="head", subprocess_run=False):
    """Run the gates on the fake builds: in this process (scipy is imported once), or as
    a command (_subprocess_run_). Returns (result, the summary file's text)."""
    summary = tmp_path / "summary.md"
    argv = [base, head, "--project", str(repo), "--base-build", base_build, "--head-build",
            head_build, "--workdir", str(tmp_path / "work"), "--rounds", "8", "--summary",
            str(summary), "--jobs", "1", *extra]
    full_env = {k: v for k, v in os.environ.items() if not k.startswith("GITHUB_")}
    full_env.update(env or {})
    if subprocess_run:
        proc = subprocess.run([sys.executable, GATES, *argv], capture_output=True, text=True,
                              env=full_env)
        result = Result(proc.returncode, proc.stdout, proc.stderr)
    else:
        if not _GATES:
            _GATES.append(load_gates())
        out, err, saved = io.StringIO(), io.StringIO(), dict(os.environ)
        os.environ.clear()
        os.environ.update(full_env)
        try:
            with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
                try:
                    rc = _GATES[0].main(argv)
                except SystemExit as e:
                    rc = e.code
        finally:
            os.environ.clear()
            os.environ.update(saved)
        result = Result(rc, out.getvalue(), err.getvalue())
    text = summary.read_text() if summary.exists() else ""
    return result, text


def benchmark_rows(summary):
    """The timing table's rows of benchmarks (not its header, not OVERALL_GEOMEAN)."""
    return [row for row in markdown_tables(summary)[-1][1:] if row[0] != "OVERALL_GEOMEAN"]


def markdown_tables(text):
    """The tables of a Markdown text, each a list of rows of cells; asserts their shape."""
    tables, block = [], []
    for line in text.splitlines() + [""]:
        if line.startswith("|"):
            block.append(line)
            continue
        if block:
            rows = [[c.strip() for c in re.split(r"(?<!\\)\|", row)[1:-1]] for row in block]
            assert len(rows) >= 2, block
            assert re.fullmatch(r"\|(\s*:?-+:?\s*\|)+", block[1]), block[1]
            assert all(len(r) == len(rows[0]) for r in rows), block
            tables.append([rows[0]] + rows[2:])
            block = []
    return tables


class TestGates:
    def test_unchanged_build_passes(self, tmp_path, repo):
        proc, summary = run_gates(tmp_path, repo, make_build(tmp_path, "base"),
                                  make_build(tmp_path, "head"))
        assert proc.returncode == 0, proc.stderr
        assert "## hrbench gates: PASS" in summary
        assert "| counts | PASS |" in summary and "| timing | PASS |" in summary
        assert "0 of 5 benchmarks significantly slower by more than 10%, 0 inconclusive" \
            in summary
        assert all(row[-1] == "no significant change" for row in benchmark_rows(summary))
        assert proc.stdout == summary  # printed as written
        assert "same commit" not in proc.stderr

    def test_thirty_percent_slower_fails_the_timing_gate(self, tmp_path, repo):
        proc, summary = run_gates(tmp_path, repo, make_build(tmp_path, "base"),
                                  make_build(tmp_path, "head", factor=1.3))
        assert proc.returncode == 1
        assert "## hrbench gates: FAIL" in summary
        assert "| counts | PASS |" in summary and "| timing | FAIL |" in summary
        timing = markdown_tables(summary)[1]
        assert timing[0][:4] == ["benchmark", "base", "head", "change"]
        rows = benchmark_rows(summary)
        assert len(rows) == 5 and all(row[-1] == "**SLOWER**" for row in rows)
        assert all(row[3].startswith("+") for row in rows)
        assert "5 of 5 benchmarks significantly slower" in summary

    def test_faster_head_passes(self, tmp_path, repo):
        proc, summary = run_gates(tmp_path, repo, make_build(tmp_path, "base"),
                                  make_build(tmp_path, "head", factor=0.7))
        assert proc.returncode == 0, proc.stderr
        assert all(row[-1] == "faster" for row in benchmark_rows(summary))

    def test_count_change_fails_with_the_counter_diff(self, tmp_path, repo):
        proc, summary = run_gates(tmp_path, repo, make_build(tmp_path, "base"),
                                  make_build(tmp_path, "head", shift="links=8"))
        assert proc.returncode == 1
        assert "| counts | FAIL |" in summary and "| timing | PASS |" in summary
        assert "CHANGED  hrbench run parallel l=64 d=1 --eps 0.25" in summary
        assert re.search(r"links\s+80\s+88\s+\+8 \(\+10\.000%\)", summary), summary
        assert "2 of 2 runs differ from tests/baseline/counts.json" in summary
        assert "CHANGED" in proc.stderr  # the check's own output, in the log

    def test_count_change_with_an_updated_baseline_passes_with_a_note(self, tmp_path, repo):
        write_baseline(tmp_path, repo, shift="links=8")
        _git(repo, "commit", "-q", "-am", "counts change on purpose")
        proc, summary = run_gates(tmp_path, repo, make_build(tmp_path, "base"),
                                  make_build(tmp_path, "head", shift="links=8"),
                                  head="main")
        assert proc.returncode == 0, proc.stderr + summary
        assert "| counts | PASS |" in summary and "baseline updated on purpose" in summary
        assert "HEAD updates tests/baseline/counts.json (on purpose)" in summary
        assert "changed  hrbench run parallel l=64 d=1 --eps 0.25" in summary
        assert "links: 80 -> 88  +8 (+10%)" in summary

    def test_updated_baseline_does_not_excuse_an_engine_that_differs_from_it(
            self, tmp_path, repo):
        write_baseline(tmp_path, repo, shift="links=8")
        _git(repo, "commit", "-q", "-am", "counts change on purpose")
        proc, summary = run_gates(tmp_path, repo, make_build(tmp_path, "base"),
                                  make_build(tmp_path, "head", shift="links=9"),
                                  "--skip-timing", head="main")
        assert proc.returncode == 1
        assert "| counts | FAIL |" in summary and "| timing | skipped |" in summary
        assert re.search(r"links\s+88\s+89\s+\+1", summary)

    def test_rounds_interleave_with_alternating_order(self, tmp_path, repo):
        proc, _ = run_gates(tmp_path, repo, make_build(tmp_path, "base"),
                            make_build(tmp_path, "head"), "--skip-counts")
        assert proc.returncode == 0, proc.stderr
        runs = (tmp_path / "bench.log").read_text().split()
        rounds = [tuple(runs[i:i + 2]) for i in range(0, len(runs), 2)]
        assert rounds == [("base", "head"), ("head", "base")] * 4
        gates = load_gates()
        assert [gates.round_order(r) for r in range(4)] == [
            ("base", "head"), ("head", "base"), ("base", "head"), ("head", "base")]

    def test_each_round_is_one_repetition_merged_per_build(self, tmp_path, repo):
        proc, summary = run_gates(tmp_path, repo, make_build(tmp_path, "base"),
                                  make_build(tmp_path, "head"), "--skip-counts", "--rounds", "7")
        assert proc.returncode == 0, proc.stderr
        assert all(row[7] == "7" for row in benchmark_rows(summary))
        results = next((tmp_path / "work" / "results").iterdir())
        merged = json.loads((results / "timing" / "head.json").read_text())
        assert len(merged["benchmarks"]) == 7 * 5

    def test_summary_is_markdown_with_the_tables(self, tmp_path, repo):
        step_summary, outputs = tmp_path / "step_summary.md", tmp_path / "outputs.txt"
        step_summary.write_text("earlier step\n")
        proc, summary = run_gates(tmp_path, repo, make_build(tmp_path, "base"),
                                  make_build(tmp_path, "head"),
                                  env={"GITHUB_STEP_SUMMARY": str(step_summary),
                                       "GITHUB_OUTPUT": str(outputs)})
        assert proc.returncode == 0, proc.stderr
        assert summary.startswith("## hrbench gates: PASS\n")
        assert summary.count("```") % 2 == 0
        gates_table, timing_table = markdown_tables(summary)
        assert [row[0] for row in gates_table] == ["gate", "counts", "timing"]
        assert timing_table[0] == ["benchmark", "base", "head", "change", "95% CI", "p",
                                   "noise", "rounds", "verdict"]
        assert timing_table[-1][0] == "OVERALL_GEOMEAN"
        for row in timing_table[1:-1]:
            assert re.fullmatch(r"`BM_\S+`", row[0])
            assert re.fullmatch(r"[+-]\d+\.\d%", row[3]) and 0 <= float(row[5]) <= 1
            low, high = re.fullmatch(r"\[([+-]\d+\.\d)%, ([+-]\d+\.\d)%\]", row[4]).groups()
            assert float(low) <= float(row[3][:-1]) <= float(high)
        for heading in ("### Counts", "### Timing", "### Machine"):
            assert heading in summary
        assert re.search(r"load average at start \d+\.\d\d, \d+\.\d\d, \d+\.\d\d", summary)
        assert step_summary.read_text() == "earlier step\n" + summary
        out = dict(line.split("=", 1) for line in outputs.read_text().splitlines())
        assert out["verdict"] == "pass" and open(out["summary"]).read() == summary

    def test_vendored_hrbench_in_a_subdirectory(self, tmp_path):
        """--project (the action's working-directory) inside a larger repository."""
        repo = tmp_path / "project"
        vendored = repo / "third_party" / "hrbench"
        vendored.mkdir(parents=True)
        _git(repo, "init", "-q", "-b", "main")
        write_baseline(tmp_path, vendored)
        _git(repo, "add", "-A")
        _git(repo, "commit", "-q", "-m", "vendor hrbench")
        proc, summary = run_gates(tmp_path, vendored, make_build(tmp_path, "base"),
                                  make_build(tmp_path, "head", shift="links=8"),
                                  "--skip-timing", base="main", head="main")
        assert proc.returncode == 1
        assert "2 of 2 runs differ from tests/baseline/counts.json" in summary

    def test_too_few_rounds_are_inconclusive_not_a_pass(self, tmp_path, repo):
        # 5 rounds: the signed-rank test cannot reach p <= 0.05 (2 / 2**5 = 0.0625), so a
        # 30% slowdown can be neither found nor ruled out.
        proc, summary = run_gates(tmp_path, repo, make_build(tmp_path, "base"),
                                  make_build(tmp_path, "head", factor=1.3), "--skip-counts",
                                  "--rounds", "5")
        assert proc.returncode == 3, proc.stderr
        assert summary.startswith("## hrbench gates: INCONCLUSIVE")
        assert "too few for the test to reach alpha" in summary
        assert all(row[-1] == "*inconclusive*" and row[6] == "inf"
                   for row in benchmark_rows(summary))

    def test_thirty_percent_noise_is_inconclusive_not_a_pass(self, tmp_path, repo):
        outputs = tmp_path / "outputs.txt"
        proc, summary = run_gates(tmp_path, repo, make_build(tmp_path, "base", noise=0.3),
                                  make_build(tmp_path, "head", noise=0.3), "--skip-counts",
                                  env={"GITHUB_OUTPUT": str(outputs)})
        assert proc.returncode == 3, proc.stderr
        assert summary.startswith("## hrbench gates: INCONCLUSIVE")
        assert "| timing | INCONCLUSIVE |" in summary
        assert "timing inconclusive" in proc.stderr and "exit code 3" in proc.stderr
        rows = benchmark_rows(summary)
        blind = [row for row in rows if row[-1] == "*inconclusive*"]
        assert blind and all(float(row[6].rstrip("%")) > 10 for row in blind)
        for row in rows:  # the others resolved: their interval stays under +10%
            high = float(row[4].split(", ")[1].rstrip("%]"))
            assert row in blind or high <= 10
        assert "verdict=inconclusive" in outputs.read_text()

    def test_a_2x_slowdown_with_little_noise_is_slower_with_p_below_alpha(self, tmp_path,
                                                                        repo):
        proc, summary = run_gates(tmp_path, repo, make_build(tmp_path, "base", noise=0.01),
                                  make_build(tmp_path, "head", factor=2.0, noise=0.01),
                                  "--skip-counts")
        assert proc.returncode == 1
        for row in benchmark_rows(summary):
            assert row[-1] == "**SLOWER**" and float(row[5]) < 0.05
            assert 95 < float(row[3].rstrip("%")) < 105
        geomean = markdown_tables(summary)[-1][-1]
        assert geomean[0] == "OVERALL_GEOMEAN" and 95 < float(geomean[3].rstrip("%")) < 105

    def test_equal_times_are_no_significant_change(self, tmp_path, repo):
        proc, summary = run_gates(tmp_path, repo, make_build(tmp_path, "base", noise=0),
                                  make_build(tmp_path, "head", noise=0), "--skip-counts")
        assert proc.returncode == 0, proc.stderr
        for row in benchmark_rows(summary):
            assert row[3:8] == ["+0.0%", "[+0.0%, +0.0%]", "1.0000", "0.0%", "8"]
            assert row[-1] == "no significant change"

    def test_base_equal_to_head_is_said_on_stderr_and_in_the_summary(self, tmp_path, repo):
        build = make_build(tmp_path, "base")
        proc, summary = run_gates(tmp_path, repo, build, build, "--skip-counts", head="base")
        assert proc.returncode == 0, proc.stderr
        warnings = [line for line in proc.stderr.splitlines() if "same commit" in line]
        assert warnings and warnings[0].startswith("gates: warning: BASE_REF base and "
                                                   "HEAD_REF base are the same commit")
        assert "nothing is compared with another version" in warnings[0]
        assert "**Same content.**" in summary

    def test_one_commit_built_twice_differently_is_compared(self, tmp_path, repo):
        """By content, not by name: `gates HEAD HEAD --base-build B --head-build H` with
        two different builds compares them, with no warning."""
        proc, summary = run_gates(tmp_path, repo, make_build(tmp_path, "base"),
                                  make_build(tmp_path, "head", factor=2), "--skip-counts",
                                  head="base")
        assert proc.returncode == 1, proc.stderr  # head is twice as slow
        assert "warning" not in proc.stderr and "Same content" not in summary
        assert "are one commit" in proc.stderr and "the builds differ in content" in proc.stderr

    def test_identical_builds_of_two_commits_are_said_the_same(self, tmp_path, repo):
        build = make_build(tmp_path, "base")
        copy = tmp_path / "copy"
        shutil.copytree(build, copy)
        proc, summary = run_gates(tmp_path, repo, build, str(copy), "--skip-counts")
        assert proc.returncode == 0, proc.stderr
        warnings = [line for line in proc.stderr.splitlines() if "warning" in line]
        assert warnings and "have the same content: identical executables (refine_bench)" \
            in warnings[0]
        assert "**Same content.**" in summary

    def test_the_default_workdir_is_the_users_own(self, tmp_path, monkeypatch):
        gates = _GATES[0] if _GATES else load_gates()
        monkeypatch.delenv("RUNNER_TEMP", raising=False)
        monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path / "cache"))
        assert gates.default_workdir() == str(tmp_path / "cache" / "hrbench-gates")
        made = gates.prepare_workdir(gates.default_workdir())
        assert os.stat(made).st_mode & 0o777 == 0o700
        monkeypatch.setenv("RUNNER_TEMP", str(tmp_path / "runner"))
        assert gates.default_workdir() == str(tmp_path / "runner" / "hrbench-gates")

    def test_any_benchmark_command_is_timed(self, tmp_path, repo):
        """--bench-cmd: the user's own benchmark, in builds without refine_bench."""
        builds = [make_build(tmp_path, side, factor=f) for side, f in (("base", 1), ("head", 2))]
        for build in builds:
            os.rename(os.path.join(build, "refine_bench"), os.path.join(build, "my_bench"))
        cmd = ('"$HRBENCH_BUILD/my_bench" --benchmark_out="$HRBENCH_BENCH_OUT" '
               '--benchmark_out_format=json  # $HRBENCH_SIDE, round $HRBENCH_ROUND')
        proc, summary = run_gates(tmp_path, repo, *builds, "--bench-cmd", cmd)
        assert proc.returncode == 1, proc.stderr
        assert "| counts | PASS |" in summary  # the engine of the build, its own baseline
        assert f"`{cmd}`" in summary
        assert len(benchmark_rows(summary)) == 5
        assert all(row[-1] == "**SLOWER**" for row in benchmark_rows(summary))
        runs = (tmp_path / "bench.log").read_text().split()
        assert runs[:4] == ["base", "head", "head", "base"]

    def test_any_command_is_timed_by_its_cpu_time(self, tmp_path, repo):
        """--time-cmd: another project's program, built at BASE and HEAD, timed itself (no
        hrbench, no refine_bench, no benchmark JSON); HEAD's does 3 times the work."""
        builds = []
        for side, n in (("base", 40000), ("head", 120000)):
            build = tmp_path / f"outside-{side}"
            build.mkdir()
            _executable(build / "work", f'#!/bin/sh\necho "$1 $HRBENCH_ROUND" >> '
                        f'"{tmp_path}/work.log"\ni=0; while [ $i -lt {n} ]; do '
                        'i=$((i+1)); done\n')
            builds.append(str(build))
        cmd = '"$HRBENCH_BUILD/work" "$HRBENCH_SIDE" > /dev/null'
        proc, summary = run_gates(tmp_path, repo, *builds, "--time-cmd", cmd, "--skip-counts")
        assert proc.returncode == 1, proc.stderr
        assert "| timing | FAIL | 1 of 1 benchmarks significantly slower" in summary
        (row,) = benchmark_rows(summary)
        assert row[0] == "`cpu time of --time-cmd`" and row[-1] == "**SLOWER**"
        assert row[3].startswith("+1") or row[3].startswith("+2"), row  # about +200%
        assert f"`{cmd}` (CPU time, user + sys, of its process tree" in summary
        assert "Wall time head / base: " in summary
        runs = (tmp_path / "work.log").read_text().splitlines()
        assert runs[:6] == ["base 0", "head 0", "base 1", "head 1", "head 2", "base 2"]
        assert len(runs) == 2 * 9  # a warm-up round and 8 rounds
        results = next((tmp_path / "work" / "results").iterdir())
        times = json.loads((results / "timing" / "times.json").read_text())
        assert times["command"] == cmd and len(times["head"]["cpu_seconds"]) == 8

    def test_a_failing_time_cmd_fails_with_a_summary(self, tmp_path, repo):
        build = make_build(tmp_path, "base")
        proc, summary = run_gates(tmp_path, repo, build, build, "--skip-counts",
                                  "--time-cmd", "echo broken >&2; exit 4")
        assert proc.returncode == 1
        assert ("the base command in a warm-up round failed (exit code 4): broken"
                in proc.stderr)
        assert summary.startswith("## hrbench gates: FAIL")

    def test_a_crashing_benchmark_fails_with_a_summary(self, tmp_path, repo):
        proc, summary = run_gates(tmp_path, repo, make_build(tmp_path, "base"),
                                  make_build(tmp_path, "head", crash=True))
        assert proc.returncode == 1
        assert "head's refine_bench in round 1 failed (exit code 3)" in proc.stderr
        assert summary.startswith("## hrbench gates: FAIL")


class TestUsageErrors:
    @pytest.mark.parametrize("case", ["unknown base", "unknown head", "empty ref",
                                      "missing build", "no refine_bench", "not git",
                                      "no baseline", "filter matches nothing", "bad rounds",
                                      "bad metric", "filter with bench-cmd",
                                      "empty bench-cmd", "bench-cmd with time-cmd",
                                      "real time with time-cmd", "min-time with time-cmd"])
    def test_exit_2_with_one_line(self, tmp_path, repo, case):
        base, head = make_build(tmp_path, "base"), make_build(tmp_path, "head")
        refs, extra = {}, []
        if case == "unknown base":
            refs["base"] = "no-such-ref"
        elif case == "unknown head":
            refs["head"] = "0123456789abcdef"
        elif case == "empty ref":
            refs["base"] = ""
        elif case == "missing build":
            head = str(tmp_path / "nowhere")
        elif case == "no refine_bench":
            os.remove(os.path.join(head, "refine_bench"))
        elif case == "not git":
            shutil.rmtree(repo / ".git")
        elif case == "no baseline":
            os.remove(repo / "tests" / "baseline" / "counts.json")
            _git(repo, "commit", "-q", "-am", "drop the baseline")
            refs["head"] = "main"
        elif case == "filter matches nothing":
            extra = ["--filter", "^BM_Nothing"]
        elif case == "bad rounds":
            extra = ["--rounds", "0"]
        elif case == "bad metric":
            extra = ["--metric", "wall"]
        elif case == "filter with bench-cmd":
            extra = ["--bench-cmd", "true", "--filter", "BM_"]
        elif case == "empty bench-cmd":
            extra = ["--bench-cmd", " "]
        elif case == "bench-cmd with time-cmd":
            extra = ["--bench-cmd", "true", "--time-cmd", "true"]
        elif case == "real time with time-cmd":
            extra = ["--time-cmd", "true", "--metric", "real_time"]
        elif case == "min-time with time-cmd":
            extra = ["--time-cmd", "true", "--min-time", "1"]
        proc, summary = run_gates(tmp_path, repo, base, head, *extra, **refs,
                                  subprocess_run=True)
        assert proc.returncode == 2, proc.stderr
        lines = proc.stderr.splitlines()
        assert len(lines) == 1 and lines[0].startswith("gates: error: "), proc.stderr
        assert proc.stdout == "" and summary == ""
        assert not (tmp_path / "bench.log").exists()  # nothing was timed

    def test_the_shim_runs_the_script(self, tmp_path):
        proc = subprocess.run([SHIM, "--help"], capture_output=True, text=True,
                              env=dict(os.environ, HRBENCH_PYTHON=sys.executable))
        assert proc.returncode == 0 and "BASE_REF" in proc.stdout and "--rounds" in proc.stdout


class TestAction:
    """action.yml runs scripts/ci/gates, and the example workflow uses the action."""

    @pytest.fixture
    def action(self):
        yaml = pytest.importorskip("yaml")
        with open(os.path.join(ROOT, "action.yml")) as f:
            return yaml.safe_load(f)

    def test_composite_with_the_documented_inputs(self, action):
        assert action["runs"]["using"] == "composite"
        assert {"base", "head", "rounds", "threshold", "filter", "metric",
                "working-directory"} <= set(action["inputs"])
        assert "pull_request.base.sha" in action["inputs"]["base"]["default"]
        assert action["inputs"]["head"]["default"] == "HEAD"
        assert any("scripts/setup.sh" in s["run"] for s in action["runs"]["steps"])

    def test_the_action_step_runs_locally(self, tmp_path, repo, action):
        """The gates step's script, run as GitHub would run it (inputs in the env)."""
        step = next(s for s in action["runs"]["steps"] if s.get("id") == "gates")
        inputs = {name: spec.get("default", "") for name, spec in action["inputs"].items()}
        inputs.update(base="base", head="head", rounds="8", metric="cpu_time",
                      args=f"--base-build {make_build(tmp_path, 'base')} --head-build "
                           f"{make_build(tmp_path, 'head')} --workdir {tmp_path / 'work'}")
        env = {k: v for k, v in os.environ.items() if not k.startswith("GITHUB_")}
        for name, value in step["env"].items():
            match = re.fullmatch(r"\$\{\{ inputs\.([\w-]+) \}\}", value)
            env[name] = inputs[match.group(1)]
        step_summary = tmp_path / "step_summary.md"
        env.update(GITHUB_ACTION_PATH=ROOT, GITHUB_STEP_SUMMARY=str(step_summary),
                   GITHUB_OUTPUT=str(tmp_path / "out.txt"), HRBENCH_PYTHON=sys.executable)
        proc = subprocess.run(["bash", "--noprofile", "--norc", "-eo", "pipefail", "-c",
                               step["run"]], cwd=repo, env=env, capture_output=True, text=True)
        assert proc.returncode == 0, proc.stderr
        assert "8 interleaved rounds" in proc.stdout
        assert step_summary.read_text() == proc.stdout

    def test_the_example_workflow_uses_the_action(self, action):
        import yaml
        with open(os.path.join(ROOT, "examples", "ci", "hrbench-gates.yml")) as f:
            workflow = yaml.safe_load(f)
        steps = [s for job in workflow["jobs"].values() for s in job["steps"]]
        checkout = next(s for s in steps if s.get("uses", "").startswith("actions/checkout"))
        assert checkout["with"]["fetch-depth"] == 0
        gates = next(s for s in steps if s.get("uses") == "./")
        assert set(gates["with"]) <= set(action["inputs"])
