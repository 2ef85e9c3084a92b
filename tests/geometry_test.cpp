// The two shapes of the engine (geometry/segment.h, geometry/polygon.h): measures,
// validation, subdivision order, sample points and the precision check of their children,
// as docs/conventions.md and docs/3d.md define them.
#include <catch2/catch.hpp>

#include <cmath>
#include <limits>
#include <numeric>
#include <random>

#include "hrbench/hrbench.h"

using namespace hrbench;
using Catch::Matchers::WithinRel;

namespace {

Polygon UnitSquare() { return Polygon::Quad({0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}); }

}  // namespace

// ---------------------------------------------------------------------------------------
// Segments (2D)

TEST_CASE("Segments report their length, midpoint and left-hand normal", "[geometry][2d]") {
    STATIC_REQUIRE(Segment::kDimension == 2);
    SECTION("a segment along x faces +y") {
        Segment s{Vec2(0, 0), Vec2(4, 0)};
        CHECK(s.Length() == 4);
        CHECK(s.Measure() == 4);
        CHECK(s.Midpoint() == Vec2(2, 0));
        CHECK(s.Centroid() == Vec2(2, 0));
        CHECK(s.Normal() == Vec2(0, 1));
    }
    SECTION("reversing a segment turns its normal around") {
        Segment s{Vec2(4, 0), Vec2(0, 0)};
        CHECK(s.Normal() == Vec2(0, -1));
    }
    SECTION("a 3-4-5 segment") {
        Segment s{Vec2(1, 1), Vec2(4, 5)};
        CHECK(s.Measure() == 5);
        CHECK(s.Centroid() == Vec2(2.5, 3));
        CHECK(s.Normal().isApprox(Vec2(-0.8, 0.6)));
    }
}

TEST_CASE("A segment's squared length is dx*dx + dy*dy; its length is the square root",
          "[geometry][2d]") {
    SECTION("hand-computed: the square root merges two squared lengths one ulp apart") {
        // (dx, dy) = (-1, 2^-26): dx*dx + dy*dy = 1 + 2^-52 exactly, the double after 1,
        // whose square root rounds (to even) to 1, the length of a unit segment.
        Segment unit{Vec2(0, 0), Vec2(1, 0)}, tilted{Vec2(1, 1), Vec2(0, 1 + 0x1p-26)};
        CHECK(unit.SquaredLength() == 1);
        CHECK(tilted.SquaredLength() == std::nextafter(1.0, 2.0));
        CHECK(tilted.SquaredMeasure() == tilted.SquaredLength());
        CHECK(tilted.Length() == 1);
        CHECK(tilted.Length() == unit.Length());
        CHECK((tilted.b - tilted.a).norm() == 1);  // Eigen's norm merges them too
    }
    SECTION("random segments: Length() is bit for bit Eigen's norm()") {
        std::mt19937_64 rng(7);
        std::uniform_real_distribution<double> u(-1e3, 1e3), e(-60, 60);
        for (int k = 0; k < 100000; ++k) {
            double scale = std::ldexp(1.0, int(e(rng)));
            Segment s{Vec2(u(rng), u(rng)) * scale, Vec2(u(rng), u(rng)) * scale};
            double dx = s.b.x() - s.a.x(), dy = s.b.y() - s.a.y();
            REQUIRE(s.SquaredLength() == dx * dx + dy * dy);
            REQUIRE(s.SquaredLength() == (s.b - s.a).squaredNorm());
            REQUIRE(s.Length() == (s.b - s.a).norm());
            REQUIRE(s.Measure() == std::sqrt(s.SquaredMeasure()));
        }
    }
}

TEST_CASE("A segment is halved at its midpoint, the half at a first", "[geometry][2d]") {
    Segment s{Vec2(0, 0), Vec2(2, 2)};
    std::array<Segment, 4> c;
    REQUIRE(s.Subdivide(Subdivision::Binary, c) == 2);
    CHECK(c[0].a == Vec2(0, 0));
    CHECK(c[0].b == Vec2(1, 1));
    CHECK(c[1].a == Vec2(1, 1));
    CHECK(c[1].b == Vec2(2, 2));
    CHECK(c[0].Measure() == s.Measure() / 2);
    CHECK(c[1].Measure() == s.Measure() / 2);
    CHECK(c[0].Normal().isApprox(s.Normal()));  // children keep the orientation
    CHECK(c[1].Normal().isApprox(s.Normal()));
}

