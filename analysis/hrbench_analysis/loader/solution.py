"""Solutions: the CSV ``hrbench solve --out`` writes, one row per leaf element of the
solved hierarchy (:class:`Solution`)."""

import csv
import math
from dataclasses import dataclass

import numpy as np

from ..errors import one_line
from .record import ResultFormatError

_COMMON = ("element", "root", "depth", "position")
_SHADING = ("measure", "radiosity", "irradiance", "reflectance", "emission",
            "red", "green", "blue")

#: Columns of a 2D (flatland) solution file, in the engine's order.
COLUMNS_2D = _COMMON + ("x", "y") + _SHADING + ("x0", "y0", "x1", "y1")

#: Columns of a 3D solution file, in the engine's order.
COLUMNS_3D = (_COMMON + ("x", "y", "z") + _SHADING + ("corners",)
              + tuple(f"{a}{k}" for k in range(4) for a in "xyz"))

_INTEGER_COLUMNS = ("element", "root", "depth", "position")
_FOURTH_CORNER = ("x3", "y3", "z3")


@dataclass(frozen=True, eq=False)
class Solution:
    """The leaves of a solved hierarchy, as written by ``hrbench solve --out``.

    Row ``i`` of every array is leaf ``i``, in the order of the file. Lengths are in scene
    units (metres for the Cornell box).

    Attributes
    ----------
    dimension : int
        2 (flatland) or 3.
    element : ndarray of int, shape (n,)
        The engine's element index.
    root : ndarray of int, shape (n,)
        Index of the leaf's root patch.
    depth : ndarray of int, shape (n,)
        Subdivision depth below its root (levels; 0 for an unsubdivided root).
    position : ndarray of int, shape (n,)
        Index among the ``2**depth`` elements of its root at that depth (in 2D, left to right
        from the root's first end point).
    centre : ndarray of float, shape (n, dimension)
        Centre of the leaf (scene units).
    measure : ndarray of float, shape (n,)
        Length (2D) or area (3D) of the leaf (scene units, squared in 3D).
    radiosity : ndarray of float, shape (n,)
        Radiosity B (>= 0, monochrome; in the units of the scene's emission).
    irradiance : ndarray of float, shape (n,)
        Irradiance (units of emission).
    reflectance : ndarray of float, shape (n,)
        Diffuse reflectance (dimensionless, in [0, 1]).
    emission : ndarray of float, shape (n,)
        Emitted radiosity E (units of emission); 0 for a leaf that does not emit.
    colour : ndarray of float, shape (n, 3)
        The material's diffuse display colour, linear red, green, blue in [0, 1].
    ends : ndarray of float, shape (n, 2, 2), or None
        2D only: the end points ``(x0, y0), (x1, y1)`` (scene units).
    corners : ndarray of float, shape (n, 4, 3), or None
        3D only: the corners in order around the polygon (scene units); the fourth is NaN
        for a triangle.
    n_corners : ndarray of int, shape (n,), or None
        3D only: 3 (triangle) or 4 (quadrilateral).
    source : str
        The file it was read from.
    """

    dimension: int
    element: np.ndarray
    root: np.ndarray
    depth: np.ndarray
    position: np.ndarray
    centre: np.ndarray
    measure: np.ndarray
    radiosity: np.ndarray
    irradiance: np.ndarray
    reflectance: np.ndarray
    emission: np.ndarray
    colour: np.ndarray
    ends: object = None
    corners: object = None
    n_corners: object = None
    source: str = ""

    def __len__(self):
        return int(self.element.size)


def _fail(path, line, message):
    raise ResultFormatError(one_line(f"{path}, line {line}: {message}"))


def _short(text):
    text = str(text)
    return repr(text if len(text) <= 40 else text[:37] + "...")


def _parse_floats(path, texts, lines, name):
    try:
        values = np.array(texts, dtype=float)
    except ValueError:
        values = None
    if values is not None and np.isfinite(values).all():
        return values
    for text, line in zip(texts, lines, strict=True):
        try:
            value = float(text)
        except ValueError:
            _fail(path, line, f"column {name!r} is not a number: {_short(text)}")
        if not math.isfinite(value):
            _fail(path, line, f"column {name!r} is not a finite number: {_short(text)}")
    raise AssertionError("unreachable")  # pragma: no cover


def _parse_integers(path, texts, lines, name):
    values = _parse_floats(path, texts, lines, name)
    bad = np.flatnonzero(values != np.round(values))
    if bad.size:
        _fail(path, lines[bad[0]], f"column {name!r} is not an integer: "
                                   f"{_short(texts[bad[0]])}")
    return values.astype(np.int64)


