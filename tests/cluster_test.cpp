// The cluster hierarchy and the clustered refinement (docs/conventions.md#clusters): a
// hand-computed case of four patches (tree, balls, oracle decisions, links, counters),
// the conservativeness of every cluster oracle, tiling, the counter invariants,
// agreement with the unclustered run, and independence of the thread count.
#include <catch2/catch.hpp>

#include <cmath>
#include <map>
#include <random>
#include <set>
#include <tuple>

#include "cluster/cluster_oracles.h"
#include "generators.h"
#include "hrbench/hrbench.h"
#include "hrbench/oracles/registry.h"
#include "refinement_helpers.h"
#include "visibility/culling.h"

using namespace hrbench;
using hrbench_test::CounterDifferences;
using hrbench_test::TilingViolations;

namespace {

RefineOptions Clustered(double eps, const std::string &oracle = "garmann", bool store = true) {
    RefineOptions o;
    o.eps = eps;
    o.oracle = oracle;
    o.storeLinks = store;
    o.clusters = true;
    return o;
}

// Two rows of two unit segments, 10 apart, facing each other; the columns 20 apart.
Scene FourPlates() {
    auto s = [](double ax, double ay, double bx, double by) {
        return Patch<Segment>{Segment{Vec2(ax, ay), Vec2(bx, by)}, {}};
    };
    return {"file",
            {},
            "",
            Patches<Segment>{s(0, 0, 1, 0), s(1, 10, 0, 10), s(20, 0, 21, 0), s(21, 10, 20, 10)}};
}

// The root patches of a node.
template <typename Shape>
std::vector<uint32_t> PatchesOf(const ClusterTree<Shape> &tree, uint32_t node) {
    if (!IsCluster(node))
        return {node};
    const auto &c = tree[ClusterIndex(node)];
    return {tree.Patches().begin() + c.begin, tree.Patches().begin() + c.end};
}

template <typename Shape>
double MeasureOf(const Refinement<Shape> &r, const Patches<Shape> &patches, uint32_t node) {
    return IsCluster(node) ? r.clusters[ClusterIndex(node)].measure : patches[node].shape.Measure();
}

// Checks the tiling of docs/conventions.md#clusters on a stored refinement: every
// unordered root pair covered once, by a cluster link, a refined root pair or (the
// rest) a culled one; and the area-weighted sum. With _exact_, the set check too.
template <typename Shape>
void CheckTiling(const Scene &scene, const Refinement<Shape> &r, const RefineOptions &o,
                 bool exact) {
    const Patches<Shape> &patches = scene.Get<Shape>();
    const uint32_t k = uint32_t(patches.size());
    const Counters &c = r.record.counters;
    double sum = 0, sumSquares = 0;
    for (const auto &p : patches)
        sum += p.shape.Measure(), sumSquares += p.shape.Measure() * p.shape.Measure();
    double linked = 0;
    for (const Link &link : r.links)
        linked += r.forest[link.i].Size() * r.forest[link.j].Size();
    for (const ClusterLink &link : r.clusterLinks)
        linked += MeasureOf(r, patches, link.a) * MeasureOf(r, patches, link.b);
    std::vector<uint8_t> cover(size_t(k) * k, 0);
    auto mark = [&](uint32_t p, uint32_t q) {
        ++cover[size_t(std::min(p, q)) * k + std::max(p, q)];
    };
    for (const ClusterLink &link : r.clusterLinks)
        for (uint32_t p : PatchesOf(r.clusters, link.a))
            for (uint32_t q : PatchesOf(r.clusters, link.b))
                mark(p, q);
    for (const PairTally &pair : r.pairs)
        mark(pair.p, pair.q);
    uint64_t culled = 0, twice = 0, notCulled = 0;
    double culledArea = 0;
    for (uint32_t p = 0; p < k; ++p)
        for (uint32_t q = p + 1; q < k; ++q) {
            uint8_t n = cover[size_t(p) * k + q];
            twice += n > 1;
            if (n == 0) {
                ++culled;
                culledArea += patches[p].shape.Measure() * patches[q].shape.Measure();
                if (exact)
                    notCulled +=
                        RefinesRootPair(ClassifyPair(patches[p].shape, patches[q].shape), p, q, o);
            }
        }
    CHECK(twice == 0);
    CHECK(notCulled == 0);
    CHECK(culled == c.culledPairs);
    CHECK(c.rootPairs == r.pairs.size() + c.culledPairs);
    double expected = (sum * sum - sumSquares) / 2;
    CHECK(linked + culledArea == Approx(expected).epsilon(1e-9));
}

// The counter invariants of docs/conventions.md#clusters.
void CheckCounters(const Counters &c, uint64_t patches) {
    CHECK(c.clusterNodes == (patches > 0 ? patches - 1 : 0));
    CHECK(c.clusterOracleCalls + c.clusterNodes == 2 * c.clusterLinks + c.rootPairs);
    CHECK(c.links == c.elementLinks + c.clusterLinks);
    CHECK(c.openedClusters <= c.clusterNodes);
}

// Element keys that name an element's shape: (root, depth, position).
template <typename Shape>
std::multiset<std::tuple<uint32_t, int, uint64_t, uint32_t, int, uint64_t>>
LinkShapes(const Refinement<Shape> &r) {
    std::multiset<std::tuple<uint32_t, int, uint64_t, uint32_t, int, uint64_t>> out;
    for (const Link &l : r.links)
        out.insert({r.forest[l.i].root, r.forest.Depth(l.i), r.forest.Position(l.i),
                    r.forest[l.j].root, r.forest.Depth(l.j), r.forest.Position(l.j)});
    return out;
}

}  // namespace

