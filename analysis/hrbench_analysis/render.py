"""Pictures of a solved hierarchy: the leaves' radiosity as an image (3D) or a profile (2D).

``hrbench solve ... --out F.csv`` writes one row per leaf element of the solved hierarchy;
:func:`hrbench_analysis.loader.read_solution` reads it into a :class:`Solution`. In 3D,
:func:`render_image` draws the leaves as seen by a perspective :class:`Camera` with a
z-buffer rasteriser written in numpy (each leaf's polygon split into triangles, nearest
depth wins), optionally with the element mesh over it; :func:`render_figure` puts the image
in a figure for the report. In 2D (flatland), :func:`plot_radiosity_profile` draws each
root patch's radiosity along its arc length. :func:`plot_solution_3d` draws the leaves as
mplot3d polygons coloured by radiosity, to turn round and explore; the command
``hrbench-render`` (:func:`main`, ``python -m hrbench_analysis.render``) solves a scene and
draws it so, with a colour bar:

    hrbench-render cornell --eps 0.05 --min-area 0.005 --out room.png

Columns of the CSV, in this order (a header line names them; extra columns are ignored):

- 2D: ``element,root,depth,position,x,y,measure,radiosity,irradiance,reflectance,emission,
  red,green,blue,x0,y0,x1,y1``;
- 3D: ``element,root,depth,position,x,y,z,measure,radiosity,irradiance,reflectance,emission,
  red,green,blue,corners,x0,y0,z0,x1,y1,z1,x2,y2,z2,x3,y3,z3`` (``x3,y3,z3`` empty for a
  triangle).

As in :mod:`hrbench_analysis.plots`, nothing here creates a pyplot figure or picks a backend.
"""

import math
import sys
import tempfile
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from matplotlib.colors import Normalize
from matplotlib.figure import Figure
from mpl_toolkits.mplot3d.art3d import Poly3DCollection

from .cli import (
    Parser,
    add_engine_options,
    engine_of,
    output_file,
    positive_int,
    positive_number,
    save_figure,
    scene_params,
)
from .engine import MESH_SCENE
from .errors import run_main
from .loader import COLUMNS_2D, COLUMNS_3D, Solution, read_solution

__all__ = [
    "COLUMNS_2D",
    "COLUMNS_3D",
    "Solution",
    "Camera",
    "CORNELL_CAMERA",
    "read_solution",
    "rasterise",
    "default_exposure",
    "srgb_encode",
    "render_image",
    "render_figure",
    "plot_radiosity_profile",
    "radiosity_scale",
    "view_direction",
    "plot_solution_3d",
    "main",
]

#: Factor on the display value of the pixels on an element boundary when ``mesh=True``.
MESH_SHADE = 0.3

#: Radiosity value (after exposure) that the default exposure gives the 99th percentile.
EXPOSURE_TARGET = 0.8

#: Relative raise of an emitting leaf's inverse depth: it wins ties with coplanar
#: surfaces, and loses to any surface nearer by more than a millionth of the distance.
EMITTER_DEPTH_BIAS = 1e-6


