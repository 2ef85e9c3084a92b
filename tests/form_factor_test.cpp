// Form factors (form_factor.h): flatland against crossed strings written out by hand, 3D
// against the closed forms of the literature (Howell's catalogue; Hottel's algebra), and
// the identities every form factor keeps: reciprocity and closed enclosures summing to 1.
#include <catch2/catch.hpp>

#include <array>
#include <cmath>
#include <random>
#include <vector>

#include <Eigen/Geometry>

#include "solve/form_factor.h"

using namespace hrbench;
using Catch::Matchers::WithinAbs;
using Catch::Matchers::WithinRel;

namespace {

const double kPi = std::acos(-1.0);

// ---------------------------------------------------------------------------------------
// 3D closed forms

// Howell C-11: parallel, directly opposed rectangles a x b at distance c.
double ParallelRectangles(double a, double b, double c) {
    double x = a / c, y = b / c, x1 = 1 + x * x, y1 = 1 + y * y;
    return 2 / (kPi * x * y) *
           (0.5 * std::log(x1 * y1 / (1 + x * x + y * y)) +
            x * std::sqrt(y1) * std::atan(x / std::sqrt(y1)) +
            y * std::sqrt(x1) * std::atan(y / std::sqrt(x1)) - x * std::atan(x) - y * std::atan(y));
}

// Howell C-14: from a rectangle w x l to a perpendicular one h x l sharing its edge l.
double PerpendicularRectangles(double w, double h, double l) {
    double W = w / l, H = h / l, w2 = W * W, h2 = H * H, s = std::sqrt(w2 + h2);
    double logs = std::log((1 + w2) * (1 + h2) / (1 + w2 + h2)) +
                  w2 * std::log(w2 * (1 + w2 + h2) / ((1 + w2) * (w2 + h2))) +
                  h2 * std::log(h2 * (1 + w2 + h2) / ((1 + h2) * (w2 + h2)));
    return (W * std::atan(1 / W) + H * std::atan(1 / H) - s * std::atan(1 / s) + logs / 4) /
           (kPi * W);
}

// Hottel's form-factor algebra along a common line: the horizontal rectangle y in
// [a0, a1], x in [0, w] and the vertical one y in [b0, b1], z in [0, h] exchange
// A F = M(a1 - b0) + M(a0 - b1) - M(a1 - b1) - M(a0 - b0), where M(u) is half of A F for
// two such rectangles sharing an edge of length |u| (C-14), as their kernel depends on y
// only through the difference of the two points' y.
double PerpendicularStrips(double w, double h, double a0, double a1, double b0, double b1) {
    auto m = [w, h](double u) {
        u = std::abs(u);
        return u > 0 ? 0.5 * w * u * PerpendicularRectangles(w, h, u) : 0.0;
    };
    double exchange = m(a1 - b0) + m(a0 - b1) - m(a1 - b1) - m(a0 - b0);
    return exchange / (w * (a1 - a0));
}

// A differential element parallel to a rectangle a x b at distance c, its normal through
// a corner (Howell, section B).
double PointUnderCorner(double a, double b, double c) {
    double x = a / c, y = b / c, sx = std::sqrt(1 + x * x), sy = std::sqrt(1 + y * y);
    return (x / sx * std::atan(y / sx) + y / sy * std::atan(x / sy)) / (2 * kPi);
}

// A differential element at the foot of a perpendicular rectangle: the rectangle in the
// plane at distance d, b wide from the element's side and c high above its plane. Lambert's
// formula by hand: the bottom edge, in the element's plane, gives atan(b/d); the top edge
// -d/sqrt(c^2 + d^2) atan(b/sqrt(c^2 + d^2)); the vertical edges nothing.
double PointAtFoot(double b, double c, double d) {
    double r = std::sqrt(c * c + d * d);
    return (std::atan(b / d) - d / r * std::atan(b / r)) / (2 * kPi);
}

// The rectangle [0,a] x [0,b] at height z, facing +z (up) or -z (down).
Polygon Horizontal(double a, double b, double z, bool up) {
    if (up)
        return Polygon::Quad({0, 0, z}, {a, 0, z}, {a, b, z}, {0, b, z});
    return Polygon::Quad({0, 0, z}, {0, b, z}, {a, b, z}, {a, 0, z});
}

// The rectangle in the plane x = 0, y in [y0, y1], z in [0, h], facing +x.
Polygon Wall(double y0, double y1, double h) {
    return Polygon::Quad({0, y0, 0}, {0, y1, 0}, {0, y1, h}, {0, y0, h});
}

// The rectangle x in [0, w], y in [y0, y1] on the floor, facing +z.
Polygon Floor(double w, double y0, double y1) {
    return Polygon::Quad({0, y0, 0}, {w, y0, 0}, {w, y1, 0}, {0, y1, 0});
}

// A square of side _a_ centred at _c_ with unit normal _n_, turned by _angle_ about it.
Polygon Square(const Vec3 &c, const Vec3 &n, double a, double angle) {
    Vec3 any = std::abs(n.x()) < 0.9 ? Vec3(1, 0, 0) : Vec3(0, 1, 0);
    Vec3 u0 = n.cross(any).normalized(), v0 = n.cross(u0);
    Vec3 u = 0.5 * a * (std::cos(angle) * u0 + std::sin(angle) * v0), v = n.cross(u);
    return Polygon::Quad(c - u - v, c + u - v, c + u + v, c - u + v);
}

}  // namespace

