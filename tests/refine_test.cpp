// ProjectKernel against DESIGN section 2: the worked example, hand-computed cases,
// and the invariants every refinement must satisfy.
#include <catch2/catch.hpp>

#include <functional>
#include <limits>
#include <map>
#include <tuple>

#include "generators.h"
#include "hrbench.h"
#include "oracles.h"
#include "refinement_helpers.h"

using namespace hrbench;
using hrbench_test::CounterDifferences;
using hrbench_test::SameLinks;

namespace {

RefineOptions Options(double eps, OracleKind oracle = OracleKind::Garmann, bool store = true) {
    RefineOptions o;
    o.eps = eps;
    o.oracle = oracle;
    o.storeLinks = store;
    return o;
}

// A direct transcription of DESIGN section 2, independent of the engine: elements
// are keyed by (root, depth, position) in a map, the recursion is plain.
struct ReferenceCounts {
    uint64_t nodes = 0, links = 0, calls = 0;
};

ReferenceCounts ReferenceGarmann(const Segment &p, const Segment &q, double eps) {
    struct Node {
        Vec2 a, b;
    };
    std::map<std::tuple<int, int, uint64_t>, Node> nodes;
    ReferenceCounts counts;
    using Key = std::tuple<int, int, uint64_t>;
    nodes[{0, 0, 0}] = {p.a, p.b};
    nodes[{1, 0, 0}] = {q.a, q.b};
    std::function<void(Key, Key)> project = [&](Key i, Key j) {
        ++counts.calls;
        Node ni = nodes[i], nj = nodes[j];
        Vec2 ci = 0.5 * (ni.a + ni.b), cj = 0.5 * (nj.a + nj.b);
        double ai = (ni.b - ni.a).norm(), aj = (nj.b - nj.a).norm();
        if (std::max(ai, aj) <= eps * (ci - cj).norm()) {
            ++counts.links;
            return;
        }
        bool splitI = ai >= aj;
        Key s = splitI ? i : j;
        Node ns = splitI ? ni : nj;
        Vec2 m = 0.5 * (ns.a + ns.b);
        Key c0{std::get<0>(s), std::get<1>(s) + 1, 2 * std::get<2>(s)};
        Key c1{std::get<0>(s), std::get<1>(s) + 1, 2 * std::get<2>(s) + 1};
        nodes[c0] = {ns.a, m};
        nodes[c1] = {m, ns.b};
        if (splitI) {
            project(c0, j);
            project(c1, j);
        } else {
            project(i, c0);
            project(i, c1);
        }
    };
    project({0, 0, 0}, {1, 0, 0});
    counts.nodes = nodes.size();
    return counts;
}

// Checks the invariants of DESIGN section 2 on a stored refinement.
template <typename Oracle>
void CheckInvariants(const Scene &scene, const Refinement &r, const Oracle &oracle) {
    const SegmentForest &f = r.forest;
    // Per root pair: oracle_calls = 2 * links - 1, and the links tile the parameter square.
    std::map<std::pair<uint32_t, uint32_t>, double> area;
    for (const Link &link : r.links)
        area[{f[link.i].root, f[link.j].root}] += f[link.i].size * f[link.j].size;
    uint64_t linksSeen = 0;
    for (const PairTally &pair : r.pairs) {
        CHECK(pair.oracleCalls == 2 * pair.links - 1);
        double expected = scene.segments[pair.p].Length() * scene.segments[pair.q].Length();
        double tiled = area[std::make_pair(pair.p, pair.q)];
        CHECK_THAT(tiled, Catch::Matchers::WithinRel(expected, 1e-12));
        linksSeen += pair.links;
    }
    CHECK(linksSeen == r.counters.links);
    CHECK(r.links.size() == r.counters.links);

    // Every link satisfies the oracle or is forced; the pair it came from did not.
    uint64_t unacceptable = 0;
    for (const Link &link : r.links) {
        unacceptable += !oracle.Acceptable(f[link.i], f[link.j]);
        uint32_t pi = f.Parent(link.i), pj = f.Parent(link.j);
        bool fromI = pi != link.i && f[pi].size >= f[link.j].size;
        bool fromJ = pj != link.j && f[link.i].size < f[pj].size;
        if (fromI || fromJ) {
            bool someParentRejected = (fromI && !oracle.Acceptable(f[pi], f[link.j])) ||
                                      (fromJ && !oracle.Acceptable(f[link.i], f[pj]));
            CHECK(someParentRejected);
        } else {
            CHECK(f.Depth(link.i) + f.Depth(link.j) == 0);  // only a root pair has no parent
        }
    }
    CHECK(unacceptable == r.counters.forcedLinks);

    // Tree counters agree with the histograms.
    uint64_t nodes = 0, links = 0;
    for (uint64_t n : r.counters.nodesPerDepth)
        nodes += n;
    for (uint64_t n : r.counters.linksPerDepth)
        links += n;
    CHECK(nodes == r.counters.nodes);
    CHECK(links == r.counters.links);
}

}  // namespace

