// `--sweep`: the counters of several values of eps or of --min-area from one
// enumeration must be those of a separate run at each value, counter by counter.
#include <catch2/catch.hpp>

#include <string>
#include <vector>

#include "cli_helpers.h"
#include "count/sweep_count.h"
#include "generators.h"
#include "hrbench/hrbench.h"
#include "refinement_helpers.h"
#include "util/format.h"

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

// "" if CountSweep() gives, for every value, the counters of a separate run.
std::string Differences(const Scene &scene, RefineOptions options, const std::string &param,
                        const std::vector<double> &values) {
    std::vector<RunRecord> swept = CountSweep(scene, options, {param, values});
    REQUIRE(swept.size() == values.size());
    std::string differences;
    for (size_t k = 0; k < values.size(); ++k) {
        (param == "eps" ? options.eps : options.minArea) = values[k];
        RunRecord single = Count(scene, options, "enumerate");
        std::string d = CounterDifferences(single.counters, swept[k].counters);
        if (!d.empty())
            differences += param + " " + FormatDouble(values[k]) + ":\n" + d;
        CHECK(swept[k].method == "enumerate");
        // The record carries the value it was counted at; the other stays the options'.
        CHECK((param == "eps" ? swept[k].sweptEps : swept[k].sweptMinArea) == values[k]);
        CHECK(!(param == "eps" ? swept[k].sweptMinArea : swept[k].sweptEps));
    }
    return differences;
}

// The same for a sweep of --min-area, and of eps.
std::string MinAreaDifferences(const Scene &scene, const RefineOptions &options,
                               const std::vector<double> &values) {
    return Differences(scene, options, "min_area", values);
}
std::string EpsDifferences(const Scene &scene, const RefineOptions &options,
                           const std::vector<double> &values) {
    return Differences(scene, options, "eps", values);
}

}  // namespace

TEST_CASE("Option --sweep min_area counts each recursion limit as a separate run does", "[sweep]") {
    SECTION("by hand: two unit segments at distance 1 that the oracle always rejects") {
        // Above 1 the root pair is linked by force; at 0.6 each plate is halved once and
        // the 4 half-pairs are forced; at 0.3 once more: 16 forced links, 2 L - 1 calls.
        Scene plates = MakeScene("parallel", {{"l", 1}, {"d", 1}});
        std::vector<RunRecord> r = CountSweep(plates, CountOnly(1e-9), {"min_area", {2, 0.3, 0.6}});
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
        REQUIRE(MinAreaDifferences(perpendicular, CountOnly(0.05), {1e-6, 1e-12, 3e-4, 0.01, 2}) ==
                "");
        Scene enclosure = MakeScene("enclosure", {{"n", 6}});
        REQUIRE(MinAreaDifferences(enclosure, CountOnly(0.01), {1e-9, 1e-5, 1e-7}) == "");
        REQUIRE(MinAreaDifferences(enclosure, CountOnly(0.01, "hanrahan"), {1e-9, 1e-5, 1e-7}) ==
                "");
        RefineOptions limited = CountOnly(0.01);
        limited.maxDepth = 9;
        REQUIRE(MinAreaDifferences(enclosure, limited, {1e-9, 1e-3, 0.05}) == "");
        Scene soup = MakeScene("random", {{"n", 64}});
        REQUIRE(MinAreaDifferences(soup, CountOnly(0.1), {1e-4, 1e-3, 0.01}) == "");
    }
    SECTION("with the bf oracle, in a room lit from the ceiling") {
        Scene room = MakeScene("room", {{"lamp", 1}});
        REQUIRE(MinAreaDifferences(room, CountOnly(0.005, "bf"), {1e-6, 1e-4, 0.008, 0.05}) == "");
    }
    SECTION("in 3D, binary and quadtree, over the Cornell box's edges") {
        Scene cornell = MakeScene("cornell", {});
        RefineOptions binary = CountOnly(0.2);
        REQUIRE(MinAreaDifferences(cornell, binary, {1e-5, 2.5e-6, 1e-4, 1e-3, 1}) == "");
        RefineOptions quadtree = binary;
        quadtree.subdivision = Subdivision::Quadtree;
        REQUIRE(MinAreaDifferences(cornell, quadtree, {1e-5, 1e-4, 3e-4}) == "");
        RefineOptions limited = binary;
        limited.maxDepth = 12;
        REQUIRE(MinAreaDifferences(cornell, limited, {1e-6, 1e-5, 1e-4}) == "");
    }
    SECTION("a single value, and values that split nothing") {
        Scene plates = MakeScene("parallel", {{"l", 8}, {"d", 1}});
        REQUIRE(MinAreaDifferences(plates, CountOnly(0.05), {0.1}) == "");
        REQUIRE(MinAreaDifferences(plates, CountOnly(0.05), {100, 1000}) == "");
    }
}