// ---------------------------------------------------------------------------------------
// Flatland

TEST_CASE("Flatland form factors are crossed strings of the facing segments", "[form-factor]") {
    SECTION("parallel facing segments, l = 1 at d = 1: sqrt(2) - 1") {
        Segment p{Vec2(0, 0), Vec2(1, 0)}, q{Vec2(1, 1), Vec2(0, 1)};
        // Crossed: (0,0)-(1,1) and (1,0)-(0,1), both sqrt(2); uncrossed: the two sides, 1.
        double expected = (std::sqrt(2.0) + std::sqrt(2.0) - 1 - 1) / 2;
        CHECK_THAT(FormFactor(p, q), WithinAbs(expected, 1e-12));
        CHECK_THAT(FormFactor(p, q), WithinAbs(std::sqrt(2.0) - 1, 1e-12));
        CHECK_THAT(FormFactor(q, p), WithinAbs(std::sqrt(2.0) - 1, 1e-12));
    }
    SECTION("perpendicular unit segments sharing a corner: (1 + 1 - sqrt(2)) / 2") {
        Segment p{Vec2(0, 0), Vec2(1, 0)}, q{Vec2(1, 0), Vec2(1, 1)};
        // Crossed: (0,0)-(1,0) and (1,0)-(1,1), both 1; uncrossed: (1,0)-(1,0), 0, and
        // (1,1)-(0,0), sqrt(2).
        double expected = (1 + 1 - 0 - std::sqrt(2.0)) / 2;
        CHECK_THAT(FormFactor(p, q), WithinAbs(expected, 1e-12));
        CHECK_THAT(FormFactor(q, p), WithinAbs(expected, 1e-12));
    }
    SECTION("an angled pair: A(0,0) -> B(2,0) and C(3,2) -> D(0,3)") {
        Segment p{Vec2(0, 0), Vec2(2, 0)}, q{Vec2(3, 2), Vec2(0, 3)};
        // ABCD is convex: crossed AC = sqrt(13), BD = sqrt(13); uncrossed BC = sqrt(5),
        // DA = 3. |AB| = 2, |CD| = sqrt(10).
        double strings = std::sqrt(13.0) + std::sqrt(13.0) - std::sqrt(5.0) - 3;
        CHECK_THAT(FormFactor(p, q), WithinAbs(strings / (2 * 2), 1e-12));
        CHECK_THAT(FormFactor(q, p), WithinAbs(strings / (2 * std::sqrt(10.0)), 1e-12));
    }
    SECTION("an offset parallel pair: A(0,0) -> B(1,0) and C(3,1) -> D(2,1)") {
        Segment p{Vec2(0, 0), Vec2(1, 0)}, q{Vec2(3, 1), Vec2(2, 1)};
        // Crossed AC = sqrt(10), BD = sqrt(2); uncrossed BC = sqrt(5), DA = sqrt(5).
        double expected = (std::sqrt(10.0) + std::sqrt(2.0) - 2 * std::sqrt(5.0)) / 2;
        CHECK_THAT(FormFactor(p, q), WithinAbs(expected, 1e-12));
        CHECK_THAT(FormFactor(q, p), WithinAbs(expected, 1e-12));
    }
    SECTION("segments facing away, back to back, or collinear exchange nothing") {
        Segment p{Vec2(0, 0), Vec2(1, 0)};
        CHECK(FormFactor(p, Segment{Vec2(0, 1), Vec2(1, 1)}) == 0);    // q faces away
        CHECK(FormFactor(p, Segment{Vec2(1, -1), Vec2(0, -1)}) == 0);  // behind p
        CHECK(FormFactor(p, Segment{Vec2(3, 0), Vec2(2, 0)}) == 0);    // collinear
        CHECK(FormFactor(p, Segment{Vec2(2, 0), Vec2(3, 0)}) == 0);
        CHECK(FormFactor(p, p) == 0);
        CHECK(FormFactor(Segment{Vec2(1, 1), Vec2(1, 1)}, p) == 0);  // degenerate
    }
    SECTION("a segment crossing the other's line counts only its part in front") {
        Segment p{Vec2(0, 0), Vec2(2, 0)}, q{Vec2(4, -1), Vec2(2, 1)};
        // q crosses p's line at C' = (3,0); p lies wholly in front of q. Clipped:
        // A(0,0) B(2,0) C'(3,0) D(2,1): crossed AC' = 3, BD = 1; uncrossed BC' = 1,
        // DA = sqrt(5); over 2 |AB| = 4.
        CHECK_THAT(FormFactor(p, q), WithinAbs((3 + 1 - 1 - std::sqrt(5.0)) / 4, 1e-12));
        // The part of q behind p (from (4,-1) to (3,0)) receives nothing: q's form factor
        // is over its full length 2 sqrt(2).
        CHECK_THAT(FormFactor(q, p),
                   WithinAbs((3 + 1 - 1 - std::sqrt(5.0)) / (2 * 2 * std::sqrt(2.0)), 1e-12));
    }
    SECTION("two segments crossing in an X: each is cut at the other's line") {
        Segment p{Vec2(-1, 0), Vec2(1, 0)}, q{Vec2(0.5, -1), Vec2(-0.5, 1)};
        // Both lines pass through O(0,0). Clipped: p to A(-1,0) -> O, q to O -> D(-0.5,1).
        // Crossed AO = 1, OD = sqrt(1.25); uncrossed OO = 0, DA = sqrt(1.25); over 2 |p|.
        double strings = 1 + std::sqrt(1.25) - 0 - std::sqrt(1.25);
        CHECK_THAT(FormFactor(p, q), WithinAbs(strings / (2 * 2), 1e-12));
        CHECK_THAT(FormFactor(q, p), WithinAbs(strings / (2 * std::sqrt(5.0)), 1e-12));
    }
}

