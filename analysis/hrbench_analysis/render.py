"""Pictures of a solved hierarchy, and the command ``hrbench-render`` that draws one.

``hrbench solve ... --out F.csv`` writes one row per leaf element of the solved hierarchy;
:func:`hrbench_analysis.loader.read_solution` reads it into a :class:`Solution`. In 3D,
:func:`render_image` draws the leaves as seen by a perspective :class:`Camera` with a
z-buffer rasteriser written in numpy (:mod:`hrbench_analysis.raster`: each leaf's polygon
split into triangles, nearest depth wins), optionally with the element mesh over it;
:func:`render_figure` puts the image in a figure for the report. In 2D (flatland),
:func:`plot_radiosity_profile` draws each root patch's radiosity along its arc length.
:func:`plot_solution_3d` draws the leaves as mplot3d polygons coloured by radiosity, to turn
round and explore (the drawings are in :mod:`hrbench_analysis.drawing`; this module
exports them with the camera and the reader). The command ``hrbench-render``
(:func:`main`, ``python -m hrbench_analysis.render``) solves a scene and draws it so, with a
colour bar:

    hrbench-render cornell --eps 0.05 --min-area 0.005 --out room.png

Columns of the CSV, in this order (a header line names them; extra columns are ignored):

- 2D: ``element,root,depth,position,x,y,measure,radiosity,irradiance,reflectance,emission,
  red,green,blue,x0,y0,x1,y1``;
- 3D: ``element,root,depth,position,x,y,z,measure,radiosity,irradiance,reflectance,emission,
  red,green,blue,corners,x0,y0,z0,x1,y1,z1,x2,y2,z2,x3,y3,z3`` (``x3,y3,z3`` empty for a
  triangle).

As in :mod:`hrbench_analysis.plots`, nothing here creates a pyplot figure or picks a backend.
"""

import sys
import tempfile
from pathlib import Path

from matplotlib.figure import Figure

from .cli import (
    MAX_IMAGE_SIDE,
    Parser,
    add_engine_options,
    engine_of,
    figure_png,
    image_side,
    input_file,
    output_file,
    positive_int,
    positive_number,
    scene_params,
)
from .drawing import (
    default_exposure,
    plot_radiosity_profile,
    plot_solution_3d,
    radiosity_scale,
    render_figure,
    render_image,
    srgb_encode,
    view_direction,
)
from .engine import MESH_SCENE
from .errors import run_main
from .loader import COLUMNS_2D, COLUMNS_3D, Solution, read_solution
from .output import refuse_inputs, write_files
from .raster import CORNELL_CAMERA, Camera, rasterise
from .solution import solve_to_csv

__all__ = [
    "COLUMNS_2D",
    "COLUMNS_3D",
    "Solution",
    "Camera",
    "CORNELL_CAMERA",
    "read_solution",
    "rasterise",
    "default_exposure",
    "srgb_encode",
    "render_image",
    "render_figure",
    "plot_radiosity_profile",
    "radiosity_scale",
    "view_direction",
    "plot_solution_3d",
    "main",
]


#: The view of ``hrbench-render`` (vertical axis, elevation and azimuth in degrees) by
#: scene family: the Cornell box, y up as in its published data, from its open side
#: (where its published camera stands), raised and turned so that the floor and a side
#: wall show; any other scene from matplotlib's default view, z up.
VIEWS = {"cornell": ("y", 15.0, 155.0)}
DEFAULT_VIEW = ("z", 30.0, -60.0)