TEST_CASE("Option --sweep eps counts each threshold as a separate run would", "[sweep]") {
    SECTION("by hand: parallel plates l=8 d=1, whose counts other tests fix") {
        // eps = 1: 30 elements (two trees of depth 3); eps = 0.01: 4094.
        Scene plates = MakeScene("parallel", {{"l", 8}, {"d", 1}});
        std::vector<RunRecord> r = CountSweep(plates, CountOnly(1), {"eps", {0.01, 1}});
        CHECK(r[0].counters.nodes == 4094);
        CHECK(r[1].counters.nodes == 30);
        CHECK(r[1].counters.oracleCalls == 2 * r[1].counters.links - 1);
        CHECK(r[0].counters.oracleCalls == 2 * r[0].counters.links - 1);
    }
    SECTION("in 2D, every oracle, with and without a recursion limit") {
        Scene plates = MakeScene("parallel", {{"l", 8}, {"d", 1}});
        std::vector<double> eps = {0.05, 0.01, 0.3, 1, 0.0123, 2.5};
        REQUIRE(EpsDifferences(plates, CountOnly(1), eps) == "");
        REQUIRE(EpsDifferences(plates, CountOnly(1, "hanrahan"), eps) == "");
        RefineOptions bf = CountOnly(1, "bf");
        bf.minArea = 0.008;
        REQUIRE(EpsDifferences(MakeScene("room", {{"lamp", 1}}), bf, {0.05, 0.01, 0.003, 1}) == "");
        RefineOptions limited = CountOnly(1);
        limited.minArea = 1e-7;
        REQUIRE(EpsDifferences(MakeScene("enclosure", {{"n", 6}}), limited, {0.05, 0.3, 0.02}) ==
                "");
        RefineOptions depth = CountOnly(1);
        depth.maxDepth = 8;
        REQUIRE(EpsDifferences(MakeScene("random", {{"n", 64}}), depth, {0.05, 0.3, 0.1, 1}) == "");
    }
    SECTION("in 3D, binary and quadtree, with both kinds of visibility") {
        RefineOptions limited = CountOnly(1);
        limited.minArea = 1e-4;
        Scene cornell = MakeScene("cornell", {});
        REQUIRE(EpsDifferences(cornell, limited, {0.1, 0.3, 0.2}) == "");
        limited.subdivision = Subdivision::Quadtree;
        REQUIRE(EpsDifferences(cornell, limited, {0.1, 0.3, 0.2}) == "");
        RefineOptions fraction = CountOnly(1);
        fraction.visibility = VisibilityMode::Fraction;
        fraction.raysPerSide = 2;
        Scene occluded = MakeScene("occluded3d", {{"l", 8}, {"bl", 2}, {"h", 0.5}});
        REQUIRE(EpsDifferences(occluded, fraction, {0.1, 0.3, 1, 0.15}) == "");
        RefineOptions refine = fraction;
        refine.visibility = VisibilityMode::Refine;
        refine.minArea = 0.25;
        REQUIRE(EpsDifferences(occluded, refine, {0.1, 0.3, 1}) == "");
        fraction.eps = 0.2;
        REQUIRE(MinAreaDifferences(occluded, fraction, {0.01, 0.1, 0.003}) == "");
    }
}

