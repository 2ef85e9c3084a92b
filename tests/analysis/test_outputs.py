"""The analysis' output files: written whole into what the user named, never half.

A regular file is replaced through a temporary file, a symbolic link's target is
written, a device or FIFO is written through; a failed write is one line and exit code
74 and leaves the previous file; the report set survives a full disk and an interrupt at
every step of its writing; distinct claim ids give distinct plot files; runs sharing a
results folder leave one complete report.
"""

import errno
import json
import multiprocessing
import os
import random
import re
import shutil
import stat
import subprocess
import sys
import threading
from pathlib import Path

import numpy as np
import pytest
from matplotlib.figure import Figure

import hrbench_analysis.report.write as report_write
import hrbench_analysis.reproduce as reproduce
from hrbench_analysis.bench.history import main as history_main
from hrbench_analysis.claimfile import load_claims
from hrbench_analysis.errors import OUTPUT_ERROR, AnalysisError, OutputError
from hrbench_analysis.output import staged, write_file, write_files
from hrbench_analysis.report import ClaimOutcome, ReportFigure, get_figures, write_report
from hrbench_analysis.summary import distinct_names
from hrbench_analysis.sweep import ClaimData
from hrbench_analysis.tiling import main as tiling_main
from hrbench_analysis.verdict import assess_claim

ROOT = Path(__file__).resolve().parents[2]

needs_dev_full = pytest.mark.skipif(not os.path.exists("/dev/full"), reason="no /dev/full")


# ---------------------------------------------------------------------------------------
# Helpers.


class FailingWriter:
    """Makes the `at`-th system call of the writer (os.write, os.fsync, os.replace called
    from hrbench_analysis.output) raise `error`; counts them all."""

    def __init__(self, monkeypatch, at=None, error=None):
        self.at, self.calls = at, 0
        self.error = error or (lambda: OSError(errno.ENOSPC, os.strerror(errno.ENOSPC)))
        for name in ("write", "fsync", "replace"):
            monkeypatch.setattr(os, name, self._wrap(getattr(os, name)))

    def _wrap(self, real):
        def call(*args, **kwargs):
            if sys._getframe(1).f_globals.get("__name__") == "hrbench_analysis.output":
                self.calls += 1
                if self.calls == self.at:
                    raise self.error()
            return real(*args, **kwargs)
        return call


def snapshot(folder):
    """Every file of a results folder but the cache and the lock: {relative path: bytes}."""
    return {str(p.relative_to(folder)): p.read_bytes() for p in sorted(folder.rglob("*"))
            if p.is_file() and not p.name.startswith(("hrbench.sqlite", ".hrbench.lock"))}


def temporaries(folder):
    return sorted(p.name for p in folder.rglob(".*.tmp"))


def assert_complete(folder):
    """A readable report: JSON whole, pages whole, every figure the Markdown shows there."""
    json.loads((folder / "claims.json").read_text())
    md = (folder / "report.md").read_text()
    assert md.startswith("# hrbench") and (folder / "report.html").read_text().endswith(
        "</body></html>")
    shown = re.findall(r"\]\((plots/[^)]+\.png)\)", md)
    assert shown and all((folder / name).is_file() for name in shown), shown
    assert not temporaries(folder)


def reproduce_args(claims, engine, results):
    return ["--claims", str(claims), "--hrbench", str(engine), "--results", str(results),
            "--jobs", "1", "--charts-only"]


def one_line(err):
    # The stages' progress lines may come first; the error is one line, the last.
    lines = err.strip().splitlines()
    assert lines and not any(line.startswith("error: ") for line in lines[:-1]), err
    assert "Traceback" not in err
    return lines[-1]


CLAIM = """
[[claim]]
id = "{cid}"
statement = "N = Theta(eps^-1)"
description = "Elements against 1/eps on short plates ({cid})."
scene = "parallel"
params = {{ l = 8, d = 1 }}
sweep.param = "eps"
sweep.range = {{ from = 1.0, to = 0.01, per_decade = 5 }}
x = "1/eps"
y = "N"
expected_exponent = 1
tolerance = 0.15
regime = {{ x_min = 1 }}
min_points = 8
min_decades = 1.5
{extra}
"""


