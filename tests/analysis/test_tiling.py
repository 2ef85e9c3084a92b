"""hrbench-tiling: the link tilings of one pair at several eps, side by side."""

import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from matplotlib.image import imread

from hrbench_analysis.tiling import (
    BAR_INCHES,
    PANEL_INCHES,
    main,
    refine_links,
    tiling_figure,
)

ROOT = Path(__file__).resolve().parents[2]
HRBENCH = ROOT / "build" / "hrbench"
needs_engine = pytest.mark.skipif(not HRBENCH.exists(), reason="build/hrbench not built")


@needs_engine
def test_three_panels_of_the_tutorials_counts(tmp_path, capsys):
    out = tmp_path / "tiling.png"
    code = main(["parallel", "l=8", "d=1", "--eps", "1", "0.5", "0.25", "--out", str(out),
                 "--hrbench", str(HRBENCH)])
    printed = capsys.readouterr().out
    assert code == 0
    # The counts of docs/tutorial.md, section 2.
    for counts in ("1 (N = 30, L = 22)", "0.5 (N = 62, L = 112)", "0.25 (N = 126, L = 496)"):
        assert counts in printed
    # One panel per eps and the colour bar, at 100 dpi.
    height, width, _ = imread(out).shape
    assert (width, height) == (round(100 * (3 * PANEL_INCHES[0] + BAR_INCHES)),
                               round(100 * PANEL_INCHES[1]))


@needs_engine
def test_panels_share_axes_and_depth_scale_and_tile_the_square(tmp_path):
    tilings = [refine_links(HRBENCH, "parallel", {"l": 8.0, "d": 1.0}, eps, tmp_path)
               for eps in (1.0, 0.5)]
    fig = tiling_figure(tilings, "parallel l=8 d=1")
    *panels, bar = fig.axes
    assert len(panels) == 2 and bar.get_ylabel().startswith("link depth")
    assert [ax.get_title() for ax in panels] == ["eps = 1\nN = 30, L = 22",
                                                 "eps = 0.5\nN = 62, L = 112"]
    for ax in panels:
        assert ax.get_xlim() == (0.0, 8.0) and ax.get_ylim() == (0.0, 8.0)
    (first,), (second,) = (ax.collections for ax in panels)
    assert first.norm is second.norm
    # Link depths run from 2 (eps = 1) to 8 (eps = 0.5): one scale spans both.
    assert (first.norm.vmin, first.norm.vmax) == (2.0, 8.0)
    # The rectangles of each panel cover the 8 x 8 square exactly once.
    for t in tilings:
        area = np.sum((t.links.t1_i - t.links.t0_i) * (t.links.t1_j - t.links.t0_j))
        assert area == pytest.approx(64.0)


def run(argv, capsys):
    # The exit code and standard error of the command; argparse exits by SystemExit.
    try:
        code = main(argv)
    except SystemExit as exc:
        code = exc.code
    return code, capsys.readouterr().err


def test_the_command_runs_as_a_module_and_exits_2_in_one_line(tmp_path):
    proc = subprocess.run([sys.executable, "-m", "hrbench_analysis.tiling", "parallel",
                           "d=1", "--eps", "-1", "--out", str(tmp_path / "t.png")],
                          capture_output=True, text=True)
    assert proc.returncode == 2
    assert proc.stderr == ("hrbench-tiling: error: argument --eps: '-1' is not a finite "
                           "number > 0\n")


@pytest.mark.parametrize("argv, words", [
    (["parallel", "l=x", "--eps", "1"], "scene parameter 'l=x' is not name=number"),
    (["l=8", "--eps", "1"], "the scene family comes first"),
    (["parallel", "--eps", "0"], "'0' is not a finite number > 0"),
    (["parallel", "--eps", "nan"], "is not a finite number > 0"),
    (["parallel"], "the following arguments are required: --eps"),
    (["parallel", "--eps", "1", "--max-links", "0"], "'0' is not an integer >= 1"),
])
def test_usage_errors_are_one_line_and_exit_2(tmp_path, capsys, argv, words):
    code, err = run([*argv, "--out", str(tmp_path / "t.png"), "--hrbench", str(HRBENCH)],
                    capsys)
    assert code == 2
    assert len(err.strip().splitlines()) == 1 and err.startswith("hrbench-tiling: error: ")
    assert words in err


def test_an_output_folder_that_does_not_exist_is_refused_before_any_run(tmp_path, capsys):
    code, err = run(["parallel", "--eps", "1", "--out", str(tmp_path / "no" / "t.png"),
                     "--hrbench", str(tmp_path / "no-engine")], capsys)
    assert code == 2 and len(err.strip().splitlines()) == 1
    assert "does not exist" in err


@needs_engine
@pytest.mark.parametrize("argv, words", [
    (["nope", "--eps", "1"], "unknown scene 'nope'"),
    (["parallel3d", "--eps", "1"], "scene 'parallel3d' is 3D"),
    (["parallel", "l=8", "--eps", "0.001"], "more than 100000 (--max-links) to draw"),
    (["parallel", "l=8", "--eps", "0.25", "--max-links", "100"], "gives 496 links"),
    (["occluded", "--eps", "1", "--pair", "0", "7"], "--pair 0 7: no links"),
])
def test_what_the_engine_cannot_draw_is_one_line_and_exit_2(tmp_path, capsys, argv, words):
    out = tmp_path / "t.png"
    code, err = run([*argv, "--out", str(out), "--hrbench", str(HRBENCH)], capsys)
    assert code == 2
    assert len(err.strip().splitlines()) == 1 and err.startswith("hrbench-tiling: error: ")
    assert words in err
    assert not out.exists()
