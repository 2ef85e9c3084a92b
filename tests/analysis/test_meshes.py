"""python -m hrbench_analysis.meshes bunny-box: a mesh in a closed box lit from its ceiling,
checked on a tetrahedron."""

import re
import subprocess
from collections import Counter
from pathlib import Path

import numpy as np
import pytest

from hrbench_analysis.errors import AnalysisError
from hrbench_analysis.meshes import bunny_box, main, read_off

ROOT = Path(__file__).resolve().parents[2]
HRBENCH = ROOT / "build" / "hrbench"
needs_engine = pytest.mark.skipif(not HRBENCH.exists(), reason="build/hrbench not built")

# A closed tetrahedron, faces counter-clockwise seen from outside, with a comment, a colour
# and the counts on the keyword's line.
TETRA = """OFF 4 4 6
# corners
0 0 0
1 0 0
0 1 0
0 0 1
3 0 2 1
3 0 1 3 255 0 0
3 0 3 2
3 1 2 3
"""


def parse_obj(text):
    """Vertices, and faces as (material, corners) of the OBJ `text` written by bunny_box."""
    vertices, faces, material = [], [], None
    for line in text.splitlines():
        words = line.split()
        if not words or words[0] == "#" or words[0] == "mtllib":
            continue
        if words[0] == "v":
            vertices.append(tuple(float(w) for w in words[1:]))
        elif words[0] == "usemtl":
            material = words[1]
        else:
            assert words[0] == "f"
            faces.append((material, [vertices[int(w) - 1] for w in words[1:]]))
    return vertices, faces


def normal(corners):
    a, b, c = (np.array(p) for p in corners[:3])
    return np.cross(b - a, c - a)


def test_read_off_takes_the_counts_faces_and_comments():
    vertices, faces = read_off(TETRA)
    assert vertices[3] == (0, 0, 1)
    assert faces == [(0, 2, 1), (0, 1, 3), (0, 3, 2), (1, 2, 3)]


@pytest.mark.parametrize("text, what", [
    ("", "not an OFF file"),
    ("COFF\n3 1 0\n", "not an OFF file"),
    ("OFF\n", "ends before the counts"),
    ("OFF\n3 x 0\n", "bad counts"),
    ("OFF\n3 1 0\n0 0 0\n1 0 0\n", "announces 3 vertices"),
    ("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 nan\n3 0 1 2\n", "bad vertex"),
    ("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 3\n", "bad face"),
    ("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n2 0 1\n", "bad face"),
])
def test_read_off_refuses_bad_files_in_one_line(text, what):
    with pytest.raises(AnalysisError, match=what) as e:
        read_off(text, "t.off")
    assert "\n" not in str(e.value) and str(e.value).startswith("t.off, line ")


def test_the_box_is_closed_faces_inward_and_holds_the_mesh_centred():
    vertices, faces = read_off(TETRA)
    obj, mtl, counts = bunny_box(vertices, faces, box=2.0, grid=4, light=2, fill=0.5,
                                 emission=3.0)
    assert counts == {"mesh_faces": 4, "wall_quads": 6 * 16 - 4, "light_quads": 4}
    assert "newmtl light\nKd 0.78\nKe 3.0\n" in mtl
    points, written = parse_obj(obj)
    assert len(written) == 4 + 6 * 16
    mesh, walls = written[:4], written[4:]
    # The mesh: its faces and their orientation kept, scaled by fill * box / extent = 1
    # and moved so that its bounding box is centred in the cube.
    assert all(m == "mesh" for m, _ in mesh)
    shift = np.array([0.5, 0.5, 0.5])
    for (_, corners), face in zip(mesh, faces, strict=True):
        assert np.allclose(np.array(corners), np.array([vertices[i] for i in face]) + shift)
        outward = np.mean(corners, axis=0) - (shift + 0.25)
        assert normal(corners) @ outward > 0
    # The walls: planar unit squares inside [0, 2]^3, facing the centre, and closed:
    # every edge met once each way.
    centre = np.array([1.0, 1.0, 1.0])
    edges = Counter()
    for material, corners in walls:
        assert len(corners) == 4 and material in ("wall", "light")
        n = normal(corners)
        assert np.isclose(np.linalg.norm(n), 0.25)  # cells of side 0.5
        assert n @ (centre - np.mean(corners, axis=0)) > 0
        for k in range(4):
            edges[(corners[k], corners[(k + 1) % 4])] += 1
    assert all(count == 1 and edges[(b, a)] == 1 for (a, b), count in edges.items())
    # The light: the central 2 x 2 cells of the ceiling y = 2, facing down.
    lights = [corners for m, corners in walls if m == "light"]
    assert len(lights) == 4
    for corners in lights:
        assert all(p[1] == 2.0 and 0.5 <= p[0] <= 1.5 and 0.5 <= p[2] <= 1.5 for p in corners)
        assert normal(corners)[1] < 0


