"""hrbench-history: recording runs, step detection, counters, machines, the page, errors."""

import datetime as dt
import hashlib
import json
import os
import re
import shutil
import subprocess

import numpy as np
import pytest

from hrbench_analysis.bench.history import (
    detect_steps,
    get_counter_changes,
    get_series,
    load_history,
    main,
)

BENCH = "BM_EpsSweep/garmann_count/inv_eps:16/real_time"
OTHER = "BM_Headline/garmann_count/threads:1/real_time"
N_COMMITS = 20
STEP_AT = 12          # 1-based: commit 12 is the first slower one
REPS = 5


def _sha(i, salt=""):
    return hashlib.sha1(f"commit {i}{salt}".encode()).hexdigest()


def _date(i):
    return (dt.datetime(2026, 1, 1, tzinfo=dt.UTC) + dt.timedelta(days=i)).isoformat()


def _bench_json(times_ms, links=83710, host="ci-1", num_cpus=2, rng=None, extra=None):
    """A Google Benchmark file: one benchmark with these repetition times, and OTHER."""
    rows = []
    for bench, times, lk in ((BENCH, times_ms, links), (OTHER, [500.0] * REPS, 5092)):
        for k, t in enumerate(times):
            rows.append({
                "name": bench, "run_name": bench, "run_type": "iteration",
                "repetitions": len(times), "repetition_index": k, "threads": 1,
                "iterations": 10, "real_time": float(t), "cpu_time": float(t) * 0.9,
                "time_unit": "ms", "links": float(lk), "oracle_calls": float(2 * lk - 1),
                "links_per_second": lk / (t * 1e-3),
                "label": "garmann count-only"})
        rows.append({"name": bench + "_median", "run_name": bench, "run_type": "aggregate",
                     "aggregate_name": "median", "real_time": float(np.median(times)),
                     "cpu_time": 0.0, "time_unit": "ms", "links": float(lk)})
    context = {"date": "2026-01-01T00:00:00+00:00", "host_name": host,
               "executable": "build/refine_bench", "num_cpus": num_cpus,
               "mhz_per_cpu": 2600, "load_avg": [0.25, 0.5, 0.75],
               "library_build_type": "release", "nonce": float(rng.random()) if rng else 0}
    if extra:
        context.update(extra)
    return {"context": context, "benchmarks": rows}


def _write(path, data):
    path.write_text(json.dumps(data))
    return path


def _record(history, bench, i, machine=None, salt="", extra=()):
    argv = ["record", "--history", str(history), str(bench), "--commit", _sha(i, salt),
            "--date", _date(i), "--subject", f"change {i}"]
    if machine:
        argv += ["--machine", machine]
    return main(argv + list(extra))


def _synthetic_history(tmp_path, step=0.25, seed=7, machine="ci-1", links_from=None,
                       history=None, scale=1.0):
    """N_COMMITS commits, REPS noisy repetitions each, the level x(1+step) from STEP_AT."""
    rng = np.random.default_rng(seed)
    history = history or tmp_path / "history"
    for i in range(1, N_COMMITS + 1):
        level = 2.0 * scale * (1 + step if i >= STEP_AT else 1.0)
        run = level * np.exp(rng.normal(0, 0.015))            # run-to-run drift
        times = run * np.exp(rng.normal(0, 0.03, REPS))      # repetition noise
        links = 90000 if links_from is not None and i >= links_from else 83710
        bench = _write(tmp_path / f"bench-{machine}-{i}.json",
                       _bench_json(times, links=links, host=machine, rng=rng))
        assert _record(history, bench, i, machine=machine) == 0
    return history


@pytest.fixture(autouse=True)
def _no_git(tmp_path, monkeypatch):
    # Outside any checkout: git knows none of the synthetic commits.
    monkeypatch.chdir(tmp_path)


# ---------------------------------------------------------------------------------------
# Step detection.


def test_detect_steps_known_step():
    values = [10, 10.1, 9.9, 10.0, 10.05, 12.5, 12.4, 12.6, 12.5, 12.45]
    (step,) = detect_steps(values)
    assert step.index == 5
    assert step.ratio == pytest.approx(1.25, rel=0.01)
    assert step.before == pytest.approx(10.0, rel=0.01)


