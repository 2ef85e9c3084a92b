"""Every command's usage errors: one line on stderr, ``PROG: error: ...``, and exit 2.

The commands are read from where they are declared (``[project.scripts]`` in
pyproject.toml, the scripts under ``tools/`` and ``scripts/ci/``), so that a new one is
tested without being listed here.
"""

import subprocess
import sys
import tomllib
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
SCRIPTS = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]["scripts"]
FILES = sorted([*ROOT.glob("tools/*.py"), *ROOT.glob("scripts/ci/*.py")])


def _entry_point(name, *args):
    # The console script _name_ as installed, run with _args_ (argv[0] its name, which
    # argparse shows as the program).
    module, function = SCRIPTS[name].split(":")
    code = (f"import sys; sys.argv[0] = {name!r}; from {module} import {function}; "
            f"sys.exit({function}())")
    return [sys.executable, "-c", code, *args], name


def _file(path, *args):
    return [sys.executable, str(path), *args], path.name


def _usage_error(argv, prog):
    proc = subprocess.run(argv, capture_output=True, text=True, cwd=ROOT, timeout=120)
    assert proc.returncode == 2, proc.stderr
    assert proc.stdout == ""
    assert proc.stderr.count("\n") == 1 and proc.stderr.endswith("\n"), proc.stderr
    # "PROG: error: ", or "PROG SUBCOMMAND: error: " (a script may name itself without .py)
    head = proc.stderr.split(": error: ")[0]
    assert head.split()[0] in (prog, prog.removesuffix(".py")), proc.stderr
    return proc.stderr


def test_the_commands_are_found():
    assert "hrbench-history" in SCRIPTS and len(SCRIPTS) >= 7
    assert any(p.name == "gates.py" for p in FILES) and len(FILES) >= 5


@pytest.mark.parametrize("name", sorted(SCRIPTS))
def test_an_unknown_option_of_each_installed_command_is_one_line_and_exit_2(name):
    # The first error argparse meets: the option, or an argument still missing.
    _usage_error(*_entry_point(name, "--no-such-option"))


@pytest.mark.parametrize("path", FILES, ids=lambda p: p.name)
def test_an_unknown_option_of_each_tool_is_one_line_and_exit_2(path):
    _usage_error(*_file(path, "--no-such-option"))


def test_history_measure_without_history_is_one_line_and_exit_2():
    message = _usage_error(*_entry_point("hrbench-history", "measure", "HEAD"))
    assert "--history" in message
