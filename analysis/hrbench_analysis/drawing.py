"""Drawings of a solved hierarchy: the leaves' radiosity as an image (3D), a profile (2D),
or mplot3d polygons.

In 3D, :func:`render_image` draws the leaves as seen by a perspective
:class:`~hrbench_analysis.raster.Camera` (through the z-buffer rasteriser of
:mod:`hrbench_analysis.raster`), optionally with the element mesh over it;
:func:`render_figure` puts the image in a figure for the report. In 2D (flatland),
:func:`plot_radiosity_profile` draws each root patch's radiosity along its arc length.
:func:`plot_solution_3d` draws the leaves as mplot3d polygons coloured by radiosity, to turn
round and explore (the command ``hrbench-render``, :mod:`hrbench_analysis.render`).

As in :mod:`hrbench_analysis.plots`, nothing here creates a pyplot figure or picks a backend.
"""

import math

import numpy as np
from matplotlib.cm import ScalarMappable
from matplotlib.colors import ListedColormap, Normalize
from matplotlib.figure import Figure
from matplotlib.lines import Line2D
from matplotlib.patches import Patch
from mpl_toolkits.mplot3d.art3d import Line3DCollection, Poly3DCollection

from .raster import CORNELL_CAMERA, _require_3d, rasterise

__all__ = [
    "default_exposure",
    "srgb_encode",
    "display_tint",
    "emitter_label",
    "render_image",
    "render_figure",
    "plot_radiosity_profile",
    "radiosity_scale",
    "view_direction",
    "plot_solution_3d",
]

#: Factor on the display value of the pixels on an element boundary when ``mesh=True``.
MESH_SHADE = 0.3

#: Radiosity value (after exposure) that the default exposure gives the 99th percentile.
EXPOSURE_TARGET = 0.8

#: Colour of the outline that marks the emitters (the lamp) in a picture.
EMITTER_MARK = "tab:cyan"

#: Most materials a rendered figure's legend names (the most seen first).
LEGEND_MATERIALS = 6


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


def display_tint(solution):
    """Each leaf's colour scaled to a mean of 1: the factor on its radiosity per channel.

    The solve is monochrome: off the emitters ``B = rho H``, the reflectance ``rho``
    being the mean of the material's colour where the scene gives one. A channel of
    reflectance ``c_k`` under the same irradiance ``H`` sends ``c_k H = B c_k / rho``, so
    a leaf drawn with ``B`` times its tint shows its material's hue, and the mean of its
    red, green and blue is its radiosity. A leaf without a colour of its own is grey
    (the Cornell box's lamp, which shows white).

    Parameters
    ----------
    solution : Solution

    Returns
    -------
    tint : ndarray of float, shape (n, 3)
        ``colour / mean(colour)`` per leaf (dimensionless); grey ``(1, 1, 1)`` for a
        black colour.
    """
    mean = solution.colour.mean(axis=1, keepdims=True)
    safe = np.where(mean > 0, mean, 1.0)
    return np.where(mean > 0, solution.colour / safe, 1.0)


def emitter_label(solution, leaves):
    """A legend label for the emitters among `leaves` (indices), or None if none emits.

    Returns
    -------
    label : str or None
        E.g. ``"emitter (lamp), E = 11 units of emission"``, with the range of E where
        the emitters differ.
    """
    emission = solution.emission[np.asarray(leaves, dtype=np.int64)]
    emission = emission[emission > 0]
    if not emission.size:
        return None
    low, high = float(emission.min()), float(emission.max())
    value = f"E = {low:.3g}" if np.isclose(low, high) else f"E = {low:.3g} to {high:.3g}"
    return f"emitter (lamp), {value} units of emission"


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
    """Render a 3D solution: each leaf in its material's hue at its radiosity.

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
        sRGB display values in [0, 1]:
        ``srgb_encode(display_tint * radiosity * exposure)`` (:func:`display_tint`),
        black where no leaf is seen.

    Raises
    ------
    ValueError
        For a 2D solution, or an exposure that is not a positive finite number.
    """
    return _render(solution, camera, size, mesh, exposure)[0]


def _render(solution, camera, size, mesh, exposure):
    # render_image's image, with the leaf seen at each pixel and the exposure taken.
    ids, _ = rasterise(solution, camera=camera, size=size)
    if exposure is None:
        exposure = default_exposure(solution, ids)
    exposure = float(exposure)
    if not (math.isfinite(exposure) and exposure > 0):
        raise ValueError(f"exposure must be a positive finite number, got {exposure}")
    seen = ids >= 0
    linear = np.zeros(ids.shape + (3,))
    leaf = ids[seen]
    linear[seen] = display_tint(solution)[leaf] * (solution.radiosity[leaf] * exposure)[:, None]
    image = srgb_encode(linear)
    if mesh:
        edge = np.zeros(ids.shape, dtype=bool)
        edge[:, :-1] |= ids[:, :-1] != ids[:, 1:]
        edge[:-1, :] |= ids[:-1, :] != ids[1:, :]
        image[edge] *= MESH_SHADE
    return image, ids, exposure


