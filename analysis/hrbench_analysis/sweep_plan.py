"""The points of a sweep: a claim expanded into the engine runs it needs.

One :class:`SweepPoint` per value of the swept parameter and combination of the values
of ``sweep.grid``: its run (:class:`~hrbench_analysis.engine.RunSpec`) and what derives
from it, its cache key, its command line, the commands that measure the hierarchy
statistics of a claim that reads them, and the run it shares with the other points of
its series when the engine counts several values at once (``--sweep``).
:mod:`hrbench_analysis.sweep` runs them.
"""

import itertools
from dataclasses import dataclass, replace

from .engine import RunSpec, format_number
from .engine.run_spec import SWEPT
from .lemmas import STATISTICS_MODE, StatisticsJob
from .store_points import PointKey

__all__ = ["DEFAULT_SWEEP_EXCLUDES", "SweepPoint", "expand_claim", "sweep_excludes"]


@dataclass(frozen=True)
class SweepPoint:
    """One run of a sweep.

    Attributes
    ----------
    key : PointKey
        Cache key of the run (:meth:`RunSpec.key`).
    value : float
        Value of the swept parameter.
    argv : tuple of str
        Command line (the engine's words first; :meth:`RunSpec.argv`).
    statistics : StatisticsJob or None
        For a claim whose formulas read hierarchy statistics (:mod:`hrbench_analysis.lemmas`):
        the commands that measure them after the run; ``None`` otherwise.
    series : str
        The values of ``sweep.grid`` this run belongs to, e.g. ``"l=16"`` ("" without a
        grid).
    shared : SharedRun or None
        For a point of an ``eps`` or ``min_area`` sweep that one engine run can count
        together with the others of its series (``--sweep``): that run, the same for all
        of them; ``None`` otherwise.
    run : RunSpec or None
        What identifies the run, from which `key`, `argv`, `statistics` and `shared` are
        derived.
    """

    key: PointKey
    value: float
    argv: tuple
    statistics: object = None
    series: str = ""
    shared: object = None
    run: RunSpec = None


#: The options taken to exclude ``--sweep`` when the engine's capabilities do not say
#: which do (its ``sweep`` entry has no ``excludes``): those hrbench refused with it
#: before it listed them (docs/engine-contract.md).
DEFAULT_SWEEP_EXCLUDES = frozenset({"threads", "method", "clusters", "link_form_factors"})


def sweep_excludes(capabilities):
    """The options with which the engine cannot count a series in one ``run --sweep``.

    Parameters
    ----------
    capabilities : Capabilities or None

    Returns
    -------
    names : frozenset of str or None
        ``None`` if the engine has no ``--sweep`` for ``run`` (or no capabilities are
        given); else the options its capabilities say exclude ``--sweep``, or
        :data:`DEFAULT_SWEEP_EXCLUDES` where they do not say.
    """
    sweep = None if capabilities is None else capabilities.option("sweep")
    if sweep is None or "run" not in sweep.commands:
        return None
    excluded = capabilities.excluded("sweep")
    return DEFAULT_SWEEP_EXCLUDES if excluded is None else excluded


def expand_claim(claim, mode, hrbench, version, capabilities=None):
    """The runs a claim needs.

    Parameters
    ----------
    claim : Claim
    mode : {"quick", "full"}
        Which of the claim's ranges to sweep.
    hrbench : str, path-like or sequence of them
        The engine: a path, or a command of several words
        (:func:`~hrbench_analysis.engine.engine_argv`).
    version : str
        Engine version, part of every cache key.
    capabilities : Capabilities, optional
        The engine's. Where they list ``--sweep`` for ``run``, the points of a count-only
        sweep over ``eps`` or ``min_area`` whose options the engine takes with it
        (:func:`sweep_excludes`) get a ``shared`` command line; without them, none does.

    Returns
    -------
    points : list of SweepPoint
        One per value of the swept parameter, in sweep order, for every combination of
        the values of ``sweep.grid`` (in the order given); command lines as in
        :func:`hrbench_analysis.engine.run_argv`, or
        :func:`~hrbench_analysis.engine.solve_argv` for a claim with ``command = "solve"``.
    """
    points = []
    options = claim.options_for(mode)
    # A mesh: the file by its path on the command line, by its bytes in the cache key.
    mesh = {} if claim.mesh is None else {"mesh": claim.mesh}
    mesh_sha256 = None if claim.mesh is None else claim.mesh_sha256
    grid = [dict(zip(claim.grid, combo, strict=True))
            for combo in itertools.product(*claim.grid.values())]
    # A solve is its own record (the counters and the solve's measures), never a count's.
    command = getattr(claim, "command", "run")
    excludes = sweep_excludes(capabilities)
    share = (excludes is not None and claim.sweep_param in SWEPT and command == "run"
             and not claim.statistics and not set(options) & excludes)
    for fixed in grid:
        for value in claim.range_for(mode).values():
            params = dict(claim.params) | fixed
            eps, min_area = claim.eps, claim.min_area
            if claim.sweep_param == "eps":
                eps = value
            elif claim.sweep_param == "min_area":
                min_area = value
            else:
                params[claim.sweep_param] = value
            run = RunSpec.of(claim.scene, params, eps, claim.oracle, min_area=min_area,
                             max_depth=claim.max_depth, options=options | mesh,
                             command=command, mesh_sha256=mesh_sha256)
            series = ", ".join(f"{k}={format_number(v)}" for k, v in fixed.items())
            # The run of the series, without the value swept.
            shared = run.shared(hrbench, claim.sweep_param) if share else None
            points.append(SweepPoint(key=run.key(version), value=value,
                                     argv=tuple(run.argv(hrbench)), series=series,
                                     shared=shared, run=run))
    return _with_statistics(claim, points, hrbench, version)


def _with_statistics(claim, points, hrbench, version):
    # A claim whose formulas read hierarchy statistics (lemmas.py) measures them
    # at every point: under its own cache key (mode STATISTICS_MODE, so that a record
    # without them is never reused), with the commands that dump and measure the links.
    if not claim.statistics:
        return points
    return [replace(point, key=point.run.key(version, STATISTICS_MODE),
                    statistics=StatisticsJob.of(point.run, hrbench))
            for point in points]
