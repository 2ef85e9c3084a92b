"""Leases of the results cache: a sweep's claim on a point it is running.

The lease row (:class:`Lease`), the timing of leases (:data:`LEASE_TIMEOUT`,
:data:`LEASE_RENEW`) and whether the process that owns one still runs; when a lease
lapses is :mod:`hrbench_analysis.store`'s (:meth:`~hrbench_analysis.store.ResultStore.acquire`).
"""

import os
from dataclasses import dataclass

__all__ = ["Lease", "LEASE_TIMEOUT", "LEASE_RENEW"]

#: Seconds after which a lease that its owner has not renewed lapses.
LEASE_TIMEOUT = 120.0
#: Seconds between two renewals of the leases of the points a sweep is running.
LEASE_RENEW = 15.0


@dataclass(frozen=True)
class Lease:
    """A sweep's claim on a point it is running.

    Attributes
    ----------
    key : str
        Canonical key text of the point (:meth:`~hrbench_analysis.store_points.PointKey.text`).
    host : str
        Host name of the owner.
    pid : int
        Process id of the owner.
    token : str
        Identifies the owning :class:`~hrbench_analysis.store.ResultStore` (one per
        sweep).
    started_at, renewed_at : float
        When it was taken and last renewed (seconds since the epoch).
    """

    key: str
    host: str
    pid: int
    token: str
    started_at: float
    renewed_at: float


def _boot_time():
    # Seconds since the epoch at which this host booted (Linux), or None.
    try:
        with open("/proc/stat", "rb") as fh:
            for line in fh:
                if line.startswith(b"btime "):
                    return float(line.split()[1])
    except (OSError, ValueError, IndexError):
        pass
    return None


def _pid_alive(pid, since=None):
    # Whether a process of this host with id `pid` still runs (a zombie does not) and,
    # given `since` (seconds since the epoch), started before then: a process started
    # later has only inherited the id of the lease's owner.
    if not isinstance(pid, int) or isinstance(pid, bool) or not 0 < pid < 2**31:
        return False
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except OSError:
        pass  # exists, owned by someone else
    try:
        with open(f"/proc/{pid}/stat", "rb") as fh:
            fields = fh.read().rsplit(b")", 1)[1].split()
    except OSError:
        return True  # no /proc: the id is all there is to go by
    if fields[:1] == [b"Z"]:
        return False
    boot = _boot_time()
    if since is None or boot is None:
        return True
    try:
        # Field 22 of stat: the start time in clock ticks after boot (20th after the name).
        started = boot + int(fields[19]) / os.sysconf("SC_CLK_TCK")
    except (IndexError, ValueError, OSError):
        return True
    return started <= since + 1.0  # btime is whole seconds
