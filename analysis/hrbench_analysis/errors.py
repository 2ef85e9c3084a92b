"""The analysis' own error class, the guards every input passes, and the exit codes.

Every error the analysis raises on purpose (a malformed claims file, a bad formula, an
engine that cannot be used or refuses a run as input error, an unusable results cache,
an unreadable record) derives from :class:`AnalysisError`. Every command of the package,
of ``tools/`` and of ``scripts/ci/`` ends through :func:`run_main`: any of them is one line
on standard error and exit code 2 (74 for an output that could not be written); any other
exception is a bug of the analysis (exit code 70, its traceback only with ``--debug``), so
that no crash is ever read as a verdict (1: a claim refuted, a regression found).

Every file the analysis reads goes through :func:`read_bounded` (or :func:`open_bounded`):
a regular file of at most a given size, checked before a byte is read, so that a FIFO, a
device or a sparse giant ends in one line instead of a hang or an exhausted memory. Every
JSON text goes through :func:`parse_json`, which refuses what JSON does not hold but
Python's reader accepts (``NaN``, ``Infinity``, a key given twice).

Standard library only, like :mod:`hrbench_analysis.engine`, so that ``tools/`` can use it too.
"""

import argparse
import errno
import json
import os
import stat
import sys
import traceback

__all__ = ["AnalysisError", "OutputError", "InputFileError", "OneLineParser", "one_line",
           "shown", "open_bounded",
           "read_bounded", "parse_json", "read_json", "run_main", "INPUT_ERROR",
           "INTERNAL_ERROR", "OUTPUT_ERROR", "INTERRUPTED"]

#: Exit codes every command shares beside its verdicts: bad input or environment, a bug
#: of the analysis (``EX_SOFTWARE`` of sysexits.h), an interrupt (128 + SIGINT).
INPUT_ERROR = 2
INTERNAL_ERROR = 70
INTERRUPTED = 130

#: Exit code of every command of the analysis when an output cannot be written
#: (``EX_IOERR`` of sysexits.h): a full disk, an I/O error, a read-only file system.
OUTPUT_ERROR = 74


class AnalysisError(Exception):
    """Bad input or environment, found by the analysis itself (exit code 2).

    Subclasses also derive from the built-in class that fits (``ValueError`` for input
    that does not follow a format, ``RuntimeError`` for an engine that cannot be used),
    so that code catching those keeps working.
    """

    #: The exit code of a command that ends with this error.
    exit_code = 2


class OutputError(AnalysisError):
    """An output file that could not be written (exit code 74, :data:`OUTPUT_ERROR`).

    Raised by :mod:`hrbench_analysis.output` after a failed write, which leaves the file
    the user named as it was.
    """

    exit_code = OUTPUT_ERROR


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
    # Any other control character (a NUL from a file) escaped: it cuts a terminal's line.
    line = "".join(c if c.isprintable() or c == " " else repr(c)[1:-1] for c in line)
    return line if len(line) <= limit else line[:limit - 3] + "..."


#: Characters of a long token (a word of a file, an argument) shown in a message.
SHOWN_CHARS = 60


def shown(token, limit=SHOWN_CHARS):
    """A token of input as a message shows it: control characters (a NUL, a line break)
    escaped, and one longer than `limit` characters cut to them, ``"..."`` and its length.

    Examples
    --------
    >>> shown("a\x00b")
    'a\\x00b'
    >>> shown("x" * 100, 4)
    'xxxx... (100 characters)'
    """
    text = str(token)
    cut = text[:limit]
    escaped = "".join(c if c.isprintable() or c == " " else repr(c)[1:-1] for c in cut)
    return escaped if len(text) <= limit else f"{escaped}... ({len(text)} characters)"


class OneLineParser(argparse.ArgumentParser):
    """An argument parser whose usage errors are one line, ``prog: error: message``, and
    exit code 2: argparse prints its usage block too, which a log or a CI summary then
    shows as several errors. Its subcommands' parsers are of the
    same class. Every command of the package, of ``tools/`` and of ``scripts/ci/`` parses
    with it (or with :class:`hrbench_analysis.cli.Parser`, a subclass)."""

    def error(self, message):
        self.exit(INPUT_ERROR, f"{self.prog}: error: {one_line(message)}\n")


class InputFileError(AnalysisError, ValueError):
    """An input that is not a regular file of bounded size, or not strict JSON.

    Attributes
    ----------
    path : str or None
        The file, when the problem is the file itself.
    reason : str
        What is wrong with it, without the file's name.
    """

    def __init__(self, path, reason):
        self.path = None if path is None else str(path)
        self.reason = reason
        super().__init__(reason if path is None else f"{path}: {reason}")


