"""The link tiling of a pair of patches at several thresholds, side by side: ``hrbench-tiling``.

::

    hrbench-tiling parallel l=8 d=1 --eps 1 0.5 0.25 --out tiling.png

One panel per eps, in the order given, on shared axes and one depth colour scale, each
titled with eps and the engine's counts N (elements) and L (links) of the whole scene;
the rectangles are the links of one root pair (``--pair``, default 0 1) in the square
of positions on the two patches (:func:`hrbench_analysis.plots.plot_link_tiling`). Set
side by side, the panels show what one figure cannot: halving eps halves the smallest
rectangles and the band they fill holds more of them across, so L grows like N^2 at
fixed geometry.
Flatland scenes only (a 3D link has no interval of positions). Also
``python -m hrbench_analysis.tiling``.
"""

import sys
import tempfile
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from matplotlib.colors import Normalize
from matplotlib.figure import Figure

from .cli import (
    Parser,
    add_engine_options,
    engine_of,
    output_file,
    positive_int,
    positive_number,
    save_figure,
    scene_params,
)
from .engine import EngineError, RunSpec, format_number, run_engine, write_links
from .errors import AnalysisError, run_main
from .loader import parse_run_json, read_links_csv
from .plots import plot_link_tiling

__all__ = ["Tiling", "MAX_LINKS", "count_run", "refine_links", "tiling_figure", "main"]

#: Most links a panel is drawn with by default: beyond that the rectangles are smaller
#: than a pixel and the engine's link file runs to megabytes.
MAX_LINKS = 100_000

#: Width and height of one panel (inches, at 100 dpi), and of the colour bar's column.
PANEL_INCHES = (4.2, 5.0)
BAR_INCHES = 1.0


@dataclass(frozen=True)
class Tiling:
    """One refinement's counts and links.

    Attributes
    ----------
    eps : float
        Oracle threshold (dimensionless).
    nodes : int
        Elements N of the whole scene (count).
    links : LinkTable
        Every link the engine stored; ``len(links)`` is L.
    """

    eps: float
    nodes: int
    links: object


def count_run(engine, scene, params, eps, oracle="garmann"):
    """The run record of one counting run (``hrbench run ... --count-only --json``).

    Returns
    -------
    result : RunResult

    Raises
    ------
    EngineError
        If the engine refuses the run (its exit code and last line of standard error).
    ResultFormatError
        If it prints no readable run record.
    """
    run = run_engine(RunSpec.of(scene, params, eps, oracle).argv(engine))
    if run.exit_code != 0:
        raise EngineError(f"{' '.join(run.argv[1:])} failed with exit code {run.exit_code}: "
                          f"{run.message or 'no message'}")
    return parse_run_json(run.stdout)


def refine_links(engine, scene, params, eps, folder, oracle="garmann", max_links=MAX_LINKS):
    """Count one refinement, then write and read its links (flatland scenes).

    Parameters
    ----------
    engine : str, path-like or sequence of them
        The engine (:func:`hrbench_analysis.engine.engine_argv`).
    scene : str
    params : dict of str to float
    eps : float
    folder : pathlib.Path
        Where the link file ``links-eps<eps>.csv`` is written.
    oracle : str, optional
    max_links : int, optional
        Refuse a refinement with more links, before they are written.

    Returns
    -------
    tiling : Tiling

    Raises
    ------
    EngineError
        If a run fails, the scene is not 2D, it has more than `max_links` links, or the
        link file does not hold the links the run counted.
    """
    record = count_run(engine, scene, params, eps, oracle)
    # Without a counter table the integer field `dimension` is read as a counter.
    dimension = record.counters.get("dimension", record.extra.get("dimension", 2))
    if dimension != 2:
        raise EngineError(f"scene {scene!r} is {dimension}D: a link tiling is drawn for "
                          "flatland scenes, whose elements are intervals of positions")
    count = int(record.counters["links"])
    if count > max_links:
        raise EngineError(f"eps={format_number(eps)} gives {count} links, more than "
                          f"{max_links} (--max-links) to draw; take a larger eps")
    path = folder / f"links-eps{format_number(eps)}.csv"
    write_links(engine, RunSpec.of(scene, params, eps, oracle), path)
    links = read_links_csv(path)
    if len(links) != count:
        raise EngineError(f"the engine counted {count} links at eps={format_number(eps)} "
                          f"but wrote {len(links)} to {path}")
    return Tiling(float(eps), int(record.counters["nodes"]), links)


