"""A page for a class: move eps and the plate length l, watch the tiling, N and L.

:func:`write_explorer` counts the elements N and links L of two parallel plates in
flatland (``parallel l=L d=1``, oracle ``garmann``) on a grid of eps and l with the
engine, writes the links of the grid points with at most :data:`MAX_TILING_LINKS` of
them, and fills ``explorer.html`` (a template beside this module) with the numbers. The
page is one self-contained file, its data inline as JSON, no network: two sliders pick
the grid point; a canvas draws its link tiling, two log-log charts place it on C1 (N
against 1/eps) and C4 (L against N). ``hrbench-reproduce`` writes it as
``results/explorer.html``; ``hrbench-explorer --out F`` (``python -m
hrbench_analysis.explorer``) writes it alone.

The page shows its numbers in elements with ids: ``eps-value``, ``length-value`` (the
plate length l), ``n-value`` (N) and ``links-value`` (L); ``#eps=0.25&l=16`` in the URL
picks a grid point on opening, and moving a slider updates it, so a link shares a view.
"""

import json
import sys
import tempfile
from pathlib import Path

from .cli import Parser, add_engine_options, engine_of, output_file
from .engine import EngineError, engine_version, get_capabilities
from .errors import run_main
from .output import write_file
from .tiling import count_run, refine_links

__all__ = ["SCENE", "DISTANCE", "ORACLE", "EPS", "LENGTHS", "MAX_TILING_LINKS", "explorer_data",
           "write_explorer", "main"]

#: The scene family, the distance d of the plates (scene units) and the oracle.
SCENE = "parallel"
DISTANCE = 1.0
ORACLE = "garmann"

#: The grid: oracle thresholds (dimensionless), halving, and plate lengths (scene units),
#: doubling, so that every step is one of the tutorial's.
EPS = (1.0, 0.5, 0.25, 0.125, 0.0625)
LENGTHS = (8.0, 16.0, 32.0, 64.0)

#: Grid points with more links than this have no tiling on the page: it keeps the file
#: near 100 kB, and smaller rectangles than these are below a pixel of the canvas.
MAX_TILING_LINKS = 5000

TEMPLATE = Path(__file__).resolve().parent / "explorer.html"
_PLACEHOLDER = "__EXPLORER_DATA__"


def _heap_indices(links, length):
    # The links of root pair (0, 1) as a flat list [i, j, i, j, ...] of heap indices
    # 2^depth + position of their elements (patch 0 first): small exact integers, from
    # which the page computes each interval [position, position + 1] * length / 2^depth.
    pairs = []
    for k in range(len(links)):
        ends = [(links.root_i[k], links.t0_i[k], links.t1_i[k], links.depth_i[k]),
                (links.root_j[k], links.t0_j[k], links.t1_j[k], links.depth_j[k])]
        ends.sort(key=lambda end: end[0])
        if [end[0] for end in ends] != [0, 1]:
            raise EngineError(f"link {k} joins patches {ends[0][0]} and {ends[1][0]}; "
                              "two plates have only the pair 0, 1")
        for _, t0, t1, depth in ends:
            size = length / 2.0 ** int(depth)
            position = round(t0 / size)
            if abs(t0 - position * size) > 1e-9 * length or abs(t1 - t0 - size) > 1e-9 * length:
                raise EngineError(f"link {k}: interval [{t0}, {t1}] is not one of the 2^"
                                  f"{depth} halves of a plate of length {length:g}")
            pairs.append((1 << int(depth)) + position)
    return pairs


