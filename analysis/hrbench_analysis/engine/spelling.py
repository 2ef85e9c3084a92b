"""The spelling of numbers, options and scenes on the engine's command line, the words
every command line of :mod:`hrbench_analysis.engine.run_spec` is made of.
"""

from .capabilities import MESH_SCENE

__all__ = ["format_number", "option_flag", "option_text", "option_argv", "scene_argv",
           "checked_options", "checked_params"]


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


def checked_options(options):
    # `options` itself, or a TypeError naming what is not an option value.
    if not isinstance(options, dict):
        raise TypeError(f"options must be a dict of option name to value, got {options!r}")
    for name, value in options.items():
        if value is not True and (isinstance(value, bool)
                                  or not isinstance(value, (str, int, float))):
            raise TypeError(f"options[{name!r}] must be a string, an integer, a float or "
                            f"True (a flag), got {value!r}")
    return options


def checked_params(params):
    # `params` itself, or a TypeError naming what is not a number.
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
    for name, value in sorted(checked_options(options).items()):
        argv += [option_flag(name)] if value is True else [option_flag(name), option_text(value)]
    return argv


def scene_argv(scene, params):
    # ["parallel", "d=1", "l=8"]: parameters sorted by name. A mesh comes as the option
    # `mesh` instead (MESH_SCENE has no parameters).
    if scene == MESH_SCENE:
        return []
    return [scene, *(f"{k}={format_number(v)}" for k, v in sorted(checked_params(params).items()))]