@dataclass(frozen=True)
class Camera:
    """A pinhole camera.

    Attributes
    ----------
    eye : (float, float, float)
        Position of the eye (scene units).
    look_at : (float, float, float)
        A point on the optical axis (scene units).
    up : (float, float, float)
        Direction that appears upwards in the image (need not be orthogonal to the axis).
    fov : float
        Vertical field of view (degrees).
    near : float
        Distance of the near clipping plane from the eye along the axis (scene units);
        geometry closer than that is cut away.

    Notes
    -----
    The image's right is ``(look_at - eye) x up``, as in a right-handed look-at camera:
    for the Cornell box (looking along +z with y up) the image's right is -x, so the red
    wall (x = 0.55 m) is on the left, as in the published pictures.
    """

    eye: tuple
    look_at: tuple
    up: tuple
    fov: float
    near: float = 1e-3

    def basis(self):
        """The camera's frame.

        Returns
        -------
        basis : ndarray, shape (3, 3)
            Rows: image right, image up, viewing direction (unit vectors, world
            coordinates).
        """
        forward = np.asarray(self.look_at, float) - np.asarray(self.eye, float)
        forward /= np.linalg.norm(forward)
        right = np.cross(forward, np.asarray(self.up, float))
        norm = np.linalg.norm(right)
        if not norm > 0:
            raise ValueError("camera: up is parallel to the viewing direction")
        right /= norm
        return np.stack([right, np.cross(right, forward), forward])

    def project(self, points, size):
        """Pixel coordinates of points in front of the camera.

        Parameters
        ----------
        points : array_like, shape (..., 3)
            World positions (scene units).
        size : (int, int)
            Image width and height (pixels).

        Returns
        -------
        px, py : ndarray, shape (...)
            Image coordinates (pixels): ``px`` to the right and ``py`` downwards from the
            top left corner of the image; pixel ``(i, j)`` (row ``j``, column ``i``) has its
            centre at ``(i + 0.5, j + 0.5)``.
        depth : ndarray, shape (...)
            Distance in front of the eye along the viewing direction (scene units).
        """
        cam = (np.asarray(points, float) - np.asarray(self.eye, float)) @ self.basis().T
        return _to_pixels(cam, size, self.fov)


#: The Cornell box's published camera (metres): from (0.278, 0.273, -0.800) towards the
#: centre of the box's open side, y up, vertical field of view 39.3 degrees (a 0.035 m lens
#: on 0.025 m film).
CORNELL_CAMERA = Camera(eye=(0.278, 0.273, -0.800), look_at=(0.278, 0.273, 0.0),
                        up=(0.0, 1.0, 0.0), fov=39.3)


def _to_pixels(cam, size, fov):
    width, height = size
    tan_half = math.tan(math.radians(fov) / 2)
    depth = cam[..., 2]
    with np.errstate(divide="ignore", invalid="ignore"):
        px = (cam[..., 0] / (depth * tan_half * width / height) + 1) * (width / 2)
        py = (1 - cam[..., 1] / (depth * tan_half)) * (height / 2)
    return px, py, depth


# ---------------------------------------------------------------------------------------
# Reading




def _require_3d(solution, what):
    if solution.dimension != 3:
        raise ValueError(f"{what} needs a 3D solution, this one is {solution.dimension}D "
                         "(use plot_radiosity_profile for flatland)")


def _triangles(solution):
    """Each leaf's polygon as triangles: vertices (m, 3, 3) and owning leaf (m,)."""
    c = solution.corners
    leaves = np.arange(len(solution))
    quads = np.flatnonzero(solution.n_corners == 4)
    tris = np.concatenate([c[:, [0, 1, 2]], c[quads][:, [0, 2, 3]]])
    owner = np.concatenate([leaves, quads])
    return tris, owner


def _clip_near(tris, owner, near):
    """Cut camera-space triangles at the plane depth = near; return the parts in front."""
    depth = tris[..., 2]
    front = (depth >= near).all(axis=1)
    crossing = np.flatnonzero(~front & (depth >= near).any(axis=1))
    pieces, piece_owner = [tris[front]], [owner[front]]
    for t in crossing:
        polygon = []
        for k in range(3):
            a, b = tris[t, k], tris[t, (k + 1) % 3]
            if a[2] >= near:
                polygon.append(a)
            if (a[2] >= near) != (b[2] >= near):
                s = (near - a[2]) / (b[2] - a[2])
                polygon.append(a + s * (b - a))
        fan = [[polygon[0], polygon[k], polygon[k + 1]] for k in range(1, len(polygon) - 1)]
        if fan:
            pieces.append(np.array(fan))
            piece_owner.append(np.full(len(fan), owner[t]))
    return np.concatenate(pieces), np.concatenate(piece_owner)


# Largest side of the pixel block one triangle is tested over at once (pixels).
_TILE = 256

# Barycentric weight down to which a pixel centre counts as inside a triangle, so that a
# centre on an edge shared by two triangles is not lost to rounding (dimensionless).
_INSIDE_TOLERANCE = -1e-9


def _pow2_at_least(n):
    """The smallest power of two >= n, elementwise for positive integers."""
    return np.left_shift(1, np.ceil(np.log2(n)).astype(np.int64))