TEST_CASE("Segment sample points are the centres of k equal parts, from a to b",
          "[geometry][2d][visibility]") {
    Segment s{Vec2(0, 0), Vec2(4, 0)};
    std::vector<Vec2> points;
    s.SamplePoints(4, points);
    REQUIRE(points.size() == 4);
    CHECK(points[0] == Vec2(0.5, 0));
    CHECK(points[1] == Vec2(1.5, 0));
    CHECK(points[2] == Vec2(2.5, 0));
    CHECK(points[3] == Vec2(3.5, 0));
    std::vector<Vec2> one;
    s.SamplePoints(1, one);
    REQUIRE(one.size() == 1);
    CHECK(one[0] == s.Centroid());
    Segment slanted{Vec2(1, 2), Vec2(-3, 7)};
    for (int k : {1, 2, 3, 5}) {
        std::vector<Vec2> p;
        slanted.SamplePoints(k, p);
        REQUIRE(p.size() == size_t(k));
        Vec2 mean = std::accumulate(p.begin(), p.end(), Vec2(0, 0)) / k;
        CHECK((mean - slanted.Centroid()).norm() < 1e-12);
    }
}

TEST_CASE("Invalid segments are named with what is wrong", "[geometry][2d]") {
    double nan = std::numeric_limits<double>::quiet_NaN();
    double inf = std::numeric_limits<double>::infinity();
    CHECK(Segment{Vec2(0, 0), Vec2(1, 0)}.Problem().empty());
    CHECK_THAT(Segment({Vec2(1, 1), Vec2(1, 1)}).Problem(), Catch::Contains("degenerate"));
    CHECK_THAT(Segment({Vec2(0, nan), Vec2(1, 0)}).Problem(), Catch::Contains("not finite"));
    CHECK_THAT(Segment({Vec2(0, 0), Vec2(inf, 0)}).Problem(), Catch::Contains("not finite"));
}

TEST_CASE("A segment's children resolve only when each measures half of it to 1e-6",
          "[geometry][2d]") {
    CHECK(Segment::Resolves(1, {0.5, 0.5}, 2));
    CHECK(Segment::Resolves(1, {0.5, 0.5 + 4e-7}, 2));
    CHECK_FALSE(Segment::Resolves(1, {0.5, 0.5 + 1e-6}, 2));
    CHECK_FALSE(Segment::Resolves(1, {0, 1}, 2));  // a midpoint that rounded onto an end
    CHECK_FALSE(Segment::Resolves(1, {0.5, std::nan("")}, 2));
    // The element [1, 1 + 2^-52]: its midpoint rounds to 1.
    Segment tiny{Vec2(1, 0), Vec2(1 + std::ldexp(1.0, -52), 0)};
    std::array<Segment, 4> c;
    tiny.Subdivide(Subdivision::Binary, c);
    CHECK_FALSE(Segment::Resolves(tiny.Measure(), {c[0].Measure(), c[1].Measure()}, 2));
}

// ---------------------------------------------------------------------------------------
// Polygons (3D)

TEST_CASE("Polygons report area, centroid and front normal", "[geometry][3d]") {
    STATIC_REQUIRE(Polygon::kDimension == 3);
    SECTION("unit square") {
        Polygon p = UnitSquare();
        CHECK(p.Area() == 1);
        CHECK(p.Measure() == 1);
        CHECK(p.Centroid().isApprox(Vec3(0.5, 0.5, 0)));
        CHECK(p.Normal() == Vec3(0, 0, 1));
    }
    SECTION("trapezoid: the area centroid, not the mean of the corners") {
        // Corners (0,0) (4,0) (3,1) (1,1): area 3, centroid y = (1/3)(4 + 2*2)/(4 + 2) = 4/9.
        Polygon p = Polygon::Quad({0, 0, 0}, {4, 0, 0}, {3, 1, 0}, {1, 1, 0});
        CHECK_THAT(p.Area(), WithinRel(3.0, 1e-15));
        CHECK_THAT(p.Centroid().y(), WithinRel(4.0 / 9, 1e-15));
        CHECK_THAT(p.Centroid().x(), WithinRel(2.0, 1e-15));
    }
    SECTION("parallelogram: the midpoint of the diagonal, exact for dyadic corners") {
        // The area-weighted form rounds (a + 2b) / 3 and (2a + b) / 3, and gives
        // 130.93749999999997 and 641.7441406249999 for these x; the midpoint is exact.
        Polygon p =
            Polygon::Quad({76.8125, 340908, 1}, {185.0625, 340908, 1},
                          {185.0625, 340908.5146484375, 1}, {76.8125, 340908.5146484375, 1});
        CHECK(p.Centroid() == Vec3(130.9375, 340908.25732421875, 1));
        Polygon q =
            Polygon::Quad({159.744140625, 6551.2890625, 0}, {1123.744140625, 6551.2890625, 0},
                          {1123.744140625, 6752.7890625, 0}, {159.744140625, 6752.7890625, 0});
        CHECK(q.Centroid() == Vec3(641.744140625, 6652.0390625, 0));
    }
    SECTION("triangle facing -z when listed clockwise from above") {
        Polygon t = Polygon::Triangle({0, 0, 0}, {0, 2, 0}, {2, 0, 0});
        CHECK(t.Area() == 2);
        CHECK(t.Normal() == Vec3(0, 0, -1));
        CHECK(t.Centroid().isApprox(Vec3(2.0 / 3, 2.0 / 3, 0)));
    }
}