def claims_file(path, ids, charts=()):
    """A claims file of claims that differ only in their ids; `charts` maps an id to
    the name of a chart of its own."""
    text = '[source]\nkey = "test"\ncitation = "hrbench test data"\n' + "".join(
        CLAIM.format(cid=cid, extra=f'chart = "{dict(charts)[cid]}"' if cid in dict(charts)
                     else "") for cid in ids)
    path.write_text(text)
    return path


# ---------------------------------------------------------------------------------------
# One file: what the name is decides how it is written.


def test_regular_file_is_replaced_whole_and_keeps_its_mode(tmp_path):
    out = tmp_path / "page.html"
    write_file(out, "first")
    assert out.read_text() == "first"
    assert stat.S_IMODE(out.stat().st_mode) == 0o666 & ~_umask()
    out.chmod(0o640)
    inode = out.stat().st_ino
    write_file(out, b"second")
    assert out.read_bytes() == b"second"
    assert out.stat().st_ino != inode                    # a new file, renamed over
    assert stat.S_IMODE(out.stat().st_mode) == 0o640
    assert not temporaries(tmp_path)


def _umask():
    mask = os.umask(0)
    os.umask(mask)
    return mask


def test_symlink_target_is_written_and_the_link_kept(tmp_path):
    site = tmp_path / "site"
    site.mkdir()
    target = site / "real.html"
    target.write_text("old")
    link = tmp_path / "page.html"
    link.symlink_to(Path("site") / "real.html")           # relative, like ln -s
    chain = tmp_path / "chain.html"
    chain.symlink_to(link)
    write_file(chain, "new")
    assert target.read_text() == "new"
    assert link.is_symlink() and chain.is_symlink()
    assert os.readlink(link) == str(Path("site") / "real.html")
    assert not temporaries(tmp_path)
    # A dangling link creates its target, as a shell redirection does.
    dangling = tmp_path / "dangling.html"
    dangling.symlink_to(site / "later.html")
    write_file(dangling, "made")
    assert dangling.is_symlink() and (site / "later.html").read_text() == "made"


def test_fifo_is_written_through_not_replaced(tmp_path):
    fifo = tmp_path / "pipe"
    os.mkfifo(fifo)
    got = []
    reader = threading.Thread(target=lambda: got.append(fifo.read_bytes()), daemon=True)
    reader.start()
    write_file(fifo, "through the pipe")
    reader.join(10)
    assert got == [b"through the pipe"]
    assert stat.S_ISFIFO(os.lstat(fifo).st_mode)


@needs_dev_full
def test_dev_full_is_written_through_and_fails_with_the_output_error():
    with pytest.raises(OutputError, match=r"/dev/full: cannot write \(No space left"):
        write_file("/dev/full", "x" * 100)
    assert stat.S_ISCHR(os.lstat("/dev/full").st_mode)     # still the device
    assert OutputError("x").exit_code == OUTPUT_ERROR == 74


def test_names_that_cannot_be_an_output_file_are_input_errors(tmp_path):
    for bad, message in ((tmp_path, "is a folder"),
                         (tmp_path / "nope" / "f.html", "does not exist"),
                         (str(tmp_path / "a\0b"), "NUL")):
        with pytest.raises(AnalysisError, match=message) as info:
            write_file(bad, "x")
        assert info.value.exit_code == 2 and not isinstance(info.value, OutputError)


def test_staged_file_appears_only_when_whole(tmp_path):
    out = tmp_path / "links.csv"
    out.write_text("old")
    with pytest.raises(RuntimeError), staged(out) as name:
        name.write_text("half")
        raise RuntimeError("the engine failed")
    assert out.read_text() == "old" and not temporaries(tmp_path)
    with staged(out) as name:
        assert name.parent == tmp_path and name != out
        name.write_text("whole")
        assert out.read_text() == "old"
    assert out.read_text() == "whole" and not temporaries(tmp_path)


