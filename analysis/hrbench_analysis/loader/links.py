"""Link lists: the CSV ``hrbench links --out`` writes, one row per link."""

import csv
import io
import math
import warnings
from dataclasses import dataclass

import numpy as np

from ..errors import InputFileError, read_bounded
from .record import ResultFormatError

#: Largest link list read (``hrbench links --out``), in bytes: the figures draw a few
#: thousand links, a sweep point's statistics up to a few hundred thousand (about 80 bytes
#: a link).
MAX_LINKS_BYTES = 1 << 30


@dataclass
class LinkTable:
    """The links written by ``hrbench links ... --out F.csv``, one array entry per link.

    Attributes
    ----------
    root_i, root_j : ndarray of int
        Root patch indices of the two elements.
    t0_i, t1_i, t0_j, t1_j : ndarray of float
        Element intervals in arc length along the root patch, from its start point
        (scene units).
    depth_i, depth_j : ndarray of int
        Element depths (levels below the root).
    """

    root_i: np.ndarray
    t0_i: np.ndarray
    t1_i: np.ndarray
    depth_i: np.ndarray
    root_j: np.ndarray
    t0_j: np.ndarray
    t1_j: np.ndarray
    depth_j: np.ndarray

    def __len__(self):
        return len(self.root_i)


_LINK_COLUMNS = ("root_i", "elem_i", "t0_i", "t1_i", "depth_i",
                 "root_j", "elem_j", "t0_j", "t1_j", "depth_j")


def read_links_csv(path):
    """Read a link list written by ``hrbench links``.

    Parameters
    ----------
    path : str or path-like
        CSV file with header ``root_i,elem_i,t0_i,t1_i,depth_i,root_j,elem_j,t0_j,t1_j,depth_j``
        (extra columns are ignored).

    Returns
    -------
    links : LinkTable

    Raises
    ------
    ResultFormatError
        If the file is not a regular file of at most :data:`MAX_LINKS_BYTES` bytes, is
        not UTF-8, lacks a required column, or a row holds a value that is not what the
        column is: root indices and depths integers ``>= 0``, positions finite numbers
        with ``t0 <= t1``. The message names the file, the line and the column.

    Notes
    -----
    The one reader of link lists (the tilings, the hierarchy statistics of
    :mod:`hrbench_analysis.lemmas`). A link list of a sweep point holds up to a few hundred
    thousand rows: numpy's C reader reads them; only a list it refuses, or whose values
    break a rule, is read again row by row, for the message that names line and column.
    """
    try:
        text = read_bounded(path, MAX_LINKS_BYTES, "link list").decode("utf-8")
    except InputFileError as exc:
        raise ResultFormatError(str(exc)) from None
    except UnicodeDecodeError as exc:
        raise ResultFormatError(f"{path}: link list is not UTF-8 text (byte {exc.start})"
                                ) from None
    try:
        reader = csv.reader(io.StringIO(text, newline=""))
        header = [h.strip() for h in next(reader, [])]
        missing = [c for c in _LINK_COLUMNS if c not in header and c not in ("elem_i", "elem_j")]
        if missing:
            raise ResultFormatError(
                f"{path}: link list lacks column(s) {', '.join(missing)}"
                + (" (positions along a root patch: the link list of a 2D scene)"
                   if any(c.startswith("t") for c in missing) else ""))
        col = {name: header.index(name) for name in _READ_COLUMNS}
        data = _read_fast(text, [col[name] for name in _READ_COLUMNS])
        if data is not None:
            return _link_table(data)
        rows = [_link_row(row, col, path, reader.line_num) for row in reader if row]
    except csv.Error as exc:
        raise ResultFormatError(f"{path}: link list is not CSV: {exc}") from None
    return _link_table(np.array(rows, dtype=float).reshape(-1, len(_READ_COLUMNS)))


def _link_table(data):
    return LinkTable(
        root_i=data[:, 0].astype(int), t0_i=data[:, 1], t1_i=data[:, 2],
        depth_i=data[:, 3].astype(int), root_j=data[:, 4].astype(int), t0_j=data[:, 5],
        t1_j=data[:, 6], depth_j=data[:, 7].astype(int))


# The columns a LinkTable holds, in its order; the integer ones.
_READ_COLUMNS = ("root_i", "t0_i", "t1_i", "depth_i", "root_j", "t0_j", "t1_j", "depth_j")
_INTEGER_COLUMNS = ("root_i", "depth_i", "root_j", "depth_j")


def _read_fast(text, columns):
    # The rows below the header with numpy's C reader, as floats, when every value keeps
    # the rules of _link_row; else None (the rows are then read one by one).
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")  # "input contained no data": no links
            data = np.loadtxt(io.StringIO(text), delimiter=",", skiprows=1, usecols=columns,
                              dtype=np.float64, ndmin=2, comments=None)
    except (ValueError, IndexError):
        return None
    data = data.reshape(-1, len(columns))
    integers = data[:, [_READ_COLUMNS.index(name) for name in _INTEGER_COLUMNS]]
    t0 = data[:, [_READ_COLUMNS.index("t0_i"), _READ_COLUMNS.index("t0_j")]]
    t1 = data[:, [_READ_COLUMNS.index("t1_i"), _READ_COLUMNS.index("t1_j")]]
    if (np.all(np.isfinite(data)) and np.all(integers >= 0) and np.all(integers < 2 ** 53)
            and np.all(integers == np.floor(integers)) and np.all(t0 <= t1)):
        return data
    return None


def _link_row(row, col, path, line):
    # One row of a link list as floats, checked.
    values = []
    for name in _READ_COLUMNS:
        text = row[col[name]].strip() if col[name] < len(row) else ""
        try:
            value = float(text)
        except ValueError:
            value = math.nan
        integer = name in _INTEGER_COLUMNS
        if not (math.isfinite(value) and (not integer or value == int(value) and
                                          0 <= value < 2 ** 53)):
            raise ResultFormatError(
                f"{path}:{line}: link list column {name} must be "
                + ("an integer >= 0" if integer else "a finite number")
                + f", got {text[:40]!r}")
        values.append(value)
    for side in ("i", "j"):
        t0, t1 = values[_READ_COLUMNS.index(f"t0_{side}")], values[
            _READ_COLUMNS.index(f"t1_{side}")]
        if t0 > t1:
            raise ResultFormatError(f"{path}:{line}: link list has t0_{side} {t0!r} > "
                                    f"t1_{side} {t1!r}")
    return values
