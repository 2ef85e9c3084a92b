// `--min-areas`: the counters of several recursion limits from one enumeration must be
// those of a separate run at each limit, counter by counter.
#include <catch2/catch.hpp>

#include <string>
#include <vector>

#include "cli_helpers.h"
#include "hrbench/generators/generators.h"
#include "hrbench/hrbench.h"
#include "refinement_helpers.h"

using namespace hrbench;
using hrbench_test::CheckError;
using hrbench_test::Cli;
using hrbench_test::CounterDifferences;

namespace {

RefineOptions CountOnly(double eps, const std::string &oracle = "garmann") {
    RefineOptions o;
    o.eps = eps;
    o.oracle = oracle;
    o.storeLinks = false;
    return o;
}

// "" if CountMinAreaSweep() gives, for every value, the counters of a separate run.
std::string Differences(const Scene &scene, RefineOptions options,
                        const std::vector<double> &minAreas) {
    std::vector<RunRecord> swept = CountMinAreaSweep(scene, options, minAreas);
    REQUIRE(swept.size() == minAreas.size());
    std::string differences;
    for (size_t k = 0; k < minAreas.size(); ++k) {
        options.minArea = minAreas[k];
        RunRecord single = Count(scene, options, "enumerate");
        std::string d = CounterDifferences(single.counters, swept[k].counters);
        if (!d.empty())
            differences += "min-area " + FormatDouble(minAreas[k]) + ":\n" + d;
        CHECK(swept[k].method == "enumerate");
    }
    return differences;
}

}  // namespace

TEST_CASE("--min-areas counts each recursion limit as a separate run would", "[min-areas]") {
    SECTION("by hand: two unit segments at distance 1 that the oracle always rejects") {
        // Above 1 the root pair is linked by force; at 0.6 each plate is halved once and
        // the 4 half-pairs are forced; at 0.3 once more: 16 forced links, 2 L - 1 calls.
        Scene plates = MakeScene("parallel", {{"l", 1}, {"d", 1}});
        std::vector<RunRecord> r = CountMinAreaSweep(plates, CountOnly(1e-9), {2, 0.3, 0.6});
        const uint64_t links[] = {1, 16, 4}, nodes[] = {2, 14, 6}, depth[] = {0, 2, 1};
        for (int k = 0; k < 3; ++k) {
            INFO("value " << k);
            CHECK(r[k].counters.links == links[k]);
            CHECK(r[k].counters.forcedLinks == links[k]);
            CHECK(r[k].counters.oracleCalls == 2 * links[k] - 1);
            CHECK(r[k].counters.nodes == nodes[k]);
            CHECK(r[k].counters.leaves == nodes[k] / 2 + 1);
            CHECK(r[k].counters.maxDepth == depth[k]);
            CHECK(r[k].counters.linksPerDepth.size() == 2 * depth[k] + 1);
        }
    }
    SECTION("in 2D, with corners, culling, both limits and every oracle but bf") {
        Scene perpendicular = MakeScene("perpendicular", {{"l", 1}, {"gap", 0}});
        REQUIRE(Differences(perpendicular, CountOnly(0.05), {1e-6, 1e-12, 3e-4, 0.01, 2}) == "");
        Scene enclosure = MakeScene("enclosure", {{"n", 6}});
        REQUIRE(Differences(enclosure, CountOnly(0.01), {1e-9, 1e-5, 1e-7}) == "");
        REQUIRE(Differences(enclosure, CountOnly(0.01, "hanrahan"), {1e-9, 1e-5, 1e-7}) == "");
        RefineOptions limited = CountOnly(0.01);
        limited.maxDepth = 9;
        REQUIRE(Differences(enclosure, limited, {1e-9, 1e-3, 0.05}) == "");
        Scene soup = MakeScene("random", {{"n", 64}});
        REQUIRE(Differences(soup, CountOnly(0.1), {1e-4, 1e-3, 0.01}) == "");
    }
    SECTION("with the bf oracle, in a room lit from the ceiling") {
        Scene room = MakeScene("room", {{"lamp", 1}});
        REQUIRE(Differences(room, CountOnly(0.005, "bf"), {1e-6, 1e-4, 0.008, 0.05}) == "");
    }
    SECTION("in 3D, binary and quadtree, over the Cornell box's edges") {
        Scene cornell = MakeScene("cornell", {});
        RefineOptions binary = CountOnly(0.2);
        REQUIRE(Differences(cornell, binary, {1e-5, 2.5e-6, 1e-4, 1e-3, 1}) == "");
        RefineOptions quadtree = binary;
        quadtree.subdivision = Subdivision::Quadtree;
        REQUIRE(Differences(cornell, quadtree, {1e-5, 1e-4, 3e-4}) == "");
        RefineOptions limited = binary;
        limited.maxDepth = 12;
        REQUIRE(Differences(cornell, limited, {1e-6, 1e-5, 1e-4}) == "");
    }
    SECTION("a single value, and values that split nothing") {
        Scene plates = MakeScene("parallel", {{"l", 8}, {"d", 1}});
        REQUIRE(Differences(plates, CountOnly(0.05), {0.1}) == "");
        REQUIRE(Differences(plates, CountOnly(0.05), {100, 1000}) == "");
    }
}