@pytest.mark.parametrize("at", [1, 2, 3, 4, 5, 6, 7])
def test_a_failure_at_any_step_of_a_set_leaves_every_file_old_or_new(tmp_path,
                                                                     monkeypatch, at):
    # Steps: write a, fsync a, write b, fsync b, replace a, replace b, fsync folder.
    old = {"a": b"old a", "b": b"old b"}
    for name, data in old.items():
        (tmp_path / name).write_bytes(data)
    failing = FailingWriter(monkeypatch, at=at)
    with pytest.raises(OutputError, match="No space left on device"):
        write_files([(tmp_path / "a", "new a"), (tmp_path / "b", "new b")])
    got = {name: (tmp_path / name).read_bytes() for name in old}
    if at <= 4:                                          # before any rename: untouched
        assert got == old
    else:
        assert all(got[n] in (old[n], f"new {n}".encode()) for n in old), got
    assert failing.calls == at and not temporaries(tmp_path)


# ---------------------------------------------------------------------------------------
# The commands: hrbench-history html, hrbench-tiling, hrbench-sweep.


def _bench(path, level=1.0):
    # A Google Benchmark file: one benchmark, three repetitions.
    rows = [{"name": "BM_X/real_time", "run_name": "BM_X/real_time",
             "run_type": "iteration", "repetitions": 3, "repetition_index": k,
             "threads": 1, "iterations": 10, "real_time": level + 0.01 * k,
             "cpu_time": 1.0, "time_unit": "ms"} for k in range(3)]
    path.write_text(json.dumps({"context": {"host_name": "ci-1", "num_cpus": 2},
                                "benchmarks": rows}))
    return path


def _history(tmp_path):
    bench = _bench(tmp_path / "bench.json")
    history = tmp_path / "history"
    assert history_main(["record", "--history", str(history), str(bench), "--commit",
                         "a" * 40, "--date", "2026-01-01T00:00:00+00:00",
                         "--subject", "one"]) == 0
    return history


def test_history_html_onto_a_symlink_writes_its_target(tmp_path, capsys, monkeypatch):
    monkeypatch.chdir(tmp_path)
    history = _history(tmp_path)
    target = tmp_path / "published.html"
    target.write_text("old page")
    link = tmp_path / "page.html"
    link.symlink_to(target)
    assert history_main(["html", "--history", str(history), "--out", str(link)]) == 0
    assert link.is_symlink() and target.read_text().startswith("<!DOCTYPE html>")
    capsys.readouterr()


@needs_dev_full
def test_history_html_onto_a_full_device_exits_74_with_one_line(tmp_path, capsys,
                                                                 monkeypatch):
    monkeypatch.chdir(tmp_path)
    history = _history(tmp_path)
    capsys.readouterr()
    assert history_main(["html", "--history", str(history), "--out", "/dev/full"]) == 74
    line = one_line(capsys.readouterr().err)
    assert line == ("hrbench-history: error: /dev/full: cannot write (No space left on "
                    "device)")
    assert stat.S_ISCHR(os.lstat("/dev/full").st_mode)
    assert history_main(["html", "--history", str(history), "--out", str(tmp_path)]) == 2
    assert "is a folder" in one_line(capsys.readouterr().err)


def test_history_record_on_a_full_disk_records_nothing(tmp_path, capsys, monkeypatch):
    history = _history(tmp_path)
    before = sorted(p.name for p in history.iterdir())
    capsys.readouterr()

    def full(fd):
        raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))

    monkeypatch.setattr(os, "fsync", full)
    bench = _bench(tmp_path / "bench2.json", level=2.0)
    code = history_main(["record", "--history", str(history), str(bench), "--commit",
                         "b" * 40, "--date", "2026-01-02T00:00:00+00:00", "--subject", "two"])
    assert code == 74
    assert "cannot write (No space left on device); nothing recorded" in one_line(
        capsys.readouterr().err)
    assert sorted(p.name for p in history.iterdir()) == before    # no half file, no temporary


