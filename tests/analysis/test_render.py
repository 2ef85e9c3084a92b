import io
import math
import os
from pathlib import Path

import numpy as np
import pytest
from matplotlib.colors import to_rgb
from matplotlib.figure import Figure
from matplotlib.image import imread

from hrbench_analysis.drawing import (
    EMITTER_MARK,
    LEGEND_MATERIALS,
    MESH_SHADE,
    display_tint,
    emitter_label,
    plot_radiosity_profile,
    plot_solution_3d,
    radiosity_scale,
    render_figure,
    render_image,
    view_direction,
)
from hrbench_analysis.loader import COLUMNS_2D, COLUMNS_3D, ResultFormatError, read_solution
from hrbench_analysis.raster import CORNELL_CAMERA, Camera, rasterise
from hrbench_analysis.render import main as render_main

HEADER_2D = ("element,root,depth,position,x,y,measure,radiosity,irradiance,reflectance,"
             "emission,red,green,blue,x0,y0,x1,y1")
HEADER_3D = ("element,root,depth,position,x,y,z,measure,radiosity,irradiance,reflectance,"
             "emission,red,green,blue,corners,x0,y0,z0,x1,y1,z1,x2,y2,z2,x3,y3,z3")

# A camera on the -z axis looking at the origin: the image's right is -x, its up +y.
EYE_Z = -5.0
FOV = 40.0
SIZE = (160, 120)  # width, height
CAMERA = Camera(eye=(0.0, 0.0, EYE_Z), look_at=(0.0, 0.0, 0.0), up=(0.0, 1.0, 0.0), fov=FOV)


def pixel_of(x, y, z, size=SIZE):
    """Row and column of the pixel that sees the world point, computed by hand."""
    width, height = size
    t = math.tan(math.radians(FOV) / 2)
    depth = z - EYE_Z
    px = (-x / (depth * t * width / height) + 1) * width / 2
    py = (1 - y / (depth * t)) * height / 2
    return int(py), int(px)


def srgb(v):
    return 12.92 * v if v <= 0.0031308 else 1.055 * v ** (1 / 2.4) - 0.055


def shown(colour, level):
    """The display value of a leaf of `colour` at radiosity times exposure `level`."""
    mean = sum(colour) / 3
    return [srgb(min(c / mean * level, 1.0)) for c in colour]


def leaf_3d(element, corners, *, colour=(1.0, 1.0, 1.0), b=1.0, emission=0.0, root=None,
            depth=0, position=0):
    corners = np.asarray(corners, float)
    centre = corners.mean(axis=0)
    fields = [element, element if root is None else root, depth, position, *centre, 1.0, b,
              b, 0.5, emission, *colour, len(corners), *corners.ravel()]
    if len(corners) == 3:
        fields += ["", "", ""]
    return ",".join(str(f) for f in fields)


def square(x0, x1, y0, y1, z):
    return [(x0, y0, z), (x1, y0, z), (x1, y1, z), (x0, y1, z)]


def write(tmp_path, header, rows, name="solution.csv"):
    path = tmp_path / name
    path.write_text("\n".join([header, *rows]) + "\n")
    return path


def test_column_lists_match_the_engine_headers():
    assert ",".join(COLUMNS_2D) == HEADER_2D
    assert ",".join(COLUMNS_3D) == HEADER_3D


# ---------------------------------------------------------------------------------------
# read_solution


def test_read_2d_solution_round_trips(tmp_path):
    rows = ["0,0,1,0,0.5,0,1,2.5,1.5,0.4,1,0.9,0.1,0.1,0,0,1,0",
            "1,0,1,1,1.5,0,1,3.5,2.5,0.4,0,0.9,0.1,0.1,1,0,2,0",
            "2,1,0,0,0,1.5,3,0.25,0.625,0.4,0,0.1,0.8,0.2,0,0,0,3"]
    sol = read_solution(write(tmp_path, HEADER_2D, rows))
    assert sol.dimension == 2 and len(sol) == 3
    assert sol.element.tolist() == [0, 1, 2]
    assert sol.root.tolist() == [0, 0, 1]
    assert sol.depth.tolist() == [1, 1, 0]
    assert sol.position.tolist() == [0, 1, 0]
    np.testing.assert_array_equal(sol.centre, [[0.5, 0], [1.5, 0], [0, 1.5]])
    np.testing.assert_array_equal(sol.measure, [1, 1, 3])
    np.testing.assert_array_equal(sol.radiosity, [2.5, 3.5, 0.25])
    np.testing.assert_array_equal(sol.irradiance, [1.5, 2.5, 0.625])
    np.testing.assert_array_equal(sol.emission, [1, 0, 0])
    np.testing.assert_array_equal(sol.colour[2], [0.1, 0.8, 0.2])
    assert sol.ends.shape == (3, 2, 2)
    np.testing.assert_array_equal(sol.ends[1], [[1, 0], [2, 0]])
    np.testing.assert_array_equal(sol.ends[2], [[0, 0], [0, 3]])
    assert sol.corners is None and sol.n_corners is None
    assert sol.source.endswith("solution.csv")