def render_figure(solution, *, mesh=False, title="", camera=CORNELL_CAMERA, size=(512, 512),
                  exposure=None):
    """A figure of the rendered image, for the report, with what its colours mean.

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
        The image (first Axes, no ticks, about one figure pixel per image pixel at 100
        dpi) with a colour bar of the radiosity B: the grey a surface of grey colour
        shows at B (a coloured one shows its hue at the same mean of red, green and
        blue), extended where brighter leaves are seen. The emitters seen are outlined
        in :data:`EMITTER_MARK`; a legend below names them and the materials seen
        (their colour and reflectance, at most :data:`LEGEND_MATERIALS`, the most seen
        first).
    """
    image, ids, exposure = _render(solution, camera, size, mesh, exposure)
    height, width = image.shape[:2]
    leaves, pixels = np.unique(ids[ids >= 0], return_counts=True)
    materials = _materials_seen(solution, leaves, pixels)
    lamp = emitter_label(solution, leaves)
    rows = -(-(len(materials) + bool(lamp)) // 2)
    fig = Figure(figsize=(max(width / 100, 2.0) + 1.2,
                          max(height / 100, 2.0) + 0.4 * bool(title) + 0.25 * rows + 0.1),
                 layout="constrained")
    ax = fig.add_subplot()
    ax.imshow(image, interpolation="nearest")
    ax.set_xticks([])
    ax.set_yticks([])
    if title:
        ax.set_title(title, fontsize=10)
    # The grey ramp as render_image draws it: B * exposure through the sRGB curve.
    ramp = ListedColormap(np.repeat(srgb_encode(np.linspace(0, 1, 256))[:, None], 3, axis=1))
    brighter = bool(leaves.size) and solution.radiosity[leaves].max() * exposure > 1
    bar = fig.colorbar(ScalarMappable(Normalize(0.0, 1.0 / exposure), ramp), ax=ax,
                       shrink=0.8, extend="max" if brighter else "neither")
    bar.set_label("radiosity B (units of emission)")
    handles = [Patch(facecolor=srgb_encode(colour), edgecolor="0.5",
                     label=f"reflectance {rho:.2f}, RGB {' '.join(f'{c:.2f}' for c in colour)}")
               for colour, rho in materials]
    if lamp:
        emitting = (ids >= 0) & (solution.emission[np.maximum(ids, 0)] > 0)
        ax.contour(emitting.astype(float), levels=[0.5], colors=[EMITTER_MARK],
                   linewidths=1.5)
        handles.append(Line2D([], [], color=EMITTER_MARK, lw=1.5,
                              label=f"{lamp} (outlined)"))
    if handles:
        fig.legend(handles=handles, loc="outside lower center", ncols=2, fontsize=8,
                   title="hue: the surface's colour; brightness: its radiosity",
                   title_fontsize=8)
    return fig


def _materials_seen(solution, leaves, pixels):
    """The distinct (colour, reflectance) of the non-emitting `leaves`, most pixels first."""
    area = {}
    for leaf, count in zip(leaves, pixels, strict=True):
        if solution.emission[leaf] == 0:
            key = (tuple(float(c) for c in solution.colour[leaf]),
                   float(solution.reflectance[leaf]))
            area[key] = area.get(key, 0) + int(count)
    ranked = sorted(area, key=lambda key: -area[key])
    return ranked[:LEGEND_MATERIALS]


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
# Polygons in mplot3d


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
        with equal scale on x, y and z (scene units). The emitting leaves are outlined
        in :data:`EMITTER_MARK` over everything, whichever way they face, by a line
        collection labelled with :func:`emitter_label` (``ax.legend()`` names it).

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
    # The lamp of a room seen from above faces away and is left out; a reader still
    # looks for it, so it is outlined on top (drawn in the order added, not by depth).
    lamps = np.flatnonzero(solution.emission > 0)
    if lamps.size:
        rings = [np.vstack([p, p[:1]]) for p in
                 (solution.corners[i, :solution.n_corners[i]] for i in lamps)]
        ax.add_collection3d(Line3DCollection(rings, colors=EMITTER_MARK, linewidths=1.5,
                                             label=emitter_label(solution, lamps)))
        ax.computed_zorder = False
    low = np.nanmin(solution.corners, axis=(0, 1))
    high = np.nanmax(solution.corners, axis=(0, 1))
    # A flat scene keeps a thin box: mplot3d cannot scale an axis of zero extent.
    span = np.maximum(high - low, 1e-3 * float(np.max(high - low)) or 1.0)
    ax.set(xlim=(low[0], low[0] + span[0]), ylim=(low[1], low[1] + span[1]),
           zlim=(low[2], low[2] + span[2]), xlabel="x", ylabel="y", zlabel="z")
    ax.set_box_aspect(span)
    return collection
