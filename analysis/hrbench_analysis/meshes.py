"""Mesh scenes built from other meshes: ``python -m hrbench_analysis.meshes``.

::

    python -m hrbench_analysis.meshes bunny-box --off data/meshes/bunny00.off --out DIR

``bunny-box`` writes ``DIR/bunny_box.obj`` and its material library ``DIR/bunny_box.mtl``
(docs/meshes.md): the triangles of an OFF mesh, scaled and centred in a closed cube,
lit from its ceiling, for ``hrbench run --mesh DIR/bunny_box.obj``.

- The cube ``[0, box]^3``, y up, has six walls facing inward (counter-clockwise seen from
  inside, as hrbench orients a patch: docs/conventions.md), each a ``grid x grid`` grid of
  square quads, so that no wall is one large patch; corners on the cube's edges are
  written once per wall, with the same coordinates.
- The light is the central ``light x light`` cells of the ceiling (``y = box``, facing
  down): material ``light`` (``Kd`` 0.78, ``Ke`` the emission); the other cells and walls
  are ``wall`` (``Kd`` 0.75), the mesh is ``mesh`` (``Kd`` 0.6).
- The mesh keeps its faces and their orientation (a closed mesh such as the Stanford
  bunny faces outward); it is scaled so that its bounding box's largest side is ``fill``
  times the box's side, and its bounding box is centred in the cube, so that it touches
  no wall.

The walls touch each other along the cube's edges (and the cells of a wall along their
sides), so a run needs a recursion limit (``--min-area`` or ``--max-depth``), as for the
``cornell`` family.
"""

import sys
from pathlib import Path

from .cli import Parser, positive_int, positive_number
from .errors import AnalysisError, run_main
from .output import write_files

#: Materials: name, Kd (reflectance), Ke (emission; the light's is an option).
WALL_REFLECTANCE = 0.75
LIGHT_REFLECTANCE = 0.78
MESH_REFLECTANCE = 0.6


def read_off(text, name="mesh"):
    """The vertices and faces of the OFF `text`: ``([(x, y, z), ...], [(i, j, k, ...), ...])``.

    A plain reader for the files this module converts: the keyword ``OFF``, the counts
    (vertices, faces, edges; on the keyword's line or the next), one vertex per line, then
    one face per line (``n i1 .. in``, anything after the indices is ignored, such as a
    colour); ``#`` comments and blank lines are skipped. Raises :class:`AnalysisError`
    with one line naming `name` for anything else; hrbench's own reader checks the rest
    (planarity, degenerate faces) when it reads the scene written.
    """
    lines = []
    for number, line in enumerate(text.splitlines(), 1):
        words = line.split("#", 1)[0].split()
        if words:
            lines.append((number, words))

    def fail(number, what):
        raise AnalysisError(f"{name}, line {number}: {what}")

    if not lines or lines[0][1][0] != "OFF":
        fail(lines[0][0] if lines else 1, "not an OFF file (it must start with OFF)")
    header = lines[0][1][1:]
    rest = lines[1:]
    if not header:
        if not rest:
            fail(lines[0][0], "the file ends before the counts")
        header, rest = rest[0][1], rest[1:]
    try:
        num_vertices, num_faces = int(header[0]), int(header[1])
    except (ValueError, IndexError):
        fail(lines[0][0], f"bad counts {' '.join(header)!r} (vertices faces edges)")
    if num_vertices < 3 or num_faces < 1 or len(rest) < num_vertices + num_faces:
        fail(lines[0][0], f"announces {num_vertices} vertices and {num_faces} faces, "
                          f"but has {len(rest)} lines after the counts")
    vertices = []
    for number, words in rest[:num_vertices]:
        try:
            x, y, z = (float(w) for w in words[:3])
        except ValueError:
            fail(number, f"bad vertex {' '.join(words)!r}")
        if len(words) < 3 or not all(abs(c) < float("inf") for c in (x, y, z)):
            fail(number, f"bad vertex {' '.join(words)!r}")
        vertices.append((x, y, z))
    faces = []
    for number, words in rest[num_vertices:num_vertices + num_faces]:
        try:
            n = int(words[0])
            face = tuple(int(w) for w in words[1:1 + n])
        except ValueError:
            fail(number, f"bad face {' '.join(words)!r}")
        if n < 3 or len(face) != n or not all(0 <= i < num_vertices for i in face):
            fail(number, f"bad face {' '.join(words)!r} (n then n indices from 0 "
                         f"below {num_vertices})")
        faces.append(face)
    return vertices, faces


def _wall_cells(box, grid, light):
    """The quads of the six walls, facing into ``[0, box]^3``: ``[(material, corners)]``.

    Each wall is the square of axes (u, v) at ``w = 0`` or ``w = box``; its cells are
    listed row by row, corners counter-clockwise seen from inside.
    """
    step = box / grid
    coordinate = [i * step for i in range(grid)] + [box]  # exact ends
    low_light, high_light = (grid - light) // 2, (grid + light) // 2
    cells = []
    # (axis w, its value, axes u and v): u x v points along +w, so the order
    # (u0,v0) (u1,v0) (u1,v1) (u0,v1) faces +w; the walls at w = box need -w.
    for w in range(3):
        u, v = (w + 1) % 3, (w + 2) % 3
        for at_far in (False, True):
            for b in range(grid):
                for a in range(grid):
                    corners = []
                    for da, db in ((0, 0), (1, 0), (1, 1), (0, 1)):
                        p = [0.0, 0.0, 0.0]
                        p[w] = box if at_far else 0.0
                        p[u], p[v] = coordinate[a + da], coordinate[b + db]
                        corners.append(tuple(p))
                    if at_far:
                        corners.reverse()
                    ceiling = w == 1 and at_far
                    lit = (ceiling and low_light <= a < high_light
                           and low_light <= b < high_light)
                    cells.append(("light" if lit else "wall", corners))
    return cells