def explorer_data(engine, eps=EPS, lengths=LENGTHS, max_links=MAX_TILING_LINKS):
    """The page's numbers: N and L at every grid point, links where they are few.

    Parameters
    ----------
    engine : str, path-like or sequence of them
        The engine (:func:`hrbench_analysis.engine.engine_argv`).
    eps : sequence of float
        Oracle thresholds, left to right on the slider.
    lengths : sequence of float
        Plate lengths l (scene units).
    max_links : int
        Links are written for grid points with at most this many (0: none, for an engine
        without ``links``).

    Returns
    -------
    data : dict
        ``scene``, ``d``, ``oracle``, ``engine`` (its version), ``eps``, ``l``,
        ``max_links`` and ``points``: for each l, for each eps, ``{"N": ..., "L": ...,
        "links": [i, j, ...] or None}``, the heap indices of :func:`_heap_indices`.

    Raises
    ------
    EngineError, ResultFormatError
        If a run fails or prints what cannot be read.
    """
    points = []
    with tempfile.TemporaryDirectory(prefix="hrbench-explorer-") as folder:
        for l in lengths:
            params = {"l": float(l), "d": DISTANCE}
            row = []
            for e in eps:
                record = count_run(engine, SCENE, params, e, ORACLE)
                nodes, count = int(record.counters["nodes"]), int(record.counters["links"])
                links = None
                if count <= max_links:
                    tiling = refine_links(engine, SCENE, params, e, Path(folder), ORACLE,
                                          max_links)
                    links = _heap_indices(tiling.links, float(l))
                row.append({"N": nodes, "L": count, "links": links})
            points.append(row)
    return {"scene": SCENE, "d": DISTANCE, "oracle": ORACLE,
            "engine": engine_version(engine), "eps": [float(e) for e in eps],
            "l": [float(l) for l in lengths], "max_links": max_links, "points": points}


def tiling_limit(engine):
    """:data:`MAX_TILING_LINKS`, or 0 for an engine without the command ``links``.

    Raises EngineError if the engine lacks the scene family or the oracle of the page.
    """
    capabilities = get_capabilities(engine)
    if capabilities.family(SCENE) is None or capabilities.oracle(ORACLE) is None:
        raise EngineError(f"engine lacks scene {SCENE!r} or oracle {ORACLE!r}")
    return MAX_TILING_LINKS if "links" in capabilities.command_names else 0


def explorer_html(data):
    """The page with `data` inline (``</`` escaped, so no text ends its script element)."""
    text = json.dumps(data, separators=(",", ":")).replace("</", "<\\/")
    return TEMPLATE.read_text().replace(_PLACEHOLDER, text)


def write_explorer(results, engine, name="explorer.html"):
    """Write the explorer page into the results folder.

    Parameters
    ----------
    results : path-like
        The folder (made if missing).
    engine : str, path-like or sequence of them
    name : str, optional

    Returns
    -------
    path : pathlib.Path

    Raises
    ------
    EngineError, ResultFormatError
        If a run fails; OutputError if the page cannot be written (the previous page is
        kept, :func:`~hrbench_analysis.output.write_file`).
    """
    path = Path(results) / name
    page = explorer_html(explorer_data(engine, max_links=tiling_limit(engine)))
    path.parent.mkdir(parents=True, exist_ok=True)
    write_file(path, page)
    return path


def _main(argv):
    parser = Parser(prog="hrbench-explorer",
                    description="Write the explorer page: sliders for eps and the plate "
                    "length, the link tiling, N and L on the charts of C1 and C4.")
    parser.add_argument("--out", type=output_file, default=Path("explorer.html"),
                        metavar="FILE", help="the page to write (default: %(default)s)")
    parser.add_argument("--max-links", type=int, default=None, metavar="N",
                        help="draw the tilings of grid points with at most N links (default: "
                        f"{MAX_TILING_LINKS}; 0 for none, and for an engine without 'links')")
    add_engine_options(parser)
    args = parser.parse_args(argv)
    if args.max_links is not None and args.max_links < 0:
        parser.error(f"--max-links must be >= 0, got {args.max_links}")
    engine = engine_of(args)
    limit = tiling_limit(engine)
    if args.max_links is not None:
        limit = min(limit, args.max_links)
    page = explorer_html(explorer_data(engine, max_links=limit))
    write_file(args.out, page)
    print(f"{args.out}: {len(page.encode()) // 1024} kB")
    return 0


def main(argv=None):
    """Run the command; return its exit code (0, 2 for bad input or environment)."""
    return run_main("hrbench-explorer", _main, argv)


if __name__ == "__main__":
    sys.exit(main())