def rasterise(solution, *, camera=CORNELL_CAMERA, size=(512, 512), max_block=1 << 21):
    """Which leaf each pixel sees: a z-buffer over the leaves' triangles.

    Each leaf is split into triangles (a quadrilateral along its diagonal from corner 0),
    cut at the camera's near plane and projected; every pixel whose centre lies in a
    triangle (barycentric test over the triangle's pixel bounding box) gets a fragment at
    the interpolated inverse depth, and the nearest fragment of each pixel wins. Triangles
    are processed in batches of similar bounding box size, so the work is vectorised.
    An emitting leaf wins a tie in depth (its inverse depth is raised by
    :data:`EMITTER_DEPTH_BIAS`): a lamp drawn in the plane of a ceiling, as the Cornell
    box's is, shows whole instead of fighting the ceiling pixel by pixel.

    Parameters
    ----------
    solution : Solution
        A 3D solution.
    camera : Camera, optional
    size : (int, int), optional
        Image width and height (pixels).
    max_block : int, optional
        Most candidate pixels handled at once (memory bound: about 50 bytes each).

    Returns
    -------
    ids : ndarray of int, shape (height, width)
        Index (row of the solution) of the leaf seen at each pixel; -1 where none.
    inverse_depth : ndarray of float, shape (height, width)
        1 / distance along the viewing direction of the surface seen (1 / scene units);
        0 where none.

    Raises
    ------
    ValueError
        For a 2D solution or an image size that is not positive.
    """
    _require_3d(solution, "rasterise")
    width, height = (int(s) for s in size)
    if width <= 0 or height <= 0:
        raise ValueError(f"image size must be positive, got {size}")
    ids = np.full(height * width, -1, dtype=np.int64)
    zbuf = np.zeros(height * width)
    if len(solution):
        tris, owner = _triangles(solution)
        cam = (tris - np.asarray(camera.eye, float)) @ camera.basis().T
        cam, owner = _clip_near(cam, owner, camera.near)
        lift = np.where(solution.emission[owner] > 0, 1 + EMITTER_DEPTH_BIAS, 1.0)
        _fill(cam, owner, lift, camera.fov, width, height, ids, zbuf, max_block)
    return ids.reshape(height, width), zbuf.reshape(height, width)


