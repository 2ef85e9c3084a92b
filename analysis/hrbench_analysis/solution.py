"""The report's pictures of radiosity solved on the hierarchy (``hrbench solve``).

Figures a reader recognises at once: the radiosity along two facing plates, as each
oracle's leaves hold it, against the dense reference; the Cornell box rendered from its
solution, with the element mesh at a toggle; and the Stanford bunny in a lit box (75,792
patches), solved through clusters (docs/meshes.md).
"""

from pathlib import Path

from matplotlib.figure import Figure

from .drawing import plot_radiosity_profile, render_figure
from .engine import MESH_SCENE, EngineError, RunSpec, run_engine
from .loader import ResultFormatError, read_record, read_solution
from .output import staged
from .raster import Camera
from .report import ReportFigure
from .stages import Stage

__all__ = ["PROFILE", "CORNELL", "BUNNY", "BUNNY_CAMERA", "solution_figures", "profile_figure",
           "cornell_figures", "bunny_figure", "solve_to_csv"]

#: The profile: scene, parameters, options, and (oracle, eps) per panel, the three
#: oracles at thresholds that give a few thousand links each.
PROFILE = ("parallel", {"l": 4, "d": 1}, {"emission": 1, "reference": 10},
           (("garmann", 0.1), ("hanrahan", 0.03), ("bf", 0.05)))

#: The Cornell box: the family's measured geometry and materials, occlusion by the
#: sampled visible fraction, and a recursion limit (walls and blocks touch).
CORNELL = ("cornell", {}, 0.02, "garmann", 0.002, {"visibility": "fraction"})


def solve_to_csv(engine, scene, params, eps, oracle, options, csv_path, min_area=None,
                 max_depth=None):
    """Run one solve that writes its leaves to `csv_path`; return its JSON record (a dict).

    The arguments are those of :func:`hrbench_analysis.engine.solve_argv` (the solve's
    :class:`~hrbench_analysis.engine.RunSpec`). The engine
    writes a temporary file beside `csv_path`, which becomes `csv_path` once the solve
    succeeded (:func:`hrbench_analysis.output.staged`): a run sharing the folder never
    reads a part of it. Raises EngineError if the solve fails (its exit code and
    message), ResultFormatError if it prints no JSON, OutputError if the file cannot be
    written.
    """
    solve = RunSpec.of(scene, params, eps, oracle, min_area=min_area, max_depth=max_depth,
                       options=options, command="solve")
    with staged(csv_path) as written:
        argv = solve.argv(engine) + ["--out", str(written)]
        run = run_engine(argv)
        command = " ".join(run.argv[1:]).replace(str(written), str(csv_path))
        if run.exit_code != 0:
            raise EngineError(f"{command} failed with exit code {run.exit_code}: "
                              f"{run.message or 'no message'}")
        try:
            return read_record(run.stdout)
        except ResultFormatError as exc:
            raise ResultFormatError(f"{command}: {exc}") from None


def profile_figure(engine, results):
    """The radiosity along the plates for each oracle, against the reference.

    Parameters
    ----------
    engine : str, path-like or sequence of them
        The engine (:func:`hrbench_analysis.engine.engine_argv`).
    results : pathlib.Path
        Folder for the solves' CSV files (``solution-parallel-<oracle>.csv``).

    Returns
    -------
    figure : ReportFigure
    """
    scene, params, options, panels = PROFILE
    fig = Figure(figsize=(14, 4.6), layout="constrained")
    axes = fig.subplots(1, len(panels), sharey=True)
    for ax, (oracle, eps) in zip(axes, panels, strict=True):
        path = results / f"solution-{scene}-{oracle}.csv"
        record = solve_to_csv(engine, scene, params, eps, oracle, options, path)
        plot_radiosity_profile(ax, read_solution(path), record["reference_radiosity"],
                               record["reference_depth"])
        ax.set_title(f"{oracle}, eps = {eps:g}: {record['links']} links, "
                     f"{record['leaves']} leaves\nrelative error L2 "
                     f"{record['reference_error_l2']:.2g}, max "
                     f"{record['reference_error_max']:.2g}", fontsize=10)
        ax.grid(True, alpha=0.3)
        ax.legend(fontsize=8)
    where = " ".join(f"{k}={v:g}" for k, v in params.items())
    caption = (f"Two facing plates ({scene} {where}), both emitting 1 with reflectance 0.5, "
               "solved on the hierarchy of each oracle (gather over the links, push-pull, "
               "Jacobi sweeps to a residual of 1e-6). Solid: the radiosity each leaf holds, "
               "a step function along the plate (the plates face each other, so the "
               "middle, which sees the most of the other plate, is brightest); dashed: "
               f"the dense reference, {2 ** options['reference']} uniform elements per "
               "plate with exact crossed-strings form factors. The errors are relative to "
               "the reference (L2 over the plates, max over its elements). The garmann "
               "oracle splits by distance alone, so its leaves are as fine at the ends as "
               "in the middle; hanrahan and bf split where the form factor (times B) is "
               "large.")
    return ReportFigure("profile", "Radiosity along the plates, each oracle against the "
                        "reference", caption, fig)


