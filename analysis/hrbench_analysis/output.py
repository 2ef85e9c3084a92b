"""Output files written whole or not at all, into what the user named.

Every file the analysis writes goes through this module: the report set of
``hrbench-reproduce`` (``report.md``, ``report.html``, ``claims.json``, ``plots/*.png``),
its explorer page, the files the engine writes for it (link and solution CSVs), the CSV
of ``hrbench-sweep --out``, the PNG of ``hrbench-tiling``, ``hrbench-render`` and the page
of ``hrbench-explorer`` and ``hrbench-history html``. What happens depends on what the
name is:

- a regular file, or a name not taken yet: the data goes to a temporary file in the same
  folder (``.NAME.XXXXXXXX.tmp``), is flushed to the disk (``fsync``) and renamed over the
  name (``os.replace``), so a reader sees the old file or the new one, never a part of
  one, and a failed write (a full disk, an I/O error, a read-only file system) leaves the
  old file as it was. A file that existed keeps its permission bits.
- a symbolic link: followed to its real target, which is written as above (the
  temporary file in the target's folder); the link stays a link.
- a device or a FIFO (``/dev/stdout``, ``/dev/null``, a named pipe): written through,
  opened and written in place, never replaced; such a write cannot be atomic, and a FIFO
  waits for its reader as a shell redirection does.
- a folder, a socket, a name whose folder does not exist: refused, exit code 2.
- a file the command also reads (``hrbench-render --csv`` naming its ``--mesh``): refused,
  exit code 2, before anything is written (:func:`refuse_inputs`; the same file by device
  and inode, whatever name or link leads to it).

A write that fails raises :class:`~hrbench_analysis.errors.OutputError` (exit code 74)
naming the file, and leaves no temporary file behind (a process killed while writing can
leave one, hidden by its leading dot).
"""

import errno
import fcntl
import os
import secrets
import stat
import sys
from contextlib import contextmanager
from pathlib import Path

from .errors import AnalysisError, OutputError

__all__ = ["write_file", "write_files", "write_stdout", "staged", "folder_lock",
           "refuse_inputs"]


def write_file(path, data):
    """Write one output file (see the module's description).

    Parameters
    ----------
    path : path-like
        The name the user gave.
    data : bytes or str
        The whole content; a ``str`` is written as UTF-8.

    Raises
    ------
    AnalysisError
        If `path` names a folder, a socket or a file in a folder that does not exist.
    OutputError
        If the write fails; the previous file is intact.
    """
    write_files([(path, data)])


def write_files(files):
    """Write several output files as one set: all of them, or none where possible.

    Every file is first written to its temporary file; only when all of them are on the
    disk are they renamed over their names, in the order given (so list the files that
    others refer to, such as figures, before those that refer to them). A failed write
    (the usual failure: the disk fills up) therefore leaves every previous file intact;
    a rename that fails (rare: an I/O error) leaves each file whole, old or new. Devices
    and FIFOs are written through after the renames.

    Parameters
    ----------
    files : iterable of (path-like, bytes or str)

    Raises
    ------
    AnalysisError, OutputError
        As :func:`write_file`.
    """
    files = [(Path(path), _target(path), _bytes(data)) for path, data in files]
    pending = []  # temporaries not yet renamed: removed whatever happens
    try:
        for path, (real, regular), data in files:
            if regular:
                with _writing(path, kept=True):
                    pending.append((path, real, _stage(real, data)))
        for path, real, tmp in list(pending):
            with _writing(path, kept=True):
                os.replace(tmp, real)
            pending.remove((path, real, tmp))
        for folder in dict.fromkeys(real.parent for _, (real, regular), _ in files
                                    if regular):
            with _writing(folder):
                _sync_folder(folder)
        for path, (real, regular), data in files:
            if not regular:
                with _writing(path):
                    _write_through(real, data)
    finally:
        for _, _, tmp in pending:
            _remove(tmp)


def refuse_inputs(outputs, inputs):
    """Refuse outputs that are inputs of the same command, or one another.

    Call it before anything is written: an output that is one of the command's inputs
    would be replaced by what was computed from it, and two outputs of one name would
    leave only the last.

    Parameters
    ----------
    outputs, inputs : iterable of (str, path-like or None)
        ``(flag, path)`` pairs, such as ``("--csv", args.csv)``; a path of None (an
        option not given) is skipped.

    Raises
    ------
    AnalysisError
        Naming both options, when an existing output is an input (the same device and
        inode), or two outputs name one file.
    """
    def identity(path):
        try:
            info = os.stat(path)
        except (OSError, ValueError):
            return None  # not there yet: no input can be it
        return info.st_dev, info.st_ino

    seen = {}
    for flag, path in outputs:
        if path is None:
            continue
        key = identity(path) or os.path.realpath(path)
        if key in seen:
            raise AnalysisError(f"{flag} {path} is also {seen[key]}: give two different files")
        seen[key] = f"{flag} {path}"
    for flag, path in inputs:
        key = None if path is None else identity(path)
        if key is not None and key in seen:
            raise AnalysisError(f"{seen[key]} is the file {flag} {path} reads; write the "
                                "output to another file")


def write_stdout(text):
    """Write `text` to standard output and flush it.

    Raises
    ------
    OutputError
        If the write fails (a closed pipe, a full device). Standard output is then
        pointed at ``/dev/null``, so that the interpreter's own flush at exit finds
        nothing left to fail on.
    """
    try:
        sys.stdout.write(text)
        sys.stdout.flush()
    except OSError as exc:
        try:
            null = os.open(os.devnull, os.O_WRONLY)
            os.dup2(null, sys.stdout.fileno())
            os.close(null)
        except (OSError, ValueError):
            pass  # no file descriptor to point elsewhere
        raise OutputError(f"standard output: cannot write ({_reason(exc)})") from None


