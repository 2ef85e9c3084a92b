"""Finding an engine: the words that start its command lines, whether it can be started,
its version (``hrbench --version``) and its capabilities.
"""

import os
import shlex
import shutil

from .capabilities import CAPABILITIES_SCHEMA_VERSION, CapabilitiesError, parse_capabilities
from .process import EngineError, run_engine


def engine_argv(hrbench):
    """The words that start every command line of an engine.

    Parameters
    ----------
    hrbench : str, path-like or sequence of them
        The path of an executable (one word, never split), or a command of several words,
        e.g. ``("python3", "examples/external_engine/engine.py")``.

    Returns
    -------
    words : list of str

    Raises
    ------
    EngineError
        If `hrbench` is an empty sequence.
    """
    if isinstance(hrbench, (str, os.PathLike)):
        return [os.fspath(hrbench)]
    words = [os.fspath(word) for word in hrbench]
    if not words:
        raise EngineError("the engine command is empty")
    return words


def engine_text(hrbench):
    """The engine command as one line of shell text, for messages and reports."""
    return shlex.join(engine_argv(hrbench))


def find_engine(hrbench):
    """Check that an engine can be started: its program exists and may be run.

    Parameters
    ----------
    hrbench : str, path-like or sequence of them
        As in :func:`engine_argv`. A program named with a ``/`` is a path (relative to
        the current directory); one without is looked up on the ``PATH``.

    Returns
    -------
    words : list of str
        :func:`engine_argv` of `hrbench`.

    Raises
    ------
    EngineError
        If the program is not an executable file, or not on the ``PATH``.
    """
    words = engine_argv(hrbench)
    program = words[0]
    if os.sep in program or (os.altsep and os.altsep in program):
        found = os.path.isfile(program) and os.access(program, os.X_OK)
    else:
        found = shutil.which(program) is not None
    if not found:
        raise EngineError(f"engine not found or not executable: {program} "
                          "(build it first, or pass --engine CMD)")
    return words


def engine_version(hrbench):
    """The version string of an engine: the first line of ``hrbench --version``.

    Parameters
    ----------
    hrbench : str, path-like or sequence of them
        The engine: a path, or a command of several words (:func:`engine_argv`).

    Returns
    -------
    version : str
        E.g. ``"hrbench 0.3.0"`` (part of every cache key).

    Raises
    ------
    EngineError
        If the executable is missing or ``--version`` fails.
    """
    words = find_engine(hrbench)
    run = run_engine([*words, "--version"], timeout=60)
    lines = run.stdout.strip().splitlines()
    if run.exit_code != 0 or not lines:
        raise EngineError(f"{shlex.join(words)} --version failed with exit code "
                          f"{run.exit_code}"
                          + (f": {run.message}" if run.message else ""))
    return lines[0].strip()


def get_capabilities(hrbench, timeout=60):
    """What an engine offers, from ``hrbench capabilities --json``.

    Parameters
    ----------
    hrbench : str, path-like or sequence of them
        The engine: a path, or a command of several words (:func:`engine_argv`).
    timeout : float, optional
        Seconds to wait for the command.

    Returns
    -------
    capabilities : Capabilities

    Raises
    ------
    EngineError
        If the executable is missing.
    CapabilitiesError
        If the engine has no ``capabilities`` command (it exits non-zero) or prints
        something else than the format. The message is one line naming the engine; the
        analysis then exits with code 2.
    """
    words = find_engine(hrbench)
    path = shlex.join(words)
    run = run_engine([*words, "capabilities", "--json"], timeout=timeout)
    if run.exit_code != 0:
        raise CapabilitiesError(
            f"engine {path} has no usable 'capabilities --json' command (exit code "
            f"{run.exit_code}: {run.message or 'no message'}); this analysis needs an engine "
            f"that lists its capabilities (schema_version {CAPABILITIES_SCHEMA_VERSION})")
    return parse_capabilities(run.stdout, engine=path)
