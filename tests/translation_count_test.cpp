// The translation method against direct enumeration: every counter and histogram
// must be identical wherever both run, ties included.
#include <catch2/catch.hpp>

#include <cmath>
#include <cstdint>
#include <functional>
#include <limits>
#include <sstream>

#include <nlohmann/json.hpp>

#include "cli_helpers.h"
#include "count/translation_count.h"
#include "generators.h"
#include "hrbench/hrbench.h"
#include "refinement_helpers.h"

using namespace hrbench;
using hrbench_test::Cli;
using hrbench_test::CounterDifferences;

namespace {

RefineOptions CountOnly(double eps) {
    RefineOptions o;
    o.eps = eps;
    o.storeLinks = false;
    return o;
}

Scene Parallel(double l, double d, double offset) {
    return MakeScene("parallel", {{"l", l}, {"d", d}, {"offset", offset}});
}

// Number of visited pairs whose oracle value equals eps exactly
// (max(A_i, A_j) == eps * r in doubles), by a plain recursion over element positions.
uint64_t CountTies(double l, double d, double offset, double eps) {
    uint64_t ties = 0;
    std::function<void(int, int64_t, int, int64_t)> project = [&](int di, int64_t p, int dj,
                                                                  int64_t q) {
        double si = std::ldexp(l, -di), sj = std::ldexp(l, -dj);
        double xi = (p + 0.5) * si, xj = offset + l - (q + 0.5) * sj;
        double m = std::max(si, sj), r = std::sqrt((xi - xj) * (xi - xj) + d * d);
        ties += m == eps * r;
        if (m <= eps * r)
            return;
        if (si >= sj) {
            project(di + 1, 2 * p, dj, q);
            project(di + 1, 2 * p + 1, dj, q);
        } else {
            project(di, p, dj + 1, 2 * q);
            project(di, p, dj + 1, 2 * q + 1);
        }
    };
    project(0, 0, 0, 0);
    return ties;
}

// Refine() and CountByTranslation() on one configuration: "" if every counter agrees.
std::string Differences(double l, double d, double offset, double eps) {
    Scene scene = Parallel(l, d, offset);
    Refinement<Segment> r = Refine<Segment>(scene, CountOnly(eps));
    TranslationCount t = CountByTranslation(scene, CountOnly(eps));
    return CounterDifferences(r.record.counters, t.record.counters);
}

// SplitMix64: a fixed sequence on every platform, unlike the standard distributions.
struct SplitMix {
    uint64_t state;
    uint64_t Next() {
        uint64_t z = (state += 0x9e3779b97f4a7c15);
        z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9;
        z = (z ^ (z >> 27)) * 0x94d049bb133111eb;
        return z ^ (z >> 31);
    }
    int64_t Int(int64_t lo, int64_t hi) { return lo + int64_t(Next() % uint64_t(hi - lo + 1)); }
    double Unit() { return double(Next() >> 11) * 0x1p-53; }  // in [0, 1)
};

}  // namespace

TEST_CASE("The translation method reproduces the worked example of docs/conventions.md",
          "[translation]") {
    TranslationCount t = CountByTranslation(Parallel(64, 1, 0), CountOnly(0.25));
    CHECK(t.record.counters.nodes == 1022);
    CHECK(t.record.counters.leaves == 512);
    CHECK(t.record.counters.links == 5092);
    CHECK(t.record.counters.oracleCalls == 10183);
    CHECK(t.record.counters.maxDepth == 8);
    CHECK(t.record.method == "translation");
    // Fewer states than pairs and elements: what makes the method fast.
    CHECK(t.pairStates > 0);
    CHECK(t.pairStates < t.record.counters.oracleCalls);
    CHECK(t.elementStates > 0);
    CHECK(t.elementStates < t.record.counters.nodes);
    // The oracle decides a few states per level; the rest follow from monotonicity.
    CHECK(t.oracleEvaluations > 0);
    CHECK(t.oracleEvaluations < t.pairStates);
}

