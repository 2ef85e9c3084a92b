import stat
import sys
from pathlib import Path

import pytest

DATA = Path(__file__).resolve().parent / "data"


@pytest.fixture
def data_dir():
    """The directory of small test inputs."""
    return DATA


@pytest.fixture
def fake_hrbench(tmp_path):
    """An executable copy of the fake engine, run by the current Python."""
    script = tmp_path / "fake_hrbench"
    body = (DATA / "fake_hrbench.py").read_text()
    script.write_text(f"#!{sys.executable}\n" + body.split("\n", 1)[1])
    script.chmod(script.stat().st_mode | stat.S_IXUSR | stat.S_IXGRP | stat.S_IXOTH)
    return script
