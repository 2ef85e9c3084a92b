"""Progress lines for the stages of a command that take more than a few seconds.

A user who sees no line for half a minute cannot tell a slow stage from a hung one: each
stage of ``hrbench-reproduce`` after the sweep (fits, the link tiling, the solves of the
pictures, rendering the figures, the explorer page) says when it starts, repeats a line
at most every :data:`EVERY_SECONDS` while it runs, and says how long it took.
"""

import sys
import threading
import time

__all__ = ["EVERY_SECONDS", "Stage"]

# The default stream: standard error as it is when a line is printed (a test may have
# replaced it since this module was imported).
_STDERR = object()

#: The most seconds between two lines of a stage (the sweep's bar keeps the same pace).
EVERY_SECONDS = 15.0


class Stage:
    """A context manager that prints a stage's start, its progress and its end.

    ``with Stage("solving the Cornell box") as stage: ...`` prints ``solving the Cornell
    box ...`` on entry, ``solving the Cornell box: 15 s`` every `every` seconds while the
    block runs (from a thread, so a block that waits on one engine run is covered too),
    and ``solving the Cornell box: done in 47.2 s`` on a normal exit. With `total`, a
    block that calls :meth:`advance` shows ``12/163`` in its lines.

    With ``beat=False`` no thread runs and the lines come from :meth:`advance` only, once
    `every` seconds have passed since the last: for a block that forks worker processes,
    which must not inherit a lock that a printing thread holds.

    Parameters
    ----------
    what : str
        The stage, as a user reads it (``"rendering 163 figures"``).
    total : int, optional
        The number of steps, for :meth:`advance`.
    stream : text stream or None, optional
        Standard error by default; ``None`` for silence.
    every : float, optional
        Seconds between progress lines; default :data:`EVERY_SECONDS`.
    beat : bool, optional
        Whether a thread prints the lines (default), or :meth:`advance` does.
    log : callable, optional
        Takes each line instead of `stream` (a command's own ``log``, which prefixes it).
    detail : callable, optional
        Returns text for each progress line (``"step 34/89"``), or ``""``.
    start : str, optional
        The line on entry; default ``"<what> ..."``.

    Attributes
    ----------
    seconds : float
        Wall time of the block so far, or in all once it has ended, s.
    """

    def __init__(self, what, total=None, stream=_STDERR, every=EVERY_SECONDS, beat=True,
                 log=None, detail=None, start=None):
        self.what, self.total, self.stream, self.every = what, total, stream, every
        self.beat, self.log, self.detail = beat, log, detail
        self.start_line = f"{what} ..." if start is None else start
        self.done = 0
        self._last = None
        self.seconds = 0.0
        self._start = None
        self._stop = threading.Event()
        self._thread = None
        self._lock = threading.Lock()

    def __enter__(self):
        self._start = self._last = time.perf_counter()
        self._print(self.start_line)
        if self._speaks() and self.beat:
            self._thread = threading.Thread(target=self._beat, daemon=True)
            self._thread.start()
        return self

    def __exit__(self, kind, value, traceback):
        self._stop.set()
        if self._thread is not None:
            self._thread.join()
        self.seconds = time.perf_counter() - self._start
        if kind is None:
            self._print(f"{self.what}: done in {self.seconds:.1f} s")
        return False

    def advance(self, steps=1):
        """Count `steps` more steps done (shown against `total` in the next line)."""
        with self._lock:
            self.done += steps
        if not self.beat and time.perf_counter() - self._last >= self.every:
            self._progress()

    def _beat(self):
        # Print a line every `every` seconds until the block ends.
        while not self._stop.wait(self.every):
            self._progress()

    def _progress(self):
        now = time.perf_counter()
        with self._lock:
            count = f"{self.done}/{self.total}, " if self.total is not None else ""
        detail = self.detail() if self.detail is not None else ""
        self._last = now
        self._print(f"{self.what}: {count}{detail + ', ' if detail else ''}"
                    f"{now - self._start:.0f} s")

    def _speaks(self):
        return self.log is not None or self.stream is not None

    def _print(self, line):
        if self.log is not None:
            self.log(line)
        elif self.stream is not None:
            print(line, file=sys.stderr if self.stream is _STDERR else self.stream, flush=True)
