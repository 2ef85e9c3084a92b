// check-links --clusters (docs/probe.md, "Cluster links"): the cluster tokens of the dump,
// hrbench's own dumps of clustered refinements passing with the engine's counts, and each
// violation on hand-written dumps of the four plates of tests/cluster_test.cpp.
#include <catch2/catch.hpp>

#include <algorithm>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "cli_helpers.h"
#include "hrbench/hrbench.h"
#include "hrbench/scene_io.h"

using namespace hrbench_test;

namespace {

const std::string kHeader = "hrbench-link-dump 1\n";

hrbench::LinkDump Parse(const std::string &text, size_t patches = 4) {
    std::istringstream in(text);
    return hrbench::ReadLinkDump(in, "d", 2, patches);
}

// Two rows of two unit segments, 10 apart, facing each other; the columns 20 apart. The
// hierarchy: C0 the root, C1 = {0, 1} (left column), C2 = {2, 3} (right column).
hrbench::Scene FourPlates() {
    auto s = [](double ax, double ay, double bx, double by) {
        return hrbench::Patch<hrbench::Segment>{
            hrbench::Segment{hrbench::Vec2(ax, ay), hrbench::Vec2(bx, by)}, {}};
    };
    return {"file",
            {},
            "",
            hrbench::Patches<hrbench::Segment>{s(0, 0, 1, 0), s(1, 10, 0, 10), s(20, 0, 21, 0),
                                               s(21, 10, 20, 10)}};
}

hrbench::RefineOptions Clustered(double eps,
                                 hrbench::ClusterBound bound = hrbench::ClusterBound::Cluster) {
    hrbench::RefineOptions o;
    o.eps = eps;
    o.clusters = true;
    o.clusterBound = bound;
    return o;
}

// hrbench's own dump of the four plates at _eps_, as text.
std::string OwnDump(double eps, hrbench::ClusterBound bound = hrbench::ClusterBound::Cluster) {
    hrbench::RefineOptions o = Clustered(eps, bound);
    o.storeLinks = true;
    std::ostringstream out;
    hrbench::Scene scene = FourPlates();
    hrbench::WriteLinkDump(hrbench::AnyRefinement(hrbench::Refine<hrbench::Segment>(scene, o)),
                           out);
    return out.str();
}

// _dump_ without the lines in _drop_ (and without its counters line), with _add_ after.
std::string Edit(const std::string &dump, const std::set<std::string> &drop,
                 const std::string &add = "") {
    std::istringstream in(dump);
    std::string out, line;
    while (std::getline(in, line))
        if (!drop.count(line) && line.rfind("counters", 0) != 0)
            out += line + "\n";
    return out + add;
}

// The categories of the violations of _text_ checked at _eps_ (none when it passes).
std::vector<std::string> Categories(const std::string &text, double eps,
                                    std::string *first = nullptr,
                                    hrbench::ClusterBound bound = hrbench::ClusterBound::Cluster) {
    hrbench::LinkDump dump = Parse(text);
    try {
        hrbench::CheckLinks(FourPlates(), Clustered(eps, bound), dump);
    } catch (const hrbench::LinkViolation &v) {
        CHECK(v.ExitCode() == hrbench::kExitViolation);
        REQUIRE(v.summary);
        if (first)
            *first = v.what();
        std::vector<std::string> ids;
        for (const auto &c : v.summary->categories)
            ids.push_back(c.id);
        return ids;
    }
    return {};
}

}  // namespace

TEST_CASE("cluster tokens in a link dump", "[check-links][clusters]") {
    hrbench::LinkDump d = Parse(kHeader + "0/1 1\nC1 C2\n3 C1\nC2147483647 0\n");
    REQUIRE(d.links.size() == 1);
    REQUIRE(d.clusterLinks.size() == 3);
    CHECK(d.clusterLinks[0].a == hrbench::ClusterNode(1));
    CHECK(d.clusterLinks[0].b == hrbench::ClusterNode(2));
    CHECK(d.clusterLinks[0].line == 3);
    CHECK((d.clusterLinks[1].a == 3 && d.clusterLinks[1].b == hrbench::ClusterNode(1)));
    CHECK(d.clusterLinks[2].a == hrbench::ClusterNode(2147483647u));
    CHECK(hrbench::LinkDump::NodeName(d.clusterLinks[1].b) == "C1");

    auto rejects = [](const std::string &line, const std::string &message) {
        INFO(line);
        CHECK_THROWS_WITH(Parse(kHeader + line + "\n"), Catch::Contains(message));
    };
    rejects("C 0", "d:2: bad cluster 'C': expected C<index>");
    rejects("Cx 0", "d:2: bad cluster 'Cx': expected C<index>");
    rejects("0 C-1", "d:2: bad cluster 'C-1'");
    rejects("C1/0 0", "d:2: bad cluster 'C1/0': a cluster has no path");
    rejects("C2147483648 0", "d:2: bad cluster 'C2147483648': the index is beyond 2^31 - 1");
    rejects("C99999999999999999999 0", "the index is beyond 2^31 - 1");
    rejects("C1 0/1", "d:2: element '0/1' in a cluster link");
    rejects("C1 7", "d:2: element '7': the scene has no patch 7 (4 patches)");
}