def tiling_figure(tilings, title="", root_pair=(0, 1)):
    """The tilings side by side, on shared axes and one depth colour scale.

    Parameters
    ----------
    tilings : sequence of Tiling
        One panel each, in order.
    title : str, optional
        Above the panels (the scene).
    root_pair : (int, int), optional
        The root pair drawn.

    Returns
    -------
    fig : matplotlib.figure.Figure
        ``len(tilings)`` panel Axes, then the colour bar's Axes;
        :data:`PANEL_INCHES` per panel plus :data:`BAR_INCHES`.
    """
    width, height = PANEL_INCHES
    fig = Figure(figsize=(width * len(tilings) + BAR_INCHES, height), layout="constrained")
    axes = fig.subplots(1, len(tilings), sharex=True, sharey=True, squeeze=False)[0]
    collections = []
    for ax, t in zip(axes, tilings, strict=True):
        collections.append(plot_link_tiling(ax, t.links, root_pair=root_pair))
        ax.set_title(f"eps = {t.eps:g}\nN = {t.nodes}, L = {len(t.links)}", fontsize=10)
        ax.label_outer()
    depths = [d for c in collections for d in (c.get_array().min(), c.get_array().max())
              if c.get_array().size]
    norm = Normalize(min(depths, default=0), max(depths, default=1))
    for c in collections:
        c.set_norm(norm)
    bar = fig.colorbar(collections[0], ax=list(axes), shrink=0.9)
    bar.set_label("link depth depth_i + depth_j (levels)")
    if title:
        fig.suptitle(title)
    return fig


def _parser():
    p = Parser(prog="hrbench-tiling",
               description="Draw the link tiling of a pair of patches at several eps side "
               "by side: each link the rectangle of its two elements' positions.")
    p.add_argument("scene", metavar="SCENE", help="a flatland scene family, e.g. parallel")
    p.add_argument("params", nargs="*", metavar="key=value",
                   help="its parameters, e.g. l=8 d=1 (default: the family's)")
    p.add_argument("--eps", type=positive_number, nargs="+", required=True, metavar="E",
                   help="the thresholds, one panel each, e.g. --eps 1 0.5 0.25")
    p.add_argument("--out", type=output_file, required=True, metavar="FILE",
                   help="PNG to write")
    p.add_argument("--oracle", default="garmann", help="oracle (default: %(default)s)")
    p.add_argument("--pair", type=int, nargs=2, default=(0, 1), metavar=("P", "Q"),
                   help="the root patches whose links are drawn (default: 0 1)")
    p.add_argument("--max-links", type=positive_int, default=MAX_LINKS, metavar="N",
                   help="refuse a panel with more links (default: %(default)s)")
    add_engine_options(p)
    return p


def _main(argv):
    parser = _parser()
    args = parser.parse_args(argv)
    scene, params = scene_params(parser, [args.scene, *args.params])
    engine = engine_of(args)
    with tempfile.TemporaryDirectory(prefix="hrbench-tiling-") as folder:
        tilings = [refine_links(engine, scene, params, eps, Path(folder), args.oracle,
                                args.max_links) for eps in args.eps]
    p, q = args.pair
    for t in tilings:
        if not np.any(((t.links.root_i == p) & (t.links.root_j == q))
                      | ((t.links.root_i == q) & (t.links.root_j == p))):
            raise AnalysisError(f"--pair {p} {q}: no links between these patches at "
                                f"eps={format_number(t.eps)} ({len(t.links)} links in all)")
    where = " ".join(f"{k}={v:g}" for k, v in params.items())
    fig = tiling_figure(tilings, f"{scene} {where}, oracle {args.oracle}: links of patches "
                        f"{args.pair[0]} and {args.pair[1]}", tuple(args.pair))
    save_figure(fig, args.out)
    print(f"{args.out}: {len(tilings)} panels, eps "
          + ", ".join(f"{t.eps:g} (N = {t.nodes}, L = {len(t.links)})" for t in tilings))
    return 0


def main(argv=None):
    """Run ``hrbench-tiling``; return its exit code (0, 2 for bad input or environment)."""
    return run_main("hrbench-tiling", _main, argv)


if __name__ == "__main__":
    sys.exit(main())