def read_solution(path):
    """Read the leaves of a solved hierarchy written by ``hrbench solve --out``.

    Parameters
    ----------
    path : str or path-like
        CSV file with a header line naming the columns of :data:`COLUMNS_2D` or
        :data:`COLUMNS_3D` (a ``z`` or ``corners`` column makes it 3D). Other columns are
        ignored.

    Returns
    -------
    solution : Solution

    Raises
    ------
    ResultFormatError
        One line naming the file and the line: a missing header or no rows, a missing
        column, a row with the wrong number of fields, a value that is not a finite number
        (or not an integer where one is expected), a corner count other than 3 or 4, or a
        fourth corner that is given for a triangle or missing for a quadrilateral.
    """
    with open(path, newline="") as fh:
        reader = csv.reader(fh)
        header = next(reader, None)
        if header is None or not any(h.strip() for h in header):
            _fail(path, 1, "empty file, expected a header line naming the columns")
        header = [h.strip() for h in header]
        dimension = 3 if "z" in header or "corners" in header else 2
        expected = COLUMNS_3D if dimension == 3 else COLUMNS_2D
        missing = [c for c in expected if c not in header]
        if missing:
            _fail(path, 1, f"{dimension}D solution lacks column(s) {', '.join(missing)}")
        rows, lines = [], []
        for row in reader:
            if not any(field.strip() for field in row):
                continue
            if len(row) != len(header):
                _fail(path, reader.line_num, f"{len(row)} fields, the header has "
                                             f"{len(header)}")
            rows.append(row)
            lines.append(reader.line_num)
    if not rows:
        _fail(path, 2, "no element rows after the header")
    index = {name: header.index(name) for name in expected}
    text = {name: [row[index[name]].strip() for row in rows] for name in expected}

    def floats(name):
        return _parse_floats(path, text[name], lines, name)

    values = {name: _parse_integers(path, text[name], lines, name)
              for name in _INTEGER_COLUMNS}
    for name in ("x", "y", "z")[:dimension] + _SHADING:
        values[name] = floats(name)
    depth, position = values["depth"], values["position"]
    bad = np.flatnonzero((depth < 0) | (depth > 62) | (position < 0)
                         | (position >= np.left_shift(1, np.clip(depth, 0, 62))))
    if bad.size:
        i = bad[0]
        _fail(path, lines[i], f"position {position[i]} is not one of the 2^depth elements "
                              f"of its root at depth {depth[i]}")
    geometry = {}
    if dimension == 2:
        geometry["ends"] = np.stack([np.stack([floats(f"x{k}"), floats(f"y{k}")], axis=1)
                                     for k in range(2)], axis=1)
    else:
        n_corners = _parse_integers(path, text["corners"], lines, "corners")
        bad = np.flatnonzero((n_corners != 3) & (n_corners != 4))
        if bad.size:
            _fail(path, lines[bad[0]], f"column 'corners' must be 3 or 4, got "
                                       f"{_short(text['corners'][bad[0]])}")
        corners = np.full((len(rows), 4, 3), np.nan)
        for k in range(3):
            for a, axis in enumerate("xyz"):
                corners[:, k, a] = floats(f"{axis}{k}")
        quad = n_corners == 4
        quad_lines = [line for line, q in zip(lines, quad, strict=True) if q]
        for a, name in enumerate(_FOURTH_CORNER):
            column = text[name]
            for i in np.flatnonzero(~quad):
                if column[i]:
                    _fail(path, lines[i], f"a triangle (corners = 3) has a fourth corner: "
                                          f"column {name!r} is {_short(column[i])}, "
                                          "expected empty")
            quad_texts = [t for t, q in zip(column, quad, strict=True) if q]
            corners[quad, 3, a] = _parse_floats(path, quad_texts, quad_lines, name)
        geometry["corners"] = corners
        geometry["n_corners"] = n_corners
    return Solution(
        dimension=dimension,
        element=values["element"], root=values["root"], depth=values["depth"],
        position=values["position"],
        centre=np.stack([values[a] for a in ("x", "y", "z")[:dimension]], axis=1),
        measure=values["measure"], radiosity=values["radiosity"],
        irradiance=values["irradiance"], reflectance=values["reflectance"],
        emission=values["emission"],
        colour=np.stack([values["red"], values["green"], values["blue"]], axis=1),
        source=str(path), **geometry)


# ---------------------------------------------------------------------------------------
# Rasterising