TEST_CASE("Flatland form factors are reciprocal", "[form-factor]") {
    std::mt19937 rng(20240611);
    std::uniform_real_distribution<double> u(0, 1);
    int interacting = 0;
    for (int k = 0; k < 2000; ++k) {
        Segment p{Vec2(u(rng), u(rng)), Vec2(u(rng), u(rng))};
        Segment q{Vec2(u(rng), u(rng)), Vec2(u(rng), u(rng))};
        double pq = FormFactor(p, q), qp = FormFactor(q, p);
        CHECK(pq >= 0);
        CHECK(pq <= 1);
        CHECK_THAT(p.Length() * pq, WithinAbs(q.Length() * qp, 1e-12));
        interacting += pq > 0;
    }
    CHECK(interacting > 200);  // the check saw pairs that exchange light
}

TEST_CASE("The walls of a closed convex flatland room see all of it", "[form-factor]") {
    auto check = [](const std::vector<Vec2> &corners) {
        int n = static_cast<int>(corners.size());
        std::vector<Segment> walls;
        for (int k = 0; k < n; ++k)
            walls.push_back({corners[k], corners[(k + 1) % n]});  // counter-clockwise: inward
        for (int i = 0; i < n; ++i) {
            double sum = 0;
            for (int j = 0; j < n; ++j)
                sum += FormFactor(walls[i], walls[j]);
            CHECK_THAT(sum, WithinAbs(1, 1e-12));
        }
    };
    SECTION("a unit square") { check({Vec2(0, 0), Vec2(1, 0), Vec2(1, 1), Vec2(0, 1)}); }
    SECTION("a regular hexagon") {
        std::vector<Vec2> corners;
        for (int k = 0; k < 6; ++k)
            corners.emplace_back(std::cos(k * kPi / 3), std::sin(k * kPi / 3));
        check(corners);
        // Neighbours meet at 120 degrees: (1 + 1 - sqrt(3)) / 2.
        Segment a{corners[0], corners[1]}, b{corners[1], corners[2]};
        CHECK_THAT(FormFactor(a, b), WithinAbs((2 - std::sqrt(3.0)) / 2, 1e-12));
    }
}

