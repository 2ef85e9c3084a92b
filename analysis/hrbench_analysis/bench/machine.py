"""The machine a benchmark runs on, as the history and the CI gates record it."""

__all__ = ["cpu_model"]


def cpu_model():
    """The CPU model of this machine from ``/proc/cpuinfo``, or None where it is unknown.

    The first of the keys that name it on x86 (``model name``), ARM (``Model``,
    ``Hardware``) and MIPS (``cpu model``).
    """
    try:
        with open("/proc/cpuinfo", encoding="utf-8", errors="replace") as f:
            for line in f:
                key, _, value = line.partition(":")
                if key.strip() in ("model name", "Model", "Hardware", "cpu model"):
                    return value.strip() or None
    except OSError:
        pass
    return None