TEST_CASE("The translation method agrees exactly with enumeration", "[translation]") {
    SECTION("on a grid of lengths, distances, offsets and thresholds") {
        int cases = 0;
        for (double l : {1.0, 3.0, 8.0, 64.0, 100.0, 0.75})
            for (double d : {1.0, 0.5, 0.3, 2.0, 4.0})
                for (double offset : {0.0, 0.5, -3.0, 7.25, 1.0, 100.0, -0.125})
                    for (double eps : {1.0, 0.5, 0.4, 0.3, 0.25, 0.2, 0.1}) {
                        Scene scene = Parallel(l, d, offset);
                        Refinement<Segment> r = Refine<Segment>(scene, CountOnly(eps));
                        TranslationCount t = CountByTranslation(scene, CountOnly(eps));
                        INFO("l=" << l << " d=" << d << " offset=" << offset << " eps=" << eps);
                        REQUIRE(CounterDifferences(r.record.counters, t.record.counters) == "");
                        ++cases;
                    }
        CHECK(cases == 6 * 5 * 7 * 7);
    }
    SECTION("on larger plates, thousands to millions of links") {
        auto [l, d, offset, eps] = GENERATE(table<double, double, double, double>({
            {1024, 1, 0, 0.05},
            {256, 1, 3.5, 0.02},
            {4096, 0.25, -17, 0.1},
            {64, 1, 0, 0.01},
            {1, 1.0 / 1024, 0.5, 0.03},
            {1000, 3, 999.75, 0.07},
        }));
        Scene scene = Parallel(l, d, offset);
        Refinement<Segment> r = Refine<Segment>(scene, CountOnly(eps));
        TranslationCount t = CountByTranslation(scene, CountOnly(eps));
        INFO("l=" << l << " d=" << d << " offset=" << offset << " eps=" << eps);
        CHECK(r.record.counters.links > 1000);
        CHECK(CounterDifferences(r.record.counters, t.record.counters) == "");
    }
}

TEST_CASE("The translation method agrees with enumeration on random dyadic plates",
          "[translation]") {
    // Lengths, distances and offsets with a few significant bits, at any binary scale,
    // and thresholds that are not round numbers: the band edges fall anywhere.
    SplitMix random{20240601};
    int nontrivial = 0;
    for (int k = 0; k < 300; ++k) {
        double d = std::ldexp(double(random.Int(1, 15)), int(random.Int(-6, 2)));
        double g = std::ldexp(double(random.Int(1, 31)), int(random.Int(-3, 3)));  // l / d
        double l = g * d;
        double offset = std::ldexp(double(random.Int(-64, 64)), int(random.Int(-4, 1))) * d;
        double eps = 0.02 + 0.98 * random.Unit();
        if (g / eps > 512)  // keep enumeration to a few million calls
            eps = g / 512;
        INFO("l=" << l << " d=" << d << " offset=" << offset << " eps=" << eps);
        Scene scene = Parallel(l, d, offset);
        Refinement<Segment> r = Refine<Segment>(scene, CountOnly(eps));
        TranslationCount t = CountByTranslation(scene, CountOnly(eps));
        REQUIRE(CounterDifferences(r.record.counters, t.record.counters) == "");
        nontrivial += r.record.counters.links > 100;
    }
    CHECK(nontrivial > 100);
}

TEST_CASE("The translation method decides ties exactly as the engine", "[translation]") {
    // Cases with pairs at exactly max(A_i, A_j) = eps * r: the worked example, and a
    // 3-4-5 triangle (offset 1 puts midpoints 3 apart at distance 4, r = 5).
    auto [l, d, offset, eps] = GENERATE(table<double, double, double, double>({
        {64, 1, 0, 0.25},
        {8, 4, 1, 0.4},
        {16, 4, 1, 0.2},
    }));
    INFO("l=" << l << " d=" << d << " offset=" << offset << " eps=" << eps);
    REQUIRE(CountTies(l, d, offset, eps) > 0);  // the case is not trivial
    Scene scene = Parallel(l, d, offset);
    Refinement<Segment> r = Refine<Segment>(scene, CountOnly(eps));
    TranslationCount t = CountByTranslation(scene, CountOnly(eps));
    CHECK(CounterDifferences(r.record.counters, t.record.counters) == "");
}