@needs_dev_full
def test_tiling_png_onto_a_full_device_exits_74(fake_hrbench, capsys):
    code = tiling_main(["parallel", "l=8", "d=1", "--eps", "1", "--out", "/dev/full",
                        "--hrbench", str(fake_hrbench)])
    assert code == 74
    assert "/dev/full: cannot write" in one_line(capsys.readouterr().err)


@needs_dev_full
def test_sweep_csv_onto_a_symlink_and_a_full_device(tmp_path, data_dir, fake_hrbench,
                                                    capsys):
    target = tmp_path / "points.csv"
    link = tmp_path / "link.csv"
    link.symlink_to(target)
    argv = ["--claims", str(data_dir / "small_claims.toml"), "--hrbench", str(fake_hrbench),
            "--results", str(tmp_path / "results"), "--jobs", "1"]
    assert reproduce.sweep_main(argv + ["--out", str(link)]) == 0
    assert link.is_symlink()
    assert target.read_text().startswith("claim,series,param,value,x,y,status\n")
    assert len(target.read_text().splitlines()) == 12     # header and 11 points
    capsys.readouterr()
    assert reproduce.sweep_main(argv + ["--out", "/dev/full"]) == 74
    assert one_line(capsys.readouterr().err).startswith("error: /dev/full: cannot write")


# ---------------------------------------------------------------------------------------
# The report set: a full disk or an interrupt at any step.


@pytest.fixture
def previous_report(tmp_path, data_dir, fake_hrbench, monkeypatch, capsys):
    """A results folder with a report, and the arguments that wrote it."""
    results = tmp_path / "results"
    calls = []
    real = reproduce.write_report

    def recording(*args, **kwargs):
        calls.append(args)
        return real(*args, **kwargs)

    with monkeypatch.context() as m:
        m.setattr(reproduce, "write_report", recording)
        assert reproduce.main(reproduce_args(data_dir / "small_claims.toml", fake_hrbench,
                                             results)) == 0
    capsys.readouterr()
    (_, outcomes, context, figures, _), = calls
    return results, outcomes, context, figures


def test_a_full_disk_at_any_step_of_the_report_leaves_the_previous_one(
        tmp_path, previous_report, monkeypatch):
    results, outcomes, context, figures = previous_report
    # A figure drawn again comes out a few pixels different (its layout settles), so
    # each is drawn once and every write below gets the same bytes.
    pngs = {f.name: f.png() for f in figures}
    monkeypatch.setattr(report_write, "render_pngs",
                        lambda figs, jobs=1, advance=None: [pngs[f.name] for f in figs])
    old = snapshot(results)
    assert {"report.md", "report.html", "claims.json", "summary.txt",
            "plots/chart-t-elements.png", "plots/slopes-t-elements.png"} <= set(old)
    later = dict(context, date="a later run")
    # The new report, written into a copy, and the writer's steps counted.
    copy = tmp_path / "copy"
    shutil.copytree(results, copy)
    with monkeypatch.context() as m:
        counter = FailingWriter(m)
        write_report(copy, outcomes, later, figures)
    new = snapshot(copy)
    assert new != old and set(new) == set(old)
    steps = counter.calls                # 6 files written, synced, renamed; 2 folders synced
    assert steps == 6 * 3 + 2
    for at in range(1, steps + 1):
        with monkeypatch.context() as m:
            FailingWriter(m, at=at)
            with pytest.raises(OutputError, match="No space left on device"):
                write_report(results, outcomes, later, figures)
        got = snapshot(results)
        assert not temporaries(results), at
        if at <= 10:                     # writing the temporaries: nothing replaced
            assert got == old, at
        else:                            # renaming or syncing: each file whole
            assert all(got[name] in (old[name], new[name]) for name in old), at
            assert_complete(results)
        for name, data in old.items():   # the next attempt starts from the old report
            (results / name).write_bytes(data)
    write_report(results, outcomes, later, figures)
    assert snapshot(results) == new