TEST_CASE("The cluster tree of four plates, by hand", "[clusters]") {
    Scene scene = FourPlates();
    ClusterTree<Segment> tree(scene.Get<Segment>());
    REQUIRE(tree.NumClusters() == 3);
    // Centroids (0.5,0), (0.5,10), (20.5,0), (20.5,10): x spans 20, y 10, so the root
    // splits on x, (x, index) ordering 0, 1 | 2, 3; each half then splits on y.
    CHECK(tree.Patches() == std::vector<uint32_t>{0, 1, 2, 3});
    const auto &root = tree[0], &left = tree[1], &right = tree[2];
    CHECK(root.children[0] == ClusterNode(1));
    CHECK(root.children[1] == ClusterNode(2));
    CHECK(left.children[0] == 0);
    CHECK(left.children[1] == 1);
    CHECK(right.children[0] == 2);
    CHECK(right.children[1] == 3);
    CHECK(root.parent == 0);
    CHECK(left.parent == 0);
    CHECK(right.parent == 0);
    CHECK(tree.ParentOfPatch(3) == 2);
    CHECK((root.begin == 0 && root.end == 4 && right.begin == 2 && right.end == 4));
    // Balls: corners [0,21] x [0,10] for the root, [0,1] x [0,10] and [20,21] x [0,10].
    CHECK(root.center == Vec2(10.5, 5));
    CHECK(root.radius == std::sqrt(10.5 * 10.5 + 25));
    CHECK(left.center == Vec2(0.5, 5));
    CHECK(left.radius == std::sqrt(0.25 + 25));
    CHECK(right.center == Vec2(20.5, 5));
    CHECK((root.measure == 4 && left.measure == 2));
    Ball<2> patch = PatchBall(scene.Get<Segment>(), 0);
    CHECK(patch.center == Vec2(0.5, 0));
    CHECK(patch.radius == 0.5);
}