def test_detect_steps_flat_and_small():
    assert detect_steps([5.0] * 10) == []
    assert detect_steps([5.0]) == []
    # A 2% step is below min_change (5%): merged away however clean.
    assert detect_steps([5.0] * 5 + [5.1] * 5) == []
    assert len(detect_steps([5.0] * 5 + [5.1] * 5, min_change=0.01)) == 1


def test_detect_steps_rejects_bad_values():
    with pytest.raises(ValueError):
        detect_steps([1.0, 0.0, 2.0])
    with pytest.raises(ValueError):
        detect_steps([1.0, float("nan")])


def test_history_step_found_at_exactly_that_commit(tmp_path):
    history = _synthetic_history(tmp_path)
    runs, notes = load_history(history)
    assert len(runs) == N_COMMITS and notes == []
    commits, series = get_series(runs)
    assert [c[0] for c in commits] == [_sha(i) for i in range(1, N_COMMITS + 1)]
    (s,) = [s for s in series if s.benchmark == BENCH]
    (step,) = s.steps
    assert s.points[step.index].sha == _sha(STEP_AT)
    assert step.ratio == pytest.approx(1.25, rel=0.04)
    (flat,) = [s for s in series if s.benchmark == OTHER]
    assert flat.steps == []


def test_noise_only_history_has_no_step(tmp_path):
    for seed in (1, 2, 3):
        history = _synthetic_history(tmp_path, step=0.0, seed=seed,
                                     history=tmp_path / f"h{seed}")
        _, series = get_series(load_history(history)[0])
        assert all(s.steps == [] for s in series), seed


# ---------------------------------------------------------------------------------------
# Counters.


def test_counter_change_shows(tmp_path, capsys):
    history = _synthetic_history(tmp_path, step=0.0, links_from=15)
    _, series = get_series(load_history(history)[0])
    changes = get_counter_changes(series)
    assert {(c.benchmark, c.counter) for c in changes} == {(BENCH, "links"),
                                                          (BENCH, "oracle_calls")}
    (links,) = [c for c in changes if c.counter == "links"]
    (s,) = [s for s in series if s.benchmark == BENCH]
    assert s.points[links.index].sha == _sha(15)
    assert (links.before, links.after) == (83710, 90000)
    # A rate (links_per_second) varies with the time: never an algorithm change.
    assert all(not c.counter.endswith("_per_second") for c in changes)
    capsys.readouterr()
    out = tmp_path / "page.html"
    assert main(["html", "--history", str(history), "--out", str(out)]) == 0
    printed = capsys.readouterr().out
    assert f"counter {BENCH} [ci-1] at {_sha(15)[:10]}: links 83,710 -> 90,000" in printed
    page = out.read_text()
    assert "Counter changes" in page and "83,710 &rarr; 90,000" in page


# ---------------------------------------------------------------------------------------
# Recording.


def test_record_stores_metadata(tmp_path, capsys):
    bench = _write(tmp_path / "b.json", _bench_json([2.0] * REPS))
    history = tmp_path / "hist"
    assert _record(history, bench, 1, machine="box") == 0
    out = capsys.readouterr().out
    assert out.startswith("recorded ") and "machine box:" in out
    (path,) = history.glob("*.json")
    record = json.loads(path.read_text())
    assert record["commit"]["sha"] == _sha(1)
    assert record["commit"]["subject"] == "change 1"
    assert record["machine"]["name"] == "box"
    assert record["machine"]["num_cpus"] == 2
    assert record["machine"]["load_avg"] == [0.25, 0.5, 0.75]
    assert record["machine"]["load_avg_source"] == "benchmark context"
    assert record["build"]["library_build_type"] == "release"
    # Nothing lost: the whole benchmark file is kept.
    assert record["benchmark"] == json.loads(bench.read_text())
    assert path.name.startswith("20260102T000000Z-" + _sha(1)[:12])


def test_recording_twice_gives_no_duplicate(tmp_path, capsys):
    bench = _write(tmp_path / "b.json", _bench_json([2.0] * REPS))
    history = tmp_path / "hist"
    assert _record(history, bench, 1) == 0
    capsys.readouterr()
    assert _record(history, bench, 1) == 0
    assert "already recorded" in capsys.readouterr().out
    assert len(list(history.glob("*.json"))) == 1
    # The same measurement under another commit is refused: it cannot be two points.
    assert _record(history, bench, 2) == 2
    err = capsys.readouterr().err.strip()
    assert "already recorded for commit" in err and len(err.splitlines()) == 1
    assert len(list(history.glob("*.json"))) == 1