TEST_CASE("Option --sweep refuses what it cannot count", "[sweep][errors]") {
    Scene plates = MakeScene("parallel", {{"l", 8}, {"d", 1}});
    RefineOptions stored = CountOnly(0.1);
    stored.storeLinks = true;
    CHECK_THROWS_AS(CountSweep(plates, stored, {"min_area", {0.1}}), InputError);
    RefineOptions threads = CountOnly(0.1);
    threads.threads = 2;
    CHECK_THROWS_AS(CountSweep(plates, threads, {"eps", {0.1}}), InputError);
    CHECK_THROWS_AS(CountSweep(plates, CountOnly(0.1), {"min_area", {}}), InputError);
    CHECK_THROWS_AS(CountSweep(plates, CountOnly(0.1), {"min_area", {0.1, 0.1}}), InputError);
    CHECK_THROWS_AS(CountSweep(plates, CountOnly(0.1), {"min_area", {0.1, 0}}), InputError);
    CHECK_THROWS_AS(CountSweep(plates, CountOnly(0.1), {"eps", {0.1, 0}}), InputError);
    CHECK_THROWS_AS(CountSweep(plates, CountOnly(0.1), {"l", {1, 2}}), InputError);
    CHECK_THROWS_AS(CountSweep(plates, CountOnly(0.1), {"eps", std::vector<double>(256, 1)}),
                    InputError);
    // Touching plates need a recursion limit at every eps.
    Scene touching = MakeScene("perpendicular", {{"gap", 0}});
    CHECK_THROWS_AS(CountSweep(touching, CountOnly(0.1), {"eps", {0.1, 0.2}}), InputError);
}

TEST_CASE("run --sweep prints one record per value, in the order given", "[cli][sweep]") {
    std::string base = "run parallel l=1 d=1 --count-only --json";
    hrbench_test::CliResult r = Cli(base + " --eps 1e-9 --sweep min_area=2,0.3,0.6");
    REQUIRE(r.exitCode == 0);
    std::istringstream lines(r.out);
    std::vector<std::string> records;
    for (std::string line; std::getline(lines, line);)
        records.push_back(line);
    REQUIRE(records.size() == 3);
    const char *links[] = {"\"links\":1,", "\"links\":16,", "\"links\":4,"};
    const char *minArea[] = {"\"min_area\":2.0,", "\"min_area\":0.3,", "\"min_area\":0.6,"};
    for (int k = 0; k < 3; ++k) {
        CHECK_THAT(records[k], Catch::Contains(links[k]));
        CHECK_THAT(records[k], Catch::Contains(minArea[k]));
    }
    r = Cli("run parallel l=8 d=1 --count-only --json --sweep eps=1,0.01");
    REQUIRE(r.exitCode == 0);
    CHECK(r.out.find("\"eps\":1.0,") < r.out.find("\"eps\":0.01,"));
    CHECK(r.out.find("\"nodes\":30,") < r.out.find("\"nodes\":4094,"));

    CheckError(base + " --eps 1 --sweep min_area=0.1,0.1", 2, "twice");
    CheckError(base + " --eps 1 --sweep min_area=0.1,", 2, "separated by commas");
    CheckError(base + " --eps 1 --sweep min_area=0.1,x", 2, "not a number");
    CheckError(base + " --eps 1 --sweep min_area=0.1,-1", 2, "--min-area");
    CheckError(base + " --eps 1 --sweep l=1,2", 2, "eps=V,V,... or min_area=V,V,...");
    CheckError(base + " --eps 1 --sweep 0.1", 2, "eps=V,V,... or min_area=V,V,...");
    CheckError(base + " --eps 1 --sweep min_area=0.1 --min-area 0.2", 2, "give one of them");
    CheckError(base + " --eps 1 --sweep eps=0.1", 2, "give one of them");
    CheckError(base + " --sweep eps=0.1 --method translation", 2,
               "--sweep counts by enumeration, which --method does not: drop one of them");
    CheckError("run parallel --sweep eps=0.1", 2, "--count-only");
    CheckError("run parallel --sweep eps=0.1 --count-only --threads 2", 2, "--threads");
    CheckError("links parallel --eps 0.1 --out x.csv --sweep eps=0.1", 2,
               "--sweep does not apply to links");
}
