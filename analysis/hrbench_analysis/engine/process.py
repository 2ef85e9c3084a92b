"""Running the engine: every engine process of the analysis is started by
:func:`run_engine`, in a process group of its own that is killed when the engine exits,
times out, prints too much or the analysis is interrupted (:func:`ending_engine_runs`).
On Linux the engine is also killed (SIGKILL) when the analysis itself dies, however it
dies (SIGKILL of it or of its process group included): the parent-death signal of
:func:`start_process`, so that no engine outlives the tool that started it.

Exit codes of the engine (README.md): 0 success, 1 internal error, 2 usage or input
error (:data:`INPUT_ERROR`), 3 a limit reached during refinement (:data:`LIMIT_REACHED`).
A run that could not be started has exit code 127 (:data:`NOT_STARTED`).
"""

import ctypes
import os
import selectors
import signal
import subprocess
import threading
import time
from contextlib import contextmanager
from dataclasses import dataclass

from ..errors import AnalysisError

#: Exit code of an engine run refused as a usage or input error (bad parameter value,
#: touching patches without a recursion limit, ...): the analysis exits with 2 as well.
INPUT_ERROR = 2
#: Exit code of an engine run that reached a limit during refinement (the safety depth,
#: the memory budget): a failed point of the sweep, left out of the fit.
LIMIT_REACHED = 3
#: Exit code of :func:`run_engine` for a process that could not be started.
NOT_STARTED = 127


class EngineError(AnalysisError, RuntimeError):
    """The engine cannot be used: missing, not executable, or a command of it failed."""


#: Bytes of standard output an engine run may print: the largest record the analysis
#: reads (``save`` of a 2D scene of 100,000 patches, ``run --sweep`` over thousands of
#: values) is a few MiB. A run that prints more is ended with its child processes and
#: fails as breaking the engine contract; its output is never read into memory whole.
OUTPUT_LIMIT = 64 * 2**20
#: Bytes of the end of standard error that are kept (the message is its last line).
STDERR_KEPT = 64 * 2**10
#: Seconds to read the pipes of an engine that has exited and whose process group is
#: killed: only a process that left the group can hold them longer, and is not waited for.
DRAIN_SECONDS = 2.0
#: Seconds between two looks at whether the engine has exited, while it prints nothing.
POLL_SECONDS = 0.05

#: Why the analysis ended an engine process (:attr:`EngineRun.stopped`): it ran past
#: its timeout,
TIMED_OUT = "timeout"
#: ... it printed more than :data:`OUTPUT_LIMIT` bytes on standard output,
OUTPUT_EXCEEDED = "output"
#: ... or the analysis was interrupted (SIGINT or SIGTERM).
INTERRUPTED = "interrupt"


class Interrupted(KeyboardInterrupt):
    """SIGINT or SIGTERM reached the analysis; every engine run it had started is ended.

    A :class:`KeyboardInterrupt`, so that what ends a command on Ctrl-C ends it on
    SIGTERM as well. :attr:`exit_code` is the shell's code for the signal: 130 for
    SIGINT, 143 for SIGTERM.
    """

    def __init__(self, signum):
        super().__init__(signal.Signals(signum).name)
        self.signum = int(signum)

    @property
    def exit_code(self):
        """int: ``128 + signum``."""
        return 128 + self.signum


def interrupt_exit_code(exc):
    """The exit code for an interrupt: 128 + the signal (130 for a plain Ctrl-C)."""
    return getattr(exc, "exit_code", 128 + signal.SIGINT)


@dataclass(frozen=True)
class EngineRun:
    """One finished engine process.

    Attributes
    ----------
    argv : tuple of str
        The command line.
    exit_code : int
        Exit code (negative for a signal; 127 when it could not be started).
    stdout, stderr : str
        What it printed: standard output up to :data:`OUTPUT_LIMIT` bytes, the last
        :data:`STDERR_KEPT` bytes of standard error.
    wall_seconds : float
        Wall time of the process (s).
    stopped : str
        Why the analysis ended the process: ``""`` (it ended by itself),
        :data:`TIMED_OUT`, :data:`OUTPUT_EXCEEDED` or :data:`INTERRUPTED`.
    reason : str
        One line saying so (``""`` when `stopped` is).
    """

    argv: tuple
    exit_code: int
    stdout: str
    stderr: str
    wall_seconds: float
    stopped: str = ""
    reason: str = ""

    @property
    def message(self):
        """str: why the analysis ended the process, else the last non-empty line of
        standard error ("" if none)."""
        if self.stopped:
            return self.reason
        lines = [line.strip() for line in self.stderr.splitlines() if line.strip()]
        return lines[-1] if lines else ""


