// 3D patches: measures, validation, subdivision order, sample points, element trees,
// the 3D oracles and root-pair culling.
#include <catch2/catch.hpp>

#include <numeric>

#include "generators.h"
#include "hrbench.h"
#include "oracles.h"
#include "oracles3d.h"
#include "polygon_forest.h"

using namespace hrbench;
using Catch::Matchers::WithinAbs;
using Catch::Matchers::WithinRel;

namespace {

Polygon UnitSquare() { return Polygon::Quad({0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}); }

Scene SceneOf(std::vector<Polygon> polygons) {
    Scene scene;
    scene.dimension = 3;
    for (const Polygon &p : polygons)
        scene.faces.push_back({p, {}});
    return scene;
}

}  // namespace

TEST_CASE("Polygons report area, centroid and front normal", "[3d]") {
    SECTION("unit square") {
        Polygon p = UnitSquare();
        CHECK(p.Area() == 1);
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
    SECTION("triangle facing -z when listed clockwise from above") {
        Polygon t = Polygon::Triangle({0, 0, 0}, {0, 2, 0}, {2, 0, 0});
        CHECK(t.Area() == 2);
        CHECK(t.Normal() == Vec3(0, 0, -1));
        CHECK(t.Centroid().isApprox(Vec3(2.0 / 3, 2.0 / 3, 0)));
    }
}

TEST_CASE("Invalid polygons are named with what is wrong", "[3d]") {
    CHECK(PolygonProblem(UnitSquare()).empty());
    CHECK_THAT(PolygonProblem(Polygon::Quad({0, 0, 0}, {1, 0, 0}, {1, 1, 0.1}, {0, 1, 0})),
               Catch::Contains("not planar"));
    CHECK_THAT(PolygonProblem(Polygon::Quad({0, 0, 0}, {1, 0, 0}, {0.2, 0.2, 0}, {0, 1, 0})),
               Catch::Contains("not a convex quad"));
    CHECK_THAT(PolygonProblem(Polygon::Quad({0, 0, 0}, {1, 1, 0}, {1, 0, 0}, {0, 1, 0})),
               Catch::Contains("self-intersecting"));  // a bow tie
    CHECK_THAT(PolygonProblem(Polygon::Triangle({0, 0, 0}, {1, 1, 1}, {2, 2, 2})),
               Catch::Contains("degenerate"));
    CHECK_THAT(PolygonProblem(Polygon::Triangle({0, 0, 0}, {0, 0, 0}, {0, 0, 0})),
               Catch::Contains("degenerate"));
    double nan = std::numeric_limits<double>::quiet_NaN();
    double inf = std::numeric_limits<double>::infinity();
    CHECK_THAT(PolygonProblem(Polygon::Triangle({0, 0, 0}, {1, 0, nan}, {0, 1, 0})),
               Catch::Contains("not finite"));
    CHECK_THAT(PolygonProblem(Polygon::Triangle({0, 0, 0}, {inf, 0, 0}, {0, 1, 0})),
               Catch::Contains("not finite"));
}

TEST_CASE("Binary subdivision cuts across the longer edges, first child at v0", "[3d]") {
    std::array<Polygon, 4> c;
    SECTION("a square ties and halves v0v1 (x) first, then y") {
        REQUIRE(Subdivide(UnitSquare(), Subdivision::Binary, c) == 2);
        CHECK(c[0].v[0] == Vec3(0, 0, 0));
        CHECK(c[0].v[1] == Vec3(0.5, 0, 0));
        CHECK(c[0].v[2] == Vec3(0.5, 1, 0));
        CHECK(c[0].v[3] == Vec3(0, 1, 0));
        CHECK(c[1].v[0] == Vec3(0.5, 0, 0));
        CHECK(c[1].v[1] == Vec3(1, 0, 0));
        CHECK(c[0].Area() == 0.5);
        CHECK(c[1].Normal() == Vec3(0, 0, 1));
        std::array<Polygon, 4> g;
        Subdivide(c[0], Subdivision::Binary, g);  // 0.5 x 1: now the y edges are longer
        CHECK(g[0].v[2] == Vec3(0.5, 0.5, 0));
        CHECK(g[0].v[3] == Vec3(0, 0.5, 0));
        CHECK(g[1].v[0] == Vec3(0, 0.5, 0));
        CHECK(g[0].Area() == 0.25);
    }
    SECTION("a rectangle long in y is halved in y, the half with v0 first") {
        Polygon p = Polygon::Quad({0, 0, 0}, {1, 0, 0}, {1, 4, 0}, {0, 4, 0});
        Subdivide(p, Subdivision::Binary, c);
        CHECK(c[0].v[2] == Vec3(1, 2, 0));
        CHECK(c[0].v[3] == Vec3(0, 2, 0));
        CHECK(c[1].v[0] == Vec3(0, 2, 0));
        CHECK(c[1].v[3] == Vec3(0, 4, 0));
    }
    SECTION("a triangle is halved at its longest edge, keeping its lower corner first") {
        // Longest edge v1v2: the first child keeps v1.
        Polygon t = Polygon::Triangle({0, 0, 0}, {2, 0, 0}, {0, 2, 0});
        Subdivide(t, Subdivision::Binary, c);
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
        Subdivide(t, Subdivision::Binary, c);
        CHECK(c[0].v[1] == Vec3(1, 0, 0));
        CHECK(c[1].v[0] == Vec3(1, 0, 0));
    }
}

TEST_CASE("Quadtree subdivision makes four children in corner order", "[3d]") {
    std::array<Polygon, 4> c;
    REQUIRE(Subdivide(UnitSquare(), Subdivision::Quadtree, c) == 4);
    CHECK(c[0].v[0] == Vec3(0, 0, 0));
    CHECK(c[1].v[1] == Vec3(1, 0, 0));
    CHECK(c[2].v[2] == Vec3(1, 1, 0));
    CHECK(c[3].v[3] == Vec3(0, 1, 0));
    for (int k = 0; k < 4; ++k) {
        CHECK(c[k].Area() == 0.25);
        CHECK(c[k].Normal() == Vec3(0, 0, 1));
    }
    Polygon t = Polygon::Triangle({0, 0, 0}, {4, 0, 0}, {0, 4, 0});
    REQUIRE(Subdivide(t, Subdivision::Quadtree, c) == 4);
    for (int k = 0; k < 4; ++k) {
        CHECK(c[k].Area() == 2);
        CHECK(c[k].Normal() == Vec3(0, 0, 1));
    }
    CHECK(c[3].Centroid().isApprox(t.Centroid()));  // the middle child last
}

TEST_CASE("Sample points are k x k, inside the polygon, with its centroid as their mean",
          "[3d][visibility]") {
    for (Polygon p : {UnitSquare(), Polygon::Triangle({0, 0, 0}, {3, 0, 0}, {0, 3, 1}),
                      Polygon::Quad({0, 0, 0}, {2, 0, 0}, {2, 1, 1}, {0, 1, 1})}) {
        for (int k : {1, 2, 3, 5}) {
            std::vector<Vec3> points;
            SamplePoints(p, k, points);
            REQUIRE(points.size() == size_t(k * k));
            Vec3 mean = std::accumulate(points.begin(), points.end(), Vec3(0, 0, 0)) / (k * k);
            CHECK((mean - p.Centroid()).norm() < 1e-12);  // parallelograms and triangles
            for (const Vec3 &x : points)  // in the plane
                CHECK(std::abs((x - p.v[0]).dot(p.Normal())) < 1e-12);
        }
    }
    std::vector<Vec3> two;
    SamplePoints(UnitSquare(), 2, two);
    CHECK(two[0] == Vec3(0.25, 0.25, 0));
    CHECK(two[1] == Vec3(0.75, 0.25, 0));
    CHECK(two[2] == Vec3(0.25, 0.75, 0));
}

TEST_CASE("Polygon forests create children once, first child first", "[3d]") {
    Scene scene = SceneOf({UnitSquare(), Polygon::Triangle({0, 0, 1}, {0, 1, 1}, {1, 0, 1})});
    SECTION("binary") {
        BinaryPolygonForest f(scene, 1000);
        STATIC_REQUIRE(BinaryPolygonForest::kArity == 2);
        REQUIRE(f.Size() == 2);
        CHECK(f[0].size == 1);
        CHECK(f[1].size == 0.5);
        uint32_t c = f.Children(0);
        CHECK(c == 2);
        CHECK(f.Children(0) == 2);  // shared
        CHECK(f.Size() == 4);
        CHECK(f[2].size == 0.5);
        CHECK(f[2].center.isApprox(Vec3(0.25, 0.5, 0)));
        CHECK(f[3].root == 0);
        CHECK(f.Parent(3) == 0);
        CHECK(f.Depth(3) == 1);
        CHECK(f.Children(1) == 4);
        CHECK(f[4].root == 1);
        CHECK(f.NumLeaves() == 4);
        CHECK(f.NodesPerDepth() == std::vector<uint64_t>{2, 4});
    }
    SECTION("quadtree") {
        QuadtreePolygonForest f(scene, 1000);
        STATIC_REQUIRE(QuadtreePolygonForest::kArity == 4);
        CHECK(f.Children(1) == 2);
        CHECK(f.Size() == 6);
        CHECK(f[5].size == 0.125);
        CHECK(f.NumLeaves() == 5);
    }
    SECTION("the memory budget is enforced") {
        BinaryPolygonForest f(scene, 3);
        CHECK_THROWS_AS(f.Children(0), LimitError);
    }
}

TEST_CASE("The 3D garmann oracle decides max(A_i, A_j) <= eps r^2 exactly", "[3d][oracle]") {
    Element<3> a{Vec3(0, 0, 0), 0.25, kNoChildren, 0}, b{Vec3(0, 0, 2), 1, kNoChildren, 1};
    CHECK(Garmann3DOracle(0.25).Acceptable(a, b));   // 1 <= 0.25 * 4: the tie is accepted
    CHECK(!Garmann3DOracle(0.2499).Acceptable(a, b));
    CHECK(Garmann3DOracle(0.2499).AcceptableVisible(a, b, 0.5));  // 0.5 <= 0.9996
    CHECK(!Garmann3DOracle(0.1).AcceptableVisible(a, b, 0.5));
}

TEST_CASE("The 3D hanrahan oracle estimates both form factors at the centroids",
          "[3d][oracle]") {
    // Directly opposed elements: cosines 1, F = A / (pi r^2 + A).
    std::vector<Vec3> normals{Vec3(0, 0, 1), Vec3(0, 0, -1)};
    Element<3> a{Vec3(0, 0, 0), 1, kNoChildren, 0}, b{Vec3(0, 0, 1), 2, kNoChildren, 1};
    double fAB = 2 / (kOraclePi + 2), fBA = 1 / (kOraclePi + 1);
    CHECK(Hanrahan3DOracle(fAB, normals).Acceptable(a, b));
    CHECK(!Hanrahan3DOracle(fAB * (1 - 1e-9), normals).Acceptable(a, b));
    CHECK(!Hanrahan3DOracle(fBA, normals).Acceptable(a, b));  // F(a<-b) > F(b<-a)
    CHECK(Hanrahan3DOracle(fAB / 2, normals).AcceptableVisible(a, b, 0.5));
    // Facing away: cosines clamped at 0, always acceptable.
    std::vector<Vec3> away{Vec3(0, 0, -1), Vec3(0, 0, 1)};
    CHECK(Hanrahan3DOracle(1e-9, away).Acceptable(a, b));
}

TEST_CASE("The weighted 2D oracles decide as the plain ones when all is visible",
          "[3d][oracle]") {
    // Pairs near the threshold of the worked example and elsewhere.
    Scene scene = MakeScene("angled", {{"angle", 50}});
    std::vector<Vec2> normals{scene.segments[0].Normal(), scene.segments[1].Normal()};
    GarmannOracle g(0.25);
    GarmannOracleND<2> g2(0.25);
    HanrahanOracle h(0.05, normals);
    HanrahanOracleND<2> h2(0.05, normals);
    int disagreements = 0, accepted = 0;
    for (int a = 0; a < 40; ++a)
        for (int b = 0; b < 40; ++b) {
            Element<2> ei{Vec2(a * 0.1, 0), 0.05 * (1 + a % 7), kNoChildren, 0};
            Element<2> ej{Vec2(b * 0.07, 1 + b * 0.03), 0.05 * (1 + b % 5), kNoChildren, 1};
            disagreements += g.Acceptable(ei, ej) != g2.Acceptable(ei, ej);
            disagreements += h.Acceptable(ei, ej) != h2.Acceptable(ei, ej);
            accepted += g.Acceptable(ei, ej) + h.Acceptable(ei, ej);
        }
    CHECK(disagreements == 0);
    CHECK(accepted > 100);  // not trivial
    CHECK(accepted < 3000);
}

TEST_CASE("3D root pairs are culled when coplanar or back-facing, and touching is found",
          "[3d][culling]") {
    Polygon floor = UnitSquare();
    SECTION("facing plates interact") {
        Scene s = MakeScene("parallel3d", {});
        CHECK(ClassifyPair(s.faces[0].polygon, s.faces[1].polygon) == PairRelation::Interacting);
    }
    SECTION("coplanar plates are culled") {
        Polygon next = Polygon::Quad({2, 0, 0}, {3, 0, 0}, {3, 1, 0}, {2, 1, 0});
        CHECK(ClassifyPair(floor, next) == PairRelation::Culled);
    }
    SECTION("plates facing away from each other are culled") {
        Polygon above = Polygon::Quad({0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1});  // faces +z
        CHECK(ClassifyPair(floor, above) == PairRelation::Culled);
    }
    SECTION("a plate behind the other's plane is culled") {
        Polygon below = Polygon::Quad({0, 1, -1}, {1, 1, -1}, {1, 0, -1}, {0, 0, -1});
        CHECK(ClassifyPair(floor, below) == PairRelation::Culled);
    }
    SECTION("perpendicular plates touch without a gap") {
        Scene s = MakeScene("perpendicular3d", {{"gap", 0}});
        CHECK(ClassifyPair(s.faces[0].polygon, s.faces[1].polygon) == PairRelation::Touching);
        Scene g = MakeScene("perpendicular3d", {{"gap", 0.1}});
        CHECK(ClassifyPair(g.faces[0].polygon, g.faces[1].polygon) == PairRelation::Interacting);
    }
}