// ---------------------------------------------------------------------------------------
// 3D: a point to a polygon

TEST_CASE("Lambert's formula matches the closed forms for a point", "[form-factor]") {
    Vec3 up(0, 0, 1);
    SECTION("under the corner of a parallel rectangle") {
        for (auto [a, b, c] : {std::array<double, 3>{1, 1, 1},
                               {2, 0.5, 1},
                               {0.3, 4, 2},
                               {10, 10, 0.1},
                               {0.01, 0.02, 5}}) {
            Polygon above = Horizontal(a, b, c, false);
            CHECK_THAT(PointToPolygonFormFactor(Vec3::Zero(), up, above),
                       WithinRel(PointUnderCorner(a, b, c), 1e-12));
        }
    }
    SECTION("under an inner point: the four corner rectangles add up") {
        // The rectangle [-1, 2] x [-0.5, 1.5] at height 0.7 over the origin.
        Polygon above =
            Polygon::Quad({-1, -0.5, 0.7}, {-1, 1.5, 0.7}, {2, 1.5, 0.7}, {2, -0.5, 0.7});
        double expected = PointUnderCorner(1, 0.5, 0.7) + PointUnderCorner(2, 0.5, 0.7) +
                          PointUnderCorner(1, 1.5, 0.7) + PointUnderCorner(2, 1.5, 0.7);
        CHECK_THAT(PointToPolygonFormFactor(Vec3::Zero(), up, above), WithinRel(expected, 1e-12));
    }
    SECTION("the part of a rectangle behind the tangent plane is clipped away") {
        // The rectangle in the plane x = d, facing -x, y in [0, b], z in [-c, c]: the
        // point (at the origin, facing +z) sees only its upper half.
        double b = 1.5, c = 0.8, d = 0.6;
        Polygon wall = Polygon::Quad({d, 0, -c}, {d, 0, c}, {d, b, c}, {d, b, -c});
        CHECK(wall.Normal().isApprox(Vec3(-1, 0, 0)));
        CHECK_THAT(PointToPolygonFormFactor(Vec3::Zero(), up, wall),
                   WithinRel(PointAtFoot(b, c, d), 1e-12));
        Polygon upper = Polygon::Quad({d, 0, 0}, {d, 0, c}, {d, b, c}, {d, b, 0});
        CHECK_THAT(PointToPolygonFormFactor(Vec3::Zero(), up, upper),
                   WithinRel(PointAtFoot(b, c, d), 1e-12));
    }
    SECTION("a triangle: the two halves of a rectangle add up") {
        Polygon above = Horizontal(2, 1, 1.5, false);
        double half0 = PointToPolygonFormFactor(
            Vec3::Zero(), up, Polygon::Triangle(above.v[0], above.v[1], above.v[2]));
        double half1 = PointToPolygonFormFactor(
            Vec3::Zero(), up, Polygon::Triangle(above.v[0], above.v[2], above.v[3]));
        CHECK_THAT(half0 + half1, WithinRel(PointUnderCorner(2, 1, 1.5), 1e-12));
    }
    SECTION("a polygon seen from its back, or wholly behind the point, gives 0") {
        CHECK(PointToPolygonFormFactor(Vec3::Zero(), up, Horizontal(1, 1, 1, true)) == 0);
        CHECK(PointToPolygonFormFactor(Vec3::Zero(), up, Horizontal(1, 1, -1, true)) == 0);
        CHECK(PointToPolygonFormFactor(Vec3::Zero(), up, Horizontal(1, 1, 0, true)) == 0);
    }
}

