"""The perspective camera and the z-buffer rasteriser that draw a 3D solution's leaves.

:class:`Camera` is a pinhole camera (:data:`CORNELL_CAMERA` the Cornell box's published
one); :func:`rasterise` finds which leaf each pixel sees, in numpy: each leaf's polygon
split into triangles, cut at the near plane, nearest depth wins. The images drawn from it
are in :mod:`hrbench_analysis.drawing`.
"""

import math
from dataclasses import dataclass

import numpy as np

__all__ = ["Camera", "CORNELL_CAMERA", "rasterise"]

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
# The z-buffer


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