@contextmanager
def staged(path):
    """A temporary name beside `path` for another program (the engine) to write.

    When the block ends without an exception, the file written there is flushed to the
    disk and renamed over `path`; whatever happens, the temporary name is gone after the
    block. So a reader of `path` (another run sharing the folder) never sees a part of
    the file. A `path` that is a device or FIFO is given as it is, to be written through.

    Yields
    ------
    name : pathlib.Path
        The file to write, then read back inside the block.

    Raises
    ------
    AnalysisError, OutputError
        As :func:`write_file`.
    """
    real, regular = _target(path)
    if not regular:
        yield real
        return
    with _writing(path):
        tmp, fd = _temporary(real)
        os.close(fd)
    try:
        yield tmp
        with _writing(path, kept=True):
            fd = os.open(tmp, os.O_RDONLY | os.O_CLOEXEC)
            try:
                os.fsync(fd)
            finally:
                os.close(fd)
            os.replace(tmp, real)
    finally:
        _remove(tmp)


@contextmanager
def folder_lock(folder, name=".hrbench.lock"):
    """Hold an exclusive lock on a results folder for the block (``flock``).

    Runs that share a folder hold it while they replace their report set and remove
    the figures of earlier runs, so that the folder ends with one run's set, complete.
    A file system without locks (some network file systems) goes without: a single
    run needs none.
    """
    lock = Path(folder) / name
    with _writing(lock):
        fd = os.open(lock, os.O_RDWR | os.O_CREAT | os.O_CLOEXEC, 0o666)
    try:
        try:
            fcntl.flock(fd, fcntl.LOCK_EX)
        except OSError as exc:
            if exc.errno not in (errno.ENOLCK, errno.EOPNOTSUPP, errno.EINVAL):
                raise
        yield
    finally:
        os.close(fd)  # releases the lock


def _target(path):
    # (the real path to write, whether it is written through a temporary file); raises
    # AnalysisError for a name that cannot be an output file.
    path = Path(path)
    try:
        real = Path(os.path.realpath(path))
        link = f" (a link to {real})" if os.path.islink(path) else ""
        mode = os.stat(real).st_mode
    except FileNotFoundError:
        if not real.parent.is_dir():
            raise AnalysisError(f"{path}{link}: folder {real.parent} does not exist") from None
        return real, True
    except OSError as exc:
        raise AnalysisError(f"{path}: cannot be written ({_reason(exc)})") from None
    except ValueError:
        raise AnalysisError(f"{str(path)!r}: a file name cannot hold a NUL") from None
    if stat.S_ISREG(mode):
        return real, True
    if stat.S_ISCHR(mode) or stat.S_ISBLK(mode) or stat.S_ISFIFO(mode):
        return real, False
    what = "a folder" if stat.S_ISDIR(mode) else "not a file, device or FIFO"
    raise AnalysisError(f"{path}{link} is {what}; give a file to write")


def _stage(real, data):
    # Write data to a new temporary file beside `real`, on the disk; return its path.
    tmp, fd = _temporary(real)
    try:
        try:
            os.fchmod(fd, stat.S_IMODE(os.stat(real).st_mode))  # keep the old file's mode
        except FileNotFoundError:
            pass  # a new file: the umask decided its mode
        _write_all(fd, data)
        os.fsync(fd)
    except BaseException:
        os.close(fd)
        _remove(tmp)
        raise
    os.close(fd)
    return tmp


def _temporary(real):
    # A new file beside `real` (mode 0666 less the umask, as open() gives), opened for
    # writing: (path, fd). The name is cut so that a long one stays within NAME_MAX.
    for _ in range(100):
        tmp = real.with_name(f".{real.name[:100]}.{secrets.token_hex(4)}.tmp")
        try:
            flags = os.O_WRONLY | os.O_CREAT | os.O_EXCL | os.O_CLOEXEC
            return tmp, os.open(tmp, flags, 0o666)
        except FileExistsError:
            continue
    raise OSError(errno.EEXIST, "no free temporary name", str(real.parent))


def _write_through(real, data):
    fd = os.open(real, os.O_WRONLY | os.O_CLOEXEC)
    try:
        _write_all(fd, data)
    finally:
        os.close(fd)


def _write_all(fd, data):
    view = memoryview(data)
    while view:
        view = view[os.write(fd, view):]


def _sync_folder(folder):
    # Make the renames in `folder` durable; a file system that cannot sync a folder
    # (EINVAL) has nothing to do.
    fd = os.open(folder, os.O_RDONLY | os.O_DIRECTORY | os.O_CLOEXEC)
    try:
        os.fsync(fd)
    except OSError as exc:
        if exc.errno != errno.EINVAL:
            raise
    finally:
        os.close(fd)


def _remove(path):
    try:
        os.unlink(path)
    except OSError:
        pass  # already renamed or removed; a leftover is hidden and harmless


@contextmanager
def _writing(path, kept=False):
    # Turn a failed system call into one OutputError naming the output (and saying that
    # its previous content is kept, for a write through a temporary file).
    try:
        yield
    except OSError as exc:
        note = "; the previous file is kept" if kept else ""
        raise OutputError(f"{path}: cannot write ({_reason(exc)}){note}") from None


def _reason(exc):
    return exc.strerror or str(exc)


def _bytes(data):
    return data.encode("utf-8") if isinstance(data, str) else bytes(data)