// ---------------------------------------------------------------------------------------
// 3D: polygon to polygon

TEST_CASE("Form factors between rectangles match the closed forms", "[form-factor]") {
    SECTION("parallel, directly opposed rectangles (C-11)") {
        for (auto [a, b, c] : {std::array<double, 3>{1, 1, 1},
                               {2, 1, 0.5},
                               {1, 3, 2},
                               {0.5, 0.5, 3},
                               {1, 1, 10},
                               {4, 1, 0.25}}) {
            Polygon below = Horizontal(a, b, 0, true), above = Horizontal(a, b, c, false);
            double expected = ParallelRectangles(a, b, c);
            CHECK_THAT(FormFactor(below, above), WithinRel(expected, 1e-8));
            CHECK_THAT(FormFactor(above, below), WithinRel(expected, 1e-8));
        }
    }
    SECTION("perpendicular rectangles sharing an edge (C-14)") {
        for (auto [w, h, l] : {std::array<double, 3>{1, 1, 1},
                               {2, 1, 1},
                               {1, 3, 0.5},
                               {0.2, 0.5, 1},
                               {3, 4, 1},
                               {1, 0.1, 2}}) {
            Polygon floor = Floor(w, 0, l), wall = Wall(0, l, h);
            CHECK_THAT(FormFactor(floor, wall), WithinRel(PerpendicularRectangles(w, h, l), 1e-7));
            CHECK_THAT(FormFactor(wall, floor), WithinRel(PerpendicularRectangles(h, w, l), 1e-7));
        }
    }
    SECTION("perpendicular rectangles sharing part of an edge, or a corner (algebra)") {
        struct Case {
            double w, h, a0, a1, b0, b1;
        };
        for (const Case &c : {Case{1, 1, 0, 1, 0.5, 1.5},       // overlapping halves
                              Case{0.7, 1.2, 0.25, 0.5, 0, 1},  // the floor's edge inside
                              Case{0.7, 1.2, 0, 1, 0.25, 0.5},  // the wall's edge inside
                              Case{1, 1, 0, 1, 1, 2},           // only a corner
                              Case{0.5, 2, 0, 0.3, 0.3, 1.3}}) {
            Polygon floor = Floor(c.w, c.a0, c.a1), wall = Wall(c.b0, c.b1, c.h);
            CHECK_THAT(FormFactor(floor, wall),
                       WithinRel(PerpendicularStrips(c.w, c.h, c.a0, c.a1, c.b0, c.b1), 1e-7));
            CHECK_THAT(FormFactor(wall, floor),
                       WithinRel(PerpendicularStrips(c.h, c.w, c.b0, c.b1, c.a0, c.a1), 1e-7));
        }
    }
}