def test_copied_run_file_counts_once(tmp_path):
    bench = _write(tmp_path / "b.json", _bench_json([2.0] * REPS))
    history = tmp_path / "hist"
    assert _record(history, bench, 1) == 0
    (path,) = history.glob("*.json")
    (history / "copy.json").write_text(path.read_text())
    runs, notes = load_history(history)
    assert len(runs) == 1
    assert any("same run" in n for n in notes)


# ---------------------------------------------------------------------------------------
# Machines.


def test_mixed_machines_separate_series_and_note(tmp_path, capsys):
    history = _synthetic_history(tmp_path, machine="fast")
    _synthetic_history(tmp_path, machine="slow", seed=11, history=history, scale=3.0)
    runs, _ = load_history(history)
    assert len(runs) == 2 * N_COMMITS                          # nothing lost
    commits, series = get_series(runs)
    assert len(commits) == N_COMMITS                           # one commit, two machines
    bench_series = [s for s in series if s.benchmark == BENCH]
    assert sorted(s.machine for s in bench_series) == ["fast", "slow"]
    for s in bench_series:
        assert len(s.points) == N_COMMITS                      # no point counted twice
        assert all(len(p.runs) == 1 and len(p.times) == REPS for p in s.points)
        level = 2e6 if s.machine == "fast" else 6e6                  # ns
        assert s.points[0].median == pytest.approx(level, rel=0.15)   # never averaged
        (step,) = s.steps
        assert s.points[step.index].sha == _sha(STEP_AT)
    capsys.readouterr()
    out = tmp_path / "page.html"
    assert main(["html", "--history", str(history), "--out", str(out)]) == 0
    printed = capsys.readouterr().out
    assert "machines: fast, slow" in printed and "note: 2 machines" in printed
    page = out.read_text()
    assert "This history holds runs of 2 machines" in page
    assert "never averaged" in page
    # Restricted to one machine.
    assert main(["html", "--history", str(history), "--out", str(out),
                 "--machine", "slow"]) == 0
    printed = capsys.readouterr().out
    assert "machines: slow" in printed and f"[slow] at {_sha(STEP_AT)[:10]}" in printed
    assert "[fast]" not in printed
    assert "Only machine <b>slow</b>" in out.read_text()
    assert main(["html", "--history", str(history), "--out", str(out),
                 "--machine", "nope"]) == 2
    assert "machines: fast, slow" in capsys.readouterr().err


def test_same_name_other_hardware_is_another_series(tmp_path):
    history = tmp_path / "hist"
    a = _write(tmp_path / "a.json", _bench_json([2.0] * REPS, num_cpus=2))
    b = _write(tmp_path / "b.json", _bench_json([1.0] * REPS, num_cpus=8))
    assert _record(history, a, 1, machine="ci") == 0
    assert _record(history, b, 2, machine="ci") == 0
    runs, notes = load_history(history)
    assert len({r.label for r in runs}) == 2
    assert any("2 different machines" in n for n in notes)
    _, series = get_series(runs)
    assert all(len(s.points) == 1 for s in series)


def test_reruns_of_one_commit_are_pooled_in_order(tmp_path):
    history = tmp_path / "hist"
    for k, t in enumerate((2.0, 2.2)):
        bench = _write(tmp_path / f"b{k}.json", _bench_json([t] * REPS))
        assert _record(history, bench, 3) == 0
    bench = _write(tmp_path / "early.json", _bench_json([1.0] * REPS))
    assert _record(history, bench, 1) == 0               # recorded last, committed first
    commits, series = get_series(load_history(history)[0])
    assert [c[0] for c in commits] == [_sha(1), _sha(3)]
    (s,) = [s for s in series if s.benchmark == BENCH]
    assert [len(p.runs) for p in s.points] == [1, 2]
    assert len(s.points[1].times) == 2 * REPS


# ---------------------------------------------------------------------------------------
# The page.