def _render_parser():
    p = Parser(prog="hrbench-render",
               description="Solve a 3D scene's radiosity on the hierarchy (hrbench solve) "
               "and draw its leaves coloured by radiosity, with a colour bar; a flatland "
               "scene is drawn as its radiosity profile along the patches.")
    p.add_argument("scene", nargs="?", metavar="SCENE",
                   help="a scene family, e.g. cornell (or --mesh F)")
    p.add_argument("params", nargs="*", metavar="key=value",
                   help="its parameters (default: the family's)")
    p.add_argument("--eps", type=positive_number, required=True, metavar="E",
                   help="oracle threshold")
    p.add_argument("--out", type=output_file, required=True, metavar="FILE",
                   help="PNG to write")
    p.add_argument("--oracle", default="garmann", help="oracle (default: %(default)s)")
    p.add_argument("--min-area", type=positive_number, metavar="A",
                   help="recursion limit on element size (scenes whose patches touch)")
    p.add_argument("--max-depth", type=int, metavar="D", help="recursion limit on depth")
    p.add_argument("--visibility", choices=("none", "fraction", "refine"),
                   help="occlusion (default: the engine's, none)")
    p.add_argument("--emission", type=float, metavar="E",
                   help="emission of every patch (for scenes without a lamp)")
    p.add_argument("--reflectance", type=float, metavar="R",
                   help="reflectance of every patch")
    p.add_argument("--threads", type=positive_int, default=1, metavar="N",
                   help="solver threads (the solution does not depend on them)")
    p.add_argument("--mesh", type=input_file, metavar="F",
                   help="an OFF or OBJ file instead of SCENE")
    p.add_argument("--triangulate", action="store_true",
                   help="with --mesh: split faces that are not planar convex quads")
    p.add_argument("--scale", type=positive_number, metavar="S",
                   help="with --mesh: multiply every coordinate by S")
    p.add_argument("--view", type=float, nargs=2, metavar=("ELEV", "AZIM"),
                   help="elevation and azimuth of the view in degrees (default: by scene)")
    p.add_argument("--up", choices=("x", "y", "z"), help="the vertical axis (default: by "
                   "scene, y for cornell, else z)")
    p.add_argument("--size", type=image_side, nargs=2, default=(900, 750),
                   metavar=("W", "H"), help="image size in pixels, each at most "
                   f"{MAX_IMAGE_SIDE} (default: 900 750)")
    p.add_argument("--csv", type=output_file, metavar="F",
                   help="also keep the leaves the engine wrote (hrbench solve --out F)")
    add_engine_options(p)
    return p


def _render_main(argv):
    parser = _render_parser()
    args = parser.parse_args(argv)
    if (args.scene is None) == (args.mesh is None):
        parser.error("give either SCENE [key=value ...] or --mesh F")
    scene, params = (scene_params(parser, [args.scene, *args.params]) if args.scene
                     else (MESH_SCENE, {}))
    if args.mesh is None and (args.triangulate or args.scale is not None):
        parser.error("--triangulate and --scale apply to --mesh only")
    options = {name: value for name, value in (
        ("mesh", None if args.mesh is None else str(args.mesh)),
        ("triangulate", args.triangulate or None), ("scale", args.scale),
        ("visibility", args.visibility), ("emission", args.emission),
        ("reflectance", args.reflectance), ("threads", args.threads)) if value is not None}
    refuse_inputs([("--out", args.out), ("--csv", args.csv)], [("--mesh", args.mesh)])
    engine = engine_of(args)
    # The engine writes into a folder of this command's own; --csv gets a copy, written
    # with the image as one set (a FIFO, a link, a full disk: as every output of the
    # analysis).
    with tempfile.TemporaryDirectory(prefix="hrbench-render-") as folder:
        csv_path = Path(folder) / "solution.csv"
        record = solve_to_csv(engine, scene, params, args.eps, args.oracle, options,
                              csv_path, min_area=args.min_area, max_depth=args.max_depth)
        solution = read_solution(csv_path)
        csv_bytes = csv_path.read_bytes() if args.csv else None
    what = " ".join([args.mesh.name if args.mesh else scene,
                     *(f"{k}={v:g}" for k, v in params.items())])
    title = (f"{what}, {args.oracle}, eps {args.eps:g}: {len(solution)} leaves, "
             f"{record['links']} links, {record['iterations']} sweeps")
    width, height = args.size
    fig = Figure(figsize=(width / 100, height / 100), layout="constrained")
    if solution.dimension == 2:
        ax = fig.add_subplot()
        plot_radiosity_profile(ax, solution)
        ax.grid(True, alpha=0.3)
    else:
        up, elev, azim = VIEWS.get(scene, DEFAULT_VIEW)
        elev, azim = args.view or (elev, azim)
        up = args.up or up
        ax = fig.add_subplot(projection="3d", proj_type="ortho")
        ax.view_init(elev=elev, azim=azim, vertical_axis=up)
        collection = plot_solution_3d(ax, solution, facing=view_direction(elev, azim, up))
        top = collection.norm.vmax
        bar = fig.colorbar(collection, ax=ax, shrink=0.7,
                           extend="max" if solution.radiosity.max() > top else "neither")
        bar.set_label("radiosity B (units of emission)")
        if solution.emission.any():
            ax.legend(loc="upper left", fontsize=8)
    ax.set_title(title, fontsize=10)
    write_files([*([(args.csv, csv_bytes)] if args.csv else []), (args.out, figure_png(fig))])
    print(f"{args.out}: {title}")
    return 0


def main(argv=None):
    """Run ``hrbench-render``; return its exit code (0, 2 for bad input or environment)."""
    return run_main("hrbench-render", _render_main, argv)


if __name__ == "__main__":
    sys.exit(main())