TEST_CASE("check-links --clusters passes hrbench's own dumps with the engine's counts",
          "[check-links][clusters]") {
    std::string dump = Scratch("clusters_own.dump");
    for (std::string config : {"enclosure n=64 --eps 0.3 --min-area 0.01",
                               "enclosure n=64 --eps 0.1 --min-area 0.01 --oracle hanrahan",
                               "random3d n=30 --eps 0.02 --min-area 0.01",
                               "random3d n=30 --eps 0.005 --min-area 0.01 --oracle hanrahan"}) {
        INFO(config);
        REQUIRE(Cli("links " + config + " --clusters --format probe --out " + dump).exitCode == 0);
        nlohmann::json run = nlohmann::json::parse(Cli("run " + config + " --clusters --json").out);
        CHECK(run["cluster_links"].get<uint64_t>() > 0);
        CHECK(run["element_links"].get<uint64_t>() > 0);
        CliResult r = Cli("check-links " + config + " --clusters --links " + dump + " --json");
        INFO(r.err);
        REQUIRE(r.exitCode == 0);
        nlohmann::json j = nlohmann::json::parse(r.out);
        CHECK(j["ok"] == true);
        const nlohmann::json &own = j["counters"]["dump"], &engine = j["counters"]["hrbench"];
        REQUIRE(engine.is_object());
        for (const char *key :
             {"links", "oracle_calls", "nodes", "forced_links", "max_depth", "cluster_links",
              "element_links", "cluster_oracle_calls", "opened_clusters", "root_pairs"}) {
            INFO(key);
            CHECK(own[key] == engine[key]);
            CHECK(own[key] == run[key]);
        }
        CHECK(j["counters"]["kernel"]["links"] == run["links"]);

        r = Cli("check-links " + config + " --clusters --links " + dump);
        CHECK(r.exitCode == 0);
        CHECK_THAT(r.out, Catch::Contains(" cluster link"));
        CHECK_THAT(r.out, Catch::Contains("cluster_links"));
    }
}

TEST_CASE("check-links --clusters on the four plates: each violation", "[check-links][clusters]") {
    // eps 0.5: the columns link at once (C1 C2), the root pairs (0, 1) and (2, 3) are
    // refined. eps 0.15: each patch of the left column links the right column.
    const std::string at05 = OwnDump(0.5), at015 = OwnDump(0.15);
    REQUIRE(at05.find("\nC1 C2\n") != std::string::npos);
    REQUIRE(at015.find("\n0 C2\n1 C2\n") != std::string::npos);
    CHECK(Categories(at05, 0.5).empty());
    CHECK(Categories(at015, 0.15).empty());
    std::string first;

    SECTION("a cluster link the cluster oracle refuses") {
        // 2 > 0.15 * 9.9501: the columns refuse at eps 0.15.
        CHECK(Categories(Edit(at015, {"0 C2", "1 C2"}, "C1 C2\n"), 0.15, &first) ==
              std::vector<std::string>{"cluster-oracle"});
        CHECK_THAT(first, Catch::Contains(": unacceptable cluster link: C1 C2 is refused by the "
                                          "cluster form of the oracle garmann (eps 0.15)"));
    }
    SECTION("two overlapping cluster links") {
        // A patch of the left column against the right one, under the columns' link.
        CHECK(Categories(Edit(at05, {}, "0 C2\n"), 0.5, &first) ==
              std::vector<std::string>{"overlapping-link"});
        CHECK_THAT(first, Catch::Contains("overlapping links: 0 C2 overlaps C1 C2 of line"));
        // Links on both sides of the pair C1 C2: each end has a partner inside the other.
        CHECK(Categories(Edit(at015, {}, "C1 2\n"), 0.15, &first) ==
              std::vector<std::string>{"overlapping-link"});
        CHECK_THAT(first, Catch::Contains("overlapping links: C1 2 overlaps"));
        // The same link twice.
        CHECK(Categories(Edit(at05, {}, "C2 C1\n"), 0.5) ==
              std::vector<std::string>{"overlapping-link"});
    }
    SECTION("an element link under a cluster link") {
        CHECK(Categories(Edit(at05, {}, "0 3/1\n"), 0.5, &first) ==
              std::vector<std::string>{"overlapping-link"});
        CHECK_THAT(first, Catch::Contains("overlapping links: 0 3/1 lies in the root pair 0 3, "
                                          "which the cluster link C1 C2 of line"));
    }
    SECTION("a missing pair: the cluster link removed") {
        // The walk opens both columns: (0, 3) and (1, 2) are refined and have no link.
        CHECK(Categories(Edit(at05, {"C1 C2"}), 0.5, &first) ==
              std::vector<std::string>{"missing-link"});
        CHECK_THAT(first, Catch::Contains("missing link: nothing covers the element pair 0 3"));
    }
    SECTION("a pair opened where the cluster oracle links it: the engine's counts differ") {
        hrbench::RefineOptions plain = Clustered(0.5);
        plain.clusters = false;
        plain.storeLinks = true;
        std::ostringstream unclustered;
        hrbench::Scene scene = FourPlates();
        hrbench::WriteLinkDump(
            hrbench::AnyRefinement(hrbench::Refine<hrbench::Segment>(scene, plain)), unclustered);
        CHECK(Categories(Edit(unclustered.str(), {}), 0.5, &first) ==
              std::vector<std::string>{"counter-mismatch"});
        CHECK_THAT(first, Catch::Contains("counts: the links give links"));
    }
    SECTION("a cluster index out of range") {
        CHECK(Categories(Edit(at05, {}, "C3 0\n"), 0.5, &first) ==
              std::vector<std::string>{"bad-cluster"});
        CHECK_THAT(first, Catch::Contains("cluster out of range: C3 0: the scene's hierarchy has "
                                          "no cluster C3 (3 clusters, C0 to C2)"));
    }
    SECTION("a link within one cluster") {
        CHECK(Categories(Edit(at05, {}, "C1 0\n"), 0.5, &first) ==
              std::vector<std::string>{"link-within-cluster"});
        CHECK_THAT(first,
                   Catch::Contains("link within one cluster: C1 0 (patch 0 lies in cluster C1)"));
        CHECK(Categories(Edit(at05, {}, "C2 C0\n"), 0.5, &first) ==
              std::vector<std::string>{"link-within-cluster"});
        CHECK_THAT(first, Catch::Contains("C2 C0 (cluster C2 lies in cluster C0)"));
    }
}