def test_html_written_with_step_table(tmp_path, capsys):
    history = _synthetic_history(tmp_path)
    out = tmp_path / "site" / "page.html"
    capsys.readouterr()
    assert main(["html", "--history", str(history), "--out", str(out)]) == 0
    printed = capsys.readouterr().out
    assert re.search(rf"step    {re.escape(BENCH)} \[ci-1\] at {_sha(STEP_AT)[:10]}: "
                     r"\S+ ms -> \S+ ms \(x1\.2\d\d\)", printed)
    assert printed.strip().endswith("1 steps, 0 counter changes")
    page = out.read_text()
    assert page.startswith("<!DOCTYPE html>") and page.rstrip().endswith("</html>")
    steps_section = page[page.index("Detected steps"):page.index("Counter changes")]
    assert "<table>" in steps_section and _sha(STEP_AT)[:10] in steps_section
    assert "+2" in steps_section                          # the ratio, e.g. 1.25 (+25.x%)
    # Self-contained: figures embedded, nothing fetched.
    assert page.count("data:image/png;base64,") == 2
    assert "src='http" not in page and "<script" not in page


# ---------------------------------------------------------------------------------------
# Bad input: exit code 2 and one line.


def _one_line_error(capsys):
    err = capsys.readouterr().err
    assert len(err.strip().splitlines()) == 1, err
    assert err.startswith("hrbench-history: error: ")
    return err


def test_record_not_json(tmp_path, capsys):
    bad = tmp_path / "bad.json"
    bad.write_text("{not json")
    assert _record(tmp_path / "h", bad, 1) == 2
    assert "not valid JSON" in _one_line_error(capsys)
    assert not (tmp_path / "h").exists() or not list((tmp_path / "h").iterdir())


def test_record_no_benchmarks(tmp_path, capsys):
    for k, data in enumerate(({"context": {}}, {"context": {}, "benchmarks": []},
                              {"benchmarks": [{"name": "x", "run_type": "aggregate",
                                               "real_time": 1}]})):
        path = _write(tmp_path / f"empty{k}.json", data)
        assert _record(tmp_path / "h", path, 1) == 2
        assert "benchmark" in _one_line_error(capsys)


def test_record_missing_file_and_date(tmp_path, capsys):
    assert _record(tmp_path / "h", tmp_path / "missing.json", 1) == 2
    assert "cannot read" in _one_line_error(capsys)
    bench = _write(tmp_path / "b.json", _bench_json([2.0] * REPS))
    assert main(["record", "--history", str(tmp_path / "h"), str(bench),
                 "--commit", _sha(1)]) == 2
    assert "--date" in _one_line_error(capsys)
    assert main(["record", "--history", str(tmp_path / "h"), str(bench),
                 "--commit", _sha(1), "--date", "yesterday"]) == 2
    assert "ISO 8601" in _one_line_error(capsys)


def test_html_missing_history_dir(tmp_path, capsys):
    out = tmp_path / "page.html"
    assert main(["html", "--history", str(tmp_path / "nope"), "--out", str(out)]) == 2
    assert "does not exist" in _one_line_error(capsys)
    assert not out.exists()
    (tmp_path / "empty").mkdir()
    assert main(["html", "--history", str(tmp_path / "empty"), "--out", str(out)]) == 2
    assert "holds no runs" in _one_line_error(capsys)


def test_html_corrupt_run_file(tmp_path, capsys):
    history = tmp_path / "hist"
    history.mkdir()
    (history / "x.json").write_text("[1, 2]")
    assert main(["html", "--history", str(history), "--out", str(tmp_path / "p.html")]) == 2
    assert "not a history run file" in _one_line_error(capsys)


# ---------------------------------------------------------------------------------------
# Too few points, unmeasured commits, measuring a range.


@pytest.mark.parametrize("values", [
    [10.0] * 8 + [13.0] * 2,               # two points after
    [10.0] * 2 + [13.0] * 8,               # two points before
    [10.0, 13.0],                          # two commits
    [10.0] * 5 + [13.0] + [10.0] * 5,      # one outlying commit
])
def test_a_step_needs_three_points_on_each_side(values):
    assert detect_steps(values) == []


def test_three_points_on_each_side_are_enough():
    (step,) = detect_steps([10.0, 10.1, 9.9, 13.0, 13.1, 12.9])
    assert step.index == 3
    assert [s.index for s in detect_steps([10.0] * 8 + [13.0] * 2, min_points=2)] == [8]
    with pytest.raises(ValueError):
        detect_steps([1.0, 2.0], min_points=0)


