"""The points of the results cache: a run's key, a cached run, and which failures are final.

A :class:`PointKey` holds everything that determines the counts of one run; its
canonical text is the key of the cache (:class:`~hrbench_analysis.store.ResultStore`). A
:class:`StoredPoint` is one cached run, successful or not; a failure is final only when
it is the engine's own verdict on the point (:func:`is_verdict`), and is run again by
the next sweep otherwise.
"""

import json
import re
from dataclasses import dataclass

__all__ = ["PointKey", "StoredPoint", "CACHED_FAILURES", "is_verdict"]

#: Exit codes of the engine's own verdicts on a run, the only failures that are cached
#: (see :func:`is_verdict`): 2 (usage or input error) and 3 (a refinement limit was
#: reached). Any other failure (a crash, a signal, a timeout, a program that could not
#: be started) is tried again on the next sweep.
CACHED_FAILURES = (2, 3)

# The message of an interpreter or shell that could not open the engine's script
# (python3, sh, perl): exit code 2, but no verdict of the engine.
_SCRIPT_NOT_OPENED = re.compile(r": can't open file |^\S+: \d+: (?:can't|cannot) open |"
                                r"^Can't open perl script ", re.IGNORECASE)
# A limit that depends on the memory free at the moment of the run.
_MEMORY_LIMIT = re.compile(r"memory budget|out of memory", re.IGNORECASE)


def is_verdict(exit_code, message, options=()):
    """Whether a failed run is the engine's own verdict on its point, so that it is cached.

    The rule: exit code 2 or 3 (:data:`CACHED_FAILURES`) with a message (the last line
    of standard error), except

    - exit code 2 from an interpreter or a shell that could not open the engine's script
      (``python3: can't open file ...``, ``sh: 0: cannot open ...``): the script missing
      for a moment, not the engine refusing the run;
    - exit code 3 for the memory budget or memory running out (``... exceed the memory
      budget ...``, ``out of memory``), unless the run gave ``--max-memory`` and the
      message names the budget: the default budget is a share of the memory free at
      that moment, and memory running out depends on the machine's load.

    Every other failure (exit code 1, 126, 127, a signal, a timeout, an unreadable
    record, output beyond the analysis's bound) is not a verdict.

    Parameters
    ----------
    exit_code : int
    message : str
        Last non-empty line of standard error.
    options : sequence of (str, str), optional
        The run's engine options (:attr:`PointKey.options`).

    Returns
    -------
    verdict : bool
    """
    message = (message or "").strip()
    if exit_code not in CACHED_FAILURES or not message:
        return False
    if exit_code == 2:
        return not _SCRIPT_NOT_OPENED.search(message)
    budget_given = "max_memory" in dict(options) and "memory budget" in message.lower()
    return budget_given or not _MEMORY_LIMIT.search(message)


@dataclass(frozen=True)
class PointKey:
    """Everything that determines the counts of one run.

    Attributes
    ----------
    version : str
        Engine version (output of ``hrbench --version``).
    scene : str
        Scene family.
    params : tuple of (str, float)
        Scene parameters as requested, sorted by name (scene units).
    eps : float
        Oracle threshold (dimensionless).
    oracle : str
        Oracle name.
    min_area : float or None
        ``--min-area`` (scene units), if given.
    max_depth : int or None
        ``--max-depth`` (levels), if given.
    mode : str
        ``"count-only"`` or ``"store"``; ``"count-only+hierarchy-statistics-v2"``
        (:data:`hrbench_analysis.lemmas.STATISTICS_MODE`) for a run stored with the
        hierarchy statistics of its link list, so that it never shares a key with a
        run without them.
    options : tuple of (str, str)
        Further engine options as passed on the command line, sorted by name, e.g.
        ``(("method", "translation"),)`` for ``--method translation``.
    """

    version: str
    scene: str
    params: tuple
    eps: float
    oracle: str
    min_area: object = None
    max_depth: object = None
    mode: str = "count-only"
    options: tuple = ()

    def text(self):
        """A canonical string form of the key, used as the database's primary key.

        A key without options has the same text as before options existed, so points
        cached then stay valid.
        """
        obj = {
            "version": self.version, "scene": self.scene,
            "params": {k: repr(float(v)) for k, v in self.params},
            "eps": repr(float(self.eps)), "oracle": self.oracle,
            "min_area": None if self.min_area is None else repr(float(self.min_area)),
            "max_depth": self.max_depth, "mode": self.mode}
        if self.options:
            obj["options"] = {k: str(v) for k, v in self.options}
        return json.dumps(obj, sort_keys=True)

    def run_text(self):
        """The key text without the engine version: the same run of any version."""
        return _without_version(self.text())


def _without_version(text):
    obj = json.loads(text)
    obj.pop("version", None)
    return json.dumps(obj, sort_keys=True)


@dataclass
class StoredPoint:
    """One cached run.

    Attributes
    ----------
    key : PointKey
    ok : bool
        Whether the run exited with code 0 and printed a readable record.
    exit_code : int
        Exit code of the run (0 when ok; negative for a signal).
    stderr : str
        Last non-empty line of standard error ("" when ok).
    output : str
        Standard output (the JSON record when ok), as the engine printed it.
    wall_seconds : float
        Wall time of the whole process (s).
    finished_at : float or None
        When it was stored (seconds since the epoch); ``None`` before it is stored.
    statistics : dict or None
        The hierarchy statistics measured after the run
        (:func:`hrbench_analysis.lemmas.stored_statistics`), kept beside `output`;
        ``None`` for a run without them.
    """

    key: PointKey
    ok: bool
    exit_code: int
    stderr: str
    output: str
    wall_seconds: float
    finished_at: object = None
    statistics: object = None

    @property
    def final(self):
        """bool: whether the point needs no new run: it succeeded, or its failure is the
        engine's own verdict (:func:`is_verdict`)."""
        return self.ok or is_verdict(self.exit_code, self.stderr, self.key.options)