TEST_CASE("Form factors do not depend on where the pair lies, how it turns, or its size",
          "[form-factor]") {
    // The C-14 pair (2 x 1 floor, 0.5 x 1 wall), turned, scaled and moved away from the
    // origin: the contact must still be found (tolerances follow the size and the
    // coordinates' rounding), and tiny integrals still converge.
    Eigen::Matrix3d turn = Eigen::AngleAxisd(0.3, Vec3(1, 2, 3).normalized()).toRotationMatrix();
    for (auto [scale, offset] : {std::array<double, 2>{1, 0}, {1e-3, 100}, {1e-6, 0}, {1e-6, 1}}) {
        auto at = [&](double x, double y, double z) {
            return Vec3(Vec3(offset, -0.7 * offset, 0.3 * offset) + turn * (scale * Vec3(x, y, z)));
        };
        Polygon floor = Polygon::Quad(at(0, 0, 0), at(2, 0, 0), at(2, 1, 0), at(0, 1, 0));
        Polygon wall = Polygon::Quad(at(0, 0, 0), at(0, 1, 0), at(0, 1, 0.5), at(0, 0, 0.5));
        CHECK_THAT(FormFactor(floor, wall), WithinRel(PerpendicularRectangles(2, 0.5, 1), 1e-7));
        CHECK_THAT(FormFactor(wall, floor), WithinRel(PerpendicularRectangles(0.5, 2, 1), 1e-7));
    }
}

TEST_CASE("Triangles add up to the rectangle they split", "[form-factor]") {
    auto halves = [](const Polygon &r) {
        return std::array<Polygon, 2>{Polygon::Triangle(r.v[0], r.v[1], r.v[2]),
                                      Polygon::Triangle(r.v[0], r.v[2], r.v[3])};
    };
    SECTION("parallel rectangles: the receiver split, then the emitter") {
        Polygon below = Horizontal(2, 1, 0, true), above = Horizontal(2, 1, 0.8, false);
        double expected = ParallelRectangles(2, 1, 0.8);
        auto parts = halves(above);
        CHECK_THAT(FormFactor(below, parts[0]) + FormFactor(below, parts[1]),
                   WithinRel(expected, 1e-7));
        parts = halves(below);
        CHECK_THAT((parts[0].Area() * FormFactor(parts[0], above) +
                    parts[1].Area() * FormFactor(parts[1], above)) /
                       below.Area(),
                   WithinRel(expected, 1e-7));
    }
    SECTION("perpendicular rectangles sharing an edge: one half touches it at a corner") {
        Polygon floor = Floor(1.5, 0, 1), wall = Wall(0, 1, 0.75);
        auto parts = halves(floor);
        CHECK_THAT((parts[0].Area() * FormFactor(parts[0], wall) +
                    parts[1].Area() * FormFactor(parts[1], wall)) /
                       floor.Area(),
                   WithinRel(PerpendicularRectangles(1.5, 0.75, 1), 1e-7));
        parts = halves(wall);
        CHECK_THAT(FormFactor(floor, parts[0]) + FormFactor(floor, parts[1]),
                   WithinRel(PerpendicularRectangles(1.5, 0.75, 1), 1e-7));
    }
}

