"""docs/tutorial.md: its count tables are what the engine counts today, and its commands
run as written, from the venv, into the tutorial's own results folder."""

import json
import re
import shlex
import subprocess
import sys
import tomllib
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
HRBENCH = ROOT / "build" / "hrbench"
TUTORIAL = ROOT / "docs" / "tutorial.md"
ROW = re.compile(r"^\| *([\d.]+) *\| *([\d.]+) *\| *([\d.]+) *\| *(\d+) *\| *(\d+) *\|$")


def tutorial_rows():
    return [ROW.match(line).groups() for line in TUTORIAL.read_text().splitlines()
            if ROW.match(line)]


def test_the_tutorial_has_count_tables():
    assert len(tutorial_rows()) >= 10


@pytest.mark.skipif(not HRBENCH.exists(), reason="build/hrbench not built")
@pytest.mark.parametrize("l, d, eps, nodes, links", tutorial_rows())
def test_tutorial_counts(l, d, eps, nodes, links):
    out = subprocess.run([HRBENCH, "run", "parallel", f"l={l}", f"d={d}", "--eps", eps,
                          "--json"], capture_output=True, text=True, check=True).stdout
    record = json.loads(out)
    assert (record["nodes"], record["links"]) == (int(nodes), int(links))
    assert record["oracle_calls"] == 2 * int(links) - 1


def tutorial_commands():
    """The command lines of the tutorial: its code blocks' lines (continuations joined)
    and its inline code that starts with a program of the clone and has arguments."""
    text = TUTORIAL.read_text()
    blocks = re.findall(r"^```\n(.*?)^```", text, re.S | re.M)
    lines = " ".join(blocks).replace("\\\n", " ").splitlines()
    inline = re.findall(r"`((?:\.venv/bin/|build/)[^` ]+ [^`]+)`", text)
    return [" ".join(c.split()) for c in lines + inline if c.strip()]


def test_the_tutorial_runs_python_from_the_venv_only():
    # Stock Debian has no `python`: every Python command is the venv's.
    bare = re.findall(r"(?<![\w/.-])python3?\b(?= -m| \S+\.py)", TUTORIAL.read_text())
    assert bare == []
    programs = {shlex.split(c)[0] for c in tutorial_commands()}
    assert programs <= {"build/hrbench", "mkdir", ".venv/bin/python", ".venv/bin/hrbench-tiling",
                        ".venv/bin/hrbench-render", ".venv/bin/hrbench-explorer"}, programs


def test_the_tutorials_reports_go_to_their_own_folder():
    # The report of `make reproduce` (results/) is never overwritten by the tutorial's.
    from hrbench_analysis.reproduce_options import _reproduce_parser

    reproductions = [c for c in tutorial_commands() if "hrbench_analysis.reproduce" in c]
    assert len(reproductions) >= 2
    for command in reproductions:
        args = _reproduce_parser().parse_args(shlex.split(command)[3:])
        assert args.results == Path("results/tutorial"), command
    outs = [c for c in tutorial_commands() if "--out" in c]
    assert len(outs) >= 3
    for command in outs:
        words = shlex.split(command)
        assert words[words.index("--out") + 1].startswith("results/tutorial/"), command


#: The tutorial's commands of the analysis package, and their modules (pyproject.toml).
SCRIPTS = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]["scripts"]


@pytest.mark.skipif(not HRBENCH.exists(), reason="build/hrbench not built")
@pytest.mark.parametrize("command", [c for c in tutorial_commands()
                                     if c.startswith(".venv/bin/hrbench-")])
def test_the_tutorials_drawing_commands_run(command, tmp_path):
    # Each as written, from the top of the clone, writing to a scratch folder instead.
    program, *argv = shlex.split(command)
    module = SCRIPTS[Path(program).name].split(":")[0]
    out = argv.index("--out") + 1
    argv[out] = str(tmp_path / Path(argv[out]).name)
    proc = subprocess.run([sys.executable, "-m", module, *argv], cwd=ROOT,
                          capture_output=True, text=True)
    assert proc.returncode == 0, proc.stderr
    assert Path(argv[out]).stat().st_size > 10_000
