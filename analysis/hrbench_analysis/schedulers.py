"""Where the engine runs of a sweep execute: the local pool, or a Dask cluster.

The sweep (:func:`hrbench_analysis.sweep.run_points`) only submits points and waits for
them; the results cache stays with it, so whichever scheduler runs the points, each
finished one is stored at once by the process that owns the cache, and a killed sweep
resumes from what is stored.

``--scheduler local`` (the default) runs the points on a pool of threads of this process,
each starting one engine process. ``--scheduler dask`` starts a ``dask.distributed``
LocalCluster of ``--jobs`` single-threaded worker processes; ``--scheduler
tcp://HOST:PORT`` uses an existing cluster (its workers need this package and the engine
at the same path). A point whose worker dies is run again on another worker. An
interrupted sweep ends the engine runs under way on every worker, with their children.
"""

import logging
import re
import uuid
from concurrent.futures import CancelledError, ThreadPoolExecutor

from .engine import kill_engine_runs
from .errors import AnalysisError

__all__ = ["LOCAL", "DASK", "SchedulerError", "check_scheduler", "open_scheduler", "Scheduler"]

#: The default: a pool of threads of this process.
LOCAL = "local"
#: A LocalCluster of worker processes started for the sweep.
DASK = "dask"

_ADDRESS = re.compile(r"^(tcp|tls)://[A-Za-z0-9.\-\[\]:]+:\d{1,5}$")

#: Seconds to wait for an existing Dask scheduler to answer.
CONNECT_TIMEOUT = 10


class SchedulerError(AnalysisError):
    """A scheduler that cannot be used: unknown, unreachable, or Dask not installed."""


def check_scheduler(text):
    """Check the text of ``--scheduler``.

    Parameters
    ----------
    text : str
        ``"local"``, ``"dask"`` or the address of a Dask scheduler
        (``tcp://HOST:PORT`` or ``tls://HOST:PORT``).

    Returns
    -------
    text : str

    Raises
    ------
    SchedulerError
        For anything else.
    """
    if text in (LOCAL, DASK) or _ADDRESS.match(text):
        return text
    raise SchedulerError(f"--scheduler {text!r}: expected 'local', 'dask' or the address of a "
                         "Dask scheduler, tcp://HOST:PORT")


class Scheduler:
    """An executor of points for :func:`hrbench_analysis.sweep.run_points`.

    Attributes
    ----------
    name : str
        As given to ``--scheduler``.
    executor : concurrent.futures.Executor
        ``submit(fn, point)`` gives a :class:`concurrent.futures.Future`.
    slots : int
        Points to keep running at once: ``jobs`` for the local pool and a LocalCluster,
        the worker threads of an existing cluster.
    lost : tuple of type
        Exceptions of a future that mean its worker was lost, not that the point failed:
        the point is submitted again.
    tag : str
        Passed to every engine run of the points (:func:`hrbench_analysis.engine.run_engine`),
        so that an interrupt ends this scheduler's runs on workers that others share.
    """

    def __init__(self, name, executor, slots, lost=(), closers=(), cancel=None):
        self.name = name
        self.tag = uuid.uuid4().hex
        self.executor = executor
        self.slots = max(1, int(slots))
        self.lost = tuple(lost)
        self._closers = list(closers)
        self._cancel = cancel

    def close(self, cancel=False):
        """Stop: wait for the running points, or with `cancel` start no new one and end
        the engine runs under way (the local pool's end by themselves: an interrupt
        of this process ends them, :func:`hrbench_analysis.engine.ending_engine_runs`)."""
        if cancel and self._cancel is not None and self._closers:
            self._cancel()
        if not self._closers:
            self.executor.shutdown(wait=True, cancel_futures=cancel)
        for close in self._closers:
            close()
        self._closers = []

    def __enter__(self):
        return self

    def __exit__(self, kind, value, traceback):
        self.close(cancel=kind is not None)


def open_scheduler(name, jobs):
    """Start the executor that ``--scheduler name`` asks for.

    Parameters
    ----------
    name : str
        As accepted by :func:`check_scheduler`.
    jobs : int
        Threads of the local pool, or worker processes of a LocalCluster.

    Returns
    -------
    scheduler : Scheduler
        Close it (or use it as a context manager) to stop the pool, the cluster or the
        connection.

    Raises
    ------
    SchedulerError
        If Dask is not installed, or no scheduler answers at the address within
        :data:`CONNECT_TIMEOUT` seconds.
    """
    check_scheduler(name)
    if name == LOCAL:
        return Scheduler(name, ThreadPoolExecutor(max_workers=jobs), jobs)
    try:
        from distributed import Client, LocalCluster
        from distributed.client import FutureCancelledError
        from distributed.scheduler import KilledWorker
    except ImportError as exc:
        raise SchedulerError(f"--scheduler {name} needs dask.distributed "
                             f"(pip install dask distributed): {exc}") from None
    closers = []
    try:
        if name == DASK:
            # One single-threaded process per job: a killed worker takes one point with it.
            cluster = LocalCluster(n_workers=jobs, threads_per_worker=1, processes=True,
                                   dashboard_address=None, silence_logs=logging.ERROR)
            closers.append(cluster.close)
            client = Client(cluster)
        else:
            client = Client(name, timeout=CONNECT_TIMEOUT)
    except (OSError, TimeoutError) as exc:
        for close in closers:
            close()
        raise SchedulerError(f"--scheduler {name}: no Dask scheduler answers "
                             f"({' '.join(str(exc).split()) or type(exc).__name__})") from None
    closers.insert(0, client.close)
    slots = jobs if name == DASK else sum(client.nthreads().values())
    if slots == 0:
        for close in closers:
            close()
        raise SchedulerError(f"--scheduler {name}: the cluster has no workers")
    lost = (KilledWorker, FutureCancelledError, CancelledError)
    executor = client.get_executor(pure=False)

    def cancel():
        # Drop the points not started, and end the engine runs under way on every worker
        # with their children: a worker's threads cannot be interrupted, and the engines
        # run in process groups of their own that would outlive a closed worker.
        executor.shutdown(wait=False)
        try:
            client.run(kill_engine_runs, scheduler.tag, on_error="ignore")
        except Exception as exc:  # an unreachable worker: its runs end with it
            logging.getLogger(__name__).warning("could not end the runs on the workers: %s",
                                                exc)

    scheduler = Scheduler(name, executor, slots, lost, closers, cancel)
    return scheduler
