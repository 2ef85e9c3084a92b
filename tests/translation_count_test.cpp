// The translation method against direct enumeration: every counter and histogram
// must be identical wherever both run, ties included.
#include <catch2/catch.hpp>

#include <cmath>
#include <functional>
#include <sstream>

#include <nlohmann/json.hpp>

#include "cli_helpers.h"
#include "hrbench/generators/generators.h"
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

TEST_CASE("hrbench run --method reports the method and the same counters", "[translation][cli]") {
    const std::string run = "run parallel l=64 d=1 offset=0.5 --eps 0.2 --count-only --json";
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
        CheckError("run parallel --eps 0.2 --count-only --method fast", 2, "method");
        CheckError("links parallel --eps 0.2 --out x.csv --method translation", 2, "method");
    }
}
