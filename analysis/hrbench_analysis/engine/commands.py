"""The command lines of engine runs from loose values: ``run``, ``solve``, ``links`` and
``save``, each the command line of a :class:`~hrbench_analysis.engine.run_spec.RunSpec`
built from them; and writing a link list (:func:`write_links`).
"""

from .process import EngineError, run_engine
from .run_spec import RunSpec


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
    return RunSpec.of(scene, params, eps, oracle, min_area, max_depth, options).argv(hrbench)


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
    run = RunSpec.of(scene, params, eps, oracle, min_area, max_depth, options)
    return run.sweep_argv(hrbench, name, values)


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
    run = RunSpec.of(scene, params, eps, oracle, min_area, max_depth, options, "solve")
    return run.argv(hrbench)


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
    run = RunSpec.of(scene, params, eps, oracle, min_area, max_depth, options)
    return run.links_argv(hrbench, out)


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
    return RunSpec.of(scene, params, None).save_argv(hrbench)


def run_links(hrbench, scene, params, eps, out, oracle="garmann"):
    """Write the link list of one refinement with ``hrbench links``.

    Parameters are those of :func:`links_argv`.

    Raises
    ------
    EngineError
        If the run fails; the message holds its exit code and last line of standard error.
    """
    write_links(hrbench, RunSpec.of(scene, params, eps, oracle), out)


def write_links(hrbench, spec, out):
    """Write the link list of `spec`'s run (a :class:`RunSpec`) with ``hrbench links --out``.

    Raises
    ------
    EngineError
        If the run fails; the message holds its exit code and last line of standard error.
    """
    run = run_engine(spec.links_argv(hrbench, out))
    if run.exit_code != 0:
        raise EngineError(f"{' '.join(run.argv[1:])} failed with exit code {run.exit_code}: "
                          f"{run.message or 'no message'}")