TEST_CASE("check-links --clusters judges a dump under its --cluster-bound",
          "[check-links][clusters]") {
    // At eps 0.5 the cluster bound links the columns {C1, C2}; the patch bound links each
    // patch of the left column with the right one (tests/cluster_test.cpp, by hand).
    const auto patch = hrbench::ClusterBound::Patch;
    std::string columns = OwnDump(0.5), patches = OwnDump(0.5, patch);
    CHECK(columns.find("\nC1 C2\n") != std::string::npos);
    CHECK(patches.find("\n0 C2\n") != std::string::npos);
    CHECK(Categories(columns, 0.5).empty());
    CHECK(Categories(patches, 0.5, nullptr, patch).empty());
    std::string first;
    CHECK(Categories(columns, 0.5, &first, patch) == std::vector<std::string>{"cluster-oracle"});
    CHECK_THAT(first, Catch::Contains("joins two clusters, which --cluster-bound patch never "
                                      "links"));
}

TEST_CASE("check-links --clusters on the command line: exit codes and refusals",
          "[check-links][clusters]") {
    std::string scene = Scratch("four_plates.json");
    hrbench::SaveScene(FourPlates(), scene);
    std::string good = Scratch("four_good.dump"), bad = Scratch("four_bad.dump");
    std::ofstream(good) << OwnDump(0.5);
    std::ofstream(bad) << Edit(OwnDump(0.5), {}, "C1 0\n");
    const std::string check = "check-links --scene-file " + scene + " --eps 0.5 --links ";
    CliResult r = Cli(check + good + " --clusters");
    CHECK(r.exitCode == 0);
    CHECK_THAT(r.out, Catch::Contains("links (1 cluster link) cover every root pair once"));
    CheckError(check + bad + " --clusters", hrbench::kExitViolation,
               "link within one cluster: C1 0");
    r = Cli(check + bad + " --clusters --summary");
    CHECK(r.exitCode == hrbench::kExitViolation);
    CHECK_THAT(r.out, Catch::Contains("link-within-cluster (link within one cluster): 1"));
    r = Cli(check + bad + " --clusters --json");
    nlohmann::json j = nlohmann::json::parse(r.out);
    CHECK(j["categories"][0]["category"] == "link-within-cluster");
    CHECK(j["counters"]["dump"]["cluster_links"] == 2);
    // A cluster token without --clusters, and what --clusters refuses.
    CheckError(check + good, 2, "C1 C2 is a cluster link: add --clusters");
    std::string directed = Scratch("four_directed.dump");
    std::ofstream(directed) << "hrbench-link-dump 2\nconventions links=directed\nC1 C2\n";
    CheckError(check + directed + " --clusters", 2, "--clusters checks undirected links");
}
