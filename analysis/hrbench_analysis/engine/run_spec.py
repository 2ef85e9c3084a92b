"""What identifies one engine run, and everything derived from it: its command lines
(``run``, ``solve``, and the ``links`` and ``save`` of the same refinement), the shared
``--sweep`` run of a series, and its key in the results cache.

A :class:`RunSpec` is built once from a claim's point (or a figure's settings); its key
and its command lines never come from separate copies of the same fields, so they cannot
disagree.
"""

import os
from dataclasses import dataclass, replace

from ..store_points import PointKey
from .capabilities import MESH_SCENE
from .locate import engine_argv
from .spelling import (
    checked_options,
    checked_params,
    format_number,
    option_argv,
    option_text,
    scene_argv,
)

__all__ = ["RunSpec", "SharedRun", "COMMANDS", "SWEPT"]

#: The refinement commands a :class:`RunSpec` runs, with the ``mode`` of their cache key:
#: a count (``run ... --count-only --json``) or a solve (``solve ... --json``).
COMMANDS = {"run": "count-only", "solve": "solve"}
#: The parameters one ``run --sweep`` varies.
SWEPT = ("eps", "min_area")


@dataclass(frozen=True)
class RunSpec:
    """Everything that determines one engine run (the engine itself aside).

    Build it with :meth:`of`, which checks and sorts the parameters and options.

    Attributes
    ----------
    scene : str
        Scene family.
    params : tuple of (str, float)
        Scene parameters, sorted by name (scene units).
    eps : float or None
        Oracle threshold (dimensionless); ``None`` only where no command line needs it
        (``save``, or the swept value of a :class:`SharedRun`).
    oracle : str
        Oracle name.
    min_area : float or None
        ``--min-area`` (scene units), if given.
    max_depth : int or None
        ``--max-depth`` (levels), if given.
    options : tuple of (str, object)
        Further engine options as :func:`~hrbench_analysis.engine.option_argv` spells
        them, sorted by name; a mesh is the option ``mesh``, its path.
    command : {"run", "solve"}
        What the run does: count the hierarchy, or solve its radiosity too.
    mesh_sha256 : str or None
        With a mesh: the SHA-256 of its bytes, which its key holds instead of the path
        (the file by its path on the command line, by its bytes in the cache key).
    """

    scene: str
    params: tuple
    eps: object
    oracle: str = "garmann"
    min_area: object = None
    max_depth: object = None
    options: tuple = ()
    command: str = "run"
    mesh_sha256: object = None

    @classmethod
    def of(cls, scene, params, eps, oracle="garmann", min_area=None, max_depth=None,
           options=None, command="run", mesh_sha256=None):
        """A run from plain values: `params` and `options` as dicts.

        Raises
        ------
        TypeError
            If `params` is not a dict of numbers (a mesh scene takes none), or `options`
            not a dict of strings, integers, floats or ``True`` (a flag).
        ValueError
            If `command` is not one of :data:`COMMANDS`.
        """
        if command not in COMMANDS:
            raise ValueError(f"command must be one of {', '.join(COMMANDS)}, got {command!r}")
        params = (params or {}) if scene == MESH_SCENE else checked_params(params)
        options = checked_options(options or {})
        return cls(scene, tuple(sorted(params.items())), eps, oracle, min_area, max_depth,
                   tuple(sorted(options.items())), command, mesh_sha256)

    def without_options(self, *names):
        """The same run less the options `names` (e.g. one a command does not take)."""
        return replace(self, options=tuple((k, v) for k, v in self.options if k not in names))

    # -- the cache key ------------------------------------------------------------------

    def key(self, version, mode=None):
        """The run's key in the results cache.

        Parameters
        ----------
        version : str
            Engine version (``hrbench --version``).
        mode : str, optional
            The key's mode; by default the command's (:data:`COMMANDS`). A run measured
            further (its hierarchy statistics) names its own.

        Returns
        -------
        key : PointKey
            Options as their command-line text; a mesh as ``sha256:<hex>``.
        """
        options = {name: option_text(value) for name, value in self.options}
        if self.mesh_sha256 is not None:
            options["mesh"] = f"sha256:{self.mesh_sha256}"
        return PointKey(version=version, scene=self.scene, params=self.params,
                        eps=float(self.eps), oracle=self.oracle, min_area=self.min_area,
                        max_depth=self.max_depth, mode=mode or COMMANDS[self.command],
                        options=tuple(sorted(options.items())))

    # -- command lines ------------------------------------------------------------------

    def argv(self, hrbench):
        """The run's command line: ``run ... --count-only --json`` or ``solve ... --json``.

        Parameters
        ----------
        hrbench : str, path-like or sequence of them
            The engine: a path, or a command of several words (:func:`engine_argv`).

        Returns
        -------
        argv : list of str
            ``[hrbench, command, scene, params..., "--eps", E, "--oracle", O,
            [--min-area A], [--max-depth D], options..., tail]``.
        """
        tail = ["--count-only", "--json"] if self.command == "run" else ["--json"]
        return self._refine_argv(hrbench, self.command) + tail

    def sweep_argv(self, hrbench, param, values=()):
        """The command line that counts this run at several values of `param` (``eps`` or
        ``min_area``): the ``run`` command line less the swept flag, with ``--sweep
        NAME=V1,V2,...``; with no values it names the parameter alone (``--sweep eps``),
        the shared run's identity."""
        spec = f"{param}=" + ",".join(format_number(v) for v in values) if values else param
        return self._refine_argv(hrbench, "run", swept=param) + [
            "--sweep", spec, "--count-only", "--json"]

    def links_argv(self, hrbench, out=None):
        """The command line that writes the run's link list: ``links ... --out FILE``
        (``--out`` left off when `out` is ``None``: the caller appends it)."""
        argv = self._refine_argv(hrbench, "links")
        return argv + ([] if out is None else ["--out", os.fspath(out)])

    def save_argv(self, hrbench, scene_options=()):
        """The command line that prints the run's scene as JSON: ``save SCENE params...``,
        with those of its options named in `scene_options` (the ones that change the
        patches, which ``save`` takes)."""
        options = {name: value for name, value in self.options if name in scene_options}
        return [*engine_argv(hrbench), "save", *scene_argv(self.scene, dict(self.params)),
                *option_argv(options)]

    def shared(self, hrbench, param):
        """The run that counts this one together with the others of its series that
        differ only in `param` (``--sweep``): the same for all of them."""
        return SharedRun(tuple(engine_argv(hrbench)), replace(self, **{param: None}), param)

    def _refine_argv(self, hrbench, command, swept=None):
        # The words `run`, `solve` and `links` share: scene, threshold, oracle, limits,
        # options; less the one of eps and min_area that --sweep varies (`swept`).
        argv = [*engine_argv(hrbench), command, *scene_argv(self.scene, dict(self.params))]
        if swept != "eps":
            argv += ["--eps", format_number(self.eps)]
        argv += ["--oracle", self.oracle]
        if self.min_area is not None and swept != "min_area":
            argv += ["--min-area", format_number(self.min_area)]
        if self.max_depth is not None:
            argv += ["--max-depth", str(int(self.max_depth))]
        return argv + option_argv(dict(self.options))


@dataclass(frozen=True)
class SharedRun:
    """One engine run that counts several points of a series (``--sweep``).

    Attributes
    ----------
    hrbench : tuple of str
        The engine's words.
    run : RunSpec
        The series' run, the swept parameter ``None``.
    param : str
        The swept parameter, ``"eps"`` or ``"min_area"``.
    """

    hrbench: tuple
    run: RunSpec
    param: str

    def argv(self, values=()):
        """The command line over `values` of the swept parameter (none: its identity)."""
        return self.run.sweep_argv(self.hrbench, self.param, values)