def bunny_box(vertices, faces, box=1.0, grid=8, light=2, fill=0.6, emission=1.0):
    """The OBJ and MTL text of the mesh (`vertices`, `faces`) in a lit box.

    Returns ``(obj_text, mtl_text, counts)``, ``counts`` a dict with ``mesh_faces``,
    ``wall_quads`` and ``light_quads``; the OBJ names its library ``bunny_box.mtl``.
    """
    if not 1 <= light <= grid or (grid - light) % 2:
        raise AnalysisError(f"--light {light}: the light must be 1 to --grid ({grid}) "
                            f"cells across, with grid - light even (centred)")
    if not 0 < fill < 1:
        raise AnalysisError(f"--fill {fill:g}: must lie in (0, 1) for the mesh to stay "
                            f"clear of the walls")
    low = [min(p[k] for p in vertices) for k in range(3)]
    high = [max(p[k] for p in vertices) for k in range(3)]
    extent = max(h - l for l, h in zip(low, high, strict=True))
    if not extent > 0:
        raise AnalysisError("the mesh has no extent: all its vertices coincide")
    scale = fill * box / extent
    centre = [(l + h) / 2 for l, h in zip(low, high, strict=True)]

    def placed(p):
        return tuple(box / 2 + scale * (p[k] - centre[k]) for k in range(3))

    out = ["# A mesh in a closed box lit from its ceiling (python -m hrbench_analysis.meshes "
           "bunny-box): faces counter-clockwise seen from the front",
           "mtllib bunny_box.mtl"]
    out += ["v {!r} {!r} {!r}".format(*placed(p)) for p in vertices]
    out.append("usemtl mesh")
    out += ["f " + " ".join(str(i + 1) for i in f) for f in faces]
    cells = _wall_cells(box, grid, light)
    index = len(vertices)
    current = None
    for material, corners in cells:
        out += ["v {!r} {!r} {!r}".format(*c) for c in corners]
        if material != current:
            out.append(f"usemtl {material}")
            current = material
        out.append("f " + " ".join(str(index + k + 1) for k in range(4)))
        index += 4
    mtl = ("# Materials of bunny_box.obj: reflectance = mean(Kd), emission = mean(Ke)\n"
           f"newmtl mesh\nKd {MESH_REFLECTANCE!r}\nKe 0\n"
           f"newmtl wall\nKd {WALL_REFLECTANCE!r}\nKe 0\n"
           f"newmtl light\nKd {LIGHT_REFLECTANCE!r}\nKe {emission!r}\n")
    lights = sum(m == "light" for m, _ in cells)
    counts = {"mesh_faces": len(faces), "wall_quads": len(cells) - lights,
              "light_quads": lights}
    return "\n".join(out) + "\n", mtl, counts


def _parser():
    p = Parser(prog="python -m hrbench_analysis.meshes",
               description="Mesh scenes built from other meshes (docs/meshes.md).")
    commands = p.add_subparsers(dest="command", required=True)
    b = commands.add_parser("bunny-box", help="an OFF mesh in a closed box lit from its ceiling")
    b.add_argument("--off", required=True, type=Path, help="the OFF mesh (bunny00.off)")
    b.add_argument("--out", required=True, type=Path,
                   help="folder to write bunny_box.obj and bunny_box.mtl in (made if missing)")
    b.add_argument("--box", type=positive_number, default=1.0,
                   help="side of the cube (default: %(default)s)")
    b.add_argument("--grid", type=positive_int, default=8,
                   help="quads per wall along each side (default: %(default)s)")
    b.add_argument("--light", type=positive_int, default=2,
                   help="the light: the central LIGHT x LIGHT cells of the ceiling "
                        "(default: %(default)s)")
    b.add_argument("--fill", type=positive_number, default=0.6,
                   help="largest side of the mesh's bounding box over the box's side "
                        "(default: %(default)s)")
    b.add_argument("--emission", type=positive_number, default=1.0,
                   help="emission of the light (MTL Ke; default: %(default)s)")
    return p


def _main(argv):
    args = _parser().parse_args(argv)
    try:
        text = args.off.read_text(encoding="utf-8", errors="replace")
    except OSError as e:
        raise AnalysisError(f"cannot read {args.off}: {e.strerror}") from None
    vertices, faces = read_off(text, str(args.off))
    obj, mtl, counts = bunny_box(vertices, faces, args.box, args.grid, args.light, args.fill,
                                 args.emission)
    args.out.mkdir(parents=True, exist_ok=True)
    obj_path = args.out / "bunny_box.obj"
    write_files([(args.out / "bunny_box.mtl", mtl), (obj_path, obj)])
    print(f"{obj_path}: {counts['mesh_faces']} mesh faces, {counts['wall_quads']} wall quads, "
          f"{counts['light_quads']} light quads")
    return 0


def main(argv=None):
    """Run ``python -m hrbench_analysis.meshes``; return its exit code (0, or 2)."""
    return run_main("python -m hrbench_analysis.meshes", _main, argv)


if __name__ == "__main__":
    sys.exit(main())