def test_reproduce_ends_a_full_disk_with_one_line_and_74(previous_report, data_dir,
                                                         fake_hrbench, monkeypatch, capsys):
    results = previous_report[0]
    old = snapshot(results)
    FailingWriter(monkeypatch, at=3)
    code = reproduce.main(reproduce_args(data_dir / "small_claims.toml", fake_hrbench,
                                         results))
    assert code == 74
    # The progress lines of the stages come first; the error is one line, the last.
    line = capsys.readouterr().err.strip().splitlines()[-1]
    assert re.fullmatch(r"error: \S+\.png: cannot write \(No space left on device\); the "
                        r"previous file is kept", line), line
    assert snapshot(results) == old


def test_reproduce_interrupted_while_writing_then_rerun_equals_an_uninterrupted_run(
        previous_report, data_dir, fake_hrbench, monkeypatch, capsys):
    results = previous_report[0]
    argv = reproduce_args(data_dir / "small_claims.toml", fake_hrbench, results)
    uninterrupted = json.loads((results / "claims.json").read_text())["claims"]
    for at in sorted(random.Random(35).sample(range(1, 18), 3)):
        with monkeypatch.context() as m:
            FailingWriter(m, at=at, error=KeyboardInterrupt)
            assert reproduce.main(argv) == 130, at
        assert_complete(results)
        assert reproduce.main(argv) == 0
        assert json.loads((results / "claims.json").read_text())["claims"] == uninterrupted
    capsys.readouterr()


# ---------------------------------------------------------------------------------------
# Plot names.


def test_distinct_names_for_ids_that_differ_in_case_or_punctuation():
    names = distinct_names(["R1", "r1", "R-1", "R.1", "C4"], "slopes")
    # printf 'R1' | sha256sum: a791366f...
    assert names == {"R1": "slopes-r1--a791366f", "r1": "slopes-r1--82f3e9c6",
                     "R-1": "slopes-r-1--aee554ed", "R.1": "slopes-r-1--638066da",
                     "C4": "slopes-c4"}
    # No plain name holds "--", so a hashed name never meets a plain one.
    assert distinct_names(["r1--a791366f", "R1", "r1"], "slopes")["r1--a791366f"] == \
        "slopes-r1-a791366f"


def _outcomes(tmp_path, ids, charts=()):
    claims = load_claims(claims_file(tmp_path / "ids.toml", ids, charts))
    x = np.logspace(0, 2, 11)
    data = ClaimData(x, x, 3 * x)
    return [ClaimOutcome(c, data, assess_claim(c, data, n_boot=20)) for c in claims]


def test_charts_of_id_lists_that_read_alike_get_distinct_names(tmp_path):
    # One chart of the claims "A" and "B", another of the claim "A, B".
    outcomes = _outcomes(tmp_path, ["A", "B", "A, B"], {"A, B": "own"})
    names = [f.name for f in get_figures(outcomes)]
    assert len(names) == len(set(names)) == 5
    assert sum(name.startswith("chart-a-b--") for name in names) == 2


def test_claims_differing_in_case_or_punctuation_get_distinct_plots(tmp_path, fake_hrbench,
                                                                   capsys):
    ids = ["R1", "r1", "R-1", "R.1"]
    results = tmp_path / "results"
    claims = claims_file(tmp_path / "ids.toml", ids, {cid: cid for cid in ids})
    assert reproduce.main(reproduce_args(claims, fake_hrbench, results)) == 0
    capsys.readouterr()
    plots = sorted(p.name for p in (results / "plots").iterdir())
    assert len(plots) == 8 and len({(results / "plots" / p).read_bytes() for p in plots}) == 8
    # Each claim's section shows its own figures, and no other section shows them.
    md = (results / "report.md").read_text()
    sections = re.split(r"\n### ", md)
    for cid in ids:
        (section,) = [s for s in sections
                      if (m := re.match(r'<a id="[^"]*"></a>(.*?): ', s)) and m[1] == cid]
        shown = re.findall(r"plots/([^)]+)\.png", section)
        names = distinct_names(ids, "slopes")[cid], distinct_names(
            [json.dumps([i]) for i in ids], "chart")[json.dumps([cid])]
        assert sorted(shown) == sorted(names), (cid, shown)


