"""The analysis' own error class, the base of every error that means bad input.

Every error the analysis raises on purpose (a malformed claims file, a bad formula, an
engine that cannot be used or refuses a run as input error, an unusable results cache,
an unreadable record) derives from :class:`AnalysisError`. The command line
(:mod:`hrbench_analysis.reproduce`) turns any of them into one line on standard error and exit
code 2; any other exception is a bug of the analysis (exit code 70, with its traceback).

Standard library only, like :mod:`hrbench_analysis.engine`, so that ``tools/`` can use it too.
"""

__all__ = ["AnalysisError", "one_line"]


class AnalysisError(Exception):
    """Bad input or environment, found by the analysis itself (exit code 2).

    Subclasses also derive from the built-in class that fits (``ValueError`` for input
    that does not follow a format, ``RuntimeError`` for an engine that cannot be used),
    so that code catching those keeps working.
    """


def one_line(text, limit=2000):
    """A message as one line: line breaks become spaces, and it is cut at `limit`.

    Parameters
    ----------
    text : object
        The message (``str()`` is applied).
    limit : int, optional
        Most characters kept (default 2000); a cut message ends with ``"..."``.

    Returns
    -------
    line : str
    """
    line = " ".join(str(text).split("\n")).replace("\r", " ")
    return line if len(line) <= limit else line[:limit - 3] + "..."