TEST_CASE("The clustered refinement of four plates, by hand", "[clusters]") {
    Scene scene = FourPlates();
    RefineOptions plain = Clustered(0.5);
    plain.clusters = false;
    Refinement<Segment> all = Refine<Segment>(scene, plain);
    // Element links and calls of a root pair, from the unclustered run.
    auto tally = [&](uint32_t p, uint32_t q) {
        for (const PairTally &t : all.pairs)
            if (t.p == p && t.q == q)
                return t;
        FAIL("no pair " << p << "," << q);
        return PairTally{};
    };
    // The gap of the two columns: 20 - 2 sqrt(25.25) = 9.9501; of a patch and the other
    // column: sqrt(425) - 0.5 - sqrt(25.25) = 15.0906. Garmann in 2D: accept iff
    // max(A_X, A_Y) <= eps g, with A_X = A_Y = 2 for the columns, 2 for patch-column.
    SECTION("eps 0.5: the columns link at once") {
        Refinement<Segment> r = Refine<Segment>(scene, Clustered(0.5));
        const Counters &c = r.record.counters;
        REQUIRE(r.clusterLinks.size() == 1);
        CHECK((r.clusterLinks[0].a == ClusterNode(1) && r.clusterLinks[0].b == ClusterNode(2)));
        CHECK(c.clusterNodes == 3);
        CHECK(c.clusterOracleCalls == 1);
        CHECK(c.clusterLinks == 1);
        CHECK(c.openedClusters == 0);
        CHECK(c.rootPairs == 2);  // (0, 1) and (2, 3), each its cluster's own pair
        CHECK(c.culledPairs == 0);
        uint64_t elementLinks = tally(0, 1).links + tally(2, 3).links;
        CHECK(c.elementLinks == elementLinks);
        CHECK(c.links == elementLinks + 1);
        CHECK(c.oracleCalls == tally(0, 1).oracleCalls + tally(2, 3).oracleCalls + 1);
        CHECK(r.pairs.size() == 2);
        CHECK((r.pairs[0].p == 0 && r.pairs[0].q == 1 && r.pairs[1].p == 2));
    }
    SECTION("eps 0.15: each patch of the left column links the right column") {
        // 2 > 0.15 * 9.9501 = 1.49: the columns refuse and the left one (ties: X) opens;
        // 2 <= 0.15 * 15.0906 = 2.26: patch-column pairs accept.
        Refinement<Segment> r = Refine<Segment>(scene, Clustered(0.15));
        const Counters &c = r.record.counters;
        REQUIRE(r.clusterLinks.size() == 2);
        CHECK((r.clusterLinks[0].a == 0 && r.clusterLinks[0].b == ClusterNode(2)));
        CHECK((r.clusterLinks[1].a == 1 && r.clusterLinks[1].b == ClusterNode(2)));
        CHECK(c.clusterOracleCalls == 3);
        CHECK(c.clusterLinks == 2);
        CHECK(c.openedClusters == 1);
        CHECK(c.rootPairs == 2);
    }
    SECTION("eps 0.1: everything opens, the rows' pairs are culled") {
        // 2 > 0.1 * 15.0906: patch-column pairs refuse and the column opens. Root pairs
        // (0,1), (2,3), then (0,2) culled, (0,3), (1,2), (1,3) culled.
        Refinement<Segment> r = Refine<Segment>(scene, Clustered(0.1));
        const Counters &c = r.record.counters;
        CHECK(r.clusterLinks.empty());
        CHECK(c.clusterOracleCalls == 3);
        CHECK(c.clusterLinks == 0);
        CHECK(c.openedClusters == 2);
        CHECK(c.rootPairs == 6);
        CHECK(c.culledPairs == 2);
        REQUIRE(r.pairs.size() == 4);
        std::vector<std::pair<uint32_t, uint32_t>> order;
        for (const PairTally &t : r.pairs)
            order.push_back({t.p, t.q});
        CHECK(order == std::vector<std::pair<uint32_t, uint32_t>>{{0, 1}, {2, 3}, {0, 3}, {1, 2}});
        RefineOptions o = Clustered(0.1);
        o.clusters = false;
        Refinement<Segment> plainRun = Refine<Segment>(scene, o);
        CHECK(c.elementLinks == plainRun.record.counters.links);
        CHECK(c.nodes == plainRun.record.counters.nodes);
        CHECK(LinkShapes(r) == LinkShapes(plainRun));
    }
}

