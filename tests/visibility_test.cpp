// Visibility: exact segment queries against the scene and sampled visible fractions on
// configurations whose answer is known (a blocker that hides everything, nothing, half).
#include <catch2/catch.hpp>

#include "hrbench/generators/generators.h"
#include "hrbench/hrbench.h"
#include "hrbench/visibility.h"

using namespace hrbench;

namespace {

double Fraction3D(const Scene &scene, int k, uint32_t i = 0, uint32_t j = 1) {
    Occluders occluders(scene.Get<Polygon>());
    Forest<Polygon> forest(scene.Get<Polygon>(), 1000, Subdivision::Binary);
    SampledVisibility<Polygon> visibility(occluders, k, VisibilityMode::Fraction);
    VisibilityTally tally;
    double v = visibility.Fraction(forest, i, j, tally);
    CHECK(tally.queries == 1);
    CHECK(tally.rays == uint64_t(k * k * k * k));
    return v;
}

double Fraction2D(const Scene &scene, int k) {
    Occluders occluders(scene.Get<Segment>());
    Forest<Segment> forest(scene.Get<Segment>(), 1000, Subdivision::Binary);
    SampledVisibility<Segment> visibility(occluders, k, VisibilityMode::Fraction);
    VisibilityTally tally;
    double v = visibility.Fraction(forest, 0, 1, tally);
    CHECK(tally.rays == uint64_t(k * k));
    return v;
}

}  // namespace

TEST_CASE("Visibility modes parse and print their names", "[visibility]") {
    for (const char *name : {"none", "fraction", "refine"})
        CHECK(VisibilityName(ParseVisibility(name)) == name);
    CHECK_THROWS_AS(ParseVisibility("some"), InputError);
}

TEST_CASE("Segments are blocked by third patches only, touching counts", "[visibility]") {
    Scene scene = MakeScene("occluded3d", {});  // blocker [0.25,0.75]^2 at z = 0.5
    Occluders occluders(scene.Get<Polygon>());
    SECTION("through the blocker") {
        CHECK(occluders.Blocked(Vec3(0.5, 0.5, 0), Vec3(0.5, 0.5, 1), 0, 1));
    }
    SECTION("past the blocker") {
        CHECK(!occluders.Blocked(Vec3(0.1, 0.1, 0), Vec3(0.1, 0.1, 1), 0, 1));
    }
    SECTION("grazing its edge is blocked (exact predicates)") {
        CHECK(occluders.Blocked(Vec3(0.25, 0.1, 0), Vec3(0.25, 0.9, 1), 0, 1));
        CHECK(!occluders.Blocked(Vec3(0.2499999, 0.1, 0), Vec3(0.2499999, 0.9, 1), 0, 1));
    }
    SECTION("the segment's own patches are ignored") {
        CHECK(!occluders.Blocked(Vec3(0.5, 0.5, 0.5), Vec3(0.5, 0.5, 1), 3, 1));
        CHECK(occluders.Blocked(Vec3(0.5, 0.5, 0), Vec3(0.5, 0.5, 1), 0, 2));  // 3 still blocks
    }
    SECTION("a patch through an end point does not block (the back of the blocker)") {
        CHECK(!occluders.Blocked(Vec3(0.5, 0.5, 0.5), Vec3(0.5, 0.5, 0), 2, 0));
    }
}

TEST_CASE("A blocker that hides everything gives visible fraction 0", "[visibility]") {
    CHECK(Fraction3D(MakeScene("occluded3d", {{"bl", 10}}), 3) == 0);
    CHECK(Fraction2D(MakeScene("occluded", {{"b", 10}}), 4) == 0);
}

TEST_CASE("A blocker out of the way hides nothing", "[visibility]") {
    CHECK(Fraction3D(MakeScene("occluded3d", {{"ox", 5}}), 3) == 1);
    CHECK(Fraction3D(MakeScene("parallel3d", {}), 2) == 1);  // the plates do not block themselves
    CHECK(Fraction2D(MakeScene("occluded", {{"offset", 5}}), 4) == 1);
}

TEST_CASE("A blocker over half of one plate, close to it, hides exactly half", "[visibility]") {
    // The blocker covers x <= l/2 at height 0.01: a ray from a sample of P at x is blocked
    // iff x < l/2, and k even puts half the samples there.
    Scene s3 = MakeScene("occluded3d", {{"bl", 10}, {"bw", 10}, {"ox", -5}, {"h", 0.01}});
    CHECK(Fraction3D(s3, 2) == 0.5);
    CHECK(Fraction3D(s3, 4) == 0.5);
    Scene s2 = MakeScene("occluded", {{"b", 10}, {"offset", -5}, {"h", 0.01}});
    CHECK(Fraction2D(s2, 2) == 0.5);
    CHECK(Fraction2D(s2, 6) == 0.5);
}

TEST_CASE("A central blocker hides a known share of the sample rays", "[visibility]") {
    // Plates [0,1]^2 at distance 1, blocker [0.225,0.775]^2 at height 0.5: a ray is
    // blocked iff the midpoint of its ends lies in the blocker (no ray grazes its edges).
    Scene scene = MakeScene("occluded3d", {{"bl", 0.55}});
    // k = 2: samples at 1/4 and 3/4 per axis; every midpoint (1/4, 1/2, 3/4) is inside.
    CHECK(Fraction3D(scene, 2) == 0);
    // k = 4: samples at (2i+1)/8, midpoints (i+j+1)/8; inside iff 1 <= i+j <= 5, which
    // holds for 14 of the 16 pairs per axis.
    CHECK(Fraction3D(scene, 4) == 1 - (14.0 / 16) * (14.0 / 16));
}