TEST_CASE("The worked example of DESIGN section 2 gives its published counts", "[refine]") {
    Scene scene = MakeScene("parallel", {{"l", 64}, {"d", 1}});
    Refinement r = Refine(scene, Options(0.25));
    CHECK(r.counters.nodes == 1022);
    CHECK(r.counters.leaves == 512);
    CHECK(r.counters.links == 5092);
    CHECK(r.counters.oracleCalls == 10183);
    CHECK(r.counters.maxDepth == 8);
    CHECK(r.counters.forcedLinks == 0);
    CHECK(r.counters.rootPairs == 1);
}

TEST_CASE("Small cases computed by hand", "[refine]") {
    SECTION("a pair acceptable at once is one link and one oracle call") {
        // l = d = 1: max(1, 1) <= 1 * 1 holds with equality, and ties are acceptable.
        Refinement r = Refine(MakeScene("parallel", {{"l", 1}, {"d", 1}}), Options(1));
        CHECK(r.counters.links == 1);
        CHECK(r.counters.oracleCalls == 1);
        CHECK(r.counters.nodes == 2);
        CHECK(r.counters.leaves == 2);
        CHECK(r.counters.maxDepth == 0);
    }
    SECTION("one level: P is halved first (tie), then Q once, its children shared") {
        // eps = 0.5: (P,Q) fails (1 > 0.5 * 1); P splits (tie). (P0,Q): 1 > 0.5*sqrt(1.0625)
        // -> Q splits; (P0,Q0): 0.5 <= 0.5*sqrt(1.25); (P0,Q1): 0.5 <= 0.5*1 (tie).
        // (P1,Q) fails likewise and reuses Q's children: (P1,Q0) tie, (P1,Q1) accepted.
        Refinement r = Refine(MakeScene("parallel", {{"l", 1}, {"d", 1}}), Options(0.5));
        CHECK(r.counters.links == 4);
        CHECK(r.counters.oracleCalls == 7);
        CHECK(r.counters.nodes == 6);
        CHECK(r.counters.leaves == 4);
        CHECK(r.counters.maxDepth == 1);
        CHECK(r.counters.linksPerDepth == std::vector<uint64_t>{0, 0, 4});
    }
    SECTION("collinear patches are culled and never refined") {
        Refinement r = Refine(MakeScene("array", {{"k", 3}}), Options(0.5));
        // 6 plates: the 3 + 3 pairs within a row are collinear, 9 pairs face each other.
        CHECK(r.counters.rootPairs == 15);
        CHECK(r.counters.culledPairs == 6);
        CHECK(r.pairs.size() == 9);
    }
}