TEST_CASE("A polygon's squared area is |V|^2 / 4 of its area vector V, in a stated order",
          "[geometry][3d]") {
    SECTION("hand-computed: the square root merges two squared areas one ulp apart") {
        // V = (0, 0, 2) for the first triangle: A^2 = 1. For the second, (v1 - v0) x
        // (v2 - v0) = (0, 1, 2^-26) x (2, 0, 0) = (0, 2^-25, -2): A^2 = (4 + 2^-50) / 4 =
        // 1 + 2^-52 exactly, whose square root is 1.
        Polygon flat = Polygon::Triangle({0, 0, 0}, {2, 0, 0}, {0, 1, 0});
        Polygon tilted = Polygon::Triangle({0, 0, 1}, {0, 1, 1 + 0x1p-26}, {2, 0, 1});
        CHECK(flat.AreaVector() == Vec3(0, 0, 2));
        CHECK(tilted.AreaVector() == Vec3(0, 0x1p-25, -2));
        CHECK(flat.SquaredArea() == 1);
        CHECK(tilted.SquaredArea() == std::nextafter(1.0, 2.0));
        CHECK(tilted.SquaredMeasure() == tilted.SquaredArea());
        CHECK(tilted.Area() == 1);
        CHECK(tilted.Area() == flat.Area());
        CHECK(0.5 * tilted.AreaVector().norm() == 1);  // the former formula merges them too
    }
    SECTION("random triangles and quads: the stated order is Eigen's, and A = |V| / 2") {
        std::mt19937_64 rng(11);
        std::uniform_real_distribution<double> u(-1e3, 1e3), e(-60, 60);
        for (int k = 0; k < 100000; ++k) {
            double scale = std::ldexp(1.0, int(e(rng)));
            Vec3 a = Vec3(u(rng), u(rng), u(rng)) * scale, b = Vec3(u(rng), u(rng), u(rng)) * scale,
                 c = Vec3(u(rng), u(rng), u(rng)) * scale, d = Vec3(u(rng), u(rng), u(rng)) * scale;
            Polygon p = k % 2 ? Polygon::Triangle(a, b, c) : Polygon::Quad(a, b, c, d);
            Vec3 eigen = k % 2 ? (b - a).cross(c - a) : (c - a).cross(d - b);
            Vec3 v = p.AreaVector();
            REQUIRE(v == eigen);
            REQUIRE(p.SquaredArea() == (v.x() * v.x() + v.y() * v.y() + v.z() * v.z()) / 4);
            REQUIRE(p.SquaredArea() * 4 == v.squaredNorm());
            // Equal to the former 0.5 |V| while A^2 is a normal double (it is here).
            REQUIRE(p.Area() == 0.5 * v.norm());
            REQUIRE(p.Measure() == std::sqrt(p.SquaredMeasure()));
        }
    }
}

TEST_CASE("Invalid polygons are named with what is wrong", "[geometry][3d]") {
    CHECK(UnitSquare().Problem().empty());
    CHECK_THAT(Polygon::Quad({0, 0, 0}, {1, 0, 0}, {1, 1, 0.1}, {0, 1, 0}).Problem(),
               Catch::Contains("not planar"));
    CHECK_THAT(Polygon::Quad({0, 0, 0}, {1, 0, 0}, {0.2, 0.2, 0}, {0, 1, 0}).Problem(),
               Catch::Contains("not a convex quad"));
    CHECK_THAT(Polygon::Quad({0, 0, 0}, {1, 1, 0}, {1, 0, 0}, {0, 1, 0}).Problem(),
               Catch::Contains("self-intersecting"));  // a bow tie
    CHECK_THAT(Polygon::Triangle({0, 0, 0}, {1, 1, 1}, {2, 2, 2}).Problem(),
               Catch::Contains("degenerate"));
    CHECK_THAT(Polygon::Triangle({0, 0, 0}, {0, 0, 0}, {0, 0, 0}).Problem(),
               Catch::Contains("degenerate"));
    double nan = std::numeric_limits<double>::quiet_NaN();
    double inf = std::numeric_limits<double>::infinity();
    CHECK_THAT(Polygon::Triangle({0, 0, 0}, {1, 0, nan}, {0, 1, 0}).Problem(),
               Catch::Contains("not finite"));
    CHECK_THAT(Polygon::Triangle({0, 0, 0}, {inf, 0, 0}, {0, 1, 0}).Problem(),
               Catch::Contains("not finite"));
}

