"""The count tables of docs/tutorial.md are what the engine counts today."""

import json
import re
import subprocess
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
