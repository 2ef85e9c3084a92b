// The translation method in 3D (`parallel3d`) against direct enumeration: every
// counter and histogram must be identical wherever both run, ties included.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>

#include "count/translation_count.h"
#include "generators.h"
#include "hrbench/hrbench.h"
#include "refinement_helpers.h"

using namespace hrbench;
using hrbench_test::CounterDifferences;

namespace {

RefineOptions CountOnly(double eps, Subdivision mode = Subdivision::Binary) {
    RefineOptions o;
    o.eps = eps;
    o.storeLinks = false;
    o.subdivision = mode;
    return o;
}

Scene Plates(double l, double w, double d) {
    return MakeScene("parallel3d", {{"l", l}, {"w", w}, {"d", d}});
}

// Refine() and CountByTranslation() on one configuration: "" if every counter agrees.
std::string Differences(const Scene &scene, const RefineOptions &options) {
    Refinement<Polygon> r = Refine<Polygon>(scene, options);
    TranslationCount t = CountByTranslation(scene, options);
    return CounterDifferences(r.record.counters, t.record.counters);
}

}  // namespace

TEST_CASE("The translation method in 3D agrees exactly with enumeration", "[translation][3d]") {
    SECTION("on a grid of sides, distances, thresholds and both subdivisions") {
        int cases = 0;
        for (Subdivision mode : {Subdivision::Binary, Subdivision::Quadtree})
            for (double l : {1.0, 3.0, 0.75, 2.0})
                for (double w : {l, l / 2, 1.25 * l})
                    for (double d : {1.0, 0.5, 2.0})
                        for (double eps : {1.0, 0.5, 0.3, 0.25, 0.1}) {
                            INFO("l=" << l << " w=" << w << " d=" << d << " eps=" << eps
                                      << " quadtree=" << (mode == Subdivision::Quadtree));
                            REQUIRE(Differences(Plates(l, w, d), CountOnly(eps, mode)) == "");
                            ++cases;
                        }
        CHECK(cases == 2 * 4 * 3 * 3 * 5);
    }
    SECTION("on larger plates, millions of links") {
        auto [l, w, d, eps, quadtree] = GENERATE(table<double, double, double, double, bool>({
            {8, 8, 1, 0.01, false},
            {8, 8, 1, 0.01, true},
            {3, 5, 0.5, 0.05, false},
            {16, 2, 1, 0.02, false},
        }));
        Scene scene = Plates(l, w, d);
        RefineOptions o = CountOnly(eps, quadtree ? Subdivision::Quadtree : Subdivision::Binary);
        INFO("l=" << l << " w=" << w << " d=" << d << " eps=" << eps << " quadtree=" << quadtree);
        Refinement<Polygon> r = Refine<Polygon>(scene, o);
        CHECK(r.record.counters.links > 100000);
        CHECK(CounterDifferences(r.record.counters, CountByTranslation(scene, o).record.counters) ==
              "");
    }
    SECTION("where ties decide") {
        // 2 x 2 plates at distance 1, eps = 1/4: the elements of depth 4 have area 1/4,
        // and a pair of them one above the other has r^2 = 1, exactly on the threshold
        // (accepted). Below that eps the same pairs are rejected: the counts differ.
        Scene scene = Plates(2, 2, 1);
        RefineOptions tie = CountOnly(0.25), below = CountOnly(std::nextafter(0.25, 0.0));
        CHECK(Differences(scene, tie) == "");
        CHECK(Differences(scene, below) == "");
        CHECK(CountByTranslation(scene, tie).record.counters.links !=
              CountByTranslation(scene, below).record.counters.links);
    }
}

TEST_CASE("The translation method in 3D agrees with enumeration on random dyadic plates",
          "[translation][3d]") {
    // Sides and distances with a few significant bits at any binary scale, thresholds
    // that are not round numbers, either subdivision.
    uint64_t state = 20261124;
    auto next = [&state] {  // SplitMix64: the same sequence on every platform
        uint64_t z = (state += 0x9e3779b97f4a7c15);
        z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9;
        z = (z ^ (z >> 27)) * 0x94d049bb133111eb;
        return z ^ (z >> 31);
    };
    auto uniform = [&](int lo, int hi) { return lo + int(next() % uint64_t(hi - lo + 1)); };
    int nontrivial = 0;
    for (int k = 0; k < 200; ++k) {
        double d = std::ldexp(double(uniform(1, 15)), uniform(-6, 2));
        double l = d * std::ldexp(double(uniform(1, 15)), uniform(-2, 1));
        double w = d * std::ldexp(double(uniform(1, 15)), uniform(-2, 1));
        double eps = 0.02 + 0.98 * double(next() >> 11) * 0x1p-53;
        eps = std::max(eps, l * w / (d * d) / 200);  // keep enumeration small
        Subdivision mode = k % 2 ? Subdivision::Quadtree : Subdivision::Binary;
        INFO("l=" << l << " w=" << w << " d=" << d << " eps=" << eps << " quadtree=" << k % 2);
        Scene scene = Plates(l, w, d);
        Refinement<Polygon> r = Refine<Polygon>(scene, CountOnly(eps, mode));
        REQUIRE(CounterDifferences(
                    r.record.counters,
                    CountByTranslation(scene, CountOnly(eps, mode)).record.counters) == "");
        nontrivial += r.record.counters.links > 100;
    }
    CHECK(nontrivial > 50);
}

