"""The explorer page's data and file (the page in a browser: test_explorer_browser.py)."""

import json
import re
from pathlib import Path

import numpy as np
import pytest

from hrbench_analysis.engine import EngineError
from hrbench_analysis.explorer import _heap_indices, explorer_data, explorer_html, main
from hrbench_analysis.loader import LinkTable

ROOT = Path(__file__).resolve().parents[2]
HRBENCH = ROOT / "build" / "hrbench"
needs_engine = pytest.mark.skipif(not HRBENCH.exists(), reason="build/hrbench not built")


def links(*rows):
    """A LinkTable of rows (root_i, t0_i, t1_i, depth_i, root_j, t0_j, t1_j, depth_j)."""
    a = np.array(rows, dtype=float)
    return LinkTable(root_i=a[:, 0].astype(int), t0_i=a[:, 1], t1_i=a[:, 2],
                     depth_i=a[:, 3].astype(int), root_j=a[:, 4].astype(int), t0_j=a[:, 5],
                     t1_j=a[:, 6], depth_j=a[:, 7].astype(int))


def test_heap_indices_put_patch_0_first():
    # Plates of length 8: [4, 6] is element 2 of depth 2 (heap index 4 + 2), [0, 4]
    # element 0 of depth 1 (2 + 0), [0, 8] the root (1).
    table = links((1, 0, 4, 1, 0, 4, 6, 2), (0, 0, 8, 0, 1, 0, 8, 0))
    assert _heap_indices(table, 8.0) == [6, 2, 1, 1]


@pytest.mark.parametrize("row, words", [
    ((0, 1, 3, 2, 1, 0, 2, 2), "not one of the 2^2 halves"),  # starts off the grid
    ((0, 0, 3, 2, 1, 0, 2, 2), "not one of the 2^2 halves"),  # too long for its depth
    ((0, 0, 4, 1, 2, 0, 4, 1), "joins patches 0 and 2"),
])
def test_heap_indices_refuse_what_is_not_two_plates(row, words):
    with pytest.raises(EngineError, match=re.escape(words)):
        _heap_indices(links(row), 8.0)


def covered(pairs):
    """How often each cell of the finest grid of the plates' square is covered."""
    depth = max(int(n).bit_length() - 1 for n in pairs)
    cells = np.zeros((2 ** depth, 2 ** depth), dtype=int)
    for a, b in zip(pairs[::2], pairs[1::2], strict=True):
        da, db = a.bit_length() - 1, b.bit_length() - 1
        sa, sb = 2 ** (depth - da), 2 ** (depth - db)
        ia, ib = (a - 2 ** da) * sa, (b - 2 ** db) * sb
        cells[ia:ia + sa, ib:ib + sb] += 1
    return cells


@needs_engine
def test_grid_counts_are_the_engines_and_links_tile_the_square():
    data = explorer_data(HRBENCH, eps=(1.0, 0.5, 0.25), lengths=(8.0, 16.0), max_links=300)
    assert data["eps"] == [1.0, 0.5, 0.25] and data["l"] == [8.0, 16.0]
    # The counts of docs/tutorial.md (l = 8) and of hrbench run parallel l=16 d=1.
    counts = [[(p["N"], p["L"]) for p in row] for row in data["points"]]
    assert counts == [[(30, 22), (62, 112), (126, 496)], [(62, 46), (126, 250), (254, 1132)]]
    for row in data["points"]:
        for p in row:
            if p["L"] > 300:
                assert p["links"] is None
                continue
            assert len(p["links"]) == 2 * p["L"]
            # Every cell of the square under exactly one link.
            assert (covered(p["links"]) == 1).all()
    assert data["engine"].startswith("hrbench ")


def test_page_is_self_contained_and_carries_the_data():
    data = {"scene": "parallel", "d": 1.0, "oracle": "garmann", "engine": "x </script> y",
            "eps": [1.0], "l": [8.0], "max_links": 10,
            "points": [[{"N": 30, "L": 22, "links": None}]]}
    page = explorer_html(data)
    inline = re.search(r'<script type="application/json" id="explorer-data">(.*?)</script>',
                       page, re.S).group(1)
    assert json.loads(inline) == data  # "</" escaped as "<\/", which JSON reads back
    assert "__EXPLORER_DATA__" not in page
    # No server, no network: nothing is fetched.
    for outside in ("http://", "https://", " src=", "<link", "import(", "fetch("):
        assert outside not in page, outside
    for element in ('id="eps-slider"', 'id="length-slider"', 'id="n-value"',
                    'id="links-value"', 'id="tiling"', 'id="chart-c1"', 'id="chart-c4"'):
        assert element in page


@needs_engine
def test_cli_writes_a_small_page(tmp_path, capsys):
    out = tmp_path / "explorer.html"
    assert main(["--out", str(out), "--hrbench", str(HRBENCH)]) == 0
    assert out.stat().st_size < 200_000
    data = json.loads(re.search(r'id="explorer-data">(.*?)</script>', out.read_text(),
                                re.S).group(1))
    drawn = [p["L"] for row in data["points"] for p in row if p["links"] is not None]
    assert drawn and max(drawn) <= data["max_links"] == 5000
    assert f"{out}: " in capsys.readouterr().out


def test_cli_without_links_draws_no_tiling(tmp_path, fake_hrbench):
    out = tmp_path / "explorer.html"
    assert main(["--out", str(out), "--hrbench", str(fake_hrbench), "--max-links", "0"]) == 0
    data = json.loads(re.search(r'id="explorer-data">(.*?)</script>', out.read_text(),
                                re.S).group(1))
    assert data["max_links"] == 0
    assert all(p["links"] is None for row in data["points"] for p in row)
    assert data["points"][0][0] == {"N": 30, "L": 22, "links": None}


@pytest.mark.parametrize("argv, words", [
    (["--max-links", "-1"], "--max-links must be >= 0"),
    (["--out", "/no/such/folder/e.html"], "folder /no/such/folder does not exist"),
])
def test_cli_bad_input_is_one_line_and_exit_2(capsys, argv, words):
    code = main(argv)
    err = capsys.readouterr().err
    assert code == 2 and len(err.strip().splitlines()) == 1 and words in err


def test_cli_engine_that_cannot_run_is_one_line_and_exit_2(tmp_path, capsys):
    assert main(["--out", str(tmp_path / "e.html"), "--hrbench",
                 str(tmp_path / "missing")]) == 2
    err = capsys.readouterr().err
    assert err.startswith("hrbench-explorer: error: engine not found")
    assert len(err.strip().splitlines()) == 1