TEST_CASE("The initial linking of four plates, by hand, under either cluster bound", "[clusters]") {
    Scene scene = FourPlates();
    auto run = [&](double eps, ClusterBound bound) {
        RefineOptions o = Clustered(eps);
        o.clusterBound = bound;
        return Refine<Segment>(scene, o);
    };
    SECTION("without clusters: every root pair, the rows' two culled") {
        RefineOptions o = Clustered(0.5);
        o.clusters = false;
        const Counters c = Refine<Segment>(scene, o).record.counters;
        CHECK(c.linkingLinks == 4);  // 6 root pairs less 2 culled
        CHECK(c.linkingCalls == 6);
    }
    SECTION("cluster, eps 0.5: the columns link, and each column's own pair") {
        const Counters c = run(0.5, ClusterBound::Cluster).record.counters;
        CHECK(c.linkingLinks == 3);  // {C1, C2}, (0, 1), (2, 3)
        CHECK(c.linkingCalls == 3);  // one cluster call, two root pairs
    }
    SECTION("patch, eps 0.5: the columns are opened by the rule, each patch links the other") {
        // Two clusters never link: refused without a bound, the smaller (ties: X) opens;
        // patch-column gap 15.0906, 2 <= 0.5 * 15.0906: both accept.
        Refinement<Segment> r = run(0.5, ClusterBound::Patch);
        const Counters &c = r.record.counters;
        REQUIRE(r.clusterLinks.size() == 2);
        CHECK((r.clusterLinks[0].a == 0 && r.clusterLinks[0].b == ClusterNode(2)));
        CHECK((r.clusterLinks[1].a == 1 && r.clusterLinks[1].b == ClusterNode(2)));
        CHECK(c.clusterOracleCalls == 3);
        CHECK(c.openedClusters == 1);
        CHECK(c.linkingLinks == 4);
        CHECK(c.linkingCalls == 5);
        CheckCounters(c, 4);
    }
    SECTION("patch, eps 0.1: the patch-column pairs refuse too, as under cluster") {
        const Counters p = run(0.1, ClusterBound::Patch).record.counters;
        const Counters q = run(0.1, ClusterBound::Cluster).record.counters;
        CHECK(CounterDifferences(p, q) == "");
        CHECK(p.linkingLinks == 4);  // 6 root pairs less 2 culled
        CHECK(p.linkingCalls == 9);
    }
}

TEST_CASE("Under --cluster-bound patch every link above the patches has a patch at one end",
          "[clusters]") {
    Scene flat = MakeScene("random", {{"n", 60}, {"seed", 4}, {"size", 30}});
    Scene space = MakeScene("random3d", {{"n", 40}, {"seed", 4}, {"size", 10}});
    for (double eps : {0.05, 0.3}) {
        RefineOptions o = Clustered(eps);
        o.clusterBound = ClusterBound::Patch;
        Refinement<Segment> r = Refine<Segment>(flat, o);
        Refinement<Polygon> s = Refine<Polygon>(space, o);
        for (const ClusterLink &l : r.clusterLinks)
            CHECK((!IsCluster(l.a) || !IsCluster(l.b)));
        for (const ClusterLink &l : s.clusterLinks)
            CHECK((!IsCluster(l.a) || !IsCluster(l.b)));
        CheckCounters(r.record.counters, 60);
        CheckCounters(s.record.counters, 40);
        CheckTiling(flat, r, o, true);
        CheckTiling(space, s, o, true);
        for (const Counters &c : {r.record.counters, s.record.counters}) {
            CHECK(c.linkingLinks == c.clusterLinks + c.rootPairs - c.culledPairs);
            CHECK(c.linkingCalls == c.clusterOracleCalls + c.rootPairs);
        }
        // The same on three threads, count-only too.
        for (bool store : {true, false}) {
            RefineOptions t = o;
            t.threads = 3, t.storeLinks = store;
            CHECK(CounterDifferences(r.record.counters, Refine<Segment>(flat, t).record.counters) ==
                  "");
        }
    }
}