TEST_CASE("The faces of a closed cube see all of it", "[form-factor]") {
    // The unit cube's faces, each counter-clockwise seen from inside.
    std::array<Polygon, 6> faces = {
        Polygon::Quad({0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}),  // z = 0
        Polygon::Quad({0, 0, 1}, {0, 1, 1}, {1, 1, 1}, {1, 0, 1}),  // z = 1
        Polygon::Quad({0, 0, 0}, {0, 1, 0}, {0, 1, 1}, {0, 0, 1}),  // x = 0
        Polygon::Quad({1, 0, 0}, {1, 0, 1}, {1, 1, 1}, {1, 1, 0}),  // x = 1
        Polygon::Quad({0, 0, 0}, {0, 0, 1}, {1, 0, 1}, {1, 0, 0}),  // y = 0
        Polygon::Quad({0, 1, 0}, {1, 1, 0}, {1, 1, 1}, {0, 1, 1}),  // y = 1
    };
    double opposite = ParallelRectangles(1, 1, 1), adjacent = PerpendicularRectangles(1, 1, 1);
    for (int i = 0; i < 6; ++i) {
        CHECK(faces[i].Normal().dot(Vec3(0.5, 0.5, 0.5) - faces[i].v[0]) > 0);
        double sum = 0;
        for (int j = 0; j < 6; ++j) {
            double f = FormFactor(faces[i], faces[j]);
            sum += f;
            if (j == i)
                CHECK(f == 0);
            else
                CHECK_THAT(f, WithinRel(j == (i ^ 1) ? opposite : adjacent, 1e-7));
        }
        CHECK_THAT(sum, WithinAbs(1, 1e-7));
    }
}

TEST_CASE("3D form factors are reciprocal", "[form-factor]") {
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> u(-1, 1);
    auto direction = [&rng, &u]() {
        Vec3 d;
        do
            d = Vec3(u(rng), u(rng), u(rng));
        while (!(d.norm() > 0.1 && d.norm() < 1));
        return Vec3(d.normalized());
    };
    SECTION("random facing squares") {
        int checked = 0;
        while (checked < 60) {
            Vec3 d = direction(), n0 = direction(), n1 = direction();
            if (n0.dot(d) < 0.2 || n1.dot(-d) < 0.2)
                continue;
            // Apart by more than their half diagonals: they do not cut through each other.
            double a0 = 0.5 + 0.4 * u(rng), a1 = 0.5 + 0.4 * u(rng);
            double r = 0.75 * (a0 + a1) + 0.1 + 0.3 * (u(rng) + 1);
            Polygon p = Square(Vec3::Zero(), n0, a0, 3 * u(rng));
            Polygon q = Square(r * d, n1, a1, 3 * u(rng));
            double pq = p.Area() * FormFactor(p, q), qp = q.Area() * FormFactor(q, p);
            CHECK(pq > 0);
            CHECK_THAT(pq, WithinRel(qp, 1e-7));
            ++checked;
        }
    }
    SECTION("rectangles hinged on a shared edge at random angles") {
        for (int k = 0; k < 12; ++k) {
            double angle = 0.3 + 1.25 * (u(rng) + 1), w = 1 + 0.8 * u(rng), h = 1 + 0.8 * u(rng);
            Vec3 d(std::cos(angle), 0, std::sin(angle));
            Polygon floor = Floor(w, 0, 1);
            Polygon leaf = Polygon::Quad(Vec3::Zero(), Vec3(0, 1, 0), Vec3(0, 1, 0) + h * d, h * d);
            double pq = floor.Area() * FormFactor(floor, leaf);
            double qp = leaf.Area() * FormFactor(leaf, floor);
            CHECK(pq > 0);
            CHECK_THAT(pq, WithinRel(qp, 1e-7));
        }
    }
}

TEST_CASE("Polygons facing away or coplanar exchange nothing", "[form-factor]") {
    Polygon floor = Horizontal(1, 1, 0, true);
    CHECK(FormFactor(floor, Horizontal(1, 1, 1, true)) == 0);    // seen from its back
    CHECK(FormFactor(floor, Horizontal(1, 1, -1, false)) == 0);  // behind the floor
    CHECK(FormFactor(floor, Horizontal(1, 1, -1, true)) == 0);   // back to back
    Polygon beside = Polygon::Quad({1, 0, 0}, {2, 0, 0}, {2, 1, 0}, {1, 1, 0});
    CHECK(FormFactor(floor, beside) == 0);  // coplanar, sharing an edge
    CHECK(FormFactor(floor, floor) == 0);
    // A wall standing on the floor's edge but facing out of the room.
    CHECK(FormFactor(floor, Polygon::Quad({0, 0, 0}, {0, 0, 1}, {0, 1, 1}, {0, 1, 0})) == 0);
}