TEST_CASE("--min-areas refuses what it cannot count", "[min-areas][errors]") {
    Scene plates = MakeScene("parallel", {{"l", 8}, {"d", 1}});
    RefineOptions stored = CountOnly(0.1);
    stored.storeLinks = true;
    CHECK_THROWS_AS(CountMinAreaSweep(plates, stored, {0.1}), InputError);
    RefineOptions threads = CountOnly(0.1);
    threads.threads = 2;
    CHECK_THROWS_AS(CountMinAreaSweep(plates, threads, {0.1}), InputError);
    CHECK_THROWS_AS(CountMinAreaSweep(plates, CountOnly(0.1), {}), InputError);
    CHECK_THROWS_AS(CountMinAreaSweep(plates, CountOnly(0.1), {0.1, 0.1}), InputError);
    CHECK_THROWS_AS(CountMinAreaSweep(plates, CountOnly(0.1), {0.1, 0}), InputError);
    RefineOptions visibility = CountOnly(0.1);
    visibility.visibility = VisibilityMode::Fraction;
    CHECK_THROWS_AS(CountMinAreaSweep(MakeScene("cornell", {}), visibility, {0.1}), InputError);
}

TEST_CASE("run --min-areas prints one record per value, in the order given", "[cli][min-areas]") {
    std::string base = "run parallel l=1 d=1 --eps 1e-9 --count-only --json";
    hrbench_test::CliResult r = Cli(base + " --min-areas 2,0.3,0.6");
    REQUIRE(r.exitCode == 0);
    std::istringstream lines(r.out);
    std::vector<std::string> records;
    for (std::string line; std::getline(lines, line);)
        records.push_back(line);
    REQUIRE(records.size() == 3);
    const char *expected[] = {"\"links\":1,", "\"links\":16,", "\"links\":4,"};
    const char *minArea[] = {"\"min_area\":2.0,", "\"min_area\":0.3,", "\"min_area\":0.6,"};
    for (int k = 0; k < 3; ++k) {
        CHECK_THAT(records[k], Catch::Contains(expected[k]));
        CHECK_THAT(records[k], Catch::Contains(minArea[k]));
    }

    CheckError(base + " --min-areas 0.1,0.1", 2, "twice");
    CheckError(base + " --min-areas 0.1,", 2, "separated by commas");
    CheckError(base + " --min-areas 0.1,x", 2, "not a number");
    CheckError(base + " --min-areas 0.1,-1", 2, "--min-area");
    CheckError(base + " --min-areas 0.1 --min-area 0.2", 2, "give one of them");
    CheckError(base + " --min-areas 0.1 --method translation", 2, "drop --method");
    CheckError("run parallel --eps 0.1 --min-areas 0.1", 2, "--count-only");
    CheckError("links parallel --eps 0.1 --out x.csv --min-areas 0.1", 2,
               "--min-areas does not apply to links");
}
