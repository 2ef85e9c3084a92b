"""Make the tools/ package (and hrbench_analysis.engine, which it uses) importable,
locate the test data, and provide a stand-in engine."""

import os
import stat
import sys

import pytest

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
TOOLS = os.path.join(ROOT, "tools")
DATA = os.path.join(os.path.dirname(os.path.abspath(__file__)), "data")
for path in (os.path.join(ROOT, "analysis"), TOOLS):
    if path not in sys.path:
        sys.path.insert(0, path)


@pytest.fixture
def engine(tmp_path):
    """An executable that behaves like `hrbench run ... --json` (tests/tools/data)."""
    path = tmp_path / "hrbench"
    path.write_text(f'#!/bin/sh\nexec "{sys.executable}" "{os.path.join(DATA, "fake_hrbench.py")}" '
                    '"$@"\n')
    path.chmod(path.stat().st_mode | stat.S_IXUSR)
    return str(path)