# The engine processes of this process that have not been reaped, and whether new ones
# may start. Guarded by _lock (reentrant: the signal handler runs in the main thread,
# which may hold it). A process leaves _live before it is reaped, so that its group id
# is never signalled once it may be reused.
_lock = threading.RLock()
_live = {}  # process -> tag
_stopping = False


# prctl(2) option: the signal a process gets when the thread that started it ends.
_PR_SET_PDEATHSIG = 1


def _load_prctl():
    try:
        prctl = ctypes.CDLL(None, use_errno=True).prctl
    except (OSError, AttributeError):
        return None  # not Linux: the process group is all there is
    prctl.argtypes = [ctypes.c_int, ctypes.c_ulong, ctypes.c_ulong, ctypes.c_ulong,
                      ctypes.c_ulong]
    prctl.restype = ctypes.c_int
    return prctl


_prctl = _load_prctl()


def _dying_with(parent):
    # The child's last step before exec (after setsid): SIGKILL when `parent` dies; if it
    # died already, in the instant between fork and prctl, the child ends itself.
    def preexec():
        if _prctl(_PR_SET_PDEATHSIG, signal.SIGKILL, 0, 0, 0) == 0 and os.getppid() != parent:
            os._exit(128 + signal.SIGKILL)
    return preexec


def start_process(argv, **popen_kwargs):
    """Start a process that ends with this one: the one way the analysis, its tools and
    the CI gates start an engine or a benchmark command.

    It runs in a process group of its own (a new session, without the terminal), which
    the caller kills to end it with its children; and, on Linux, with the parent-death
    signal SIGKILL (``prctl(PR_SET_PDEATHSIG)``), so that it is killed when this process
    dies without the chance to (SIGKILL, a CI job's time limit killing its group). The
    signal is tied to the thread that calls this function, which must outlive the
    process: callers wait for it in the same thread. It reaches the process itself (an
    engine, or a benchmark command's shell, which ``exec`` makes the command), not the
    children it starts.

    Parameters
    ----------
    argv : sequence of str
    **popen_kwargs
        Passed to :class:`subprocess.Popen` (standard streams, environment).

    Returns
    -------
    proc : subprocess.Popen
    """
    preexec = _dying_with(os.getpid()) if _prctl is not None else None
    return subprocess.Popen(argv, start_new_session=True, preexec_fn=preexec, **popen_kwargs)


def _kill_group(proc):
    # SIGKILL to the engine's process group: the engine and every child it started.
    try:
        os.killpg(proc.pid, signal.SIGKILL)
    except (ProcessLookupError, PermissionError):
        pass


def _exited(proc):
    # Whether the engine has exited, without reaping it: while it is a zombie its pid,
    # and so its group id, cannot be reused, and the group can still be killed safely.
    if hasattr(os, "waitid"):
        try:
            return os.waitid(os.P_PID, proc.pid,
                             os.WEXITED | os.WNOHANG | os.WNOWAIT) is not None
        except ChildProcessError:
            return True
    return proc.poll() is not None


def kill_engine_runs(tag=None):
    """End the engine runs under way in this process, with their children.

    Each :func:`run_engine` ended returns at once with the signal's exit code; later
    calls start their engines as usual. A Dask worker runs it when the sweep it works
    for is interrupted (:mod:`hrbench_analysis.schedulers`).

    Parameters
    ----------
    tag : str, optional
        End only the runs started with this `tag` (those of one sweep, on a worker that
        other sweeps share); default all.

    Returns
    -------
    count : int
        Number of runs ended.
    """
    with _lock:
        ended = [proc for proc, t in _live.items() if tag is None or t == tag]
        for proc in ended:
            _kill_group(proc)
        return len(ended)


def stop_engine_runs():
    """End every engine run of this process, with its children, and start no new one.

    For an interrupt: every :func:`run_engine` under way returns at once (stopped as
    :data:`INTERRUPTED`), and any started later returns without starting its process,
    until :func:`ending_engine_runs` is left.
    """
    global _stopping
    with _lock:
        _stopping = True
        kill_engine_runs()


def _on_signal(signum, frame):
    stop_engine_runs()
    raise Interrupted(signum)


@contextmanager
def ending_engine_runs():
    """The scope of a command that runs engines: SIGINT and SIGTERM end them.

    Inside it (in the main thread), SIGINT and SIGTERM kill the process group of every
    engine run under way (:func:`stop_engine_runs`) and raise :class:`Interrupted` in the
    main thread, whose handlers then wait for nothing: the threads running engines
    return at once. A signal this process ignores (a background job's SIGINT) stays
    ignored. Leaving the scope, by any way, ends what is still running and restores
    the handlers.
    """
    global _stopping
    previous = {}
    if threading.current_thread() is threading.main_thread():
        for signum in (signal.SIGINT, signal.SIGTERM):
            if signal.getsignal(signum) is not signal.SIG_IGN:
                previous[signum] = signal.signal(signum, _on_signal)
    try:
        yield
    finally:
        stop_engine_runs()
        for signum, handler in previous.items():
            signal.signal(signum, handler)
        with _lock:
            _stopping = False