TEST_CASE("Counts agree with an independent transcription of DESIGN section 2", "[refine]") {
    auto [l, d, offset, l2, eps] = GENERATE(table<double, double, double, double, double>({
        {64, 1, 0, 64, 0.25},
        {16, 2, 0, 16, 0.1},
        {10, 1, 0, 10, 0.3},
        {8, 1, 3, 8, 0.2},
        {8, 0.5, -2, 5, 0.35},
        {1, 1, 0, 1, 0.05},
        {32, 1, 0.25, 32, 0.5},
    }));
    Scene scene = MakeScene("parallel", {{"l", l}, {"d", d}, {"offset", offset}, {"l2", l2}});
    ReferenceCounts ref = ReferenceGarmann(scene.segments[0], scene.segments[1], eps);
    Refinement r = Refine(scene, Options(eps, OracleKind::Garmann, false));
    INFO("l=" << l << " d=" << d << " offset=" << offset << " l2=" << l2 << " eps=" << eps);
    CHECK(r.counters.nodes == ref.nodes);
    CHECK(r.counters.links == ref.links);
    CHECK(r.counters.oracleCalls == ref.calls);
}

TEST_CASE("Refinements satisfy the invariants on many scenes and thresholds", "[refine]") {
    auto [family, params] = GENERATE(table<std::string, ParamMap>({
        {"parallel", {{"l", 16}, {"d", 1}}},
        {"parallel", {{"l", 10}, {"d", 3}, {"offset", 2.5}, {"l2", 4}}},
        {"perpendicular", {{"l", 1}, {"gap", 0.05}}},
        {"angled", {{"angle", 45}, {"l2", 2}}},
        {"angled", {{"angle", 150}, {"gap", 0.3}}},
        {"array", {{"k", 3}, {"spacing", 0.5}}},
        {"random", {{"n", 12}, {"seed", 7}, {"size", 6}}},
    }));
    double eps = GENERATE(1.0, 0.3, 0.1);
    Scene scene = MakeScene(family, params);
    INFO(family << " eps=" << eps);

    SECTION("garmann") {
        Refinement r = Refine(scene, Options(eps));
        CheckInvariants(scene, r, GarmannOracle(eps));
        REQUIRE(r.counters.links > 0);
    }
    SECTION("hanrahan") {
        std::vector<Vec2> normals;
        for (const Segment &s : scene.segments)
            normals.push_back(s.Normal());
        Refinement r = Refine(scene, Options(eps / 10, OracleKind::Hanrahan));
        CheckInvariants(scene, r, HanrahanOracle(eps / 10, normals));
        REQUIRE(r.counters.links > 0);
    }
}

TEST_CASE("Counts are identical in count-only and store mode and on every run", "[refine]") {
    Scene scene = MakeScene("random", {{"n", 20}, {"seed", 3}, {"size", 8}});
    OracleKind oracle = GENERATE(OracleKind::Garmann, OracleKind::Hanrahan);
    double eps = oracle == OracleKind::Garmann ? 0.2 : 0.02;
    Refinement stored = Refine(scene, Options(eps, oracle, true));
    Refinement counted = Refine(scene, Options(eps, oracle, false));
    Refinement again = Refine(scene, Options(eps, oracle, false));
    REQUIRE(stored.counters.links > 100);  // not a trivial case
    for (const Refinement *r : {&counted, &again}) {
        CHECK(CounterDifferences(stored.counters, r->counters) == "");
        CHECK(r->links.empty());
    }
}

