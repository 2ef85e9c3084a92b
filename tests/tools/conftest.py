"""Locate the test data, load scripts/ci/gates.py, and provide a stand-in engine."""

import importlib.util
import os
import stat
import sys

import pytest

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
TOOLS = os.path.join(ROOT, "tools")
DATA = os.path.join(os.path.dirname(os.path.abspath(__file__)), "data")
GATES = os.path.join(ROOT, "scripts", "ci", "gates.py")


def load_gates():
    """scripts/ci/gates.py as a module (it is a script, not part of a package)."""
    spec = importlib.util.spec_from_file_location("gates_under_test", GATES)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


@pytest.fixture
def engine(tmp_path):
    """An executable that behaves like `hrbench run ... --json` (tests/tools/data)."""
    path = tmp_path / "hrbench"
    path.write_text(f'#!/bin/sh\nexec "{sys.executable}" "{os.path.join(DATA, "fake_hrbench.py")}" '
                    '"$@"\n')
    path.chmod(path.stat().st_mode | stat.S_IXUSR)
    return str(path)