TEST_CASE("A scene of one or two patches has no cluster pair", "[clusters]") {
    Scene two = MakeScene("parallel", {{"l", 1}, {"d", 1}});
    Refinement<Segment> r = Refine<Segment>(two, Clustered(0.5));
    RefineOptions o = Clustered(0.5);
    o.clusters = false;
    Refinement<Segment> plain = Refine<Segment>(two, o);
    CHECK(r.record.counters.clusterNodes == 1);
    CHECK(r.record.counters.clusterOracleCalls == 0);
    CHECK(r.record.counters.links == plain.record.counters.links);
    CHECK(r.record.counters.oracleCalls == plain.record.counters.oracleCalls);
    Scene one = MakeScene("random", {{"n", 1}});
    Refinement<Segment> single = Refine<Segment>(one, Clustered(0.5));
    CHECK(single.record.counters.clusterNodes == 0);
    CHECK(single.record.counters.rootPairs == 0);
    CHECK(single.clusters.Patches() == std::vector<uint32_t>{0});
}

TEST_CASE("Clustered refinement tiles every root pair once, in 2D and 3D", "[clusters]") {
    for (uint32_t seed : {1u, 2u, 3u}) {
        Scene flat = MakeScene("random", {{"n", 40}, {"seed", seed}, {"size", 20}});
        for (double eps : {0.05, 0.2, 1.0}) {
            RefineOptions o = Clustered(eps);
            Refinement<Segment> r = Refine<Segment>(flat, o);
            CHECK(r.clusters.NumClusters() == 39);
            CheckCounters(r.record.counters, 40);
            CheckTiling(flat, r, o, true);
            CHECK(r.clusterLinks.size() == r.record.counters.clusterLinks);
        }
        Scene space = MakeScene("random3d", {{"n", 30}, {"seed", seed}, {"size", 10}});
        for (const std::string oracle : {"garmann", "hanrahan"}) {
            RefineOptions o = Clustered(oracle == "garmann" ? 0.05 : 0.01, oracle);
            Refinement<Polygon> r = Refine<Polygon>(space, o);
            CheckCounters(r.record.counters, 30);
            CheckTiling(space, r, o, true);
        }
    }
    // A larger scene: the sum only, and the invariants.
    Scene large = MakeScene("random", {{"n", 600}, {"seed", 7}, {"size", 200}});
    RefineOptions o = Clustered(0.1);
    Refinement<Segment> r = Refine<Segment>(large, o);
    CheckCounters(r.record.counters, 600);
    CheckTiling(large, r, o, false);
    CHECK(r.record.counters.rootPairs < 600 * 599 / 2);
    CHECK(r.record.counters.clusterLinks > 0);
}

TEST_CASE("Each refined root pair under clusters keeps oracle_calls = 2L - 1 and its tiling",
          "[clusters]") {
    Scene scene = MakeScene("random", {{"n", 50}, {"seed", 4}, {"size", 20}});
    Refinement<Segment> r = Refine<Segment>(scene, Clustered(0.1));
    // TilingViolations reads every link as an element link: compare on a copy whose
    // counters are the element ones.
    Refinement<Segment> elements = std::move(r);
    Counters &c = elements.record.counters;
    c.links = c.elementLinks;
    c.oracleCalls -= c.clusterOracleCalls;
    CHECK(TilingViolations(scene, elements) == "");
}