def _kind(mode):
    # What a file that is not a regular file is, for a message.
    for test, name in ((stat.S_ISDIR, "a directory"), (stat.S_ISFIFO, "a FIFO (named pipe)"),
                       (stat.S_ISCHR, "a character device"), (stat.S_ISBLK, "a block device"),
                       (stat.S_ISSOCK, "a socket")):
        if test(mode):
            return name
    return "not a regular file"


def open_bounded(path, limit, what="file"):
    """Open a regular file of at most `limit` bytes for binary reading.

    The file is opened without blocking (a FIFO without a writer would wait forever)
    and checked before a byte is read: a directory, FIFO, device or socket is refused,
    and so is a file larger than `limit` (a sparse 10 GB file is refused by its size,
    not read).

    Parameters
    ----------
    path : str or path-like
    limit : int
        Most bytes allowed.
    what : str, optional
        What the file is, for the message (``"claims file"``, ``"mesh file"``).

    Returns
    -------
    file : io.BufferedReader
        Open in blocking binary mode; the caller closes it.

    Raises
    ------
    InputFileError
        Naming the file and why: not found, not readable, a NUL in its name, not a
        regular file, or larger than `limit` bytes.
    """
    try:
        fd = os.open(path, os.O_RDONLY | os.O_NONBLOCK | getattr(os, "O_CLOEXEC", 0))
    except ValueError:  # a NUL byte in the path
        raise InputFileError(repr(str(path)), f"{what} path holds a NUL byte") from None
    except OSError as exc:
        raise InputFileError(path, f"cannot read the {what}: {exc.strerror or exc}") from None
    try:
        info = os.fstat(fd)
        if not stat.S_ISREG(info.st_mode):
            raise InputFileError(path, f"the {what} is {_kind(info.st_mode)}, not a regular "
                                 "file")
        if info.st_size > limit:
            raise InputFileError(path, f"the {what} has {info.st_size} bytes; at most "
                                 f"{limit} are allowed")
        os.set_blocking(fd, True)
        return os.fdopen(fd, "rb")
    except BaseException:
        os.close(fd)
        raise


def read_bounded(path, limit, what="file"):
    """The bytes of a regular file of at most `limit` bytes (see :func:`open_bounded`).

    A file that grows past `limit` while it is read is refused too: never more than
    ``limit + 1`` bytes are read.

    Raises
    ------
    InputFileError
    """
    with open_bounded(path, limit, what) as fh:
        try:
            data = fh.read(limit + 1)
        except OSError as exc:
            raise InputFileError(path, f"cannot read the {what}: "
                                 f"{exc.strerror or exc}") from None
    if len(data) > limit:
        raise InputFileError(path, f"the {what} has more than {limit} bytes")
    return data


def _refuse_constant(name):
    raise ValueError(f"{name} is not a JSON number")


def _no_duplicates(pairs):
    obj = {}
    for key, value in pairs:
        if key in obj:
            raise ValueError(f"key {key!r} is given twice in one object")
        obj[key] = value
    return obj


def parse_json(text, what="JSON text", error=None):
    """Parse strict JSON: no ``NaN`` or ``Infinity``, no key given twice in one object.

    Python's reader accepts both (the last value of a duplicate key winning), so that a
    record with ``"links": 5, "links": 7`` or a time of ``NaN`` would be read as valid.

    Parameters
    ----------
    text : str or bytes
        Bytes must be UTF-8.
    what : str, optional
        What the text is, for the message (``"run output"``, ``"base.json"``).
    error : callable, optional
        The exception class to raise, called with the message (default
        :class:`InputFileError` without a path).

    Returns
    -------
    object

    Raises
    ------
    error
        ``"{what} is not valid JSON: ..."``, also for text that is not UTF-8, nested too
        deeply or with an integer of more than 4300 digits. No other exception comes out
        of arbitrary text.
    """
    error = error or (lambda message: InputFileError(None, message))
    try:
        if isinstance(text, (bytes, bytearray)):
            text = text.decode("utf-8")
        return json.loads(text, object_pairs_hook=_no_duplicates,
                          parse_constant=_refuse_constant)
    except UnicodeDecodeError as exc:
        raise error(f"{what} is not valid JSON: not UTF-8 text (byte {exc.start})") from None
    except RecursionError:
        raise error(f"{what} is not valid JSON: nested too deeply") from None
    except ValueError as exc:  # JSONDecodeError, the hooks' refusals, 5000-digit integers
        raise error(f"{what} is not valid JSON: {one_line(exc, 300)}") from None


def read_json(path, limit, what, where, error):
    """A JSON file of at most `limit` bytes (:func:`read_bounded`), parsed strictly
    (:func:`parse_json`); a file that cannot be read and text that is not JSON both raise
    `error` (a class taking one message), with `where` naming the text."""
    try:
        return parse_json(read_bounded(path, limit, what), where, error)
    except InputFileError as exc:
        raise error(str(exc)) from None