def test_read_3d_solution_with_triangles_and_quads(tmp_path):
    tri = [(0, 0, 0), (1, 0, 0), (0, 1, 0)]
    quad = square(0, 2, 0, 1, 3)
    rows = [leaf_3d(7, tri, colour=(0.25, 0.5, 0.75), b=2.0),
            leaf_3d(8, quad, b=0.5, emission=0.5, root=1, depth=2, position=3)]
    sol = read_solution(write(tmp_path, HEADER_3D, rows))
    assert sol.dimension == 3 and len(sol) == 2
    assert sol.element.tolist() == [7, 8]
    assert sol.depth.tolist() == [0, 2] and sol.position.tolist() == [0, 3]
    assert sol.n_corners.tolist() == [3, 4]
    assert sol.corners.shape == (2, 4, 3)
    np.testing.assert_array_equal(sol.corners[0, :3], tri)
    assert np.isnan(sol.corners[0, 3]).all()
    np.testing.assert_array_equal(sol.corners[1], quad)
    np.testing.assert_allclose(sol.centre[1], [1, 0.5, 3])
    np.testing.assert_array_equal(sol.colour[0], [0.25, 0.5, 0.75])
    np.testing.assert_array_equal(sol.radiosity, [2.0, 0.5])
    np.testing.assert_array_equal(sol.emission, [0.0, 0.5])
    assert sol.ends is None


def good_3d_rows():
    return [leaf_3d(0, square(0, 1, 0, 1, 0)),
            leaf_3d(1, [(0, 0, 1), (1, 0, 1), (0, 1, 1)])]


@pytest.mark.parametrize("edit, line, words", [
    (lambda h, r: (h.replace(",emission", ""),
                   [x.replace(",0.5,0.0,1.0,", ",0.5,1.0,") for x in r]), 1, "emission"),
    (lambda h, r: (h, [r[0], r[1].replace(",0.5,", ",abc,", 1)]), 3, "not a number"),
    (lambda h, r: (h, [r[0].replace(",4,", ",5,", 1), r[1]]), 2, "3 or 4"),
    (lambda h, r: (h, [r[0], r[1].replace(",,,", ",1,1,")]), 3, "fourth corner"),
    (lambda h, r: (h, [r[0], r[1].replace(",,", ",nan,", 1)]), 3, "fourth corner"),
    (lambda h, r: (h, [r[0], r[1] + ",1"]), 3, "fields"),
    (lambda h, r: (h, [r[0].replace("0,0,0,0,", "0,0,0.5,0,", 1), r[1]]), 2, "integer"),
    (lambda h, r: (h, [r[0].replace("0,0,0,0,", "0,0,1,2,", 1), r[1]]), 2, "2^depth"),
    (lambda h, r: (h, [r[0], r[1].replace(",1.0,", ",inf,", 1)]), 3, "finite"),
    (lambda h, r: (h, []), 2, "no element rows"),
    (lambda h, r: ("", []), 1, "empty"),
])
def test_read_refuses_malformed_files(tmp_path, edit, line, words):
    header, rows = edit(HEADER_3D, good_3d_rows())
    path = write(tmp_path, header, rows, name="bad.csv") if header else tmp_path / "bad.csv"
    if not header:
        path.write_text("")
    with pytest.raises(ResultFormatError) as err:
        read_solution(path)
    message = str(err.value)
    assert "\n" not in message
    assert str(path) in message
    assert f"line {line}:" in message
    assert words in message


def test_read_refuses_a_quad_without_its_fourth_corner(tmp_path):
    rows = good_3d_rows()
    parts = rows[0].split(",")
    parts[-3:] = ["", "", ""]
    with pytest.raises(ResultFormatError, match=r"line 2: .*'x3' is not a number"):
        read_solution(write(tmp_path, HEADER_3D, [",".join(parts), rows[1]]))


def test_the_good_rows_of_the_refusal_tests_are_read(tmp_path):
    assert len(read_solution(write(tmp_path, HEADER_3D, good_3d_rows()))) == 2


# ---------------------------------------------------------------------------------------
# render_image


FAR = dict(corners=square(-1, 1, -1, 1, 0), colour=(0.2, 0.4, 0.8))
NEAR = dict(corners=square(0, 1.5, -0.5, 0.5, -1), colour=(0.9, 0.6, 0.1))


def two_squares(tmp_path, near_first):
    far = leaf_3d(0, FAR["corners"], colour=FAR["colour"])
    near = leaf_3d(1, NEAR["corners"], colour=NEAR["colour"])
    rows = [near, far] if near_first else [far, near]
    return read_solution(write(tmp_path, HEADER_3D, rows))