def test_two_commits_at_different_levels_are_no_step(tmp_path, capsys):
    history = tmp_path / "hist"
    for i, level in ((1, 2.0), (2, 1.2)):     # x0.6, as two runs at different loads
        bench = _write(tmp_path / f"b{i}.json", _bench_json([level] * REPS))
        assert _record(history, bench, i) == 0
    capsys.readouterr()
    assert main(["html", "--history", str(history), "--out", str(tmp_path / "p.html")]) == 0
    assert capsys.readouterr().out.strip().endswith("0 steps, 0 counter changes")


def _git(repo, *args, date=None):
    env = {"GIT_COMMITTER_DATE": date, "GIT_AUTHOR_DATE": date} if date else {}
    proc = subprocess.run(["git", "-C", str(repo), "-c", "user.name=t", "-c",
                           "user.email=t@t", *args], check=True, capture_output=True,
                          text=True, env={**os.environ, **env})
    return proc.stdout.strip()


def _commit(repo, i, subject, files):
    for name, text in files.items():
        (repo / name).write_text(text)
    _git(repo, "add", "-A")
    _git(repo, "commit", "-q", "--allow-empty", "-m", subject, date=_date(i))
    return _git(repo, "rev-parse", "HEAD")


def test_a_step_is_credited_to_a_range_listing_the_unmeasured_commits(tmp_path, capsys):
    repo = tmp_path / "repo"
    repo.mkdir()
    _git(repo, "init", "-q", "-b", "main")
    subjects = {5: "refine: a new split order", 6: "docs: the new split order",
                7: "docs: typo"}
    shas = [_commit(repo, i, subjects.get(i, f"change {i}"), {"f.txt": f"{i}\n"})
            for i in range(1, 11)]
    history = tmp_path / "hist"
    for i, sha in enumerate(shas, 1):
        if i in (5, 6, 7):
            continue                           # not measured
        level = 2.0 if i < 5 else 1.5          # the change is commit 5 (or 6, or 7)
        times = [level * (1 + 0.002 * k) for k in range(REPS)]
        bench = _write(tmp_path / f"b{i}.json",
                       _bench_json(times, rng=np.random.default_rng(i)))
        assert main(["record", "--history", str(history), str(bench), "--commit", sha,
                     "--date", _date(i), "--subject", f"change {i}"]) == 0
    capsys.readouterr()
    out = tmp_path / "page.html"
    assert main(["html", "--history", str(history), "--out", str(out),
                 "--repo", str(repo)]) == 0
    printed = capsys.readouterr().out
    (line,) = [x for x in printed.splitlines() if x.startswith("step")]
    assert line.startswith(f"step    {BENCH} [ci-1] in {shas[3][:10]}..{shas[7][:10]} "
                           f"(4 commits; not measured: {shas[4][:10]} "
                           f"'refine: a new split order', {shas[5][:10]} 'docs: the new "
                           f"split order', {shas[6][:10]} 'docs: typo'): ")
    assert line.endswith("(x0.750)")
    page = out.read_text()
    assert f"not measured: {shas[4][:10]}" in page
    # Outside the repository git cannot list them: said once, the step at its commit.
    assert main(["html", "--history", str(history), "--out", str(out)]) == 0
    printed = capsys.readouterr().out
    assert "note: git does not know these commits" in printed
    assert f"[ci-1] at {shas[7][:10]}: " in printed


# A project with hrbench's two targets, built in no time: `refine_bench` writes Google
# Benchmark JSON whose times are the commit's speed.txt (milliseconds).
FAKE_CMAKE = """cmake_minimum_required(VERSION 3.20)
project(fake NONE)
file(READ "${CMAKE_CURRENT_SOURCE_DIR}/speed.txt" SPEED)
string(STRIP "${SPEED}" SPEED)
foreach(exe hrbench refine_bench)
  configure_file("${exe}.in" "${CMAKE_BINARY_DIR}/${exe}" @ONLY
                 FILE_PERMISSIONS OWNER_READ OWNER_WRITE OWNER_EXECUTE)
  add_custom_target(${exe})
endforeach()
"""
FAKE_REFINE_BENCH = r"""#!/bin/sh
out=; reps=1
for a in "$@"; do
  case "$a" in
    --benchmark_out=*) out="${a#*=}" ;;
    --benchmark_repetitions=*) reps="${a#*=}" ;;
  esac
done
row='{"name": "BM_K", "run_name": "BM_K", "run_type": "iteration", "repetitions": %s,'
row="$row"' "repetition_index": %s, "iterations": 1, "real_time": %s, "cpu_time": %s,'
row="$row"' "time_unit": "ms", "links": 5092}'
{
  printf '{"context": {"date": "%s", "host_name": "box", "num_cpus": 2}, "benchmarks": [' \
    "$(date +%s.%N)"
  k=0
  while [ "$k" -lt "$reps" ]; do
    [ "$k" -eq 0 ] || printf ', '
    t="@SPEED@$k"   # the speed, its last digit the repetition
    printf "$row" "$reps" "$k" "$t" "$t"
    k=$((k + 1))
  done
  printf ']}\n'
} > "$out"
"""
FAKE_HRBENCH = """#!/bin/sh
case "$1" in
  --version) echo "hrbench 0.0.0-fake" ;;
  *) echo '{"context": {"build_type": "Release"}}' ;;
esac
"""


