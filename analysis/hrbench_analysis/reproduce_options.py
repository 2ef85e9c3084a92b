"""The options of ``hrbench-reproduce`` and ``hrbench-sweep``, and the engine they run.

The parsers of both commands (:mod:`hrbench_analysis.reproduce`) and the engine when no
option names one (:func:`default_engine`): ``$HRBENCH_ENGINE``, ``build/hrbench`` under
the current directory or ``hrbench`` on the ``PATH``. The drawing commands take the same
engine options (:func:`hrbench_analysis.cli.add_engine_options`).
"""

import argparse
import os
import shlex
import shutil
from pathlib import Path

from .cli import positive_number
from .engine import EngineError
from .errors import OneLineParser
from .schedulers import LOCAL, SchedulerError, check_scheduler

__all__ = ["CLAIMS_DIR", "ENGINE_ENV", "default_engine"]

#: The claims shipped with the package.
CLAIMS_DIR = Path(__file__).resolve().parent / "claims"

#: The environment variable that names the engine command when ``--engine`` is not given.
ENGINE_ENV = "HRBENCH_ENGINE"


def _engine_words(text, where=""):
    # A command line as its words (shell quoting rules), or a one-line error.
    where = f"{where}: " if where else ""
    try:
        words = shlex.split(text)
    except ValueError as exc:
        raise EngineError(f"{where}cannot split {text!r} into words ({exc})") from None
    if not words:
        raise EngineError(f"{where}the engine command is empty")
    return tuple(words)


def default_engine():
    """The engine to run when neither ``--engine`` nor ``--hrbench`` is given.

    In this order: the command in ``$HRBENCH_ENGINE`` (:data:`ENGINE_ENV`, split into words
    like a shell); ``build/hrbench`` under the current directory, if it exists;
    ``hrbench`` on the ``PATH``.

    Returns
    -------
    engine : tuple of str or Path
        A command of several words, or the path of an executable
        (:func:`~hrbench_analysis.engine.engine_argv`).

    Raises
    ------
    EngineError
        If there is none of them (one line naming the three ways to give one).
    """
    text = os.environ.get(ENGINE_ENV, "")
    if text.strip():
        return _engine_words(text, f"${ENGINE_ENV}")
    local = Path("build") / "hrbench"
    if local.exists():
        return local
    found = shutil.which("hrbench")
    if found:
        return Path(found)
    raise EngineError(f"no engine: pass --engine CMD, set ${ENGINE_ENV}, run from a "
                      "directory that holds build/hrbench, or put hrbench on the PATH")


def _engine_arg(text):
    # argparse type of --engine: the words of a command.
    try:
        return _engine_words(text)
    except EngineError as exc:
        raise argparse.ArgumentTypeError(str(exc)) from None


def _scheduler_arg(text):
    try:
        return check_scheduler(text)
    except SchedulerError as exc:
        raise argparse.ArgumentTypeError(str(exc)) from None


def _parser(prog="hrbench-reproduce",
            description="Sweep the hrbench engine, fit exponents and judge the published "
                        "claims."):
    p = OneLineParser(prog=prog, description=description)
    p.add_argument("--debug", action="store_true",
                   help="print the traceback of an internal error (a bug)")
    mode = p.add_mutually_exclusive_group()
    mode.add_argument("--quick", dest="mode", action="store_const", const="quick",
                      help="short sweeps, a few minutes on two cores (default)")
    mode.add_argument("--full", dest="mode", action="store_const", const="full",
                      help="longer sweeps over more decades")
    p.add_argument("--jobs", type=int, default=os.cpu_count() or 1, metavar="N",
                   help="concurrent engine runs (default: number of cores, %(default)s)")
    p.add_argument("--run-timeout", type=positive_number, default=None, metavar="SECONDS",
                   help="end an engine run, with its child processes, after this many "
                   "seconds; the point fails and is run again next time (default: no limit)")
    p.add_argument("--scheduler", type=_scheduler_arg, default=LOCAL, metavar="S",
                   help="where the engine runs execute: 'local' (default: a pool of --jobs "
                   "threads), 'dask' (a dask.distributed LocalCluster of --jobs worker "
                   "processes) or tcp://HOST:PORT (an existing Dask cluster, all its "
                   "workers); the results cache stays here, so results do not depend on it")
    p.add_argument("--results", type=Path, default=Path("results"), metavar="DIR",
                   help="results directory: cache, report, plots (default: results/ under "
                   "the current directory)")
    p.add_argument("--cache", type=Path, default=None, metavar="FILE",
                   help="the results cache, which sweeps running at the same time may "
                   "share (default: DIR/hrbench.sqlite of --results)")
    engine = p.add_mutually_exclusive_group()
    engine.add_argument("--engine", type=_engine_arg, default=None, metavar="CMD",
                        help="the engine command, split into words like a shell, e.g. "
                        "'python3 my_engine.py' (default: $HRBENCH_ENGINE, else "
                        "build/hrbench under the current directory, else hrbench on the "
                        "PATH); docs/engine-contract.md says what it must do")
    engine.add_argument("--hrbench", dest="engine", type=Path, metavar="PATH",
                        help="the engine as the path of one executable (never split)")
    p.add_argument("--claims", type=Path, default=CLAIMS_DIR, metavar="PATH",
                   help="a claims file, or a directory of *.toml claims files (default: "
                   "the claims shipped with the package)")
    p.add_argument("--claim", action="append", default=[], metavar="ID",
                   help="judge only this claim (repeatable)")
    p.set_defaults(mode="quick")
    return p


def _reproduce_parser():
    p = _parser()
    p.add_argument("--no-pictures", action="store_true",
                   help="draw no figure at all: no charts, no link tiling ('hrbench "
                   "links'), no radiosity profile, Cornell box or bunny ('hrbench solve'), "
                   "no explorer page; the report keeps its tables and verdicts")
    p.add_argument("--charts-only", "--no-tiling", dest="charts_only", action="store_true",
                   help="draw only the charts of the sweeps' points: no figure that needs "
                   "runs of its own (the link tiling, the solves' pictures, the explorer "
                   "page)")
    return p


def _sweep_parser():
    p = _parser(prog="hrbench-sweep",
                description="Run the sweeps of claims (reusing the results cache) and write "
                "their measured points as CSV, without fits or verdicts.")
    p.add_argument("--out", type=Path, default=None, metavar="FILE",
                   help="CSV file to write (default: standard output)")
    return p