TEST_CASE("Binary subdivision cuts across the longer edges, first child at v0", "[geometry][3d]") {
    std::array<Polygon, 4> c;
    SECTION("a square ties and halves v0v1 (x) first, then y") {
        REQUIRE(UnitSquare().Subdivide(Subdivision::Binary, c) == 2);
        CHECK(c[0].v[0] == Vec3(0, 0, 0));
        CHECK(c[0].v[1] == Vec3(0.5, 0, 0));
        CHECK(c[0].v[2] == Vec3(0.5, 1, 0));
        CHECK(c[0].v[3] == Vec3(0, 1, 0));
        CHECK(c[1].v[0] == Vec3(0.5, 0, 0));
        CHECK(c[1].v[1] == Vec3(1, 0, 0));
        CHECK(c[0].Area() == 0.5);
        CHECK(c[1].Normal() == Vec3(0, 0, 1));
        std::array<Polygon, 4> g;
        c[0].Subdivide(Subdivision::Binary, g);  // 0.5 x 1: now the y edges are longer
        CHECK(g[0].v[2] == Vec3(0.5, 0.5, 0));
        CHECK(g[0].v[3] == Vec3(0, 0.5, 0));
        CHECK(g[1].v[0] == Vec3(0, 0.5, 0));
        CHECK(g[0].Area() == 0.25);
    }
    SECTION("a rectangle long in y is halved in y, the half with v0 first") {
        Polygon p = Polygon::Quad({0, 0, 0}, {1, 0, 0}, {1, 4, 0}, {0, 4, 0});
        p.Subdivide(Subdivision::Binary, c);
        CHECK(c[0].v[2] == Vec3(1, 2, 0));
        CHECK(c[0].v[3] == Vec3(0, 2, 0));
        CHECK(c[1].v[0] == Vec3(0, 2, 0));
        CHECK(c[1].v[3] == Vec3(0, 4, 0));
    }
    SECTION("a triangle is halved at its longest edge, keeping its lower corner first") {
        // Longest edge v1v2: the first child keeps v1.
        Polygon t = Polygon::Triangle({0, 0, 0}, {2, 0, 0}, {0, 2, 0});
        t.Subdivide(Subdivision::Binary, c);
        CHECK(c[0].v[0] == Vec3(0, 0, 0));
        CHECK(c[0].v[1] == Vec3(2, 0, 0));
        CHECK(c[0].v[2] == Vec3(1, 1, 0));
        CHECK(c[1].v[1] == Vec3(1, 1, 0));
        CHECK(c[1].v[2] == Vec3(0, 2, 0));
        CHECK(c[0].Area() == 1);
        CHECK(c[1].Area() == 1);
        CHECK(c[0].Normal() == Vec3(0, 0, 1));
        CHECK(c[1].Normal() == Vec3(0, 0, 1));
    }
    SECTION("equilateral ties go to the first edge v0v1") {
        Polygon t = Polygon::Triangle({0, 0, 0}, {2, 0, 0}, {1, std::sqrt(3.0), 0});
        t.Subdivide(Subdivision::Binary, c);
        CHECK(c[0].v[1] == Vec3(1, 0, 0));
        CHECK(c[1].v[0] == Vec3(1, 0, 0));
    }
}

TEST_CASE("Quadtree subdivision makes four children in corner order", "[geometry][3d]") {
    std::array<Polygon, 4> c;
    REQUIRE(UnitSquare().Subdivide(Subdivision::Quadtree, c) == 4);
    CHECK(c[0].v[0] == Vec3(0, 0, 0));
    CHECK(c[1].v[1] == Vec3(1, 0, 0));
    CHECK(c[2].v[2] == Vec3(1, 1, 0));
    CHECK(c[3].v[3] == Vec3(0, 1, 0));
    for (int k = 0; k < 4; ++k) {
        CHECK(c[k].Area() == 0.25);
        CHECK(c[k].Normal() == Vec3(0, 0, 1));
    }
    Polygon t = Polygon::Triangle({0, 0, 0}, {4, 0, 0}, {0, 4, 0});
    REQUIRE(t.Subdivide(Subdivision::Quadtree, c) == 4);
    for (int k = 0; k < 4; ++k) {
        CHECK(c[k].Area() == 2);
        CHECK(c[k].Normal() == Vec3(0, 0, 1));
    }
    CHECK(c[3].Centroid().isApprox(t.Centroid()));  // the middle child last
}

