"""Hostile input to the CI tools: one line on stderr and an exit code that is not a verdict.

1 means a regression and 3 an inconclusive measurement (docs/ci.md); bad input is 2, an
output that cannot be written 74, a bug 70. No traceback without --debug.
"""

import json
import os
import subprocess
import sys

import pytest

from conftest import DATA, ROOT, load_gates
from hrbench_analysis.bench import benchcompare, check_baseline, compare_bench, history

gates = load_gates()


def base():
    return os.path.join(DATA, "base.json")


def one_line(err, prog):
    lines = err.strip().splitlines()
    assert len(lines) == 1 and "Traceback" not in err, err
    assert lines[0].startswith(f"{prog}: "), err
    return lines[0]


def bench_with(tmp_path, name, edit):
    """base.json with `edit(text)` applied, as a file."""
    with open(base(), encoding="utf-8") as f:
        text = f.read()
    path = tmp_path / name
    path.write_text(edit(text))
    return str(path)


def first_time_to(value):
    def edit(text):
        data = json.loads(text)
        row = next(r for r in data["benchmarks"] if r.get("run_type") == "iteration")
        row["real_time"] = "@"
        return json.dumps(data).replace('"@"', value, 1)
    return edit


@pytest.fixture
def hostile(tmp_path):
    """Input files that are no benchmark file, by kind."""
    fifo = tmp_path / "fifo.json"
    os.mkfifo(fifo)
    sparse = tmp_path / "sparse.json"
    with open(sparse, "wb") as f:
        f.truncate(10 << 30)          # 10 GiB, no disk blocks
    binary = tmp_path / "binary.json"
    binary.write_bytes(bytes(range(256)) * 40)
    return {
        "NaN": (bench_with(tmp_path, "nan.json", first_time_to("NaN")),
                "is not valid JSON: NaN is not a JSON number"),
        "Infinity": (bench_with(tmp_path, "inf.json", first_time_to("Infinity")),
                     "is not valid JSON: Infinity is not a JSON number"),
        "negative": (bench_with(tmp_path, "neg.json", first_time_to("-5")),
                     "real_time -5 is not a finite time >= 0"),
        "huge": (bench_with(tmp_path, "huge.json", first_time_to("1" + "0" * 400)),
                 "is not a finite time >= 0"),
        "duplicate key": (bench_with(tmp_path, "dup.json",
                                     lambda t: t.replace('"real_time":', '"real_time": 1, '
                                                         '"real_time":', 1)),
                          "key 'real_time' is given twice in one object"),
        "binary": (str(binary), "is not valid JSON: not UTF-8 text"),
        "sparse": (str(sparse), "the benchmark file has 10737418240 bytes; at most "
                                "268435456 are allowed"),
        "FIFO": (str(fifo), "is a FIFO (named pipe), not a regular file"),
        "device": ("/dev/zero", "is a character device, not a regular file"),
        "directory": (str(tmp_path), "is a directory, not a regular file"),
    }


KINDS = ["NaN", "Infinity", "negative", "huge", "duplicate key", "binary", "sparse", "FIFO",
         "device", "directory"]


@pytest.mark.parametrize("kind", KINDS)
def test_compare_refuses_hostile_files_with_exit_2(hostile, kind, capsys):
    path, message = hostile[kind]
    assert compare_bench.main([base(), path]) == 2
    line = one_line(capsys.readouterr().err, "compare_bench.py")
    assert message in line and path in line


@pytest.mark.parametrize("kind", ["NaN", "negative", "sparse", "FIFO", "device"])
def test_history_record_refuses_hostile_files_with_exit_2(hostile, kind, tmp_path, capsys):
    path, message = hostile[kind]
    code = history.main(["record", "--history", str(tmp_path / "h"), path, "--commit",
                         "a" * 40, "--date", "2024-01-01T00:00:00+00:00"])
    assert code == 2
    assert message in one_line(capsys.readouterr().err, "hrbench-history")
    assert not (tmp_path / "h").exists() or not list((tmp_path / "h").glob("*.json"))


def test_history_refuses_a_hand_edited_run_file(tmp_path, capsys):
    runs = tmp_path / "h"
    assert history.main(["record", "--history", str(runs), base(), "--commit", "b" * 40,
                         "--date", "2024-01-01T00:00:00+00:00"]) == 0
    capsys.readouterr()
    (stored,) = runs.glob("*.json")
    stored.write_text(stored.read_text().replace('"real_time": ', '"real_time": -', 1))
    code = history.main(["html", "--history", str(runs), "--out", str(tmp_path / "p.html")])
    assert code == 2
    assert "is not a finite time >= 0" in one_line(capsys.readouterr().err,
                                                   "hrbench-history")


def run_tool(args, stdout):
    """A tool as a process (standard output as given); its exit code and stderr."""
    proc = subprocess.run([sys.executable, *args], stdout=stdout, stderr=subprocess.PIPE,
                          text=True, timeout=120)
    return proc.returncode, proc.stderr


@pytest.mark.skipif(not os.path.exists("/dev/full"), reason="needs /dev/full")
def test_a_full_standard_output_is_exit_74_not_a_regression():
    # Without the check, the FAIL verdict's exit code 1 would hide the lost report.
    with open("/dev/full", "w") as full:
        code, err = run_tool([os.path.join(ROOT, "tools", "compare_bench.py"), base(),
                              os.path.join(DATA, "slower.json")], full)
    assert code == 74
    assert one_line(err, "compare_bench.py") == (
        "compare_bench.py: error: standard output: No space left on device")