TEST_CASE("The translation method decides ties at every offset and level", "[translation]") {
    // Pythagorean triples (a, b, c): pairs a units apart horizontally at distance b have
    // r = c exactly, so eps = size / c puts them on the threshold. Offsets move the ties
    // across the band, and eps one ulp either side must flip them as the engine does.
    struct Triple {
        double a, b, c;
    };
    int withTies = 0, cases = 0;
    for (Triple t : {Triple{3, 4, 5}, Triple{4, 3, 5}, Triple{5, 12, 13}, Triple{8, 15, 17}})
        for (double unit : {0.25, 0.125})
            for (double offset : {0.0, t.a * unit, -t.a * unit, 0.5 * t.a * unit, 1.0, -0.75})
                for (double size : {1.0, 0.5, 0.25, 2.0})
                    for (double towards : {0.0, -1.0, 1.0}) {
                        double l = 16, d = t.b * unit, tie = size / (t.c * unit);
                        double eps = towards == 0 ? tie : std::nextafter(tie, towards * 1e300);
                        INFO("l=" << l << " d=" << d << " offset=" << offset << " eps=" << eps);
                        withTies += CountTies(l, d, offset, eps) > 0;
                        REQUIRE(Differences(l, d, offset, eps) == "");
                        ++cases;
                    }
    CHECK(cases == 4 * 2 * 6 * 4 * 3);
    CHECK(withTies >= 40);
}

TEST_CASE("The translation method rejects what it cannot count exactly", "[translation][errors]") {
    Scene scene = Parallel(64, 1, 0);
    SECTION("another oracle") {
        RefineOptions o = CountOnly(0.25);
        o.oracle = "hanrahan";
        CHECK_THROWS_AS(CountByTranslation(scene, o), InputError);
    }
    SECTION("store mode") {
        RefineOptions o = CountOnly(0.25);
        o.storeLinks = true;
        CHECK_THROWS_AS(CountByTranslation(scene, o), InputError);
    }
    SECTION("a recursion limit") {
        RefineOptions o = CountOnly(0.25);
        o.minArea = 0.5;
        CHECK_THROWS_AS(CountByTranslation(scene, o), InputError);
    }
    SECTION("a visibility mode") {
        RefineOptions o = CountOnly(0.25);
        o.visibility = VisibilityMode::Fraction;
        CHECK_THROWS_AS(CountByTranslation(scene, o), InputError);
    }
    SECTION("plates of different lengths") {
        Scene unequal = MakeScene("parallel", {{"l", 64}, {"d", 1}, {"l2", 32}});
        CHECK_THROWS_WITH(CountByTranslation(unequal, CountOnly(0.25)), Catch::Contains("l2 = l"));
    }
    SECTION("another scene") {
        CHECK_THROWS_AS(CountByTranslation(MakeScene("perpendicular", {}), CountOnly(0.25)),
                        InputError);
    }
    SECTION("midpoints that are not exact in double precision") {
        CHECK_THROWS_WITH(CountByTranslation(Parallel(0.1, 1, 0), CountOnly(0.25)),
                          Catch::Contains("not exact"));
        CHECK_THROWS_WITH(CountByTranslation(Parallel(64, 1, 0.1), CountOnly(0.25)),
                          Catch::Contains("not exact"));
    }
    SECTION("midpoints that stop being exact deep in the trees") {
        // 2^52 + 1 has 53 significant bits: its halves are not exact.
        CHECK_THROWS_WITH(CountByTranslation(Parallel(4503599627370497.0, 1, 0), CountOnly(0.25)),
                          Catch::Contains("not exact"));
    }
}