def cornell_figures(engine, results, jobs=1):
    """The Cornell box rendered from its solution, and the same with its element mesh.

    Parameters
    ----------
    engine : str, path-like or sequence of them
    results : pathlib.Path
        Folder for the solve's CSV file (``solution-cornell.csv``).
    jobs : int, optional
        Threads of the solve (``--threads``); the solution does not depend on them.

    Returns
    -------
    figure : ReportFigure
        The image, with the meshed image as its ``alternate``.
    """
    scene, params, eps, oracle, min_area, options = CORNELL
    path = results / "solution-cornell.csv"
    record = solve_to_csv(engine, scene, params, eps, oracle, options | {"threads": jobs},
                          path, min_area=min_area)
    solution = read_solution(path)
    facts = (f"{scene}, {oracle}, eps {eps:g}, min-area {min_area:g}, visibility "
             f"{options['visibility']}\n{record['leaves']} leaves, {record['links']} links")
    plain = render_figure(solution, title=facts)
    meshed = render_figure(solution, mesh=True, title=facts)
    seconds = sum(_cpu_seconds(record).values())
    caption = ("The Cornell box (measured geometry and reflectances of the Cornell "
               "University Program of Computer Graphics), solved on the hierarchy and seen "
               "from its published camera: every leaf drawn flat, rasterised with a "
               "depth buffer, in its material's hue (the legend: red left wall, green "
               "right wall, white elsewhere) at the brightness of its radiosity (the "
               "colour bar; the solve is monochrome, so a leaf's red, green and blue "
               "average to its radiosity), exposed so that the brightest lit surfaces "
               "are near white. The lamp, outlined, emits far more than any surface "
               "reflects and is drawn white, beyond the top of the bar. Occlusion enters "
               "the link coefficients as the visible fraction of each linked pair, sampled "
               "as during refinement, which casts the blocks' shadows. Solve: "
               f"{record['iterations']} Jacobi sweeps, {seconds:.1f} s of CPU for "
               "refinement, coefficients and sweeps. The toggle shows the element mesh: "
               "the leaves' boundaries seen from the camera.")
    mesh_figure = ReportFigure("cornell-mesh", "Show the element mesh", caption, meshed)
    return ReportFigure("cornell", "The Cornell box rendered from its radiosity solution",
                        caption, plain, alternate=mesh_figure)


def _cpu_seconds(record):
    # A solve record's CPU seconds by stage, in the order the solve runs them.
    return {s: record[f"cpu_seconds_{s}"] for s in ("refine", "coefficients", "solve")}


#: The bunny in its box (`make bunny-box`; docs/meshes.md): the mesh, relative to the
#: working directory, then eps, oracle, min-area and the solve's options: clusters, and
#: occlusion sampled from 2 x 2 points an element side and 2 sample patches a cluster end.
BUNNY = (Path("data/meshes/bunny_box.obj"), 0.5, "garmann", 1e-3,
         {"clusters": True, "rays_per_side": 2})

#: From inside the box near a top corner, toward the bunny.
BUNNY_CAMERA = Camera(eye=(0.96, 0.85, 0.96), look_at=(0.45, 0.3, 0.45), up=(0.0, 1.0, 0.0),
                      fov=80)