@pytest.mark.parametrize("near_first", [False, True])
def test_z_buffer_shows_the_nearer_square(tmp_path, near_first):
    sol = two_squares(tmp_path, near_first)
    image = render_image(sol, camera=CAMERA, size=SIZE, exposure=0.5)
    assert image.shape == (SIZE[1], SIZE[0], 3)
    assert image.min() >= 0 and image.max() <= 1
    near_colour = shown(NEAR["colour"], 0.5)
    far_colour = shown(FAR["colour"], 0.5)
    # On the near square, in front of the far one.
    overlap = pixel_of(0.5, 0.0, -1.0)
    assert image[overlap] == pytest.approx(near_colour)
    # On the far square only (x < 0 is not covered by the near square).
    assert image[pixel_of(-0.5, 0.5, 0.0)] == pytest.approx(far_colour)
    # On the near square only, outside the far one (its projection reaches x = 1.875).
    assert image[pixel_of(1.3, 0.0, -1.0)] == pytest.approx(near_colour)
    # Outside both.
    assert image[pixel_of(-1.5, 0.0, 0.0)] == pytest.approx([0, 0, 0])
    assert image[pixel_of(0.0, 1.5, 0.0)] == pytest.approx([0, 0, 0])
    # The image's right is -x: the far-only pixel is right of the overlap.
    assert pixel_of(-0.5, 0.5, 0.0)[1] > overlap[1]
    ids, inverse_depth = rasterise(sol, camera=CAMERA, size=SIZE)
    near_row = 0 if near_first else 1
    assert ids[overlap] == near_row
    assert inverse_depth[overlap] == pytest.approx(1 / 4)
    assert ids[pixel_of(-1.5, 0.0, 0.0)] == -1