TEST_CASE("The translation method counts beyond 10^14 links", "[translation]") {
    // g = l / d = 2^31 at eps = 0.01: 1.43e14 links, far out of reach of enumeration
    // (about a day at 1e8 oracle calls per second); here a few milliseconds.
    TranslationCount t = CountByTranslation(Parallel(2147483648.0, 1, 0), CountOnly(0.01));
    CHECK(t.record.counters.links == 142867791169060);
    CHECK(t.record.counters.links >= uint64_t(1e14));
    CHECK(t.record.counters.oracleCalls == 2 * t.record.counters.links - 1);
    CHECK(t.record.counters.leaves == t.record.counters.nodes / 2 + 1);
    uint64_t sum = 0;
    for (uint64_t n : t.record.counters.linksPerDepth)
        sum += n;
    CHECK(sum == t.record.counters.links);
}

TEST_CASE("The translation method keeps the counts of its first, state by state, version",
          "[translation]") {
    // Far past enumeration: the counters that the version evaluating the oracle on every
    // state gave (11 s there, here well under a second), quadratic regime and an offset.
    struct Expected {
        double l, offset, eps;
        uint64_t links, oracleCalls, nodes, maxDepth;
    };
    auto e =
        GENERATE(Expected{1024, 0, 1e-6, 5865876496863902, 11731752993727803, 4294967294, 30},
                 Expected{1048576, 0.5, 0.0002, 196313010633391, 392626021266781, 34359738366, 33});
    INFO("l=" << e.l << " offset=" << e.offset << " eps=" << e.eps);
    TranslationCount t = CountByTranslation(Parallel(e.l, 1, e.offset), CountOnly(e.eps));
    CHECK(t.record.counters.links == e.links);
    CHECK(t.record.counters.oracleCalls == e.oracleCalls);
    CHECK(t.record.counters.nodes == e.nodes);
    CHECK(t.record.counters.leaves == e.nodes / 2 + 1);
    CHECK(t.record.counters.maxDepth == e.maxDepth);
}

TEST_CASE("hrbench run --method reports the method and the same counters", "[translation][cli]") {
    const std::string run = GENERATE(
        as<std::string>{}, "run parallel l=64 d=1 offset=0.5 --eps 0.2 --count-only --json",
        "run parallel3d l=8 w=4 d=1 --eps 0.05 --count-only --json");
    INFO(run);
    hrbench_test::CliResult enumerated = Cli(run), translated = Cli(run + " --method translation");
    REQUIRE(enumerated.exitCode == 0);
    REQUIRE(translated.exitCode == 0);
    nlohmann::json e = nlohmann::json::parse(enumerated.out),
                   t = nlohmann::json::parse(translated.out);
    CHECK(e["method"] == "enumerate");
    CHECK(t["method"] == "translation");
    for (const char *key : {"nodes", "leaves", "links", "oracle_calls", "max_depth", "forced_links",
                            "culled_pairs", "root_pairs", "nodes_per_depth", "links_per_depth"}) {
        INFO(key);
        CHECK(e[key] == t[key]);
    }
    SECTION("out of scope or misspelt: exit code 2") {
        using hrbench_test::CheckError;
        CheckError("run parallel --eps 0.2 --method translation", 2, "count-only");  // store mode
        CheckError("run parallel --eps 0.2 --count-only --oracle hanrahan --method translation", 2,
                   "garmann");
        CheckError("run parallel l2=3 --eps 0.2 --count-only --method translation", 2, "l2");
        CheckError("run room --eps 0.2 --count-only --min-area 0.1 --method translation", 2,
                   "recursion limit");
        CheckError("run room --eps 0.2 --count-only --method translation", 2, "parallel");
        CheckError("run parallel3d oy=1 --eps 0.2 --count-only --method translation", 2,
                   "ox = oy = 0");
        CheckError("run parallel --eps 0.2 --count-only --method fast", 2, "method");
        CheckError("links parallel --eps 0.2 --out x.csv --method translation", 2, "method");
    }
}