#: The errors of a write that failed on a file that could be opened: exit code 74.
_WRITE_ERRORS = {errno.ENOSPC, errno.EDQUOT, errno.EIO, errno.EFBIG, errno.EROFS, errno.EPIPE}


class _NamedStdout:
    """Standard output whose failed writes name it (a write error carries no file name)."""

    def __init__(self, stream):
        self._stream = stream

    def _call(self, method, *args):
        try:
            return getattr(self._stream, method)(*args)
        except OSError as exc:
            raise OSError(exc.errno, exc.strerror or str(exc), "standard output") from None

    def write(self, text):
        return self._call("write", text)

    def flush(self):
        return self._call("flush")

    def __getattr__(self, name):
        return getattr(self._stream, name)


def _stdout_broken():
    # Whether standard output can no longer take what is buffered for it (a full disk, a
    # closed pipe). If so, it is pointed at /dev/null, so that the interpreter's own
    # flush at exit does not fail again with a traceback of its own.
    try:
        sys.stdout.flush()
        return False
    except (OSError, ValueError):
        try:
            null = os.open(os.devnull, os.O_WRONLY)
            os.dup2(null, sys.stdout.fileno())
            os.close(null)
        except (OSError, ValueError, AttributeError):
            pass
        return True


def run_main(prog, body, argv=None, input_errors=(), prefix=None, interrupted=None):
    """Run a command's body and return its exit code; no exception escapes.

    The body runs in :func:`~hrbench_analysis.engine.ending_engine_runs`: SIGINT and
    SIGTERM end the engine runs under way, with their children, before it returns.

    - its own return value (0, or a verdict such as 1 or 3), or argparse's exit code (0
      after ``--help``, 2 for a usage error), once standard output took everything
      written to it (else one line, exit code 2);
    - :class:`AnalysisError` or one of `input_errors`: one line, exit code 2 (the
      error's ``exit_code``: 74 for an :class:`OutputError`);
    - :class:`OSError`: one line naming the file; exit code 74 for a write that failed
      (a full disk, a closed pipe, standard output that cannot take what was printed),
      else 2;
    - an interrupt: exit code 130 (or the interrupt's ``exit_code``: 143 for SIGTERM);
    - any other exception, a bug: one line naming it, exit code 70; its traceback only
      when `argv` holds ``--debug``.

    Parameters
    ----------
    prog : str
        The command's name.
    body : callable
        ``body(argv)``, returning the exit code.
    argv : list of str, optional
        Default ``sys.argv[1:]``.
    input_errors : tuple of exception classes, optional
        The command's own input errors that do not derive from :class:`AnalysisError`.
    prefix : str, optional
        The start of an error line (default ``"{prog}: error: "``).
    interrupted : str, optional
        The line printed on an interrupt (default ``"{prog}: interrupted"``).

    Returns
    -------
    code : int
    """
    argv = sys.argv[1:] if argv is None else list(argv)
    prefix = f"{prog}: error: " if prefix is None else prefix

    def say(line):
        try:
            print(line, file=sys.stderr, flush=True)
        except (OSError, ValueError):
            pass

    from .engine import ending_engine_runs  # the engine package imports this module

    stdout, sys.stdout = sys.stdout, _NamedStdout(sys.stdout)
    try:
        with ending_engine_runs():
            code = body(argv)
    except SystemExit as exc:   # argparse: --help (0) or a usage error (2)
        if exc.code is None or isinstance(exc.code, int):
            code = exc.code or 0
        else:
            say(f"{prefix}{one_line(exc.code)}")
            return INPUT_ERROR
    except (AnalysisError, *input_errors) as exc:
        say(f"{prefix}{one_line(exc)}")
        return getattr(exc, "exit_code", INPUT_ERROR)
    except OSError as exc:
        broken = _stdout_broken()
        where = ("standard output" if broken else exc.filename)
        say(f"{prefix}{one_line((f'{where}: ' if where else '') + (exc.strerror or str(exc)))}")
        return OUTPUT_ERROR if broken or exc.errno in _WRITE_ERRORS else INPUT_ERROR
    except KeyboardInterrupt as exc:   # SIGINT (130), or SIGTERM where it is one (143)
        say(interrupted or f"{prog}: interrupted")
        return getattr(exc, "exit_code", INTERRUPTED)
    except Exception as exc:
        if "--debug" in argv:
            traceback.print_exc()
        _stdout_broken()
        say(f"{prog}: internal error, a bug: {type(exc).__name__}: {one_line(exc, 300)} "
            "(rerun with --debug for the traceback, and please report it)")
        return INTERNAL_ERROR
    finally:
        sys.stdout = stdout
    if _stdout_broken():
        say(f"{prefix}standard output: cannot write (a full disk or a closed pipe)")
        return OUTPUT_ERROR
    return code