@pytest.mark.parametrize("lamp_first", [False, True])
def test_an_emitter_wins_a_tie_with_a_coplanar_surface(tmp_path, lamp_first):
    # A lamp in the plane of the ceiling (as in the Cornell box): the lamp shows whole,
    # in whichever order the leaves come; a surface nearer than the lamp still hides it.
    ceiling = leaf_3d(0, square(-1, 1, -1, 1, 0), colour=(0.2, 0.2, 0.2))
    lamp = leaf_3d(1, square(-0.5, 0.5, -0.5, 0.5, 0), emission=5.0)
    rows = [lamp, ceiling] if lamp_first else [ceiling, lamp]
    ids, _ = rasterise(read_solution(write(tmp_path, HEADER_3D, rows)), camera=CAMERA,
                       size=SIZE)
    lamp_row = 0 if lamp_first else 1
    inside = ids[SIZE[1] // 2 - 8:SIZE[1] // 2 + 8, SIZE[0] // 2 - 8:SIZE[0] // 2 + 8]
    assert (inside == lamp_row).all()
    assert ids[pixel_of(0.8, 0.8, 0.0)] == 1 - lamp_row
    cover = leaf_3d(2, square(-0.2, 0.2, -0.2, 0.2, -0.01))
    ids, _ = rasterise(read_solution(write(tmp_path, HEADER_3D, [*rows, cover], "c.csv")),
                       camera=CAMERA, size=SIZE)
    assert ids[SIZE[1] // 2, SIZE[0] // 2] == 2


def test_exposure_and_srgb_on_one_pixel(tmp_path):
    # Colour mean 0.3: the tint colour / 0.3 is (2, 0.996, 0.004), the hue kept and the
    # mean of the channels the radiosity.
    rows = [leaf_3d(0, square(-1, 1, -1, 1, 0), colour=(0.6, 0.2988, 0.0012), b=2.0)]
    sol = read_solution(write(tmp_path, HEADER_3D, rows))
    image = render_image(sol, camera=CAMERA, size=SIZE, exposure=0.125)
    # tint * B * exposure = (0.5, 0.249, 0.001), then the piecewise sRGB curve by hand:
    # 1.055 * 0.5^(1/2.4) - 0.055, 1.055 * 0.249^(1/2.4) - 0.055, 12.92 * 0.001.
    assert image[pixel_of(0, 0, 0)] == pytest.approx(
        [0.735357, 1.055 * 0.249 ** (1 / 2.4) - 0.055, 0.01292], abs=1e-6)
    # Over-exposed: clipped to white before the transfer curve.
    image = render_image(sol, camera=CAMERA, size=SIZE, exposure=4.0)
    assert image[pixel_of(0, 0, 0)] == pytest.approx([1.0, 1.0, srgb(0.032)])
    with pytest.raises(ValueError, match="exposure"):
        render_image(sol, camera=CAMERA, size=SIZE, exposure=0.0)


def test_a_leaf_keeps_its_hue_and_its_channels_average_its_radiosity(tmp_path):
    # A red and a grey leaf at the same radiosity: as bright on average, in their hues;
    # a black colour is drawn grey.
    red, grey, black = (0.6, 0.06, 0.09), (0.4, 0.4, 0.4), (0.0, 0.0, 0.0)
    rows = [leaf_3d(0, square(0.2, 1, -1, 1, 0), colour=red, b=1.0),
            leaf_3d(1, square(-1, -0.2, -1, 0, 0), colour=grey, b=1.0),
            leaf_3d(2, square(-1, -0.2, 0, 1, 0), colour=black, b=1.0)]
    sol = read_solution(write(tmp_path, HEADER_3D, rows))
    np.testing.assert_allclose(display_tint(sol), [[2.4, 0.24, 0.36], [1, 1, 1], [1, 1, 1]])
    image = render_image(sol, camera=CAMERA, size=SIZE, exposure=0.3)
    assert image[pixel_of(0.6, 0, 0)] == pytest.approx([srgb(0.72), srgb(0.072), srgb(0.108)])
    assert image[pixel_of(-0.6, -0.5, 0)] == pytest.approx([srgb(0.3)] * 3)
    assert image[pixel_of(-0.6, 0.5, 0)] == pytest.approx([srgb(0.3)] * 3)


def test_default_exposure_maps_visible_non_emitters_to_0_8(tmp_path):
    rows = [
        # Visible, not emitting: its B = 4 is the 99th percentile, mapped to 0.8.
        leaf_3d(0, square(-1, 1, -1, 1, -1), b=4.0),
        # Hidden behind it: brighter, but not seen, so it does not count.
        leaf_3d(1, square(-0.5, 0.5, -0.5, 0.5, 0), b=100.0),
        # Visible emitter: does not count either, and is clipped to white.
        leaf_3d(2, square(1.5, 2.5, -0.5, 0.5, 0), b=50.0, emission=50.0),
    ]
    sol = read_solution(write(tmp_path, HEADER_3D, rows))
    image = render_image(sol, camera=CAMERA, size=SIZE)
    assert image[pixel_of(0, 0, -1)] == pytest.approx([srgb(0.8)] * 3)
    assert image[pixel_of(2, 0, 0)] == pytest.approx([1, 1, 1])


def test_mesh_darkens_visible_element_boundaries_only(tmp_path):
    rows = [
        # Two adjacent leaves of one root, sharing the edge x = 0 (image column W/2).
        leaf_3d(0, square(-1, 0, -1, 1, 0), root=0, depth=1, position=0),
        leaf_3d(1, square(0, 1, -1, 1, 0), root=0, depth=1, position=1),
        # A third leaf in front, hiding the lower part of that edge.
        leaf_3d(2, square(-0.4, 0.4, -0.9, -0.3, -1)),
    ]
    sol = read_solution(write(tmp_path, HEADER_3D, rows))
    plain = render_image(sol, camera=CAMERA, size=SIZE, exposure=0.5)
    meshed = render_image(sol, camera=CAMERA, size=SIZE, mesh=True, exposure=0.5)
    ids, _ = rasterise(sol, camera=CAMERA, size=SIZE)
    changed = (plain != meshed).any(axis=2)
    assert changed.any()
    # Changed pixels are darkened to MESH_SHADE of their value, never brightened.
    np.testing.assert_allclose(meshed[changed], MESH_SHADE * plain[changed])
    # The shared edge: the pixel left of it (its right neighbour is the other leaf) is
    # darkened, both neighbours across are not.
    half = SIZE[0] // 2
    row, _ = pixel_of(0.0, 0.5, 0.0)
    assert ids[row, half - 1] != ids[row, half]
    assert changed[row, half - 1]
    assert not changed[row, half] and not changed[row, half - 2]
    # Interiors are untouched: away from every boundary nothing changes.
    for x, y, z in [(-0.5, 0.5, 0), (0.5, 0.5, 0), (0, -0.6, -1), (0.7, -0.8, 0)]:
        r, c = pixel_of(x, y, z)
        assert not changed[r - 2:r + 3, c - 2:c + 3].any()
    # The hidden part of the shared edge (behind the third leaf) is not drawn.
    r, _ = pixel_of(0.0, -0.6, -1)
    assert not changed[r, half - 1]
    # Exactly the pixels whose right or lower neighbour is another leaf (or background).
    edge = np.zeros(ids.shape, bool)
    edge[:, :-1] |= ids[:, :-1] != ids[:, 1:]
    edge[:-1] |= ids[:-1] != ids[1:]
    np.testing.assert_array_equal(changed, edge & (ids >= 0))


def test_geometry_behind_the_eye_is_clipped_not_dropped(tmp_path):
    # A floor from behind the eye (z = -10) to z = 10, one quad.
    floor = [(-5, -1, -10), (5, -1, -10), (5, -1, 10), (-5, -1, 10)]
    sol = read_solution(write(tmp_path, HEADER_3D, [leaf_3d(0, floor, colour=(0, 1, 0))]))
    image = render_image(sol, camera=CAMERA, size=SIZE, exposure=1.0)
    width, height = SIZE
    assert image[height - 1, width // 2] == pytest.approx([0, 1, 0])
    assert image[height - 1, 0] == pytest.approx([0, 1, 0])
    # Above the horizon of the floor's far edge: nothing.
    assert image[height // 4, width // 2] == pytest.approx([0, 0, 0])
    assert image[pixel_of(0, -1, 0)] == pytest.approx([0, 1, 0])


def test_cornell_camera_puts_the_red_wall_left(tmp_path):
    red = [(0.5528, 0, 0), (0.5496, 0, 0.5592), (0.556, 0.5488, 0.5592), (0.556, 0.5488, 0)]
    green = [(0, 0, 0.5592), (0, 0, 0), (0, 0.5488, 0), (0, 0.5488, 0.5592)]
    back = [(0.5496, 0, 0.5592), (0, 0, 0.5592), (0, 0.5488, 0.5592), (0.556, 0.5488, 0.5592)]
    rows = [leaf_3d(0, red, colour=(1, 0, 0)), leaf_3d(1, green, colour=(0, 1, 0)),
            leaf_3d(2, back, colour=(1, 1, 1))]
    sol = read_solution(write(tmp_path, HEADER_3D, rows))
    assert CORNELL_CAMERA.fov == pytest.approx(2 * math.degrees(math.atan(0.0125 / 0.035)),
                                               abs=0.05)
    image = render_image(sol, size=(64, 64), exposure=1.0)
    mid = 32
    assert image[mid, 2] == pytest.approx([1, 0, 0])
    assert image[mid, 61] == pytest.approx([0, 1, 0])
    assert image[mid, mid] == pytest.approx([1, 1, 1])


def test_render_refuses_2d(tmp_path):
    sol = read_solution(write(tmp_path, HEADER_2D,
                              ["0,0,0,0,0.5,0,1,1,1,0.5,0,1,1,1,0,0,1,0"]))
    with pytest.raises(ValueError, match="3D"):
        render_image(sol)


def test_render_figure(tmp_path):
    sol = two_squares(tmp_path, near_first=False)
    fig = render_figure(sol, mesh=True, title="two squares", camera=CAMERA)
    assert isinstance(fig, Figure)
    ax, bar = fig.axes
    (im,) = ax.get_images()
    assert im.get_array().shape == (512, 512, 3)
    assert list(ax.get_xticks()) == [] and list(ax.get_yticks()) == []
    assert ax.get_title() == "two squares"
    # A colour bar of the radiosity, its grey the one a grey leaf shows at each value.
    assert bar.get_ylabel() == "radiosity B (units of emission)"
    scale = bar._colorbar.mappable  # the Colorbar of its Axes
    top = scale.norm.vmax
    assert scale.to_rgba(top / 4)[:3] == pytest.approx([srgb(0.25)] * 3, abs=0.01)
    assert scale.to_rgba(top)[:3] == pytest.approx([1, 1, 1])
    # The legend names each material seen (no emitter here): hue, then brightness.
    (legend,) = fig.legends
    labels = [t.get_text() for t in legend.get_texts()]
    # The far square, larger on screen, first.
    assert labels == ["reflectance 0.50, RGB 0.20 0.40 0.80",
                      "reflectance 0.50, RGB 0.90 0.60 0.10"]
    assert "hue" in legend.get_title().get_text()
    buf = io.BytesIO()
    fig.savefig(buf, format="png")
    assert buf.getvalue().startswith(b"\x89PNG")


def test_render_figure_outlines_the_lamp_and_extends_the_bar(tmp_path):
    # A grey ceiling at B = 1 around a lamp at B = 50: the lamp off the top of the bar,
    # outlined and named with its emission.
    rows = [leaf_3d(0, square(-1, 1, -1, 1, 0), colour=(0.5, 0.5, 0.5), b=1.0),
            leaf_3d(1, square(-0.3, 0.3, -0.3, 0.3, 0), b=50.0, emission=50.0)]
    sol = read_solution(write(tmp_path, HEADER_3D, rows))
    fig = render_figure(sol, camera=CAMERA, size=SIZE)
    ax, bar = fig.axes
    assert bar.get_ylabel() == "radiosity B (units of emission)"
    # The default exposure maps the ceiling's B = 1 to 0.8: the bar tops at 1.25.
    assert bar.get_ylim()[1] == pytest.approx(1.25)
    assert bar._colorbar.extend == "max"  # the Colorbar of its Axes
    labels = [t.get_text() for t in fig.legends[0].get_texts()]
    assert labels == ["reflectance 0.50, RGB 0.50 0.50 0.50",
                      "emitter (lamp), E = 50 units of emission (outlined)"]
    assert emitter_label(sol, [0]) is None
    # The outline: one contour around the lamp's pixels, in the emitter's mark.
    (contour,) = [c for c in ax.get_children() if hasattr(c, "levels")]
    assert contour.get_edgecolor()[0][:3] == pytest.approx(to_rgb(EMITTER_MARK))
    path = np.concatenate([p.vertices for p in contour.get_paths()])
    ids, _ = rasterise(sol, camera=CAMERA, size=SIZE)
    rows_, cols = np.nonzero(ids == 1)
    assert path[:, 0].min() == pytest.approx(cols.min() - 0.5, abs=0.6)
    assert path[:, 1].max() == pytest.approx(rows_.max() + 0.5, abs=0.6)


def test_render_figure_names_the_most_seen_materials_only(tmp_path):
    # More materials than the legend holds: the largest on screen are named.
    rows = [leaf_3d(k, square(-1 + 0.2 * k, -0.8 + 0.2 * k, -1, -1 + 0.03 * k * k, 0),
                    colour=(0.1 * k, 0.05, 0.05)) for k in range(1, 9)]
    sol = read_solution(write(tmp_path, HEADER_3D, rows))
    fig = render_figure(sol, camera=CAMERA, size=SIZE)
    labels = [t.get_text() for t in fig.legends[0].get_texts()]
    assert len(labels) == LEGEND_MATERIALS
    assert labels[0].endswith("RGB 0.80 0.05 0.05")   # the tallest leaf


# ---------------------------------------------------------------------------------------
# plot_radiosity_profile


def profile_solution(tmp_path):
    # Root 0 (length 2 along x): leaves (1, 0), (2, 3), (2, 2), written out of order.
    # Root 1 (length 3 along y): one unsubdivided leaf.
    rows = ["0,0,1,0,0.5,0,1,2.0,0,0.5,0,1,1,1,0,0,1,0",
            "4,0,2,3,1.75,0,0.5,5.0,0,0.5,0,1,1,1,1.5,0,2,0",
            "3,0,2,2,1.25,0,0.5,4.0,0,0.5,0,1,1,1,1,0,1.5,0",
            "5,1,0,0,0,1.5,3,7.0,0,0.5,0,1,1,1,0,0,0,3"]
    return read_solution(write(tmp_path, HEADER_2D, rows))


def test_profile_is_a_step_function_per_root(tmp_path):
    sol = profile_solution(tmp_path)
    fig = Figure()
    ax = fig.add_subplot()
    lines = plot_radiosity_profile(ax, sol)
    assert len(ax.lines) == 2 and lines == list(ax.lines)
    assert [line.get_label() for line in lines] == ["patch 0", "patch 1"]
    np.testing.assert_allclose(lines[0].get_xdata(), [0, 1, 1, 1.5, 1.5, 2])
    np.testing.assert_allclose(lines[0].get_ydata(), [2, 2, 4, 4, 5, 5])
    np.testing.assert_allclose(lines[1].get_xdata(), [0, 3])
    np.testing.assert_allclose(lines[1].get_ydata(), [7, 7])
    assert "scene units" in ax.get_xlabel() and "radiosity B" in ax.get_ylabel()


def test_profile_with_reference(tmp_path):
    sol = profile_solution(tmp_path)
    fig = Figure()
    ax = fig.add_subplot()
    reference = [1, 2, 3, 4, 10, 20, 30, 40]
    lines = plot_radiosity_profile(ax, sol, reference=reference, reference_depth=2)
    assert len(ax.lines) == 4
    refs = [line for line in ax.lines if line not in lines]
    assert all(line.get_linestyle() == "--" for line in refs)
    for ref, length, values in zip(refs, (2, 3), ([1, 2, 3, 4], [10, 20, 30, 40]),
                                   strict=True):
        x = np.asarray(ref.get_xdata())
        assert x.min() == 0 and x.max() == pytest.approx(length)
        np.testing.assert_allclose(x[1:-1:2], np.arange(1, 4) * length / 4)
        np.testing.assert_allclose(ref.get_ydata(), np.repeat(values, 2))
    assert refs[0].get_color() == lines[0].get_color()
    # The depth is inferred from the reference's size.
    ax2 = Figure().add_subplot()
    plot_radiosity_profile(ax2, sol, reference=reference)
    assert len(ax2.lines) == 4
    with pytest.raises(ValueError, match="per root"):
        plot_radiosity_profile(Figure().add_subplot(), sol, reference=reference,
                               reference_depth=1)
    with pytest.raises(ValueError, match="multiple"):
        plot_radiosity_profile(Figure().add_subplot(), sol, reference=[1, 2, 3])


def test_profile_refuses_3d_and_untiled_roots(tmp_path):
    sol3 = read_solution(write(tmp_path, HEADER_3D, good_3d_rows(), name="s3.csv"))
    with pytest.raises(ValueError, match="2D"):
        plot_radiosity_profile(Figure().add_subplot(), sol3)
    rows = ["0,0,1,0,0.5,0,1,2.0,0,0.5,0,1,1,1,0,0,1,0"]  # half of its root is missing
    sol = read_solution(write(tmp_path, HEADER_2D, rows, name="s2.csv"))
    with pytest.raises(ValueError, match="tile"):
        plot_radiosity_profile(Figure().add_subplot(), sol)


def test_large_triangles_are_filled_without_seams(tmp_path):
    # Wider than the rasteriser's tiles: every pixel is covered, each by the nearer leaf.
    rows = [leaf_3d(0, square(-20, 20, -20, 20, 0), colour=(0.5, 0.5, 0.5)),
            leaf_3d(1, square(-20, 0, -20, 20, -1), colour=(1, 1, 1))]
    sol = read_solution(write(tmp_path, HEADER_3D, rows))
    size = (700, 300)
    ids, _ = rasterise(sol, camera=CAMERA, size=size)
    assert ids.shape == (300, 700)
    # x < 0 (the near leaf) is the image's right half.
    assert (ids[:, :350] == 0).all() and (ids[:, 350:] == 1).all()


# ---------------------------------------------------------------------------------------
# mplot3d polygons and the command hrbench-render


def test_radiosity_scale_leaves_out_emitters(tmp_path):
    path = tmp_path / "s.csv"
    path.write_text("\n".join([HEADER_3D,
                               leaf_3d(0, square(0, 1, 0, 1, 0), b=1.0),
                               leaf_3d(1, square(1, 2, 0, 1, 0), b=2.0),
                               leaf_3d(2, square(0, 1, 0, 1, 1), b=50.0, emission=50.0)]))
    # The 99th percentile of 1 and 2, by linear interpolation: 1 + 0.99.
    assert radiosity_scale(read_solution(path)) == pytest.approx(1.99)


def test_plot_solution_3d_colours_by_radiosity_and_culls_back_faces(tmp_path):
    # A floor facing +z (corners counter-clockwise from above) and a ceiling facing -z.
    path = tmp_path / "s.csv"
    path.write_text("\n".join([HEADER_3D,
                               leaf_3d(0, square(0, 2, 0, 1, 0), b=0.25),
                               leaf_3d(1, square(0, 2, 0, 1, 1)[::-1], b=0.75)]))
    solution = read_solution(path)
    fig = Figure()
    ax = fig.add_subplot(projection="3d")
    both = plot_solution_3d(ax, solution)
    assert list(both.get_array()) == [0.25, 0.75]
    assert (both.norm.vmin, both.norm.vmax) == (0.0, radiosity_scale(solution))
    assert ax.get_xlim() == (0, 2) and ax.get_ylim() == (0, 1) and ax.get_zlim() == (0, 1)
    from_above = plot_solution_3d(fig.add_subplot(projection="3d"), solution,
                                  facing=(0.1, 0.2, 1.0))
    assert list(from_above.get_array()) == [0.25]
    from_below = plot_solution_3d(fig.add_subplot(projection="3d"), solution,
                                  facing=(0.0, 0.0, -1.0))
    assert list(from_below.get_array()) == [0.75]


def test_plot_solution_3d_outlines_the_lamp_even_facing_away(tmp_path):
    # A floor facing up and a lamp above it facing down, seen from above: the lamp is
    # culled but outlined, and the legend names it.
    path = tmp_path / "s.csv"
    path.write_text("\n".join([HEADER_3D,
                               leaf_3d(0, square(0, 2, 0, 1, 0), b=0.25),
                               leaf_3d(1, square(0.5, 1, 0.25, 0.75, 1)[::-1], b=7.0,
                                       emission=7.0)]))
    solution = read_solution(path)
    fig = Figure()
    ax = fig.add_subplot(projection="3d")
    shown = plot_solution_3d(ax, solution, facing=(0.0, 0.0, 1.0))
    assert list(shown.get_array()) == [0.25]
    (outline,) = [c for c in ax.collections if c is not shown]
    assert outline.get_label() == "emitter (lamp), E = 7 units of emission"
    assert outline.get_color()[0][:3] == pytest.approx(to_rgb(EMITTER_MARK))
    fig.draw_without_rendering()  # projects the 3D lines to the screen
    (ring,) = outline.get_segments()
    assert len(ring) == 5 and ring[0] == pytest.approx(ring[-1])  # four corners, closed
    (text,) = ax.legend().get_texts()
    assert text.get_text() == outline.get_label()
    # Without an emitter there is nothing to outline.
    ax = Figure().add_subplot(projection="3d")
    plot_solution_3d(ax, read_solution(write(tmp_path, HEADER_3D, [leaf_3d(0, square(
        0, 1, 0, 1, 0))], "dark.csv")))
    assert len(ax.collections) == 1


@pytest.mark.parametrize("elev, azim, up", [(30, -60, "z"), (15, 155, "y"), (-20, 40, "x"),
                                            (0, 180, "y")])
def test_view_direction_is_mplot3d_s_line_of_sight(elev, azim, up):
    # In an orthographic view, a point and the point moved along the direction to the
    # eye fall on the same spot of the screen.
    ax = Figure().add_subplot(projection="3d", proj_type="ortho")
    ax.set(xlim=(0, 1), ylim=(0, 1), zlim=(0, 1))
    ax.set_box_aspect((1, 1, 1))
    ax.view_init(elev=elev, azim=azim, vertical_axis=up)
    matrix = ax.get_proj()
    direction = view_direction(elev, azim, up)
    screen = [matrix @ np.append(p, 1.0) for p in (np.full(3, 0.5), 0.5 + 0.3 * direction)]
    (x0, y0), (x1, y1) = ((s[0] / s[3], s[1] / s[3]) for s in screen)
    assert (x1, y1) == pytest.approx((x0, y0), abs=1e-12)
    assert np.linalg.norm(direction) == pytest.approx(1.0)


def test_view_direction_looks_down_the_up_axis_from_above():
    assert view_direction(90, 0, "z") == pytest.approx([0, 0, 1], abs=1e-12)
    assert view_direction(90, 0, "y") == pytest.approx([0, 1, 0], abs=1e-12)
    assert view_direction(0, 0, "z") == pytest.approx([1, 0, 0], abs=1e-12)


HRBENCH = Path(__file__).resolve().parents[2] / "build" / "hrbench"
needs_engine = pytest.mark.skipif(not HRBENCH.exists(), reason="build/hrbench not built")


def render(argv, capsys):
    # The exit code, standard output and error of hrbench-render (argparse exits).
    try:
        code = render_main([*argv, "--hrbench", str(HRBENCH)])
    except SystemExit as exc:
        code = exc.code
    out, err = capsys.readouterr()
    return code, out, err


@needs_engine
def test_render_a_3d_solve_to_png(tmp_path, capsys):
    out, leaves = tmp_path / "plates.png", tmp_path / "leaves.csv"
    code, printed, err = render(["parallel3d", "d=1", "--eps", "0.5", "--emission", "1",
                                 "--size", "400", "300", "--csv", str(leaves), "--out",
                                 str(out)], capsys)
    assert code == 0, err
    assert imread(out).shape == (300, 400, 4)
    solution = read_solution(leaves)
    assert solution.dimension == 3
    assert f": {len(solution)} leaves, " in printed


@needs_engine
def test_render_the_cornell_box_from_its_open_side(tmp_path, capsys):
    out = tmp_path / "room.png"
    code, printed, err = render(["cornell", "--eps", "0.5", "--min-area", "0.05", "--out",
                                 str(out)], capsys)
    assert code == 0, err
    assert imread(out).shape == (750, 900, 4)
    assert printed.startswith(f"{out}: cornell, garmann, eps 0.5: ")


@needs_engine
def test_the_cornell_box_shows_its_lamp_brightest_and_its_walls_red_and_green(tmp_path):
    # The family's own scene through the engine: its materials reach the picture.
    from hrbench_analysis.solution import solve_to_csv

    path = tmp_path / "cornell.csv"
    solve_to_csv(str(HRBENCH), "cornell", {}, 0.5, "garmann", {}, path, min_area=0.05)
    sol = read_solution(path)
    x, y, z = sol.centre.T
    lamp = (np.isclose(y, 0.5488) & (0.213 < x) & (x < 0.343) & (0.227 < z) & (z < 0.332))
    assert lamp.any() and (sol.emission[lamp] > 0).all() and (sol.emission[~lamp] == 0).all()
    size = (128, 128)
    image = render_image(sol, size=size)
    ids, _ = rasterise(sol, size=size)
    seen = ids >= 0
    at_lamp = seen & lamp[np.maximum(ids, 0)]
    assert at_lamp.sum() > 10
    # The lamp is white, and no other surface is as bright on average.
    brightness = image.mean(axis=2)
    np.testing.assert_allclose(image[at_lamp], 1.0)
    assert brightness[seen & ~at_lamp].max() < 1 - 1e-6
    # The left wall (x = 0.55 m) is red, the right one (x = 0) green: on every pixel its
    # own channel at least 1.5 times the others (display values: sRGB narrows ratios).
    red = seen & (x > 0.54)[np.maximum(ids, 0)]
    green = seen & (x < 0.01)[np.maximum(ids, 0)]
    assert red.sum() > 100 and green.sum() > 100
    r, g, b = image[red].T
    assert (r > 1.5 * g).all() and (r > 1.5 * b).all()
    r, g, b = image[green].T
    assert (g > 1.5 * r).all() and (g > 1.5 * b).all()
    # The report's figure outlines the lamp and names it with its emission.
    fig = render_figure(sol, size=size)
    labels = [t.get_text() for t in fig.legends[0].get_texts()]
    assert "emitter (lamp), E = 11 units of emission (outlined)" in labels
    assert any(label.startswith("reflectance 0.25, RGB 0.63 0.07 0.05") for label in labels)


@needs_engine
def test_render_a_mesh_file(tmp_path, capsys):
    out = tmp_path / "room.png"
    mesh = Path(__file__).resolve().parents[1] / "data" / "room_box.obj"
    code, printed, err = render(["--mesh", str(mesh), "--eps", "0.3", "--min-area", "0.05",
                                 "--size", "300", "300", "--out", str(out)], capsys)
    assert code == 0, err
    assert imread(out).shape == (300, 300, 4)
    assert printed.startswith(f"{out}: room_box.obj, garmann, eps 0.3: ")


@needs_engine
def test_render_a_flatland_solve_as_its_profile(tmp_path, capsys):
    out = tmp_path / "plates.png"
    code, _, err = render(["parallel", "l=4", "d=1", "--eps", "0.5", "--emission", "1",
                           "--size", "500", "300", "--out", str(out)], capsys)
    assert code == 0, err
    assert imread(out).shape == (300, 500, 4)


@needs_engine
@pytest.mark.parametrize("argv, words", [
    (["--eps", "1"], "give either SCENE [key=value ...] or --mesh F"),
    (["cornell", "--mesh", "room.obj", "--eps", "1"], "give either SCENE"),
    (["cornell", "--eps", "-1"], "'-1' is not a finite number > 0"),
    (["cornell", "--eps", "1", "--size", "0", "10"], "'0' is not an integer >= 1"),
    (["cornell", "--eps", "1", "--view", "up", "0"], "invalid float value: 'up'"),
    (["cornell", "--eps", "1", "--triangulate"], "apply to --mesh only"),
    (["cornell", "--eps", "1", "--csv", "no/such/folder/x.csv"], "does not exist"),
    (["cornell", "--eps", "0.5"], "touch, so refinement cannot terminate"),
    (["parallel3d", "--eps", "0.5"], "nothing emits"),
    (["--mesh", "no-such.obj", "--eps", "0.5"], "'no-such.obj': cannot read (No such file"),
    # A FIFO would hold the engine that reads it; a huge image, the memory.
    (["--mesh", "FIFO", "--eps", "0.5"], "'FIFO' is not a regular file"),
    (["cornell", "--eps", "1", "--size", "200000", "200000"], "more than the 8192"),
    (["cornell", "--eps", "1", "--size", "1" * 5000, "10"], "... (5000 characters)"),
])
def test_render_bad_input_is_one_line_and_exit_2(tmp_path, capsys, argv, words, monkeypatch):
    monkeypatch.chdir(tmp_path)
    (tmp_path / "room.obj").write_text("")
    os.mkfifo(tmp_path / "FIFO")
    out = tmp_path / "x.png"
    code, _, err = render([*argv, "--out", str(out)], capsys)
    assert code == 2
    assert len(err.strip().splitlines()) == 1 and err.startswith("hrbench-render: error: ")
    assert words in err
    assert not out.exists()