TEST_CASE("Sample points are k x k, inside the polygon, with its centroid as their mean",
          "[geometry][3d][visibility]") {
    for (Polygon p : {UnitSquare(), Polygon::Triangle({0, 0, 0}, {3, 0, 0}, {0, 3, 1}),
                      Polygon::Quad({0, 0, 0}, {2, 0, 0}, {2, 1, 1}, {0, 1, 1})}) {
        for (int k : {1, 2, 3, 5}) {
            std::vector<Vec3> points;
            p.SamplePoints(k, points);
            REQUIRE(points.size() == size_t(k * k));
            Vec3 mean = std::accumulate(points.begin(), points.end(), Vec3(0, 0, 0)) / (k * k);
            CHECK((mean - p.Centroid()).norm() < 1e-12);  // parallelograms and triangles
            for (const Vec3 &x : points)                  // in the plane
                CHECK(std::abs((x - p.v[0]).dot(p.Normal())) < 1e-12);
        }
    }
    std::vector<Vec3> two;
    UnitSquare().SamplePoints(2, two);
    CHECK(two[0] == Vec3(0.25, 0.25, 0));
    CHECK(two[1] == Vec3(0.75, 0.25, 0));
    CHECK(two[2] == Vec3(0.25, 0.75, 0));
}

TEST_CASE("A polygon's children resolve only when positive and adding up to it to 1e-6",
          "[geometry][3d]") {
    CHECK(Polygon::Resolves(1, {0.5, 0.5}, 2));
    CHECK(Polygon::Resolves(1, {0.25, 0.25, 0.25, 0.25}, 4));
    CHECK(Polygon::Resolves(1, {0.3, 0.7}, 2));    // unequal halves of a trapezoid
    CHECK_FALSE(Polygon::Resolves(1, {0, 1}, 2));  // a child without area
    CHECK_FALSE(Polygon::Resolves(1, {0.5, 0.5 + 2e-6}, 2));
    CHECK_FALSE(Polygon::Resolves(1, {0.25, 0.25, 0.25, 0}, 4));
    CHECK_FALSE(Polygon::Resolves(1, {0.5, std::nan("")}, 2));
}

// ---------------------------------------------------------------------------------------
// Both shapes

TEMPLATE_TEST_CASE("Children cover their parent: measures add up, centroids average to it",
                   "[geometry]", Segment, Polygon) {
    std::vector<TestType> shapes;
    if constexpr (TestType::kDimension == 2) {
        shapes = {{Vec2(0, 0), Vec2(3, 0)}, {Vec2(-1, 2), Vec2(5, -7)}};
    } else {
        shapes = {UnitSquare(), Polygon::Triangle({0, 0, 0}, {3, 0, 0}, {0, 3, 1}),
                  Polygon::Quad({0, 0, 0}, {4, 0, 0}, {3, 1, 0}, {1, 1, 0})};
    }
    for (Subdivision mode : {Subdivision::Binary, Subdivision::Quadtree}) {
        if (TestType::kDimension == 2 && mode == Subdivision::Quadtree)
            continue;  // segments are only halved
        for (const TestType &s : shapes) {
            INFO(SubdivisionName(mode));
            std::array<TestType, 4> c;
            int n = s.Subdivide(mode, c);
            CHECK(n == SubdivisionArity(mode));
            double measure = 0;
            typename TestType::Vec weighted = TestType::Vec::Zero();
            std::array<double, 4> measures{};
            for (int k = 0; k < n; ++k) {
                measures[k] = c[k].Measure();
                measure += measures[k];
                weighted += c[k].Measure() * c[k].Centroid();
                CHECK(c[k].Normal().isApprox(s.Normal()));
                CHECK(c[k].Problem().empty());
            }
            CHECK_THAT(measure, WithinRel(s.Measure(), 1e-12));
            CHECK(((weighted / measure) - s.Centroid()).norm() < 1e-12);
            CHECK(TestType::Resolves(s.Measure(), measures, n));
        }
    }
}