TEST_CASE("Recursion limits force links and are counted", "[refine]") {
    Scene room = MakeScene("room", {{"w", 2}, {"h", 1}});
    SECTION("--min-area stops subdivision of elements shorter than A") {
        RefineOptions o = Options(0.1);
        o.minArea = 0.01;
        Refinement r = Refine(room, o);
        CHECK(r.counters.forcedLinks > 0);
        CHECK(r.counters.rootPairs == 6);
        CHECK(r.counters.culledPairs == 0);  // in a convex room every wall sees every other
        CheckInvariants(room, r, GarmannOracle(0.1));
        for (uint32_t e = 0; e < r.forest.Size(); ++e)
            if (r.forest[e].firstChild != kNoChildren)
                CHECK(r.forest[e].size >= 0.01);
    }
    SECTION("--max-depth bounds the depth of every element") {
        RefineOptions o = Options(0.1);
        o.maxDepth = 5;
        Refinement r = Refine(room, o);
        CHECK(r.counters.maxDepth == 5);
        CHECK(r.counters.forcedLinks > 0);
        CheckInvariants(room, r, GarmannOracle(0.1));
    }
}

TEST_CASE("Refinement that cannot terminate is an error, not a hang", "[refine][errors]") {
    SECTION("touching patches without a recursion limit are rejected before refining") {
        Scene touching = MakeScene("perpendicular", {{"gap", 0}});
        CHECK_THROWS_AS(Refine(touching, Options(0.5)), InputError);
        CHECK_THROWS_WITH(Refine(touching, Options(0.5)), Catch::Contains("--min-area"));
    }
    SECTION("a recursion limit makes touching patches terminate") {
        RefineOptions o = Options(0.5);
        o.minArea = 1e-3;
        Refinement r = Refine(MakeScene("perpendicular", {{"gap", 0}}), o);
        CHECK(r.counters.forcedLinks > 0);
    }
    SECTION("a --min-area too small for the safety depth names the pair") {
        RefineOptions o = Options(0.5);
        o.minArea = 1e-300;
        CHECK_THROWS_AS(Refine(MakeScene("perpendicular", {{"gap", 0}}), o), LimitError);
    }
    SECTION("a memory budget too small for the links stops the run") {
        RefineOptions o = Options(0.01);
        o.memoryBudget = 1 << 20;
        CHECK_THROWS_AS(Refine(MakeScene("parallel", {{"l", 1024}}), o), LimitError);
    }
}

TEST_CASE("Invalid refinement options are rejected with the option's name", "[refine][errors]") {
    Scene scene = MakeScene("parallel", {});
    double nan = std::numeric_limits<double>::quiet_NaN(), inf = std::numeric_limits<double>::infinity();
    for (double eps : {0.0, -1.0, nan, inf})
        CHECK_THROWS_WITH(Refine(scene, Options(eps)), Catch::Contains("--eps"));
    RefineOptions o = Options(0.5);
    o.minArea = -1;
    CHECK_THROWS_WITH(Refine(scene, o), Catch::Contains("--min-area"));
    o.minArea = 0;
    o.maxDepth = kSafetyDepth + 1;
    CHECK_THROWS_WITH(Refine(scene, o), Catch::Contains("--max-depth"));
}

TEST_CASE("Counts, element ids and links do not depend on the number of threads", "[refine][threads]") {
    auto [family, params, eps] = GENERATE(table<std::string, ParamMap, double>({
        {"parallel", {{"l", 128}, {"d", 1}}, 0.05},
        {"random", {{"n", 15}, {"seed", 4}, {"size", 6}}, 0.03},
        {"array", {{"k", 4}}, 0.02},
    }));
    Scene scene = MakeScene(family, params);
    RefineOptions o = Options(eps);
    Refinement one = Refine(scene, o);
    REQUIRE(one.counters.links > 10000);  // deep enough to hand tasks to the workers
    for (int threads : {2, 3}) {
        INFO(family << " threads=" << threads);
        o.threads = threads;
        Refinement many = Refine(scene, o);
        CHECK(CounterDifferences(one.counters, many.counters) == "");
        CHECK(SameLinks(one.links, many.links));
        for (size_t p = 0; p < one.pairs.size(); ++p)
            CHECK(many.pairs[p].oracleCalls == one.pairs[p].oracleCalls);
        CheckInvariants(scene, many, GarmannOracle(eps));
    }
}
