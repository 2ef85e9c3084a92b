"""What the drawing commands share: one-line usage errors, the engine, the scene words.

``hrbench-tiling``, ``hrbench-render`` and ``hrbench-explorer`` find the engine as
``hrbench-reproduce`` does (``--engine CMD``, ``--hrbench PATH``, ``$HRBENCH_ENGINE``,
``build/hrbench``, ``hrbench`` on the ``PATH``), end every error of input or
environment with one line on standard error and exit code 2, and write their files
through :mod:`hrbench_analysis.output` (exit code 74 when one cannot be written).
"""

import argparse
import io
import math
import os
import stat
from pathlib import Path

from .errors import OneLineParser, shown
from .output import write_file

__all__ = ["Parser", "add_engine_options", "engine_of", "positive_number", "positive_int",
           "output_file", "input_file", "image_side", "MAX_IMAGE_SIDE", "scene_params",
           "figure_png", "save_figure"]


class Parser(OneLineParser):
    """A :class:`~hrbench_analysis.errors.OneLineParser` (usage errors in one line, exit
    2) with the option ``--debug`` of :func:`~hrbench_analysis.errors.run_main`."""

    def __init__(self, *args, **kwargs):
        super().__init__(*args, **kwargs)
        self.add_argument("--debug", action="store_true",
                          help="print the traceback of an internal error (a bug)")


def add_engine_options(parser):
    """Add ``--engine CMD`` and ``--hrbench PATH`` (as ``hrbench-reproduce`` has them)."""
    # Imported here: reproduce_options imports this module.
    from .reproduce_options import _engine_arg

    group = parser.add_mutually_exclusive_group()
    group.add_argument("--engine", type=_engine_arg, default=None, metavar="CMD",
                       help="the engine command, split into words like a shell (default: "
                       "$HRBENCH_ENGINE, else build/hrbench under the current directory, "
                       "else hrbench on the PATH)")
    group.add_argument("--hrbench", dest="engine", type=Path, metavar="PATH",
                       help="the engine as the path of one executable (never split)")


def engine_of(args):
    """The engine the options name, else
    :func:`hrbench_analysis.reproduce_options.default_engine`."""
    from .reproduce_options import default_engine

    return args.engine if args.engine is not None else default_engine()


def positive_number(text):
    """argparse type: a finite number > 0 (an eps, a length)."""
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"'{shown(text)}' is not a number") from None
    if not (math.isfinite(value) and value > 0):
        raise argparse.ArgumentTypeError(f"'{shown(text)}' is not a finite number > 0")
    return value


def input_file(text):
    """argparse type: a regular file to read (a mesh). A FIFO, a device or a folder is
    refused at once: the engine would wait on a FIFO for a writer that may never come."""
    try:
        mode = os.stat(text).st_mode
    except (OSError, ValueError) as exc:
        reason = exc.strerror if isinstance(exc, OSError) else "a NUL in the name"
        raise argparse.ArgumentTypeError(f"'{shown(text)}': cannot read ({reason})") from None
    if not stat.S_ISREG(mode):
        raise argparse.ArgumentTypeError(f"'{shown(text)}' is not a regular file")
    return Path(text)


#: Pixels of the longest side of an image (``--size``): 8192 x 8192 RGBA is 256 MiB.
MAX_IMAGE_SIDE = 8192


def image_side(text):
    """argparse type: an image side in pixels, 1 to :data:`MAX_IMAGE_SIDE`."""
    value = positive_int(text)
    if value > MAX_IMAGE_SIDE:
        raise argparse.ArgumentTypeError(f"{value} pixels is more than the {MAX_IMAGE_SIDE} "
                                         "an image side may have")
    return value


def output_file(text):
    """argparse type: a file to write, in a folder that exists (checked before any run)."""
    path = Path(text)
    if not path.parent.is_dir():
        raise argparse.ArgumentTypeError(f"{text}: folder {path.parent} does not exist")
    if path.is_dir():
        raise argparse.ArgumentTypeError(f"{text} is a folder")
    return path


def positive_int(text):
    """argparse type: an integer >= 1 (a count)."""
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"'{shown(text)}' is not an integer") from None
    if value < 1:
        raise argparse.ArgumentTypeError(f"'{shown(text)}' is not an integer >= 1")
    return value


def scene_params(parser, words):
    """The scene family and its parameters of ``SCENE key=value ...``.

    Parameters
    ----------
    parser : Parser
        Reports a malformed word as a usage error.
    words : list of str
        E.g. ``["parallel", "l=8", "d=1"]``.

    Returns
    -------
    scene : str
    params : dict of str to float
        The engine checks the names and ranges itself (its message is passed on).
    """
    scene, *pairs = words
    if "=" in scene:
        parser.error(f"the scene family comes first, got '{shown(scene)}'")
    params = {}
    for pair in pairs:
        name, sep, text = pair.partition("=")
        try:
            value = float(text)
        except ValueError:
            value = math.nan
        if not sep or not name or not math.isfinite(value):
            parser.error(f"scene parameter '{shown(pair)}' is not name=number")
        params[name] = value
    return scene, params


def figure_png(fig, dpi=100):
    """The bytes of a figure as PNG."""
    png = io.BytesIO()
    fig.savefig(png, dpi=dpi, format="png")
    return png.getvalue()


def save_figure(fig, out, dpi=100):
    """Write a figure as PNG to `out` (:func:`~hrbench_analysis.output.write_file`)."""
    write_file(out, figure_png(fig, dpi))