TEST_CASE("The translation method in 3D decides ties as the engine", "[translation][3d]") {
    // eps = A_k / r^2 with r^2 = d^2 (a pair one above the other) or 2 d^2 (one apart by
    // d along a side), both exact: the pairs of elements of area A_k at that offset lie
    // on the threshold; one ulp either side must flip them as the engine does.
    int cases = 0, flipped = 0;
    for (double l : {2.0, 4.0})
        for (double d : {1.0, 0.5})
            for (int k = 0; k < 8; ++k)
                for (double r2 : {d * d, 2 * d * d}) {
                    double tie = std::ldexp(l * l, -k) / r2;
                    if (l * l / (d * d) / tie > 2000)  // keep enumeration small
                        continue;
                    uint64_t links[3];
                    for (int side = 0; side < 3; ++side) {
                        double eps = side == 1 ? tie : std::nextafter(tie, side == 0 ? 0 : 1e300);
                        INFO("l=" << l << " d=" << d << " eps=" << eps);
                        REQUIRE(Differences(Plates(l, l, d), CountOnly(eps)) == "");
                        links[side] = CountByTranslation(Plates(l, l, d), CountOnly(eps))
                                          .record.counters.links;
                    }
                    ++cases;
                    flipped += links[0] != links[1];  // the tie decided some pairs
                }
    CHECK(cases == 64);
    CHECK(flipped > 50);  // 58: the tie decided pairs in almost every case
}

TEST_CASE("The translation method in 3D counts beyond 10^18 links", "[translation][3d]") {
    // 1024 x 1024 plates at distance 1, eps = 1e-6: 6.7e18 links, where enumeration at
    // 1e8 oracle calls per second would take four thousand years.
    TranslationCount t = CountByTranslation(Plates(1024, 1024, 1), CountOnly(1e-6));
    const Counters &c = t.record.counters;
    CHECK(c.links == 6725685441400998228u);
    CHECK(c.links >= uint64_t(1e18));
    CHECK(c.oracleCalls == 2 * c.links - 1);
    CHECK(c.leaves == c.nodes / 2 + 1);
    CHECK(c.nodes == 4398046511102u);  // two full trees of depth 40
    CHECK(c.maxDepth == 40);
    // The links tile P x Q: a link of depth n covers 2^-n of it.
    unsigned __int128 covered = 0, sum = 0;
    size_t deepest = c.linksPerDepth.size() - 1;
    for (size_t n = 0; n <= deepest; ++n) {
        covered += (unsigned __int128)c.linksPerDepth[n] << (deepest - n);
        sum += c.linksPerDepth[n];
    }
    CHECK(covered == (unsigned __int128)1 << deepest);
    CHECK(sum == c.links);
    CHECK(t.pairStates < c.nodes);
}

TEST_CASE("The translation method in 3D rejects what it cannot count exactly",
          "[translation][3d][errors]") {
    SECTION("an offset between the plates") {
        Scene shifted = MakeScene("parallel3d", {{"l", 8}, {"d", 1}, {"ox", 0.5}});
        CHECK_THROWS_WITH(CountByTranslation(shifted, CountOnly(0.1)),
                          Catch::Contains("ox = oy = 0"));
    }
    SECTION("another scene") {
        CHECK_THROWS_AS(CountByTranslation(MakeScene("occluded3d", {}), CountOnly(0.1)),
                        InputError);
        CHECK_THROWS_AS(CountByTranslation(MakeScene("perpendicular3d", {}), CountOnly(0.1)),
                        InputError);
    }
    SECTION("store mode") {
        RefineOptions o = CountOnly(0.1);
        o.storeLinks = true;
        CHECK_THROWS_AS(CountByTranslation(Plates(8, 8, 1), o), InputError);
    }
    SECTION("centroids that are not exact in double precision") {
        CHECK_THROWS_WITH(CountByTranslation(Plates(0.1, 1, 1), CountOnly(0.25)),
                          Catch::Contains("not exact"));
        // 2^30 + 1 has 31 significant bits: exact to 20 halvings of a side, which this eps
        // passes at depth 41.
        CHECK_THROWS_WITH(CountByTranslation(Plates(1073741825, 1073741825, 1), CountOnly(0.25)),
                          Catch::Contains("not exact in double precision at depth 41"));
    }
}
