#include "space.h"

#include <cmath>
#include <cstdint>
#include <limits>
#include <random>

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>

#include "family_helpers.h"
#include "hrbench/util/error.h"
#include "util/format.h"

namespace hrbench {

namespace {

Patch<Polygon> Quad(const Vec3 &a, const Vec3 &b, const Vec3 &c, const Vec3 &d, Material m = {}) {
    return {Polygon::Quad(a, b, c, d), m};
}

// The rectangle [x0,x1] x [y0,y1] at height z, facing +z (up) or -z; either way
// its first edge runs along +x, so that ties halve x first.
Patch<Polygon> Horizontal(double x0, double x1, double y0, double y1, double z, bool up) {
    if (up)
        return Quad(Vec3(x0, y0, z), Vec3(x1, y0, z), Vec3(x1, y1, z), Vec3(x0, y1, z));
    return Quad(Vec3(x0, y1, z), Vec3(x1, y1, z), Vec3(x1, y0, z), Vec3(x0, y0, z));
}

// P spans [0,l] x [0,w] at z=0 facing +z; Q the same rectangle moved by (ox, oy) at z=d
// facing -z.
Patches<Polygon> Parallel(const ParamMap &p) {
    double l = p.at("l"), w = p.at("w"), d = p.at("d"), ox = p.at("ox"), oy = p.at("oy");
    return {Horizontal(0, l, 0, w, 0, true), Horizontal(ox, ox + l, oy, oy + w, d, false)};
}

// P on the floor z=0, x in [0,l], y in [gap, gap+w], facing +z; Q on the arm
// (0, cos angle, sin angle) from the x axis, from gap to gap+h, facing into the wedge.
Patches<Polygon> Angled(double l, double w, double h, double angleDegrees, double gap) {
    double angle = angleDegrees * kPi / 180;
    Vec3 arm(0, std::cos(angle), std::sin(angle));
    if (angleDegrees == 90)
        arm = Vec3(0, 0, 1);  // exact, so that `perpendicular3d` has exact coordinates
    Vec3 x(l, 0, 0);
    Patch<Polygon> p = Horizontal(0, l, gap, gap + w, 0, true);
    Vec3 far = (gap + h) * arm, near = gap * arm;
    Patch<Polygon> q = Quad(far, far + x, near + x, near);
    return {p, q};
}

// Two plates as in `parallel3d` (no offset) with a blocker between them: a rectangle
// bl x bw at height h, centred over the plates' centre moved by (ox, oy), made of two
// back-to-back patches (facing P, then facing Q).
Patches<Polygon> Occluded(const ParamMap &p) {
    double l = p.at("l"), w = p.at("w"), d = p.at("d"), bl = p.at("bl"), bw = p.at("bw"),
           h = p.at("h"), ox = p.at("ox"), oy = p.at("oy");
    if (!(h < d))
        throw InputError("scene occluded3d: the blocker height h=" + FormatDouble(h) +
                         " must lie between the plates (h < d=" + FormatDouble(d) + ")");
    double x0 = 0.5 * l + ox - 0.5 * bl, x1 = 0.5 * l + ox + 0.5 * bl;
    double y0 = 0.5 * w + oy - 0.5 * bw, y1 = 0.5 * w + oy + 0.5 * bw;
    return {Horizontal(0, l, 0, w, 0, true), Horizontal(0, l, 0, w, d, false),
            Horizontal(x0, x1, y0, y1, h, false), Horizontal(x0, x1, y0, y1, h, true)};
}

// k x k plates l x l on z=0 facing up and k x k facing down at z=d, _spacing_ apart.
Patches<Polygon> Array(const ParamMap &p) {
    int k = int(p.at("k"));
    double l = p.at("l"), d = p.at("d"), spacing = p.at("spacing");
    Patches<Polygon> faces;
    for (bool up : {true, false})
        for (int b = 0; b < k; ++b)
            for (int a = 0; a < k; ++a) {
                double x = a * (l + spacing), y = b * (l + spacing);
                faces.push_back(Horizontal(x, x + l, y, y + l, up ? 0 : d, up));
            }
    return faces;
}

// The Cornell box, from the measured data of the Cornell University Program of Computer
// Graphics, https://www.graphics.cornell.edu/online/box/data.html (millimetres; the
// box is open at z = 0). Scalar reflectance and emission are the means of the RGB
// values of the widely used rendering of that data (B. Bitterli, "Rendering resources",
// https://benedikt-bitterli.me/resources/, scene cornell-box): white (0.725, 0.71, 0.68),
// red (0.63, 0.065, 0.05), green (0.14, 0.45, 0.091), light emission (17, 12, 4).
Patches<Polygon> Cornell(const ParamMap &p) {
    double s = p.at("scale");
    auto v = [s](double x, double y, double z) { return Vec3(s * x, s * y, s * z); };
    // The RGB is kept as the display colour; the light has none: shown grey of its 0.78.
    const Material white{(0.725 + 0.71 + 0.68) / 3, 0, Rgb{0.725, 0.71, 0.68}};
    const Material red{(0.63 + 0.065 + 0.05) / 3, 0, Rgb{0.63, 0.065, 0.05}};
    const Material green{(0.14 + 0.45 + 0.091) / 3, 0, Rgb{0.14, 0.45, 0.091}};
    const Material light{0.78, (17.0 + 12.0 + 4.0) / 3};  // 0.78: the lamp's reflectance
    Patches<Polygon> f;
    auto quad = [&](Vec3 a, Vec3 b, Vec3 c, Vec3 d, Material m) {
        f.push_back(Quad(a, b, c, d, m));
    };

    // The measured data, one patch per line.
    // clang-format off
    // Walls, facing into the box.
    quad(v(552.8, 0, 0), v(0, 0, 0), v(0, 0, 559.2), v(549.6, 0, 559.2), white);                // floor
    quad(v(556, 548.8, 0), v(556, 548.8, 559.2), v(0, 548.8, 559.2), v(0, 548.8, 0), white);    // ceiling
    quad(v(549.6, 0, 559.2), v(0, 0, 559.2), v(0, 548.8, 559.2), v(556, 548.8, 559.2), white);  // back
    quad(v(0, 0, 559.2), v(0, 0, 0), v(0, 548.8, 0), v(0, 548.8, 559.2), green);                // right
    // The measured left wall is not planar (a corner lies 3.2 mm off the plane of the
    // other three), so it is given as two triangles.
    f.push_back({Polygon::Triangle(v(552.8, 0, 0), v(549.6, 0, 559.2), v(556, 548.8, 559.2)), red});
    f.push_back({Polygon::Triangle(v(552.8, 0, 0), v(556, 548.8, 559.2), v(556, 548.8, 0)), red});
    // The light, in the plane of the ceiling, facing down.
    quad(v(343, 548.8, 227), v(343, 548.8, 332), v(213, 548.8, 332), v(213, 548.8, 227), light);

    // Short block: top and four sides, facing out.
    quad(v(130, 165, 65), v(82, 165, 225), v(240, 165, 272), v(290, 165, 114), white);
    quad(v(290, 0, 114), v(290, 165, 114), v(240, 165, 272), v(240, 0, 272), white);
    quad(v(130, 0, 65), v(130, 165, 65), v(290, 165, 114), v(290, 0, 114), white);
    quad(v(82, 0, 225), v(82, 165, 225), v(130, 165, 65), v(130, 0, 65), white);
    quad(v(240, 0, 272), v(240, 165, 272), v(82, 165, 225), v(82, 0, 225), white);
    // Tall block: top and four sides, facing out.
    quad(v(423, 330, 247), v(265, 330, 296), v(314, 330, 456), v(472, 330, 406), white);
    quad(v(423, 0, 247), v(423, 330, 247), v(472, 330, 406), v(472, 0, 406), white);
    quad(v(472, 0, 406), v(472, 330, 406), v(314, 330, 456), v(314, 0, 456), white);
    quad(v(314, 0, 456), v(314, 330, 456), v(265, 330, 296), v(265, 0, 296), white);
    quad(v(265, 0, 296), v(265, 330, 296), v(423, 330, 247), v(423, 0, 247), white);
    // clang-format on
    return f;
}

// n pairwise disjoint triangles: uniform centres in [0,size]^3, corners uniform in the
// cube of side _length_ around the centre. A candidate thinner than 5% of length^2 in
// area, or that meets an earlier triangle, is drawn again. With _density_ (centres per
// unit volume) the cube's side is cbrt(n / density) instead of _size_, so that the soup
// keeps its density as n grows.
Patches<Polygon> Random(const ParamMap &p) {
    using K = CGAL::Exact_predicates_inexact_constructions_kernel;
    int n = int(p.at("n"));
    auto density = p.find("density");
    double size = density == p.end() ? p.at("size") : std::cbrt(n / density->second);
    double length = p.at("length");
    std::mt19937_64 rng(uint64_t(p.at("seed")));
    Patches<Polygon> faces;
    std::vector<K::Triangle_3> placed;
    PlacementGrid<3> grid(length, size + 2 * length);
    const int64_t maxDraws = MaxDraws(n);
    for (int64_t draw = 0; int(faces.size()) < n; ++draw) {
        if (draw == maxDraws)
            throw InputError("scene random3d: cannot place " + std::to_string(n) +
                             " disjoint triangles of size " + FormatDouble(length) +
                             " in a box of size " + FormatDouble(size) +
                             (density == p.end() ? "; enlarge size" : "; lower density"));
        Vec3 c(size * Uniform(rng), size * Uniform(rng), size * Uniform(rng));
        std::array<Vec3, 3> corner;
        for (Vec3 &x : corner) {
            double dx = Uniform(rng) - 0.5, dy = Uniform(rng) - 0.5, dz = Uniform(rng) - 0.5;
            x = c + length * Vec3(dx, dy, dz);
        }
        Polygon t = Polygon::Triangle(corner[0], corner[1], corner[2]);
        if (!(t.Area() >= 0.05 * length * length))
            continue;
        auto point = [](const Vec3 &x) { return K::Point_3(x.x(), x.y(), x.z()); };
        K::Triangle_3 candidate(point(corner[0]), point(corner[1]), point(corner[2]));
        std::array<double, 3> lo, hi;
        for (int d = 0; d < 3; ++d) {
            lo[d] = std::min({corner[0][d], corner[1][d], corner[2][d]});
            hi[d] = std::max({corner[0][d], corner[1][d], corner[2][d]});
        }
        if (grid.AnyNear(lo, hi,
                         [&](uint32_t k) { return CGAL::do_intersect(candidate, placed[k]); }))
            continue;
        grid.Insert(uint32_t(placed.size()), lo, hi);
        faces.push_back({t, {}});
        placed.push_back(candidate);
    }
    return faces;
}

// A closed sphere by octahedral subdivision: each face of the octahedron |x|+|y|+|z| = n
// is cut into n^2 triangles on the integer points of its plane, and every point (a, b, c)
// is moved to radius * (a, b, c) / |(a, b, c)|. A corner is computed from its integer
// point alone, so neighbouring triangles share their corners exactly, also across the
// octants. Triangles are counter-clockwise seen from the centre (normals inward).
Patches<Polygon> Sphere(const ParamMap &p) {
    int n = int(p.at("n"));
    double radius = p.at("radius");
    auto corner = [&](int64_t a, int64_t b, int64_t c) {
        double scale = radius / std::sqrt(double(a * a + b * b + c * c));
        return Vec3(double(a) * scale, double(b) * scale, double(c) * scale);
    };
    Patches<Polygon> faces;
    faces.reserve(8 * size_t(n) * size_t(n));
    for (int octant = 0; octant < 8; ++octant) {
        int sx = octant & 1 ? -1 : 1, sy = octant & 2 ? -1 : 1, sz = octant & 4 ? -1 : 1;
        // Point (i, j) of the octant: n - i - j along x, i along y, j along z.
        auto at = [&](int i, int j) { return corner(sx * (n - i - j), sy * i, sz * j); };
        // (x, y, z) turns counter-clockwise seen from outside the positive octant; each
        // mirrored axis reverses that, and inward normals need the clockwise order.
        bool outwardOrder = sx * sy * sz < 0;
        auto add = [&](const Vec3 &a, const Vec3 &b, const Vec3 &c) {
            faces.push_back(
                {outwardOrder ? Polygon::Triangle(a, b, c) : Polygon::Triangle(a, c, b), {}});
        };
        for (int i = 0; i < n; ++i)
            for (int j = 0; i + j < n; ++j) {
                add(at(i, j), at(i + 1, j), at(i, j + 1));
                if (i + j + 1 < n)
                    add(at(i + 1, j), at(i + 1, j + 1), at(i, j + 1));
            }
    }
    return faces;
}

}  // namespace

std::vector<Family> SpaceFamilies() {
    return {
        {"parallel3d",
         "two facing parallel rectangles: P [0,l]x[0,w] at z=0 facing +z, Q the same moved by "
         "(ox,oy) at z=d facing -z",
         {Length("l", 1, "side of the plates along x"),
          LengthLike("w", "l", "side of the plates along y (default: l)"),
          Length("d", 1, "distance between the plates"),
          Offset("ox", "lateral offset of Q along x"), Offset("oy", "lateral offset of Q along y")},
         3,
         Parallel},
        {"perpendicular3d",
         "two rectangles at a right angle sharing the x axis: P on the floor z=0 (l x w), Q on "
         "the wall y=0 (l x h), both facing the quadrant between them",
         {Length("l", 1, "length of both plates along the common x axis"),
          LengthLike("w", "l", "width of P along y (default: l)"),
          LengthLike("h", "w", "height of Q along z (default: w)"),
          Gap("gap", 0.1, "distance of both plates from the common edge; 0 means touching")},
         3,
         [](const ParamMap &p) {
             return Angled(p.at("l"), p.at("w"), p.at("h"), 90, p.at("gap"));
         }},
        {"angled3d",
         "two rectangles hinged on the x axis with an opening angle, facing into the wedge",
         {Length("l", 1, "length of both plates along the hinge"),
          LengthLike("w", "l", "width of P (on the floor) (default: l)"),
          LengthLike("h", "w", "width of Q (on the tilted arm) (default: w)"),
          {"angle", 60, "", 0, 180, true, true, false, "opening angle in degrees"},
          Gap("gap", 0.1, "distance of both plates from the hinge; 0 means touching")},
         3,
         [](const ParamMap &p) {
             return Angled(p.at("l"), p.at("w"), p.at("h"), p.at("angle"), p.at("gap"));
         }},
        {"occluded3d",
         "parallel3d plates (l x w, distance d) with a blocker bl x bw at height h between "
         "them, made of two back-to-back patches",
         {Length("l", 1, "side of the plates along x"),
          LengthLike("w", "l", "side of the plates along y (default: l)"),
          Length("d", 1, "distance between the plates"),
          Length("bl", 0.5, "side of the blocker along x"),
          LengthLike("bw", "bl", "side of the blocker along y (default: bl)"),
          Length("h", 0.5, "height of the blocker above P (< d)"),
          Offset("ox", "offset of the blocker's centre from the plates' centre along x"),
          Offset("oy", "offset of the blocker's centre from the plates' centre along y")},
         3,
         Occluded},
        {"cornell",
         "the Cornell box (measured data, 556 x 548.8 x 559.2 mm): walls, light and two blocks "
         "with their reflectances and emission (walls and blocks touch: needs a recursion limit)",
         {Length("scale", 0.001, "length unit per millimetre (default: metres)")},
         3,
         Cornell},
        {"array3d",
         "a k x k grid of l x l plates on z=0 facing k x k plates at z=d: the geometry grows, "
         "each pair stays the same",
         {Count("k", 2, 1, 1000, "plates per row and column"), Length("l", 1, "side of each plate"),
          Length("d", 1, "distance between the layers"),
          Gap("spacing", 1, "gap between neighbouring plates in a layer")},
         3,
         Array},
        {"random3d",
         "n disjoint triangles with uniform centres in a cube and corners in a cube of side "
         "length around each centre",
         {Count("n", 10, 1, 100000, "number of triangles"),
          Count("seed", 1, 0, 9.0e15, "random seed (same seed, same scene)"),
          Length("size", 10, "side of the cube of centres"),
          Length("length", 1, "side of the cube each triangle's corners lie in"),
          OptionalPositive("density", "size",
                           "triangle centres per unit volume: the cube's side is "
                           "cbrt(n / density) (instead of size)")},
         3,
         Random},
        {"sphere",
         "closed sphere of 8 n^2 triangles (octahedral subdivision projected onto the sphere), "
         "normals inward (neighbours touch: needs a recursion limit)",
         {Count("n", 4, 1, 1000, "triangles per octant edge (n = 354: 1,002,528 triangles)"),
          Length("radius", 1, "radius")},
         3,
         Sphere},
    };
}

}  // namespace hrbench