# ---------------------------------------------------------------------------------------
# Runs sharing a results folder.


def _write_reports(folder, outcomes, tag, rounds):
    for k in range(rounds):
        figures = [ReportFigure(f"chart-{tag}-{k % 3}", f"{tag} {k}", "", Figure((1, 1)),
                                (outcomes[0].claim.id,)),
                   ReportFigure(f"slopes-{tag}", tag, "", Figure((1, 1)))]
        write_report(folder, outcomes, {"run": f"{tag} {k}"}, figures)


def test_concurrent_report_writers_leave_one_complete_set(tmp_path):
    outcomes = _outcomes(tmp_path, ["C"])
    folder = tmp_path / "results"
    context = multiprocessing.get_context("fork")
    procs = [context.Process(target=_write_reports, args=(folder, outcomes, tag, 20))
             for tag in ("a", "b", "c")]
    for p in procs:
        p.start()
    for p in procs:
        p.join(120)
    assert [p.exitcode for p in procs] == [0, 0, 0]
    assert_complete(folder)
    # Only the last writer's figures are left: the others removed theirs as stale.
    md = (folder / "report.md").read_text()
    shown = set(re.findall(r"plots/([^)]+\.png)", md))
    assert {p.name for p in (folder / "plots").iterdir()} == shown


def test_two_reproduce_runs_on_one_results_folder_both_exit_0(tmp_path, data_dir,
                                                              fake_hrbench):
    results = tmp_path / "results"
    env = dict(os.environ, PYTHONPATH=str(ROOT / "analysis"))
    claims = [data_dir / "small_claims.toml",
              claims_file(tmp_path / "ids.toml", ["R1", "r1"])]
    # The run that finishes last removes the other's figures as those of an earlier run.
    procs = [subprocess.Popen([sys.executable, "-m", "hrbench_analysis.reproduce",
                               *reproduce_args(c, fake_hrbench, results)],
                              env=env, cwd=tmp_path, stdout=subprocess.PIPE,
                              stderr=subprocess.PIPE, text=True) for c in claims]
    outputs = [p.communicate(timeout=300) for p in procs]
    for p, (_, err) in zip(procs, outputs, strict=True):
        assert p.returncode == 0, err
    assert_complete(results)
    shown = set(re.findall(r"plots/([^)]+\.png)", (results / "report.md").read_text()))
    assert {p.name for p in (results / "plots").iterdir()} == shown


# ---------------------------------------------------------------------------------------
# Every command that writes a file, against a full file system, a folder, a FIFO, a
# symbolic link and its own input. The engine's commands exit 2 on a failed write, the
# analysis' 74; both name the file and the system's reason, and leave the previous file.

ENGINE = ROOT / "build" / "hrbench"
PREVIOUS = b"the user's previous file\n"


def _py(module, *args):
    return [sys.executable, "-m", module, *args]