def _read(proc, timeout):
    # Read both pipes until they close, bounded in time and size; kill the group when
    # the engine exits (its children must not hold the pipes), times out or prints too
    # much. Returns (stdout bytes, stderr bytes, stopped).
    out, err = [], bytearray()
    out_size, stopped, exited_at = 0, "", None
    deadline = None if timeout is None else time.monotonic() + timeout
    with selectors.DefaultSelector() as sel:
        sel.register(proc.stdout, selectors.EVENT_READ)
        sel.register(proc.stderr, selectors.EVENT_READ)
        while sel.get_map():
            now = time.monotonic()
            if exited_at is None and _exited(proc):
                _kill_group(proc)
                exited_at = now
            elif exited_at is not None and now - exited_at > DRAIN_SECONDS:
                break
            if deadline is not None and now > deadline and not stopped:
                stopped = TIMED_OUT
                _kill_group(proc)
            for key, _ in sel.select(POLL_SECONDS):
                data = os.read(key.fd, 65536)
                if not data:
                    sel.unregister(key.fileobj)
                elif key.fileobj is proc.stderr:
                    err += data
                    del err[:-STDERR_KEPT]
                elif not stopped:
                    out_size += len(data)
                    if out_size > OUTPUT_LIMIT:
                        stopped = OUTPUT_EXCEEDED
                        _kill_group(proc)
                    else:
                        out.append(data)
    return b"".join(out), bytes(err), stopped


def run_engine(argv, timeout=None, tag=None, env=None):
    """Run the engine once and wait for it: the one place where the analysis starts an
    engine process.

    The process is started by :func:`start_process`: in a process group of its own, so
    that it and every child it starts can be ended together, and killed if this process
    dies. The group is
    killed when the engine has exited (a child left behind, say one that keeps standard
    output open, is ended, never waited for), when it runs past `timeout`, when it
    prints more than :data:`OUTPUT_LIMIT` bytes on standard output, when this call is
    interrupted (KeyboardInterrupt in the main thread) and on SIGINT or SIGTERM within
    :func:`ending_engine_runs`. No process of the group survives the call.

    Parameters
    ----------
    argv : sequence of str or path-like
        The command line, the engine first.
    timeout : float, optional
        Seconds to let it run (default: no limit).
    tag : str, optional
        Names the run for :func:`kill_engine_runs`.
    env : dict, optional
        The process' whole environment (default: this process').

    Returns
    -------
    run : EngineRun
        A process that could not be started has exit code 127 (:data:`NOT_STARTED`) and
        the reason as its standard error. One the analysis ended has the signal's
        negative exit code, :attr:`EngineRun.stopped` says why and
        :attr:`EngineRun.message` says so in a line. Output that is not UTF-8 is decoded
        with replacement characters.
    """
    argv = tuple(os.fspath(a) for a in argv)
    start = time.perf_counter()

    def finished(code, out, err, stopped="", reason=""):
        return EngineRun(argv, code, out, err, time.perf_counter() - start, stopped, reason)

    proc = None
    try:
        with _lock:
            if _stopping:
                return finished(-signal.SIGKILL, "", "", INTERRUPTED,
                                "not started: the analysis was interrupted")
            try:
                proc = start_process(argv, stdin=subprocess.DEVNULL, stdout=subprocess.PIPE,
                                     stderr=subprocess.PIPE, env=env)
            except (OSError, ValueError) as exc:
                return finished(NOT_STARTED, "", f"cannot run {argv[0]}: {exc}")
            _live[proc] = tag
        out, err, stopped = _read(proc, timeout)
    finally:
        if proc is not None:
            with _lock:
                _live.pop(proc, None)
                if proc.returncode is None:
                    _kill_group(proc)
            proc.stdout.close()
            proc.stderr.close()
            proc.wait()
    with _lock:
        if not stopped and _stopping and proc.returncode < 0:
            stopped = INTERRUPTED
    reasons = {
        TIMED_OUT: f"did not finish within {timeout} s; the analysis ended it and its "
                   "child processes",
        OUTPUT_EXCEEDED: f"printed more than {OUTPUT_LIMIT / 2**20:g} MiB on standard output, "
                         "the most the analysis reads; the analysis ended it",
        INTERRUPTED: "ended: the analysis was interrupted"}
    return finished(proc.returncode, out.decode("utf-8", errors="replace"),
                    err.decode("utf-8", errors="replace"), stopped, reasons.get(stopped, ""))
