// Root-pair classification with exact predicates, in 2D and 3D.
#include <catch2/catch.hpp>

#include "hrbench/generators/generators.h"
#include "hrbench/hrbench.h"

using namespace hrbench;

static Segment S(double ax, double ay, double bx, double by) {
    return {Vec2(ax, ay), Vec2(bx, by)};
}

TEST_CASE("Root pairs are culled, touching or interacting as docs/conventions.md defines",
          "[culling][2d]") {
    SECTION("facing plates interact") {
        CHECK(ClassifyPair(S(0, 0, 1, 0), S(1, 1, 0, 1)) == PairRelation::Interacting);
    }
    SECTION("collinear plates are culled") {
        CHECK(ClassifyPair(S(0, 0, 1, 0), S(2, 0, 3, 0)) == PairRelation::Culled);
    }
    SECTION("plates facing away from each other are culled") {
        CHECK(ClassifyPair(S(1, 0, 0, 0), S(0, 1, 1, 1)) == PairRelation::Culled);
    }
    SECTION("a plate wholly behind the other's line is culled even if it faces it") {
        CHECK(ClassifyPair(S(0, 0, 1, 0), S(1, -1, 0, -2)) == PairRelation::Culled);
    }
    SECTION("a plate lying partly in front interacts") {
        CHECK(ClassifyPair(S(0, 0, 1, 0), S(2, -1, 2, 1)) == PairRelation::Interacting);
    }
    SECTION("plates meeting at a corner touch") {
        CHECK(ClassifyPair(S(0, 0, 1, 0), S(0, 1, 0, 0)) == PairRelation::Touching);
    }
    SECTION("crossing plates touch") {
        CHECK(ClassifyPair(S(-1, 0, 1, 0), S(0, -1, 0, 1)) == PairRelation::Touching);
    }
    SECTION("the decision is exact for a point a rounding error off the line") {
        double y = 1e-300;
        CHECK(ClassifyPair(S(0, 0, 1, 0), S(1, y, 0, y)) == PairRelation::Interacting);
    }
}

TEST_CASE("3D root pairs are culled when coplanar or back-facing, and touching is found",
          "[culling][3d]") {
    Polygon floor = Polygon::Quad({0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0});
    SECTION("facing plates interact") {
        const Patches<Polygon> s = MakeScene("parallel3d", {}).Get<Polygon>();
        CHECK(ClassifyPair(s[0].shape, s[1].shape) == PairRelation::Interacting);
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
        const Patches<Polygon> s = MakeScene("perpendicular3d", {{"gap", 0}}).Get<Polygon>();
        CHECK(ClassifyPair(s[0].shape, s[1].shape) == PairRelation::Touching);
        const Patches<Polygon> g = MakeScene("perpendicular3d", {{"gap", 0.1}}).Get<Polygon>();
        CHECK(ClassifyPair(g[0].shape, g[1].shape) == PairRelation::Interacting);
    }
}