def bunny_figure(engine, results, jobs=1):
    """The Stanford bunny in its lit box, refined and solved through clusters.

    Parameters
    ----------
    engine : str, path-like or sequence of them
    results : pathlib.Path
        Folder for the solve's CSV file (``solution-bunny.csv``).
    jobs : int, optional
        Threads of the solve; the solution does not depend on them.

    Returns
    -------
    figure : ReportFigure

    Raises
    ------
    FileNotFoundError
        If the mesh is not there (``make bunny-box`` makes it).
    """
    mesh, eps, oracle, min_area, options = BUNNY
    if not mesh.is_file():
        raise FileNotFoundError(f"{mesh} is missing (make bunny-box writes it)")
    path = results / "solution-bunny.csv"
    record = solve_to_csv(engine, MESH_SCENE, {}, eps, oracle,
                          options | {"mesh": str(mesh), "threads": jobs}, path,
                          min_area=min_area)
    seconds = _cpu_seconds(record)
    balance = record["absorbed_power"] / record["emitted_power"] - 1
    more = "more" if balance >= 0 else "less"
    # In plain words: "+5.3% of the emitted power" read as a share absorbed.
    energy = (f"the surfaces absorb {abs(balance):.1%} {more} power than the lamp emits "
              f"({record['absorbed_power']:.3g} against {record['emitted_power']:.3g})")
    facts = (f"{record['patches']:,} patches, {record['links']:,} links "
             f"({record['cluster_links']:,} cluster links)\n{energy[0].upper() + energy[1:]}, "
             f"{sum(seconds.values()):.0f} s of CPU")
    image = render_figure(read_solution(path), title=facts, camera=BUNNY_CAMERA)
    caption = ("The Stanford bunny (75,408 triangles, from Debian's libcgal-demo) in a closed "
               "box of 8 x 8 cells a wall lit by the four central cells of its ceiling, seen "
               "from inside near a top corner, every leaf drawn flat in grey at the "
               "brightness of its radiosity (the colour bar; the legend gives each "
               "material's reflectance), the lamp outlined. Without clusters its "
               "refinement would start from 2.9e9 pairs of root patches; through the "
               f"cluster tree (--clusters) it reaches {record['root_pairs']:,} of them and "
               f"makes {record['cluster_links']:,} links with a cluster at one end at "
               "least, whose light each cluster's patches share alike: the blocks of "
               "uniform grey on the bunny are such clusters. Occlusion: "
               "each element link is weighed by its sampled visible fraction, each cluster "
               "link by the share of unblocked segments between sample patches of its ends. "
               f"CPU seconds: refinement {seconds['refine']:.1f}, coefficients "
               f"{seconds['coefficients']:.1f}, {record['iterations']} Jacobi sweeps "
               f"{seconds['solve']:.1f}. Energy balance: {energy}; in a closed box every "
               "watt emitted is absorbed once, so the difference is the error of the cluster "
               "links' approximations (docs/meshes.md).")
    return ReportFigure("bunny", "The Stanford bunny in a lit box, solved through clusters",
                        caption, image)


def solution_figures(engine, results, jobs=1, warn=print, progress=None):
    """The report's solution figures that could be made.

    Parameters
    ----------
    engine : str, path-like or sequence of them
    results : pathlib.Path
    jobs : int, optional
    warn : callable, optional
        Called with one line for each figure that could not be made (an engine without
        ``solve`` or the options it needs, or a failed solve); the report goes on.
    progress : text stream, optional
        Where each figure's solves print their progress lines
        (:class:`~hrbench_analysis.stages.Stage`); none by default.

    Returns
    -------
    figures : list of ReportFigure
    """
    figures = []
    for name, make in (("profile", lambda: profile_figure(engine, results)),
                       ("Cornell box", lambda: cornell_figures(engine, results, jobs)),
                       ("bunny", lambda: bunny_figure(engine, results, jobs))):
        try:
            with Stage(f"solving for the {name} figure", stream=progress):
                figures.append(make())
        except (EngineError, ResultFormatError, OSError, KeyError, ValueError) as exc:
            warn(f"warning: no {name} figure: {' '.join(str(exc).split())}")
    return figures