def test_a_closed_pipe_is_exit_74():
    proc = subprocess.Popen([sys.executable, os.path.join(ROOT, "tools", "compare_bench.py"),
                             base(), os.path.join(DATA, "slower.json")],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    proc.stdout.close()               # the reader is gone before the report is written
    err = proc.stderr.read()
    assert proc.wait(timeout=120) == 74
    assert one_line(err, "compare_bench.py").endswith("standard output: Broken pipe")


@pytest.mark.parametrize("debug", [False, True])
def test_a_bug_is_exit_70_never_1_and_its_traceback_needs_debug(monkeypatch, capsys, debug):
    def broken(*args, **kwargs):
        raise ZeroDivisionError("a bug")
    monkeypatch.setattr(benchcompare, "get_comparison_report", broken)
    code = benchcompare.main([base(), os.path.join(DATA, "slower.json")]
                             + (["--debug"] if debug else []))
    assert code == 70
    err = capsys.readouterr().err
    assert err.strip().splitlines()[-1] == (
        "hrbench-compare: internal error, a bug: ZeroDivisionError: a bug (rerun with "
        "--debug for the traceback, and please report it)")
    assert ("Traceback" in err) == debug


# --- check_baseline.py ----------------------------------------------------------------------


def baseline_file(tmp_path, runs, text=None):
    path = tmp_path / "counts.json"
    path.write_text(text if text is not None else json.dumps({"schema_version": 1,
                                                              "runs": runs}))
    return str(path)


@pytest.mark.parametrize("runs, text, message", [
    ([{"args": [1, 2]}], None, "run 1: 'args' must be a list of strings"),
    ([{"args": ["parallel", "a\0b"]}], None, "run 1: 'args' must be a list of strings"),
    ([{"args": ["parallel"], "counts": []}], None, "run 1: 'counts' must be an object"),
    ([{"args": ["parallel"], "counts": {"links": [1, "x"]}}], None,
     "counter 'links' must be an integer >= 0 or a list of them"),
    ([{"args": ["parallel"], "counts": {"links": -1}}], None, "counter 'links'"),
    (None, '{"schema_version": 1, "runs": [], "runs": []}', "key 'runs' is given twice"),
    (None, '{"schema_version": 1, "runs": [{"args": [], "counts": {"links": NaN}}]}',
     "NaN is not a JSON number"),
    (None, "\xff\xfe", "is not valid JSON"),
])
def test_check_baseline_refuses_malformed_baselines_with_exit_2(tmp_path, engine, capsys, runs,
                                                                 text, message):
    path = baseline_file(tmp_path, runs, text)
    assert check_baseline.main(["--hrbench", engine, "--baseline", path]) == 2
    assert message in one_line(capsys.readouterr().err, "check_baseline.py")


@pytest.mark.parametrize("kind", ["sparse", "FIFO", "device", "binary"])
def test_check_baseline_refuses_hostile_files_with_exit_2(hostile, kind, engine, capsys):
    path, _ = hostile[kind]
    assert check_baseline.main(["--hrbench", engine, "--baseline", path]) == 2
    assert path in one_line(capsys.readouterr().err, "check_baseline.py")


def test_check_baseline_refuses_an_engine_record_with_a_key_twice(tmp_path, capsys):
    from hrbench_analysis.bench.baseline import RunError, run_counts
    engine = tmp_path / "dup"
    engine.write_text('#!/bin/sh\necho \'{"links": 5, "links": 7, "version": "x"}\'\n')
    engine.chmod(0o755)
    with pytest.raises(RunError, match="key 'links' is given twice"):
        run_counts(str(engine), ["parallel"], ["links"])


@pytest.mark.skipif(not os.path.exists("/dev/full"), reason="needs /dev/full")
def test_check_baseline_report_on_a_full_device_is_74(tmp_path, engine):
    path = baseline_file(tmp_path, [{"args": ["parallel", "l=64", "d=1", "--eps", "0.25"]}])
    with open("/dev/full", "w") as full:
        code, err = run_tool([os.path.join(ROOT, "tools", "check_baseline.py"), "--hrbench",
                              engine, "--baseline", path], full)
    assert code == 74 and "standard output: No space left on device" in err


# --- scripts/ci/gates ---------------------------------------------------------------------


@pytest.mark.parametrize("option, message", [
    (["--rounds", "1000000"], "--rounds must be from 1 to 1000"),
    (["--min-time", "1e9"], "--min-time must be a number of seconds > 0 and at most 60"),
    (["--min-time", "nan"], "--min-time must be a number of seconds > 0"),
])
def test_gates_bound_rounds_and_min_time(option, message, capsys):
    assert gates.main(["HEAD", "HEAD", *option]) == 2
    assert message in one_line(capsys.readouterr().err, "gates")


@pytest.mark.parametrize("code, expect", [(1, "fail"), (2, "usage"), (70, "crash"),
                                           (74, "crash"), (-9, "crash")])
def test_a_crash_of_check_baseline_is_never_a_failed_gate(tmp_path, monkeypatch, code, expect):
    monkeypatch.setattr(gates, "read_file_at", lambda repo, sha, path: b"{}")
    monkeypatch.setattr(gates.subprocess, "run", lambda *a, **k: subprocess.CompletedProcess(
        a[0], code, "", "check_baseline.py: trouble\n"))
    def gate():
        return gates.count_gate(".", "", "a" * 40, "a" * 40, str(tmp_path), str(tmp_path), 1)
    if expect == "fail":
        assert gate()["status"] == "fail"
    elif expect == "usage":
        with pytest.raises(gates.UsageError, match="check_baseline.py: check_baseline.py: "
                           "trouble"):
            gate()
    else:
        with pytest.raises(RuntimeError, match=f"ended with exit code {code}: "):
            gate()