def _fill(cam, owner, lift, fov, width, height, ids, zbuf, max_block):
    px, py, depth = _to_pixels(cam, (width, height), fov)
    inv = lift[:, None] / depth
    # Pixel columns and rows whose centres (i + 0.5) lie within the triangle's extent.
    i0 = np.maximum(np.ceil(px.min(axis=1) - 0.5), 0)
    i1 = np.minimum(np.floor(px.max(axis=1) - 0.5), width - 1)
    j0 = np.maximum(np.ceil(py.min(axis=1) - 0.5), 0)
    j1 = np.minimum(np.floor(py.max(axis=1) - 0.5), height - 1)
    x0, x1, x2 = px.T
    y0, y1, y2 = py.T
    area = (x1 - x0) * (y2 - y0) - (x2 - x0) * (y1 - y0)
    keep = (i1 >= i0) & (j1 >= j0) & (np.abs(area) > 1e-12)
    if not keep.any():
        return
    sel = np.flatnonzero(keep)
    i0, j0 = i0[sel].astype(np.int64), j0[sel].astype(np.int64)
    bw = i1[sel].astype(np.int64) - i0 + 1
    bh = j1[sel].astype(np.int64) - j0 + 1
    x0, x1, x2, y0, y1, y2 = (v[sel] for v in (x0, x1, x2, y0, y1, y2))
    area, inv, owner = area[sel], inv[sel], owner[sel]
    # Barycentric weights as affine functions of the pixel centre: w_k = a_k x + b_k y + c_k.
    a = np.stack([y1 - y2, y2 - y0, y0 - y1], axis=1) / area[:, None]
    b = np.stack([x2 - x1, x0 - x2, x1 - x0], axis=1) / area[:, None]
    c = np.stack([x1 * y2 - x2 * y1, x2 * y0 - x0 * y2, x0 * y1 - x1 * y0],
                 axis=1) / area[:, None]
    # Cut bounding boxes larger than a tile into tiles (one task each), so that the work
    # of one task stays bounded whatever the image size; then process the tasks in groups
    # of equal (power of two) box size, a block of candidate pixels per group at a time.
    tiles_x, tiles_y = -(-bw // _TILE), -(-bh // _TILE)
    count = tiles_x * tiles_y
    tri = np.repeat(np.arange(count.size), count)
    k = np.arange(tri.size) - np.repeat(np.cumsum(count) - count, count)
    tx, ty = k % tiles_x[tri] * _TILE, k // tiles_x[tri] * _TILE
    i0, j0 = i0[tri] + tx, j0[tri] + ty
    bw = np.minimum(bw[tri] - tx, _TILE)
    bh = np.minimum(bh[tri] - ty, _TILE)
    keys = _pow2_at_least(bw) * (2 * _TILE) + _pow2_at_least(bh)
    for key in np.unique(keys):
        group = np.flatnonzero(keys == key)
        gw, gh = int(key // (2 * _TILE)), int(key % (2 * _TILE))
        step = max(1, max_block // (gw * gh))
        ox = np.arange(gw)[None, None, :]
        oy = np.arange(gh)[None, :, None]
        for start in range(0, group.size, step):
            task = group[start:start + step]
            t = tri[task]
            cols = i0[task, None, None] + ox
            rows = j0[task, None, None] + oy
            inside = (ox < bw[task, None, None]) & (oy < bh[task, None, None])
            cx = cols + 0.5
            cy = rows + 0.5
            z = np.zeros(inside.shape)
            for k in range(3):
                w = a[t, k, None, None] * cx + b[t, k, None, None] * cy + c[t, k, None, None]
                inside &= w >= _INSIDE_TOLERANCE
                z += w * inv[t, k, None, None]
            tt, rr, cc = np.nonzero(inside)
            if not tt.size:
                continue
            pix = rows[tt, rr, 0] * width + cols[tt, 0, cc]
            z = z[tt, rr, cc]
            # The z-buffer test: keep the largest inverse depth (the nearest surface) of
            # each pixel, and the leaf of the fragment that set it.
            np.maximum.at(zbuf, pix, z)
            won = z >= zbuf[pix]
            ids[pix[won]] = owner[t[tt[won]]]


# ---------------------------------------------------------------------------------------
# Images


def srgb_encode(linear):
    """The standard sRGB transfer function (IEC 61966-2-1), after clipping to [0, 1].

    Parameters
    ----------
    linear : array_like
        Linear intensities (1 is display white).

    Returns
    -------
    encoded : ndarray
        Display values in [0, 1]: ``12.92 v`` up to ``v = 0.0031308``, then
        ``1.055 v^(1/2.4) - 0.055``.
    """
    v = np.clip(np.asarray(linear, dtype=float), 0.0, 1.0)
    return np.where(v <= 0.0031308, 12.92 * v, 1.055 * v ** (1 / 2.4) - 0.055)


def default_exposure(solution, ids):
    """The exposure that maps the visible, non-emitting leaves' 99th percentile to 0.8.

    Parameters
    ----------
    solution : Solution
    ids : ndarray of int
        The leaf seen at each pixel (-1 for none), from :func:`rasterise`.

    Returns
    -------
    exposure : float
        Factor on the radiosity (1 / units of emission): :data:`EXPOSURE_TARGET` over the
        99th percentile of the radiosity of the distinct leaves seen with ``emission == 0``
        (each leaf counted once, whatever its size on screen). 1 when no such leaf is seen
        or their percentile is 0.
    """
    seen = np.unique(ids[ids >= 0])
    seen = seen[solution.emission[seen] == 0]
    if not seen.size:
        return 1.0
    level = float(np.percentile(solution.radiosity[seen], 99))
    return EXPOSURE_TARGET / level if level > 0 else 1.0


def render_image(solution, *, camera=CORNELL_CAMERA, size=(512, 512), mesh=False,
                 exposure=None):
    """Render a 3D solution: each leaf in its colour times its radiosity.

    Parameters
    ----------
    solution : Solution
        A 3D solution.
    camera : Camera, optional
        Default the Cornell box's published camera.
    size : (int, int), optional
        Image width and height (pixels).
    mesh : bool, optional
        Draw the element mesh: the pixels whose leaf differs from that of their right or
        lower neighbour (the visible element boundaries, silhouettes included) are
        darkened to :data:`MESH_SHADE` of their display value.
    exposure : float, optional
        Factor on the radiosity (1 / units of emission); default
        :func:`default_exposure`.

    Returns
    -------
    image : ndarray of float, shape (height, width, 3)
        sRGB display values in [0, 1]: ``srgb_encode(colour * radiosity * exposure)``,
        black where no leaf is seen.

    Raises
    ------
    ValueError
        For a 2D solution, or an exposure that is not a positive finite number.
    """
    ids, _ = rasterise(solution, camera=camera, size=size)
    if exposure is None:
        exposure = default_exposure(solution, ids)
    exposure = float(exposure)
    if not (math.isfinite(exposure) and exposure > 0):
        raise ValueError(f"exposure must be a positive finite number, got {exposure}")
    seen = ids >= 0
    linear = np.zeros(ids.shape + (3,))
    leaf = ids[seen]
    linear[seen] = solution.colour[leaf] * (solution.radiosity[leaf] * exposure)[:, None]
    image = srgb_encode(linear)
    if mesh:
        edge = np.zeros(ids.shape, dtype=bool)
        edge[:, :-1] |= ids[:, :-1] != ids[:, 1:]
        edge[:-1, :] |= ids[:-1, :] != ids[1:, :]
        image[edge] *= MESH_SHADE
    return image


def render_figure(solution, *, mesh=False, title="", camera=CORNELL_CAMERA, size=(512, 512),
                  exposure=None):
    """A figure of the rendered image, for the report.

    Parameters
    ----------
    solution : Solution
        A 3D solution.
    mesh : bool, optional
        Draw the element mesh (see :func:`render_image`).
    title : str, optional
        Title above the image.
    camera, size, exposure : optional
        As for :func:`render_image`.

    Returns
    -------
    fig : matplotlib.figure.Figure
        One Axes with the image at one figure pixel per image pixel (100 dpi), no ticks.
    """
    image = render_image(solution, camera=camera, size=size, mesh=mesh, exposure=exposure)
    height, width = image.shape[:2]
    fig = Figure(figsize=(max(width / 100, 2.0), max(height / 100, 2.0) + 0.4 * bool(title)),
                 layout="constrained")
    ax = fig.add_subplot()
    ax.imshow(image, interpolation="nearest")
    ax.set_xticks([])
    ax.set_yticks([])
    if title:
        ax.set_title(title, fontsize=10)
    return fig


# ---------------------------------------------------------------------------------------
# Flatland profiles


def plot_radiosity_profile(ax, solution, reference=None, reference_depth=None):
    """Draw each root patch's radiosity along its arc length (2D).

    Parameters
    ----------
    ax : matplotlib.axes.Axes
    solution : Solution
        A 2D solution.
    reference : array_like, optional
        Radiosities of a uniform reference solution, root by root (in increasing root
        index) and, for each root, its ``2**reference_depth`` elements in position order;
        flat or of shape (roots, ``2**reference_depth``). Drawn as a thin dashed step line
        in each root's colour over the same arc lengths.
    reference_depth : int, optional
        Depth of the reference; default inferred from its length.

    Returns
    -------
    lines : list of matplotlib.lines.Line2D
        The solution's line of each root, in increasing root index, labelled
        ``"patch k"``. Each is a step function of the arc length from the root's first end
        point (scene units): leaf ``(depth, position)`` spans
        ``[position, position + 1] * 2**-depth`` of the root's length, which is the sum of
        its leaves' lengths.

    Raises
    ------
    ValueError
        For a 3D solution, leaves that do not tile their root, or a reference whose size
        does not match the roots and depth.
    """
    if solution.dimension != 2:
        raise ValueError("plot_radiosity_profile needs a 2D solution, this one is "
                         f"{solution.dimension}D (use render_image)")
    roots = np.unique(solution.root)
    ref = None
    if reference is not None:
        ref = np.asarray(reference, dtype=float)
        if ref.ndim == 1:
            if ref.size % max(roots.size, 1):
                raise ValueError(f"reference has {ref.size} values, not a multiple of the "
                                 f"{roots.size} root(s)")
            ref = ref.reshape(roots.size, -1)
        per_root = ref.shape[1] if ref.ndim == 2 else -1
        if ref.ndim != 2 or ref.shape[0] != roots.size:
            raise ValueError(f"reference must hold one row per root ({roots.size}), got "
                             f"shape {np.shape(reference)}")
        if reference_depth is None:
            reference_depth = per_root.bit_length() - 1
        if per_root != 2 ** int(reference_depth):
            raise ValueError(f"reference has {per_root} values per root, expected "
                             f"2^{reference_depth}")
    lines = []
    for n, r in enumerate(roots):
        leaves = np.flatnonzero(solution.root == r)
        scale = 2.0 ** -solution.depth[leaves].astype(float)
        start = solution.position[leaves] * scale
        order = np.argsort(start, kind="stable")
        leaves, start, scale = leaves[order], start[order], scale[order]
        end = start + scale
        if not (np.isclose(start[0], 0) and np.isclose(end[-1], 1)
                and np.allclose(start[1:], end[:-1])):
            raise ValueError(f"the leaves of root {r} do not tile it")
        length = float(solution.measure[leaves].sum())
        x = np.column_stack([start, end]).ravel() * length
        y = np.repeat(solution.radiosity[leaves], 2)
        (line,) = ax.plot(x, y, "-", lw=1.4, color=f"C{n % 10}", label=f"patch {r}")
        lines.append(line)
        if ref is not None:
            edges = np.linspace(0.0, length, ref.shape[1] + 1)
            ax.plot(np.column_stack([edges[:-1], edges[1:]]).ravel(), np.repeat(ref[n], 2),
                    "--", lw=0.8, color=line.get_color(),
                    label=f"uniform reference (depth {reference_depth})" if n == 0
                    else "_nolegend_")
    ax.set_xlabel("arc length along the patch (scene units)")
    ax.set_ylabel("radiosity B (scene units of emission)")
    if lines:
        ax.legend(fontsize=8)
    return lines


# ---------------------------------------------------------------------------------------
# Polygons in mplot3d, and the command hrbench-render


def radiosity_scale(solution):
    """The top of a colour scale of radiosity: emitters must not wash out the rest.

    Returns
    -------
    top : float
        The 99th percentile of the radiosity of the leaves that do not emit (each leaf
        counted once), else of all leaves; the largest radiosity if that is 0; 1 if all
        are 0 (units of emission).
    """
    lit = solution.radiosity[solution.emission == 0]
    values = lit if lit.size else solution.radiosity
    top = float(np.percentile(values, 99))
    if top <= 0:
        top = float(solution.radiosity.max())
    return top if top > 0 else 1.0


def view_direction(elev, azim, up="z"):
    """The unit vector from the scene towards the eye of an mplot3d view.

    Parameters
    ----------
    elev, azim : float
        Elevation and azimuth (degrees), as ``Axes3D.view_init`` takes them.
    up : {"x", "y", "z"}
        The vertical axis (``view_init``'s ``vertical_axis``).

    Returns
    -------
    direction : ndarray, shape (3,)
        In data coordinates, for axes of equal scale (as :func:`plot_solution_3d` sets).
    """
    e, a = np.radians(elev), np.radians(azim)
    direction = np.array([np.cos(e) * np.cos(a), np.cos(e) * np.sin(a), np.sin(e)])
    # mplot3d's own rule: the z-up vector rolled so that its last entry is the up axis.
    return np.roll(direction, "xyz".index(up) - 2)


def plot_solution_3d(ax, solution, *, cmap="inferno", norm=None, edges=True, facing=None):
    """Draw a 3D solution's leaves as polygons coloured by their radiosity.

    Parameters
    ----------
    ax : mpl_toolkits.mplot3d.axes3d.Axes3D
    solution : Solution
        A 3D solution.
    cmap : str or Colormap, optional
    norm : matplotlib.colors.Normalize, optional
        Default ``Normalize(0, radiosity_scale(solution))``: brighter leaves (the lamp)
        get the colour map's top colour.
    edges : bool, optional
        Outline every leaf (the element mesh).
    facing : array_like, shape (3,), optional
        The direction towards the eye (:func:`view_direction`): leaves whose front faces
        away from it are left out, as a patch sends light from its front only (and the
        walls of a room seen from outside would hide its inside).

    Returns
    -------
    collection : mpl_toolkits.mplot3d.art3d.Poly3DCollection
        Pass it to ``Figure.colorbar`` for the scale. The axes span the corners' box
        with equal scale on x, y and z (scene units).

    Notes
    -----
    mplot3d sorts whole polygons by depth (the painter's algorithm): near and far
    leaves that overlap on screen can be drawn in the wrong order, which a z-buffer
    (:func:`render_image`) never does. Give `facing` for an orthographic view
    (``ax.set_proj_type("ortho")``); in perspective, leaves seen almost edge-on may be
    culled wrongly.
    """
    _require_3d(solution, "plot_solution_3d")
    shown = np.arange(len(solution))
    if facing is not None:
        c = solution.corners
        front = np.cross(c[:, 1] - c[:, 0], c[:, 2] - c[:, 0])
        shown = np.flatnonzero(front @ np.asarray(facing, dtype=float) > 0)
    polygons = [solution.corners[i, :solution.n_corners[i]] for i in shown]
    collection = Poly3DCollection(
        polygons, cmap=cmap, norm=norm or Normalize(0.0, radiosity_scale(solution)),
        edgecolor=(0, 0, 0, 0.25) if edges else "face", linewidth=0.2 if edges else 0)
    collection.set_array(solution.radiosity[shown])
    ax.add_collection3d(collection)
    low = np.nanmin(solution.corners, axis=(0, 1))
    high = np.nanmax(solution.corners, axis=(0, 1))
    # A flat scene keeps a thin box: mplot3d cannot scale an axis of zero extent.
    span = np.maximum(high - low, 1e-3 * float(np.max(high - low)) or 1.0)
    ax.set(xlim=(low[0], low[0] + span[0]), ylim=(low[1], low[1] + span[1]),
           zlim=(low[2], low[2] + span[2]), xlabel="x", ylabel="y", zlabel="z")
    ax.set_box_aspect(span)
    return collection


#: The view of ``hrbench-render`` (vertical axis, elevation and azimuth in degrees) by
#: scene family: the Cornell box, y up as in its published data, from its open side
#: (where its published camera stands), raised and turned so that the floor and a side
#: wall show; any other scene from matplotlib's default view, z up.
VIEWS = {"cornell": ("y", 15.0, 155.0)}
DEFAULT_VIEW = ("z", 30.0, -60.0)


def _render_parser():
    p = Parser(prog="hrbench-render",
               description="Solve a 3D scene's radiosity on the hierarchy (hrbench solve) "
               "and draw its leaves coloured by radiosity, with a colour bar; a flatland "
               "scene is drawn as its radiosity profile along the patches.")
    p.add_argument("scene", nargs="?", metavar="SCENE",
                   help="a scene family, e.g. cornell (or --mesh F)")
    p.add_argument("params", nargs="*", metavar="key=value",
                   help="its parameters (default: the family's)")
    p.add_argument("--eps", type=positive_number, required=True, metavar="E",
                   help="oracle threshold")
    p.add_argument("--out", type=output_file, required=True, metavar="FILE",
                   help="PNG to write")
    p.add_argument("--oracle", default="garmann", help="oracle (default: %(default)s)")
    p.add_argument("--min-area", type=positive_number, metavar="A",
                   help="recursion limit on element size (scenes whose patches touch)")
    p.add_argument("--max-depth", type=int, metavar="D", help="recursion limit on depth")
    p.add_argument("--visibility", choices=("none", "fraction", "refine"),
                   help="occlusion (default: the engine's, none)")
    p.add_argument("--emission", type=float, metavar="E",
                   help="emission of every patch (for scenes without a lamp)")
    p.add_argument("--reflectance", type=float, metavar="R",
                   help="reflectance of every patch")
    p.add_argument("--threads", type=positive_int, default=1, metavar="N",
                   help="solver threads (the solution does not depend on them)")
    p.add_argument("--mesh", type=Path, metavar="F", help="an OFF or OBJ file instead of SCENE")
    p.add_argument("--triangulate", action="store_true",
                   help="with --mesh: split faces that are not planar convex quads")
    p.add_argument("--scale", type=positive_number, metavar="S",
                   help="with --mesh: multiply every coordinate by S")
    p.add_argument("--view", type=float, nargs=2, metavar=("ELEV", "AZIM"),
                   help="elevation and azimuth of the view in degrees (default: by scene)")
    p.add_argument("--up", choices=("x", "y", "z"), help="the vertical axis (default: by "
                   "scene, y for cornell, else z)")
    p.add_argument("--size", type=positive_int, nargs=2, default=(900, 750),
                   metavar=("W", "H"), help="image size in pixels (default: 900 750)")
    p.add_argument("--csv", type=output_file, metavar="F",
                   help="also keep the leaves the engine wrote (hrbench solve --out F)")
    add_engine_options(p)
    return p


def _render_main(argv):
    from .solution import solve_to_csv  # solution draws with this module

    parser = _render_parser()
    args = parser.parse_args(argv)
    if (args.scene is None) == (args.mesh is None):
        parser.error("give either SCENE [key=value ...] or --mesh F")
    scene, params = (scene_params(parser, [args.scene, *args.params]) if args.scene
                     else (MESH_SCENE, {}))
    if args.mesh is None and (args.triangulate or args.scale is not None):
        parser.error("--triangulate and --scale apply to --mesh only")
    options = {name: value for name, value in (
        ("mesh", None if args.mesh is None else str(args.mesh)),
        ("triangulate", args.triangulate or None), ("scale", args.scale),
        ("visibility", args.visibility), ("emission", args.emission),
        ("reflectance", args.reflectance), ("threads", args.threads)) if value is not None}
    engine = engine_of(args)
    with tempfile.TemporaryDirectory(prefix="hrbench-render-") as folder:
        csv_path = args.csv or Path(folder) / "solution.csv"
        record = solve_to_csv(engine, scene, params, args.eps, args.oracle, options,
                              csv_path, min_area=args.min_area, max_depth=args.max_depth)
        solution = read_solution(csv_path)
    what = " ".join([args.mesh.name if args.mesh else scene,
                     *(f"{k}={v:g}" for k, v in params.items())])
    title = (f"{what}, {args.oracle}, eps {args.eps:g}: {len(solution)} leaves, "
             f"{record['links']} links, {record['iterations']} sweeps")
    width, height = args.size
    fig = Figure(figsize=(width / 100, height / 100), layout="constrained")
    if solution.dimension == 2:
        ax = fig.add_subplot()
        plot_radiosity_profile(ax, solution)
        ax.grid(True, alpha=0.3)
    else:
        up, elev, azim = VIEWS.get(scene, DEFAULT_VIEW)
        elev, azim = args.view or (elev, azim)
        up = args.up or up
        ax = fig.add_subplot(projection="3d", proj_type="ortho")
        ax.view_init(elev=elev, azim=azim, vertical_axis=up)
        collection = plot_solution_3d(ax, solution, facing=view_direction(elev, azim, up))
        top = collection.norm.vmax
        bar = fig.colorbar(collection, ax=ax, shrink=0.7,
                           extend="max" if solution.radiosity.max() > top else "neither")
        bar.set_label("radiosity B (units of emission)")
    ax.set_title(title, fontsize=10)
    save_figure(fig, args.out)
    print(f"{args.out}: {title}")
    return 0


def main(argv=None):
    """Run ``hrbench-render``; return its exit code (0, 2 for bad input or environment)."""
    return run_main("hrbench-render", _render_main, argv)


if __name__ == "__main__":
    sys.exit(main())

