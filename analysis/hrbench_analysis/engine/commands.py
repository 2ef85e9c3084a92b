"""The command lines of engine runs: ``run``, ``solve``, ``links`` and ``save``, and the
spelling of numbers and options on them.
"""

import os
from dataclasses import dataclass

from .capabilities import MESH_SCENE
from .locate import engine_argv
from .process import EngineError, run_engine


def format_number(value):
    """Format a number for the command line.

    Parameters
    ----------
    value : float
        Any finite number (in its parameter's unit).

    Returns
    -------
    text : str
        Up to 10 significant digits, or as many as it takes to give back exactly the same
        double (``repr``).
    """
    value = float(value)
    text = f"{value:.10g}"
    return text if float(text) == value else repr(value)


def option_flag(name):
    """The command-line flag of an option name: ``"rays_per_side"`` -> ``"--rays-per-side"``.

    This is the engine's rule for every option (the ``flag`` of its capabilities).
    """
    return "--" + name.replace("_", "-")


def option_text(value):
    """The command-line form of an option value.

    Parameters
    ----------
    value : str, bool, int or float

    Returns
    -------
    text : str
        A string as it is, an integer exactly, a float as in :func:`format_number`,
        ``True`` (a flag) as ``"true"``.
    """
    if value is True:
        return "true"
    if isinstance(value, str):
        return value
    if isinstance(value, int) and not isinstance(value, bool):
        return str(value)
    return format_number(value)


def _options_iv(options):
    if not isinstance(options, dict):
        raise TypeError(f"options must be a dict of option name to value, got {options!r}")
    for name, value in options.items():
        if value is not True and (isinstance(value, bool)
                                  or not isinstance(value, (str, int, float))):
            raise TypeError(f"options[{name!r}] must be a string, an integer, a float or "
                            f"True (a flag), got {value!r}")
    return options


def _params_iv(params):
    if not isinstance(params, dict):
        raise TypeError(f"params must be a dict of parameter name to number, got {params!r}")
    for name, value in params.items():
        if isinstance(value, bool) or not isinstance(value, (int, float)):
            raise TypeError(f"params[{name!r}] must be a number, got {value!r}")
    return params


def option_argv(options):
    """The command-line form of engine options.

    Parameters
    ----------
    options : dict of str to (str, int, float or True)
        E.g. ``{"rays_per_side": 4, "triangulate": True, "visibility": "fraction"}``.

    Returns
    -------
    argv : list of str
        ``["--rays-per-side", "4", "--triangulate", "--visibility", "fraction"]``: sorted
        by name, flags as in :func:`option_flag`, values as in :func:`option_text`; an
        option whose value is ``True`` is a flag without a value.

    Raises
    ------
    TypeError
        If `options` is not a dict, or a value is not a string, integer or float.
    """
    argv = []
    for name, value in sorted(_options_iv(options).items()):
        argv += [option_flag(name)] if value is True else [option_flag(name), option_text(value)]
    return argv


def _scene_argv(scene, params):
    # ["parallel", "d=1", "l=8"]: parameters sorted by name. A mesh comes as the option
    # `mesh` instead (MESH_SCENE has no parameters).
    if scene == MESH_SCENE:
        return []
    return [scene, *(f"{k}={format_number(v)}" for k, v in sorted(_params_iv(params).items()))]


def run_argv(hrbench, scene, params, eps, oracle, min_area=None, max_depth=None,
             options=None):
    """The command line of one counting run: ``hrbench run ... --count-only --json``.

    Parameters
    ----------
    hrbench : str, path-like or sequence of them
        The engine: a path, or a command of several words (:func:`engine_argv`).
    scene : str
        Scene family.
    params : dict of str to float
        Scene parameters (scene units), written ``name=value`` sorted by name.
    eps : float
        Oracle threshold (dimensionless).
    oracle : str
        Oracle name.
    min_area : float, optional
        ``--min-area`` (scene units).
    max_depth : int, optional
        ``--max-depth`` (levels).
    options : dict of str to (str, int or float), optional
        Further options, as in :func:`option_argv`.

    Returns
    -------
    argv : list of str
        ``[hrbench, "run", scene, params..., "--eps", E, "--oracle", O, [--min-area A],
        [--max-depth D], options..., "--count-only", "--json"]``.
    """
    return (_refine_argv(hrbench, "run", scene, params, eps, oracle, min_area, max_depth,
                         options) + ["--count-only", "--json"])


def sweep_argv(hrbench, scene, params, eps, oracle, sweep, min_area=None, max_depth=None,
               options=None):
    """The command line of one counting run over several values of eps or ``--min-area``:
    ``hrbench run ... --sweep NAME=V1,V2,... --count-only --json``.

    Parameters
    ----------
    hrbench, scene, params, eps, oracle, min_area, max_depth, options
        As in :func:`run_argv`; the one of `eps` and `min_area` that `sweep` names is
        left out (the run takes its values from ``--sweep``).
    sweep : (str, sequence of float)
        The parameter (``"eps"`` or ``"min_area"``) and its values; with no values the
        command line names the parameter alone (``--sweep eps``), the run's identity.

    Returns
    -------
    argv : list of str
        As :func:`run_argv`'s, less the swept flag and its value, with ``--sweep`` before
        ``--count-only --json``.
    """
    name, values = sweep
    argv = _refine_argv(hrbench, "run", scene, params, eps, oracle, min_area, max_depth,
                        options, swept=name)
    spec = f"{name}=" + ",".join(format_number(v) for v in values) if values else name
    return argv + ["--sweep", spec, "--count-only", "--json"]


