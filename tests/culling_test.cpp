// Root-pair classification with exact predicates.
#include <catch2/catch.hpp>

#include "hrbench.h"

using namespace hrbench;

static Segment S(double ax, double ay, double bx, double by) {
    return {Vec2(ax, ay), Vec2(bx, by), {}};
}

TEST_CASE("Root pairs are culled, touching or interacting as DESIGN section 2 defines",
          "[culling]") {
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