def _writers(tmp_path, data_dir, fake_hrbench):
    """name -> (argv for an output path, the input it reads or None, its failure code)."""
    links = tmp_path / "links.dump"
    mesh = tmp_path / "box.obj"
    scene = tmp_path / "scene.json"
    history = _history(tmp_path)
    bench = _bench(tmp_path / "gbench.json")
    claims = data_dir / "small_claims.toml"
    results = tmp_path / "results"
    baseline = tmp_path / "counts.json"
    baseline.write_text(json.dumps({"schema_version": 1, "runs": [
        {"args": ["parallel", "l=8", "d=1", "--eps", "0.5"]}]}))
    fake_tools = tmp_path / "fake_tools_hrbench"
    fake_tools.write_text(f'#!/bin/sh\nexec "{sys.executable}" '
                          f'"{ROOT / "tests" / "tools" / "data" / "fake_hrbench.py"}" "$@"\n')
    fake_tools.chmod(0o755)
    engine = [str(ENGINE)]
    writers = {
        "tiling --out": (lambda o: _py("hrbench_analysis.tiling", "parallel", "l=8", "d=1",
                                       "--eps", "1", "--hrbench", str(fake_hrbench),
                                       "--out", o), None, 74),
        "sweep --out": (lambda o: [sys.executable, "-c",
                                   "import sys; from hrbench_analysis.reproduce import "
                                   "sweep_main; sys.exit(sweep_main(sys.argv[1:]))",
                                   "--claims", str(claims), "--hrbench", str(fake_hrbench),
                                   "--results", str(results), "--jobs", "1", "--out", o],
                        claims, 74),
        "history html --out": (lambda o: _py("hrbench_analysis.bench.history", "html",
                                             "--history", str(history), "--out", o),
                               None, 74),
        "merge_bench": (lambda o: [sys.executable, str(ROOT / "tools" / "merge_bench.py"),
                                   o, str(bench)], bench, 74),
        "check_baseline --update": (lambda o: [sys.executable,
                                               str(ROOT / "tools" / "check_baseline.py"),
                                               "--hrbench", str(fake_tools), "--update",
                                               "--baseline", o], None, 74),
    }
    if ENGINE.exists():
        subprocess.run([*engine, "links", "parallel", "l=4", "d=1", "--eps", "0.5",
                        "--format", "probe", "--out", str(links)], check=True)
        subprocess.run([*engine, "save", "parallel3d", "l=1", "d=1", "--out", str(mesh)],
                       check=True)
        subprocess.run([*engine, "save", "parallel", "--out", str(scene)], check=True)
        writers.update({
            "solve --out": (lambda o: [*engine, "solve", "--mesh", str(mesh), "--eps", "1",
                                       "--emission", "1", "--out", o], mesh, 2),
            "links --out": (lambda o: [*engine, "links", "--scene-file", str(scene), "--eps",
                                       "0.5", "--out", o], scene, 2),
            "links --format probe --out": (lambda o: [*engine, "links", "parallel", "--eps",
                                                      "0.5", "--format", "probe", "--out", o],
                                           None, 2),
            "dump-paths --out": (lambda o: [*engine, "dump-paths", "parallel", "l=4", "d=1",
                                            "--links", str(links), "--out", o], links, 2),
            "save --out F.json": (lambda o: [*engine, "save", "--scene-file", str(scene),
                                             "--out", o], scene, 2),
            "save --out F.obj": (lambda o: [*engine, "save", "--mesh", str(mesh),
                                            "--out", o], mesh, 2),
            "render --out": (lambda o: _py("hrbench_analysis.render", "--mesh", str(mesh),
                                           "--eps", "1", "--emission", "1", "--hrbench",
                                           str(ENGINE), "--out", o),
                             mesh, 74),
            "render --csv": (lambda o: _py("hrbench_analysis.render", "--mesh", str(mesh),
                                           "--eps", "1", "--emission", "1", "--hrbench",
                                           str(ENGINE), "--out", str(tmp_path / "render.png"),
                                           "--csv", o), mesh, 74),
        })
    return writers


WRITERS = ["tiling --out", "sweep --out", "history html --out", "merge_bench",
           "check_baseline --update", "solve --out", "links --out",
           "links --format probe --out", "dump-paths --out", "save --out F.json",
           "save --out F.obj", "render --out", "render --csv"]


def _suffix(name):
    return {"save --out F.obj": ".obj", "save --out F.json": ".json", "tiling --out": ".png",
            "render --out": ".png", "history html --out": ".html"}.get(name, ".out")


def _previous(name, tmp_path):
    # check_baseline --update rewrites the baseline it reads: its previous file is one.
    if name == "check_baseline --update":
        return (tmp_path / "counts.json").read_bytes()
    return PREVIOUS


def _last_line(err):
    # The error: the last line, after any progress lines.
    lines = err.strip().splitlines()
    return lines[-1] if lines else ""


def _run(argv):
    env = dict(os.environ, PYTHONPATH=str(ROOT / "analysis"))
    return subprocess.run(argv, env=env, capture_output=True, text=True, timeout=300)