TEST_CASE("Without an accepted cluster pair, clusters change no element count", "[clusters]") {
    // eps so small that no cluster pair is accepted: the element refinement is the
    // unclustered one, in another order.
    Scene flat = MakeScene("random", {{"n", 25}, {"seed", 5}, {"size", 6}});
    for (const std::string oracle : {"garmann", "hanrahan"}) {
        double eps = oracle == "garmann" ? 0.02 : 0.002;
        RefineOptions o = Clustered(eps, oracle);
        o.minArea = 1e-3;
        Refinement<Segment> r = Refine<Segment>(flat, o);
        o.clusters = false;
        Refinement<Segment> plain = Refine<Segment>(flat, o);
        const Counters &c = r.record.counters, &p = plain.record.counters;
        REQUIRE(c.clusterLinks == 0);
        CHECK(c.nodes == p.nodes);
        CHECK(c.elementLinks == p.links);
        CHECK(c.oracleCalls - c.clusterOracleCalls == p.oracleCalls);
        CHECK(c.forcedLinks == p.forcedLinks);
        CHECK(c.culledPairs == p.culledPairs);
        CHECK(c.rootPairs == p.rootPairs);
        CHECK(LinkShapes(r) == LinkShapes(plain));
    }
    Scene space = MakeScene("random3d", {{"n", 15}, {"seed", 2}, {"size", 4}});
    RefineOptions o = Clustered(0.01, "garmann");
    o.minArea = 1e-3;
    o.subdivision = Subdivision::Quadtree;
    Refinement<Polygon> r = Refine<Polygon>(space, o);
    o.clusters = false;
    Refinement<Polygon> plain = Refine<Polygon>(space, o);
    const Counters &c = r.record.counters, &p = plain.record.counters;
    REQUIRE(c.clusterLinks == 0);
    CHECK(c.nodes == p.nodes);
    CHECK(c.elementLinks == p.links);
    CHECK(c.oracleCalls - c.clusterOracleCalls == p.oracleCalls);
    CHECK(c.forcedLinks == p.forcedLinks);
    CHECK(c.culledPairs == p.culledPairs);
    CHECK(LinkShapes(r) == LinkShapes(plain));
}

TEST_CASE("Clustered counts and links do not depend on the thread count", "[clusters]") {
    // Facing plates refine past the task depth (kernel.h), far ones link as clusters.
    Scene scene = MakeScene("array", {{"k", 80}, {"d", 1}, {"spacing", 1}});
    for (bool store : {true, false}) {
        RefineOptions o = Clustered(0.01, "hanrahan", store);
        Refinement<Segment> one = Refine<Segment>(scene, o);
        REQUIRE(one.record.counters.clusterLinks > 0);
        REQUIRE(one.record.counters.maxDepth >= 6);
        for (int threads : {2, 3}) {
            o.threads = threads;
            Refinement<Segment> r = Refine<Segment>(scene, o);
            CHECK(CounterDifferences(one.record.counters, r.record.counters) == "");
            CHECK(hrbench_test::SameLinks(one.links, r.links));
            // Count-only keeps no record of a root pair, on any number of threads.
            CHECK(r.pairs.empty() == !store);
            CHECK(one.pairs.empty() == !store);
            REQUIRE(r.clusterLinks.size() == one.clusterLinks.size());
            for (size_t k = 0; k < r.clusterLinks.size(); ++k)
                CHECK((r.clusterLinks[k].a == one.clusterLinks[k].a &&
                       r.clusterLinks[k].b == one.clusterLinks[k].b));
        }
    }
}