@pytest.mark.parametrize("options, what", [
    ({"grid": 4, "light": 1}, "grid - light even"),
    ({"grid": 2, "light": 4}, "--light 4"),
    ({"fill": 1.0}, "--fill 1"),
])
def test_bad_layouts_are_refused(options, what):
    vertices, faces = read_off(TETRA)
    with pytest.raises(AnalysisError, match=what):
        bunny_box(vertices, faces, **options)


def test_the_command_writes_obj_and_mtl(tmp_path, capsys):
    off = tmp_path / "tetra.off"
    off.write_text(TETRA)
    assert main(["bunny-box", "--off", str(off), "--out", str(tmp_path / "out"),
                 "--grid", "2"]) == 0
    assert "4 mesh faces, 20 wall quads, 4 light quads" in capsys.readouterr().out
    obj = (tmp_path / "out" / "bunny_box.obj").read_text()
    assert "mtllib bunny_box.mtl\n" in obj
    assert (tmp_path / "out" / "bunny_box.mtl").read_text().startswith("# Materials")
    assert main(["bunny-box", "--off", str(tmp_path / "none.off"), "--out",
                 str(tmp_path)]) == 2
    assert "cannot read" in capsys.readouterr().err


@needs_engine
def test_the_engine_reads_the_box_without_warnings_and_needs_a_recursion_limit(tmp_path):
    off = tmp_path / "tetra.off"
    off.write_text(TETRA)
    assert main(["bunny-box", "--off", str(off), "--out", str(tmp_path), "--grid", "4"]) == 0
    obj = str(tmp_path / "bunny_box.obj")
    run = [str(HRBENCH), "run", "--mesh", obj, "--eps", "0.5", "--count-only"]
    unlimited = subprocess.run(run, capture_output=True, text=True)
    assert unlimited.returncode == 2 and "touch" in unlimited.stderr
    limited = subprocess.run([*run, "--min-area", "0.01", "--json"], capture_output=True,
                             text=True)
    assert limited.returncode == 0 and limited.stderr == ""
    assert '"patches":100' in limited.stdout


def test_the_bunny_figure_says_where_its_mesh_is_missing(tmp_path, monkeypatch):
    from hrbench_analysis import solution

    monkeypatch.chdir(tmp_path)
    with pytest.raises(FileNotFoundError, match="make bunny-box"):
        solution.bunny_figure(str(HRBENCH), tmp_path)
    warnings = []
    figures = solution.solution_figures("/nonexistent/hrbench", tmp_path, warn=warnings.append)
    assert figures == []
    assert any(w.startswith("warning: no bunny figure:") and "make bunny-box" in w
               for w in warnings)


@needs_engine
def test_the_bunny_figure_of_a_box_solved_through_clusters(tmp_path, monkeypatch):
    # The report's figure on the tetrahedron's box: the solve's counts and energy balance
    # in the title and caption, its leaves in the CSV.
    from hrbench_analysis import solution

    off = tmp_path / "tetra.off"
    off.write_text(TETRA)
    assert main(["bunny-box", "--off", str(off), "--out", str(tmp_path), "--fill", "0.3"]) == 0
    mesh, *rest = solution.BUNNY
    monkeypatch.setattr(solution, "BUNNY", (tmp_path / "bunny_box.obj", *rest))
    figure = solution.bunny_figure(str(HRBENCH), tmp_path)
    assert figure.name == "bunny"
    assert (tmp_path / "solution-bunny.csv").stat().st_size > 0
    title = figure.figure.axes[0].get_title()
    assert title.startswith("388 patches, ")  # 4 faces, 380 wall quads, 4 light quads
    # Absorbed against emitted in plain words: more or less, by how much, both powers.
    assert "cluster links" in title
    assert re.search(r"The surfaces absorb \d+\.\d% (more|less) power than the lamp emits "
                     r"\([\d.e+-]+ against [\d.e+-]+\)", title), title
    assert re.search(r"Energy balance: the surfaces absorb \d+\.\d% (more|less) power than the "
                     r"lamp emits", figure.caption)