@pytest.fixture
def full_folder(tmp_path):
    """A folder on a tmpfs of 64 KiB (root only; CI runs as root)."""
    if os.geteuid() != 0:
        pytest.skip("mounting a file system to fill needs root")
    folder = tmp_path / "full"
    folder.mkdir()
    mounted = subprocess.run(["mount", "-t", "tmpfs", "-o", "size=64k", "tmpfs", str(folder)],
                             capture_output=True, text=True)
    if mounted.returncode != 0:
        pytest.skip(f"cannot mount a tmpfs: {mounted.stderr.strip()}")
    yield folder
    subprocess.run(["umount", "-l", str(folder)], check=False)


def _fill(folder):
    fd = os.open(folder / "filler", os.O_WRONLY | os.O_CREAT)
    try:
        while True:
            os.write(fd, b"\0" * 1024)
    except OSError as exc:
        assert exc.errno == errno.ENOSPC
    finally:
        os.close(fd)


@pytest.mark.parametrize("name", WRITERS)
def test_every_writer_on_a_full_disk_keeps_the_previous_file(name, full_folder, tmp_path,
                                                             data_dir, fake_hrbench):
    writers = _writers(tmp_path, data_dir, fake_hrbench)
    if name not in writers:
        pytest.skip("build/hrbench not built")
    argv, _, code = writers[name]
    out = full_folder / f"target{_suffix(name)}"
    previous = _previous(name, tmp_path)
    out.write_bytes(previous)
    mtl = out.with_suffix(".mtl")
    if name == "save --out F.obj":
        mtl.write_bytes(PREVIOUS)   # save writes it first: it must survive too
    _fill(full_folder)
    done = _run(argv(str(out)))
    assert done.returncode == code, done.stderr
    line = _last_line(done.stderr)
    # (save names the MTL, which it writes first)
    assert "No space left on device" in line and out.stem in line, line
    assert out.read_bytes() == previous
    if name == "save --out F.obj":
        assert mtl.read_bytes() == PREVIOUS
    assert temporaries(full_folder) == []


@pytest.mark.parametrize("kind", ["folder", "fifo", "symlink", "input"])
@pytest.mark.parametrize("name", WRITERS)
def test_every_writer_onto_a_folder_fifo_symlink_or_its_input(name, kind, tmp_path, data_dir,
                                                             fake_hrbench):
    writers = _writers(tmp_path, data_dir, fake_hrbench)
    if name not in writers:
        pytest.skip("build/hrbench not built")
    argv, source, _ = writers[name]
    out = tmp_path / f"target{_suffix(name)}"
    if kind == "folder":
        out.mkdir()
        done = _run(argv(str(out)))
        assert done.returncode == 2 and out.is_dir(), done.stderr
        assert re.search("folder|directory", _last_line(done.stderr))
    elif kind == "fifo" and name == "check_baseline --update":
        os.mkfifo(out)   # the baseline it rewrites is its input: a FIFO is refused
        done = _run(argv(str(out)))
        assert done.returncode == 2 and "FIFO" in _last_line(done.stderr), done.stderr
    elif kind == "fifo":
        os.mkfifo(out)
        got = []
        reader = threading.Thread(target=lambda: got.append(out.read_bytes()))
        reader.start()
        done = _run(argv(str(out)))
        if done.returncode != 0:
            os.close(os.open(out, os.O_WRONLY | os.O_NONBLOCK))  # free a waiting reader
        reader.join(10)
        assert done.returncode == 0, done.stderr
        assert stat.S_ISFIFO(os.lstat(out).st_mode) and got and got[0]
    elif kind == "symlink":
        target = tmp_path / f"real{_suffix(name)}"
        target.write_bytes(_previous(name, tmp_path))
        out.symlink_to(target)
        done = _run(argv(str(out)))
        assert done.returncode == 0, done.stderr
        assert out.is_symlink() and target.read_bytes() != PREVIOUS
    else:
        if source is None:
            pytest.skip("reads no file that could be its output")
        before = source.read_bytes()
        done = _run(argv(str(source)))
        assert done.returncode == 2, done.stderr
        assert re.search("reads|is also", _last_line(done.stderr)), done.stderr
        assert source.read_bytes() == before