namespace {

// For each cluster link of _r_: the element oracle accepts every root pair under it,
// and pairs of their descendants down to depth 2.
template <typename Shape, typename Oracle>
uint64_t CheckConservative(const Scene &scene, const Refinement<Shape> &r, const Oracle &oracle,
                           Subdivision mode) {
    Forest<Shape> forest(scene.Get<Shape>(), SIZE_MAX, mode);
    uint64_t checked = 0, refused = 0;
    auto descendants = [&](uint32_t root) {
        std::vector<uint32_t> out{root};
        for (size_t k = 0; k < out.size() && forest.Depth(out[k]) < 2; ++k) {
            uint32_t first = forest.Children(out[k]);
            for (int c = 0; c < forest.Arity(); ++c)
                out.push_back(first + uint32_t(c));
        }
        return out;
    };
    for (const ClusterLink &link : r.clusterLinks)
        for (uint32_t p : PatchesOf(r.clusters, link.a))
            for (uint32_t q : PatchesOf(r.clusters, link.b))
                for (uint32_t i : descendants(p))
                    for (uint32_t j : descendants(q)) {
                        ++checked;
                        refused += !oracle.Acceptable(forest[i], forest[j]);
                    }
    CHECK(refused == 0);
    return checked;
}

// Checks every oracle's cluster form on _scene_ at each of _eps_ (squared for the form
// factor oracles); returns the element pairs checked per oracle.
template <typename Shape>
std::map<std::string, uint64_t> CheckAllOracles(Scene scene, const std::vector<double> &eps) {
    std::map<std::string, uint64_t> checked;
    // Some emission, for bf.
    std::mt19937 random(11);
    for (auto &p : scene.Get<Shape>())
        p.material.emission = std::uniform_real_distribution<double>(0, 2)(random);
    for (Subdivision mode : {Subdivision::Binary, Subdivision::Quadtree}) {
        if (Shape::kDimension == 2 && mode == Subdivision::Quadtree)
            continue;
        AllOracles::ForEach([&](auto tag) {
            using Oracle = typename decltype(tag)::template Type<Shape>;
            for (FfEstimate estimate :
                 {FfEstimate::ClampedCosine, FfEstimate::CentreCosine, FfEstimate::SolidAngle}) {
                bool readsEstimate = Oracle::kInfo.Reads("ff_estimate");
                if (!readsEstimate && estimate != kDefaultFfEstimate)
                    continue;
                for (double e : eps) {
                    RefineOptions o =
                        Clustered(std::string(Oracle::kInfo.name) == "garmann" ? e : e * e,
                                  Oracle::kInfo.name);
                    o.subdivision = mode;
                    o.ffEstimate = estimate;
                    o.minArea = 1e-2;
                    Refinement<Shape> r = Refine<Shape>(scene, o);
                    if (r.clusterLinks.empty())
                        continue;
                    INFO(Oracle::kInfo.name << " eps " << o.eps);
                    checked[Oracle::kInfo.name] += CheckConservative(
                        scene, r, MakeOracle<Oracle>(o, scene.Get<Shape>()), mode);
                }
            }
        });
    }
    return checked;
}

}  // namespace

TEST_CASE("Every cluster oracle is conservative: its links' element pairs would be accepted",
          "[clusters]") {
    for (uint32_t seed : {1u, 2u}) {
        auto flat = CheckAllOracles<Segment>(
            MakeScene("random", {{"n", 30}, {"seed", seed}, {"size", 15}}), {0.05, 0.2, 0.5});
        auto space = CheckAllOracles<Polygon>(
            MakeScene("random3d", {{"n", 25}, {"seed", seed}, {"size", 8}}), {0.05, 0.2, 0.5});
        for (const char *oracle : {"garmann", "hanrahan", "bf"}) {
            INFO(oracle << " seed " << seed);
            CHECK(flat[oracle] > 0);
            CHECK(space[oracle] > 0);
        }
    }
}

TEST_CASE("The translation method refuses clusters", "[clusters]") {
    Scene scene = MakeScene("parallel", {{"l", 4}, {"d", 1}});
    RefineOptions o = Clustered(0.5, "garmann", false);
    CHECK_THROWS_AS(Count(scene, o, "translation"), InputError);
}