@dataclass(frozen=True)
class SharedRun:
    """One engine run that counts several points of a series (``--sweep``): what
    :func:`sweep_argv` builds its command line from, less the
    values.

    Attributes
    ----------
    hrbench : tuple of str
        The engine's words.
    scene : str
    params : tuple of (str, float)
        Scene parameters, sorted by name.
    eps : float or None
        ``None`` when it is the swept parameter.
    oracle : str
    param : str
        The swept parameter, ``"eps"`` or ``"min_area"``.
    min_area : float or None
        ``None`` when it is the swept parameter.
    max_depth : int or None
    options : tuple of (str, object)
        Engine options, sorted by name.
    """

    hrbench: tuple
    scene: str
    params: tuple
    eps: object
    oracle: str
    param: str
    min_area: object
    max_depth: object
    options: tuple

    def argv(self, values=()):
        """The command line over `values` of the swept parameter (none: its identity)."""
        return sweep_argv(self.hrbench, self.scene, dict(self.params), self.eps, self.oracle,
                          (self.param, values), min_area=self.min_area,
                          max_depth=self.max_depth, options=dict(self.options))


def solve_argv(hrbench, scene, params, eps, oracle, min_area=None, max_depth=None,
               options=None):
    """The command line of one solve: ``hrbench solve ... --json``.

    Parameters are those of :func:`run_argv`; the options must be ones ``solve`` accepts
    (``emission``, ``reference``, ``tolerance``, ...).

    Returns
    -------
    argv : list of str
        ``[hrbench, "solve", scene, params..., "--eps", E, "--oracle", O, [limits],
        options..., "--json"]``.
    """
    return (_refine_argv(hrbench, "solve", scene, params, eps, oracle, min_area, max_depth,
                         options) + ["--json"])


def links_argv(hrbench, scene, params, eps, out, oracle="garmann", min_area=None,
               max_depth=None, options=None):
    """The command line that writes a link list: ``hrbench links ... --out FILE``.

    Parameters
    ----------
    hrbench : str, path-like or sequence of them
        The engine: a path, or a command of several words (:func:`engine_argv`).
    scene : str
        Scene family.
    params : dict of str to float
        Scene parameters (scene units).
    eps : float
        Oracle threshold (dimensionless).
    out : str or path-like or None
        CSV file to write; ``None`` leaves ``--out FILE`` off (the caller appends it).
    oracle : str, optional
        Oracle name (the claims' default, ``garmann``, by default).
    min_area, max_depth, options : optional
        Recursion limits and further options, as in :func:`run_argv` (the options must
        be ones ``links`` accepts).

    Returns
    -------
    argv : list of str
    """
    argv = _refine_argv(hrbench, "links", scene, params, eps, oracle, min_area, max_depth,
                        options)
    return argv + ([] if out is None else ["--out", os.fspath(out)])


def _refine_argv(hrbench, command, scene, params, eps, oracle, min_area, max_depth,
                 options, swept=None):
    # The words `run`, `solve` and `links` share: scene, threshold, oracle, limits, options;
    # less the one of eps and min_area that --sweep varies (`swept`).
    argv = [*engine_argv(hrbench), command, *_scene_argv(scene, params)]
    if swept != "eps":
        argv += ["--eps", format_number(eps)]
    argv += ["--oracle", oracle]
    if min_area is not None and swept != "min_area":
        argv += ["--min-area", format_number(min_area)]
    if max_depth is not None:
        argv += ["--max-depth", str(int(max_depth))]
    return argv + option_argv(options or {})


def save_argv(hrbench, scene, params):
    """The command line that prints a scene's patches as JSON: ``hrbench save SCENE ...``.

    Parameters
    ----------
    hrbench : str, path-like or sequence of them
        The engine: a path, or a command of several words (:func:`engine_argv`).
    scene : str
        Scene family.
    params : dict of str to float
        Scene parameters (scene units).

    Returns
    -------
    argv : list of str
    """
    return [*engine_argv(hrbench), "save", *_scene_argv(scene, params)]


def run_links(hrbench, scene, params, eps, out, oracle="garmann"):
    """Write the link list of one refinement with ``hrbench links``.

    Parameters are those of :func:`links_argv`.

    Raises
    ------
    EngineError
        If the run fails; the message holds its exit code and last line of standard error.
    """
    run = run_engine(links_argv(hrbench, scene, params, eps, out, oracle))
    if run.exit_code != 0:
        raise EngineError(f"{' '.join(run.argv[1:])} failed with exit code {run.exit_code}: "
                          f"{run.message or 'no message'}")