@pytest.mark.skipif(shutil.which("cmake") is None, reason="needs cmake")
def test_measure_builds_runs_and_records_a_range(tmp_path, capsys):
    repo = tmp_path / "repo"
    repo.mkdir()
    _git(repo, "init", "-q", "-b", "main")
    files = {"CMakeLists.txt": FAKE_CMAKE, "refine_bench.in": FAKE_REFINE_BENCH,
             "hrbench.in": FAKE_HRBENCH}
    speeds = [2.0, 2.0, 2.0, 2.0, 3.0, 3.0, 3.0, 3.0]
    shas = [_commit(repo, i, f"change {i}", {**files, "speed.txt": f"{v}\n"})
            for i, v in enumerate(speeds, 1)]
    history, work = tmp_path / "hist", tmp_path / "work"

    def measure(rng, *extra):
        return main(["measure", rng, "--history", str(history), "--project", str(repo),
                     "--workdir", str(work), "--machine", "box", "--jobs", "1",
                     "--repetitions", "3", *extra])

    assert measure(shas[0]) == 0                              # one commit
    assert measure(f"{shas[0]}..{shas[2]}") == 0              # commits 2 and 3
    assert measure(f"{shas[4]}..{shas[7]}") == 0              # 6, 7, 8
    printed = capsys.readouterr().out
    assert sum(x.startswith("recorded ") for x in printed.splitlines()) == 6
    assert measure(f"{shas[0]}..{shas[2]}") == 0              # measured already
    assert "2 commits skipped" in capsys.readouterr().out
    runs, _ = load_history(history)
    assert sorted(r.sha for r in runs) == sorted(shas[i] for i in (0, 1, 2, 5, 6, 7))
    assert all(r.build["engine"]["version"] == "hrbench 0.0.0-fake" for r in runs)
    by_sha = {r.sha: r.times["BM_K"] for r in runs}
    assert by_sha[shas[1]] == pytest.approx([2.00e6, 2.01e6, 2.02e6])   # ms -> ns, 3 reps
    assert by_sha[shas[7]] == pytest.approx([3.00e6, 3.01e6, 3.02e6])
    assert main(["html", "--history", str(history), "--out", str(tmp_path / "p.html"),
                 "--repo", str(repo)]) == 0
    (line,) = [x for x in capsys.readouterr().out.splitlines() if x.startswith("step")]
    assert f"in {shas[2][:10]}..{shas[5][:10]} (3 commits; not measured: {shas[3][:10]} " \
           f"'change 4', {shas[4][:10]} 'change 5')" in line
    # A commit that does not build: said, skipped, exit 1; the others are recorded.
    broken = _commit(repo, 9, "broken", {"CMakeLists.txt": 'message(FATAL_ERROR "no")\n'})
    fixed = _commit(repo, 10, "fixed", files)
    assert measure(f"{shas[7]}..{fixed}") == 1
    captured = capsys.readouterr()
    assert f"measure: {broken[:12]} not measured: the build of commit {broken[:12]} " \
           "failed" in captured.err
    assert "1 runs recorded" in captured.out and f"1 failed ({broken[:12]})" in captured.out
    assert fixed in {r.sha for r in load_history(history)[0]}
    # Bad input: one line, exit 2.
    assert measure("no-such-ref..HEAD") == 2
    assert "is not a commit" in _one_line_error(capsys)
    assert measure(f"{shas[2]}..{shas[2]}") == 2
    assert "holds no commits" in _one_line_error(capsys)
