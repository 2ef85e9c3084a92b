// Visibility: exact segment queries against the scene and sampled visible fractions on
// configurations whose answer is known (a blocker that hides everything, nothing, half).
#include <catch2/catch.hpp>

#include <set>

#include "generators.h"
#include "hrbench/hrbench.h"
#include "visibility/visibility.h"

using namespace hrbench;

namespace {

// The backends of this build: CGAL always, Embree where it was found.
std::vector<VisibilityBackend> Backends() {
    if (HasEmbree())
        return {VisibilityBackend::Cgal, VisibilityBackend::Embree};
    return {VisibilityBackend::Cgal};
}

double Fraction3D(const Scene &scene, int k, uint32_t i = 0, uint32_t j = 1,
                  VisibilityBackend backend = VisibilityBackend::Auto) {
    Occluders occluders(scene.Get<Polygon>(), backend);
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
    VisibilityBackend backend = GENERATE(from_range(Backends()));
    CAPTURE(int(backend));
    Occluders occluders(scene.Get<Polygon>(), backend);
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
    for (VisibilityBackend backend : Backends())
        CHECK(Fraction3D(MakeScene("occluded3d", {{"bl", 10}}), 3, 0, 1, backend) == 0);
    CHECK(Fraction2D(MakeScene("occluded", {{"b", 10}}), 4) == 0);
}

TEST_CASE("A blocker out of the way hides nothing", "[visibility]") {
    for (VisibilityBackend backend : Backends()) {
        CHECK(Fraction3D(MakeScene("occluded3d", {{"ox", 5}}), 3, 0, 1, backend) == 1);
        // the plates do not block themselves
        CHECK(Fraction3D(MakeScene("parallel3d", {}), 2, 0, 1, backend) == 1);
    }
    CHECK(Fraction2D(MakeScene("occluded", {{"offset", 5}}), 4) == 1);
}

TEST_CASE("A blocker over half of one plate, close to it, hides exactly half", "[visibility]") {
    // The blocker covers x <= l/2 at height 0.01: a ray from a sample of P at x is blocked
    // iff x < l/2, and k even puts half the samples there.
    Scene s3 = MakeScene("occluded3d", {{"bl", 10}, {"bw", 10}, {"ox", -5}, {"h", 0.01}});
    for (VisibilityBackend backend : Backends()) {
        CHECK(Fraction3D(s3, 2, 0, 1, backend) == 0.5);
        CHECK(Fraction3D(s3, 4, 0, 1, backend) == 0.5);
    }
    Scene s2 = MakeScene("occluded", {{"b", 10}, {"offset", -5}, {"h", 0.01}});
    CHECK(Fraction2D(s2, 2) == 0.5);
    CHECK(Fraction2D(s2, 6) == 0.5);
}

TEST_CASE("A central blocker hides a known share of the sample rays", "[visibility]") {
    // Plates [0,1]^2 at distance 1, blocker [0.225,0.775]^2 at height 0.5: a ray is
    // blocked iff the midpoint of its ends lies in the blocker (no ray grazes its edges).
    Scene scene = MakeScene("occluded3d", {{"bl", 0.55}});
    for (VisibilityBackend backend : Backends()) {
        // k = 2: samples at 1/4 and 3/4 per axis; every midpoint (1/4, 1/2, 3/4) is inside.
        CHECK(Fraction3D(scene, 2, 0, 1, backend) == 0);
        // k = 4: samples at (2i+1)/8, midpoints (i+j+1)/8; inside iff 1 <= i+j <= 5, which
        // holds for 14 of the 16 pairs per axis.
        CHECK(Fraction3D(scene, 4, 0, 1, backend) == 1 - (14.0 / 16) * (14.0 / 16));
    }
}

TEST_CASE("Embree and CGAL agree ray for ray on the Cornell box", "[visibility][embree]") {
    if (!HasEmbree())
        return;
    // Every root pair, 8 x 8 samples per patch: 4096 rays per pair, many of them
    // grazing the blocks' edges or leaving the light, which lies in the ceiling.
    Scene scene = MakeScene("cornell", {});
    const auto &patches = scene.Get<Polygon>();
    Occluders cgal(patches, VisibilityBackend::Cgal), embree(patches, VisibilityBackend::Embree);
    std::vector<Vec3> from, to;
    uint64_t rays = 0;
    for (uint32_t p = 0; p < patches.size(); ++p)
        for (uint32_t q = p + 1; q < patches.size(); ++q) {
            from.clear(), to.clear();
            patches[p].shape.SamplePoints(8, from);
            patches[q].shape.SamplePoints(8, to);
            for (const Vec3 &a : from)
                for (const Vec3 &b : to) {
                    REQUIRE(cgal.Blocked(a, b, p, q) == embree.Blocked(a, b, p, q));
                    ++rays;
                }
            CHECK(cgal.CountVisible(from, to, p, q) == embree.CountVisible(from, to, p, q));
        }
    CHECK(rays == 136 * 4096);
}

TEST_CASE("Visibility counts do not depend on the thread count", "[visibility][embree]") {
    RefineOptions o;
    o.oracle = "hanrahan", o.eps = 0.05, o.minArea = 1e-3, o.visibility = VisibilityMode::Fraction;
    Scene scene = MakeScene("cornell", {});
    Counters one = Refine<Polygon>(scene, o).record.counters;
    o.threads = 2;
    Counters two = Refine<Polygon>(scene, o).record.counters;
    CHECK(one.rays > 0);
    CHECK(one.rays == two.rays);
    CHECK(one.visibilityQueries == two.visibilityQueries);
    CHECK(one.occludedPairs == two.occludedPairs);
    CHECK(one.links == two.links);
    CHECK(one.nodes == two.nodes);
}

TEST_CASE("Samples kept from the last query are those a fresh query takes", "[visibility][3d]") {
    // The occluded plates, split two levels deep: pairs of elements that the blocker
    // hides to different degrees, queried in an order where i repeats, j repeats, both
    // change and the two swap, against a fresh policy for every query.
    Scene scene = MakeScene("occluded3d", {});
    Occluders occluders(scene.Get<Polygon>());
    Forest<Polygon> forest(scene.Get<Polygon>(), 1000, Subdivision::Binary);
    uint32_t p = forest.Children(0), q = forest.Children(1);
    uint32_t pp = forest.Children(p), qq = forest.Children(q + 1);
    std::vector<std::pair<uint32_t, uint32_t>> pairs = {
        {p, q},       {p, q + 1},       {p + 1, q + 1},   {pp, q + 1},      {pp + 1, q + 1},
        {pp + 1, qq}, {pp + 1, qq + 1}, {qq + 1, pp + 1}, {pp + 1, qq + 1}, {p, q},
        {0, 1}};
    SampledVisibility<Polygon> kept(occluders, 3, VisibilityMode::Fraction);
    VisibilityTally keptTally, freshTally;
    std::set<double> seen;
    for (auto [i, j] : pairs) {
        INFO("pair " << i << ", " << j);
        SampledVisibility<Polygon> fresh(occluders, 3, VisibilityMode::Fraction);
        double v = kept.Fraction(forest, i, j, keptTally);
        CHECK(v == fresh.Fraction(forest, i, j, freshTally));
        seen.insert(v);
    }
    CHECK(keptTally.rays == freshTally.rays);
    CHECK(seen.size() >= 3);  // the pairs differ, so stale samples would show

    // Another forest, whose elements 0 and 1 lie elsewhere, is not served from the first.
    Scene moved = MakeScene("parallel3d", {{"ox", 1.5}});
    Forest<Polygon> other(moved.Get<Polygon>(), 1000, Subdivision::Binary);
    SampledVisibility<Polygon> fresh(occluders, 3, VisibilityMode::Fraction);
    double elsewhere = fresh.Fraction(other, 0, 1, freshTally);
    REQUIRE(elsewhere != kept.Fraction(forest, 0, 1, keptTally));
    CHECK(kept.Fraction(other, 0, 1, keptTally) == elsewhere);
}
