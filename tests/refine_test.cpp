// ProjectKernel against docs/conventions.md, in 2D and 3D: the worked examples,
// hand-computed cases, an independent transcription, the invariants every refinement
// must satisfy (tiling, oracle calls, trees), thread independence, visibility, and errors.
#include <catch2/catch.hpp>

#include <functional>
#include <limits>
#include <map>
#include <random>
#include <tuple>
#include <variant>

#if defined(__linux__)
#include <sys/mman.h>
#include <unistd.h>
#endif

#include "generators.h"
#include "hrbench/hrbench.h"
#include "refine/kernel.h"
#include "refinement_helpers.h"

using namespace hrbench;
using hrbench_test::CounterDifferences;
using hrbench_test::ForestDifferences;
using hrbench_test::RefinementDifferences;
using hrbench_test::SameLinks;
using hrbench_test::TilingViolations;

namespace {

RefineOptions Options(double eps, const std::string &oracle = "garmann", bool store = true) {
    RefineOptions o;
    o.eps = eps;
    o.oracle = oracle;
    o.storeLinks = store;
    return o;
}

RefineOptions Options3D(double eps, const std::string &oracle = "garmann",
                        Subdivision subdivision = Subdivision::Binary) {
    RefineOptions o = Options(eps, oracle, true);
    o.subdivision = subdivision;
    return o;
}

// A direct transcription of docs/conventions.md, independent of the engine: elements
// are keyed by (root, depth, position) in a map, the recursion is plain.
using ElementKey = std::tuple<uint32_t, int, uint64_t>;  // root, depth, position
struct ReferenceCounts {
    uint64_t nodes = 0, links = 0, calls = 0;
    std::vector<ElementKey> made;  // the elements below the roots, in the order made
    size_t madeFirst = 0;          // how many of them the first pass made (before the tasks)
};

// With _byLength_, the element to split is picked by comparing the lengths A instead of
// A^2 (the rule before docs/conventions.md stated A^2), to show where the two differ.
ReferenceCounts ReferenceGarmann(const Segment &p, const Segment &q, double eps,
                                 bool byLength = false) {
    struct Node {
        Vec2 a, b;
    };
    using Key = ElementKey;
    std::map<Key, Node> nodes;
    ReferenceCounts counts;
    nodes[{0, 0, 0}] = {p.a, p.b};
    nodes[{1, 0, 0}] = {q.a, q.b};
    // Ids follow the task order: a first pass leaves the pairs whose depths add up to
    // kTaskDepth as tasks, which are then refined in order.
    std::vector<std::pair<Key, Key>> tasks;
    bool firstPass = true;
    std::function<void(Key, Key)> project = [&](Key i, Key j) {
        if (firstPass && std::get<1>(i) + std::get<1>(j) >= kTaskDepth) {
            tasks.emplace_back(i, j);
            return;
        }
        ++counts.calls;
        Node ni = nodes[i], nj = nodes[j];
        Vec2 ci = 0.5 * (ni.a + ni.b), cj = 0.5 * (nj.a + nj.b);
        // A^2 = dx*dx + dy*dy, A = sqrt(A^2); the larger A^2 is split, ties to i.
        auto squared = [](const Node &n) {
            double dx = n.b.x() - n.a.x(), dy = n.b.y() - n.a.y();
            return dx * dx + dy * dy;
        };
        double ai2 = squared(ni), aj2 = squared(nj);
        if (std::max(std::sqrt(ai2), std::sqrt(aj2)) <= eps * (ci - cj).norm()) {
            ++counts.links;
            return;
        }
        bool splitI = byLength ? std::sqrt(ai2) >= std::sqrt(aj2) : ai2 >= aj2;
        Key s = splitI ? i : j;
        Node ns = splitI ? ni : nj;
        Vec2 m = 0.5 * (ns.a + ns.b);
        Key c0{std::get<0>(s), std::get<1>(s) + 1, 2 * std::get<2>(s)};
        Key c1{std::get<0>(s), std::get<1>(s) + 1, 2 * std::get<2>(s) + 1};
        if (nodes.count(c0) == 0)
            counts.made.insert(counts.made.end(), {c0, c1});
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
    firstPass = false;
    counts.madeFirst = counts.made.size();
    for (const auto &[i, j] : tasks)
        project(i, j);
    counts.nodes = nodes.size();
    return counts;
}

// Checks the invariants of docs/conventions.md on a stored refinement: the tiling, and
// every link satisfies the oracle or is forced, while the pair it came from did not.
template <typename Shape, typename Oracle>
void CheckInvariants(const Scene &scene, const Refinement<Shape> &r, const Oracle &oracle) {
    CHECK(TilingViolations(scene, r) == "");
    const Forest<Shape> &f = r.forest;
    uint64_t unacceptable = 0;
    for (const Link &link : r.links) {
        unacceptable += !oracle.Acceptable(f[link.i], f[link.j]);
        uint32_t pi = f.Parent(link.i), pj = f.Parent(link.j);
        bool fromI = pi != link.i && f[pi].sizeSquared >= f[link.j].sizeSquared;
        bool fromJ = pj != link.j && f[link.i].sizeSquared < f[pj].sizeSquared;
        if (fromI || fromJ) {
            bool someParentRejected = (fromI && !oracle.Acceptable(f[pi], f[link.j])) ||
                                      (fromJ && !oracle.Acceptable(f[link.i], f[pj]));
            CHECK(someParentRejected);
        } else {
            CHECK(f.Depth(link.i) + f.Depth(link.j) == 0);  // only a root pair has no parent
        }
    }
    CHECK(unacceptable == r.record.counters.forcedLinks);
}

}  // namespace

// ---------------------------------------------------------------------------------------
// Worked examples and hand-computed counts

TEST_CASE("The worked example of docs/conventions.md gives its published counts", "[refine]") {
    Scene scene = MakeScene("parallel", {{"l", 64}, {"d", 1}});
    Refinement<Segment> r = Refine<Segment>(scene, Options(0.25));
    CHECK(r.record.counters.nodes == 1022);
    CHECK(r.record.counters.leaves == 512);
    CHECK(r.record.counters.links == 5092);
    CHECK(r.record.counters.oracleCalls == 10183);
    CHECK(r.record.counters.maxDepth == 8);
    CHECK(r.record.counters.forcedLinks == 0);
    CHECK(r.record.counters.rootPairs == 1);
}

TEST_CASE("Small cases give the counts computed by hand", "[refine]") {
    SECTION("a pair acceptable at once is one link and one oracle call") {
        // l = d = 1: max(1, 1) <= 1 * 1 holds with equality, and ties are acceptable.
        Scene scene = MakeScene("parallel", {{"l", 1}, {"d", 1}});
        Refinement<Segment> r = Refine<Segment>(scene, Options(1));
        CHECK(r.record.counters.links == 1);
        CHECK(r.record.counters.oracleCalls == 1);
        CHECK(r.record.counters.nodes == 2);
        CHECK(r.record.counters.leaves == 2);
        CHECK(r.record.counters.maxDepth == 0);
    }
    SECTION("one level: P is halved first (tie), then Q once, its children shared") {
        // eps = 0.5: (P,Q) fails (1 > 0.5 * 1); P splits (tie). (P0,Q): 1 > 0.5*sqrt(1.0625)
        // -> Q splits; (P0,Q0): 0.5 <= 0.5*sqrt(1.25); (P0,Q1): 0.5 <= 0.5*1 (tie).
        // (P1,Q) fails likewise and reuses Q's children: (P1,Q0) tie, (P1,Q1) accepted.
        Scene scene = MakeScene("parallel", {{"l", 1}, {"d", 1}});
        Refinement<Segment> r = Refine<Segment>(scene, Options(0.5));
        CHECK(r.record.counters.links == 4);
        CHECK(r.record.counters.oracleCalls == 7);
        CHECK(r.record.counters.nodes == 6);
        CHECK(r.record.counters.leaves == 4);
        CHECK(r.record.counters.maxDepth == 1);
        CHECK(r.record.counters.linksPerDepth == std::vector<uint64_t>{0, 0, 4});
    }
    SECTION("collinear patches are culled and never refined") {
        Scene scene = MakeScene("array", {{"k", 3}});
        Refinement<Segment> r = Refine<Segment>(scene, Options(0.5));
        // 6 plates: the 3 + 3 pairs within a row are collinear, 9 pairs face each other.
        CHECK(r.record.counters.rootPairs == 15);
        CHECK(r.record.counters.culledPairs == 6);
        CHECK(r.pairs.size() == 9);
    }
}

TEST_CASE("Two unit squares at distance 1 give the hand-computed 3D counts", "[3d][refine]") {
    Scene scene = MakeScene("parallel3d", {});
    SECTION("eps = 1 accepts the root pair: max(1, 1) <= 1 * 1^2") {
        Refinement<Polygon> r = Refine<Polygon>(scene, Options3D(1));
        CHECK(r.record.counters.links == 1);
        CHECK(r.record.counters.oracleCalls == 1);
        CHECK(r.record.counters.nodes == 2);
    }
    SECTION("eps = 0.5 halves both plates along x; two pairs are ties r^2 = 1, accepted") {
        // (P,Q) rejected, P halved; (P0,Q) rejected (1 > 0.5 * 1.0625), Q halved;
        // (P0,Q0) 0.5 <= 0.5 * 1, (P0,Q1) 0.5 <= 0.5 * 1.25; (P1,Q) rejected, Q's halves
        // shared; (P1,Q0), (P1,Q1) accepted.
        Refinement<Polygon> r = Refine<Polygon>(scene, Options3D(0.5));
        CHECK(r.record.counters.nodes == 6);
        CHECK(r.record.counters.leaves == 4);
        CHECK(r.record.counters.links == 4);
        CHECK(r.record.counters.oracleCalls == 7);
        CHECK(r.record.counters.maxDepth == 1);
        CHECK(r.record.counters.linksPerDepth == std::vector<uint64_t>{0, 0, 4});
        REQUIRE(r.links.size() == 4);
        CHECK(r.forest[r.links[0].i].center.isApprox(Vec3(0.25, 0.5, 0)));
        CHECK(r.forest[r.links[0].j].center.isApprox(Vec3(0.25, 0.5, 1)));
    }
    SECTION("quadtree, eps = 0.5: both plates in four, 16 links") {
        // (P,Q) rejected; (P_k,Q): 1 > 0.5 r^2 for every quarter, Q split; quarters at
        // r^2 >= 1 satisfy 0.25 <= 0.5 r^2.
        Refinement<Polygon> r =
            Refine<Polygon>(scene, Options3D(0.5, "garmann", Subdivision::Quadtree));
        CHECK(r.record.counters.nodes == 10);
        CHECK(r.record.counters.links == 16);
        CHECK(r.record.counters.oracleCalls == 21);
    }
}

TEST_CASE("Refine dispatches on the shape of the scene's patches", "[refine]") {
    Scene flatScene = MakeScene("parallel", {{"l", 1}, {"d", 1}});
    AnyRefinement flat = Refine(flatScene, Options(0.5));
    REQUIRE(std::holds_alternative<Refinement<Segment>>(flat));
    const RunRecord &flatRecord = std::get<Refinement<Segment>>(flat).record;
    CHECK(flatRecord.method == "enumerate");
    CHECK(flatRecord.counters.links == 4);
    CHECK(flatRecord.seconds >= 0);
    Scene spaceScene = MakeScene("parallel3d", {});
    AnyRefinement space = Refine(spaceScene, Options3D(0.5));
    REQUIRE(std::holds_alternative<Refinement<Polygon>>(space));
    CHECK(std::get<Refinement<Polygon>>(space).record.counters.links == 4);
    CHECK_THROWS_WITH(Refine<Polygon>(flatScene, Options(0.5)),
                      Catch::Contains("does not hold polygons"));
    CHECK_THROWS_AS(Refine<Segment>(spaceScene, Options(0.5)), InputError);
}

// ---------------------------------------------------------------------------------------
// Preferred subdivision: the larger A^2, exactly

TEST_CASE("The element with the larger A^2 is split, even where sqrt merges the lengths",
          "[refine]") {
    SECTION("2D: A_P = A_Q = 1, but A_Q^2 is one ulp above A_P^2 = 1") {
        // Q's (dx, dy) = (-1, 2^-26): A_Q^2 = 1 + 2^-52, A_Q = sqrt(1 + 2^-52) = 1. The
        // root pair is rejected (1 > 0.5 r, r ~ 1): a comparison of the lengths would
        // tie and split P; the squared lengths split Q.
        Segment p{Vec2(0, 0), Vec2(1, 0)}, q{Vec2(1, 1), Vec2(0, 1 + 0x1p-26)};
        REQUIRE(p.Length() == q.Length());
        REQUIRE(q.SquaredLength() == std::nextafter(p.SquaredLength(), 2.0));
        Scene scene{"file", {}, "", Patches<Segment>{{p, {}}, {q, {}}}};
        Refinement<Segment> r = Refine<Segment>(scene, Options(0.5));
        // Links come depth-first, first child first. Q split first: (P, Q0) is rejected
        // and splits P, so the first two links are (P0, Q0), (P1, Q0), sharing Q0 (had P
        // been split first, they would be (P0, Q0), (P0, Q1), sharing P0).
        REQUIRE(r.links.size() == 4);
        CHECK(r.links[0].j == r.links[1].j);
        CHECK(r.links[0].i != r.links[1].i);
        CHECK(r.forest.Depth(r.links[0].j) == 1);
        CHECK(r.record.counters.oracleCalls == 7);
        ReferenceCounts ref = ReferenceGarmann(p, q, 0.5);
        CHECK(r.record.counters.nodes == ref.nodes);
        CHECK(r.record.counters.links == ref.links);
        CHECK(r.record.counters.oracleCalls == ref.calls);
        CheckInvariants(scene, r, GarmannOracle<Segment>(0.5, scene.Get<Segment>()));
        SECTION("in the other scene order the tie is gone as well: Q, now first, is split") {
            Scene swapped{"file", {}, "", Patches<Segment>{{q, {}}, {p, {}}}};
            Refinement<Segment> s = Refine<Segment>(swapped, Options(0.5));
            REQUIRE(s.links.size() == 4);
            CHECK(s.links[0].i == s.links[1].i);  // (Q0, P0), (Q0, P1)
            CHECK(s.links[0].j != s.links[1].j);
        }
    }
    SECTION("3D: A_P = A_Q = 1, but A_Q^2 is one ulp above A_P^2 = 1") {
        // P: V = (0, 0, 2), A^2 = 1. Q: V = (0, 2^-25, -2), A^2 = (4 + 2^-50) / 4 =
        // 1 + 2^-52, A = 1. The root pair is rejected (1 > 0.5 r^2, r ~ 1).
        Polygon p = Polygon::Triangle({0, 0, 0}, {2, 0, 0}, {0, 1, 0});
        Polygon q = Polygon::Triangle({0, 0, 1}, {0, 1, 1 + 0x1p-26}, {2, 0, 1});
        REQUIRE(p.Area() == q.Area());
        REQUIRE(q.SquaredArea() == std::nextafter(p.SquaredArea(), 2.0));
        Scene scene{"file", {}, "", Patches<Polygon>{{p, {}}, {q, {}}}};
        REQUIRE_NOTHROW(ValidateScene(scene));
        Refinement<Polygon> r = Refine<Polygon>(scene, Options3D(0.5));
        // As in 2D: Q split first, then P under (P, Q0): the first two links share Q0.
        REQUIRE(r.links.size() >= 2);
        CHECK(r.links[0].j == r.links[1].j);
        CHECK(r.links[0].i != r.links[1].i);
        CHECK(r.forest.Depth(r.links[0].j) == 1);
        CheckInvariants(scene, r, GarmannOracle<Polygon>(0.5, scene.Get<Polygon>()));
    }
}

TEST_CASE("The angled example of docs/conventions.md: Q first, one deeper tie decided by A^2",
          "[refine]") {
    // angled l=1.9 angle=37.3 gap=0.07: A_P = 1.9, A_P^2 = 3.61; Q's (dx, dy) give
    // A_Q^2 = 3.6100000000000003 and A_Q = 1.9000000000000001 (a hypot() would give 1.9
    // and a tie). Q is split first. At depths (6, 6) a pair has equal lengths
    // 0.029687499999999978 whose squares differ in the last bit, and Q's is larger: Q is
    // split there too (a comparison of the lengths split P: 843 calls, 422 links).
    Scene scene = MakeScene("angled", {{"l", 1.9}, {"angle", 37.3}, {"gap", 0.07}});
    const Segment &p = scene.Get<Segment>()[0].shape, &q = scene.Get<Segment>()[1].shape;
    CHECK(p.SquaredLength() == 3.61);
    CHECK(q.SquaredLength() == std::nextafter(3.61, 4.0));
    Refinement<Segment> r = Refine<Segment>(scene, Options(0.231));
    CHECK(r.record.counters.oracleCalls == 841);
    CHECK(r.record.counters.links == 421);
    CHECK(r.record.counters.nodes == 138);
    ReferenceCounts ref = ReferenceGarmann(p, q, 0.231);
    CHECK(r.record.counters.nodes == ref.nodes);
    CHECK(r.record.counters.links == ref.links);
    CHECK(r.record.counters.oracleCalls == ref.calls);
    ReferenceCounts byLength = ReferenceGarmann(p, q, 0.231, true);
    CHECK(byLength.calls == 843);
    CHECK(byLength.links == 422);
    CheckInvariants(scene, r, GarmannOracle<Segment>(0.231, scene.Get<Segment>()));
}

TEST_CASE("Option --min-area compares A = sqrt(A^2) with the bound, exactly, on A^2", "[refine]") {
    // SquaredSizeBound(m) is the least s with sqrt(s) >= m: s < bound iff sqrt(s) < m.
    CHECK(SquaredSizeBound(0) == 0);
    CHECK(SquaredSizeBound(1) == 1);
    CHECK(SquaredSizeBound(0.5) == 0.25);
    CHECK(SquaredSizeBound(std::numeric_limits<double>::max()) ==
          std::numeric_limits<double>::infinity());
    CHECK(SquaredSizeBound(std::numeric_limits<double>::denorm_min()) > 0);
    std::mt19937_64 rng(5);
    std::uniform_real_distribution<double> u(0.5, 1), e(-700, 700);
    for (int k = 0; k < 20000; ++k) {
        double m = std::ldexp(u(rng), int(e(rng)));
        double bound = SquaredSizeBound(m);
        double s = m * m;
        for (int step = 0; step < 4; ++step)
            s = std::nextafter(s, 0.0);
        for (int step = 0; step < 8; ++step, s = std::nextafter(s, HUGE_VAL))
            REQUIRE((std::sqrt(s) < m) == (s < bound));
    }
}

// ---------------------------------------------------------------------------------------
// An independent transcription

TEST_CASE("Counts agree with an independent transcription of docs/conventions.md", "[refine]") {
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
    ReferenceCounts ref =
        ReferenceGarmann(scene.Get<Segment>()[0].shape, scene.Get<Segment>()[1].shape, eps);
    Refinement<Segment> r = Refine<Segment>(scene, Options(eps, "garmann", false));
    INFO("l=" << l << " d=" << d << " offset=" << offset << " l2=" << l2 << " eps=" << eps);
    CHECK(r.record.counters.nodes == ref.nodes);
    CHECK(r.record.counters.links == ref.links);
    CHECK(r.record.counters.oracleCalls == ref.calls);
}

TEST_CASE("Element ids follow the order the refinement first splits each element, in task "
          "order, on every thread count",
          "[refine][threads]") {
    // The last column: how many elements the tasks make, by the reference (the rest are
    // made by the first pass).
    auto [l, d, offset, l2, eps, byTasks] =
        GENERATE(table<double, double, double, double, double, size_t>({
            {64, 1, 0, 64, 0.1, 3968},
            {8, 0.5, -2, 5, 0.35, 28},
            {32, 1, 0.25, 32, 0.5, 128},
            {1, 1, 0, 1, 0.05, 0},
        }));
    Scene scene = MakeScene("parallel", {{"l", l}, {"d", d}, {"offset", offset}, {"l2", l2}});
    ReferenceCounts ref =
        ReferenceGarmann(scene.Get<Segment>()[0].shape, scene.Get<Segment>()[1].shape, eps);
    CHECK(ref.made.size() - ref.madeFirst == byTasks);
    for (int threads : {1, 2, 3}) {
        INFO("l=" << l << " d=" << d << " offset=" << offset << " l2=" << l2 << " eps=" << eps
                  << " threads=" << threads);
        RefineOptions o = Options(eps);
        o.threads = threads;
        Refinement<Segment> r = Refine<Segment>(scene, o);
        const Forest<Segment> &f = r.forest;
        REQUIRE(f.Size() == 2 + ref.made.size());
        size_t differ = 0;
        for (uint32_t e = 2; e < f.Size(); ++e)
            differ += ElementKey{f[e].root, f.Depth(e), f.Position(e)} != ref.made[e - 2];
        CHECK(differ == 0);
    }
}

// ---------------------------------------------------------------------------------------
// Invariants: tiling, oracle calls, trees

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
        Refinement<Segment> r = Refine<Segment>(scene, Options(eps));
        CheckInvariants(scene, r, GarmannOracle<Segment>(eps, scene.Get<Segment>()));
        REQUIRE(r.record.counters.links > 0);
    }
    SECTION("hanrahan") {
        Refinement<Segment> r = Refine<Segment>(scene, Options(eps / 10, "hanrahan"));
        CheckInvariants(scene, r, HanrahanOracle<Segment>(eps / 10, scene.Get<Segment>()));
        REQUIRE(r.record.counters.links > 0);
    }
}

TEST_CASE("3D links tile every root pair and oracle calls follow from the links", "[3d][refine]") {
    std::vector<std::pair<Scene, double>> cases = {
        {MakeScene("parallel3d", {{"l", 4}, {"w", 2}, {"ox", 0.5}}), 0.05},
        {MakeScene("angled3d", {{"angle", 70}}), 0.1},
        {MakeScene("occluded3d", {}), 0.1},
        {MakeScene("array3d", {{"k", 2}}), 0.2},
        {MakeScene("random3d", {{"n", 8}, {"seed", 4}, {"size", 3}}), 0.2},
    };
    for (const auto &[scene, eps] : cases) {
        INFO(scene.family);
        for (std::string oracle : {"garmann", "hanrahan"})
            for (Subdivision s : {Subdivision::Binary, Subdivision::Quadtree}) {
                double e = oracle == "garmann" ? eps : eps / 4;
                Refinement<Polygon> r = Refine<Polygon>(scene, Options3D(e, oracle, s));
                CHECK(r.record.counters.links > 2);
                CHECK(r.record.counters.rays == 0);
                CHECK(r.record.counters.visibilityQueries == 0);
                CHECK(r.record.counters.occludedPairs == 0);
                CHECK(r.forest.Mode() == s);
                CHECK(TilingViolations(scene, r) == "");
            }
    }
}

TEST_CASE("Every 3D link satisfies the 3D oracle unless forced", "[3d][refine]") {
    Scene scene = MakeScene("perpendicular3d", {{"gap", 0}});
    RefineOptions o = Options3D(0.05);
    o.minArea = 1e-3;
    Refinement<Polygon> r = Refine<Polygon>(scene, o);
    GarmannOracle<Polygon> oracle(0.05, scene.Get<Polygon>());
    uint64_t unacceptable = 0;
    for (const Link &link : r.links)
        unacceptable += !oracle.Acceptable(r.forest[link.i], r.forest[link.j]);
    CHECK(unacceptable == r.record.counters.forcedLinks);
    CHECK(r.record.counters.forcedLinks > 0);
    CheckInvariants(scene, r, oracle);
}

// ---------------------------------------------------------------------------------------
// Modes and recursion limits

TEST_CASE("Counts are identical in count-only and store mode and on every run", "[refine]") {
    Scene scene = MakeScene("random", {{"n", 20}, {"seed", 3}, {"size", 8}});
    std::string oracle = GENERATE(as<std::string>{}, "garmann", "hanrahan");
    double eps = oracle == "garmann" ? 0.2 : 0.02;
    Refinement<Segment> stored = Refine<Segment>(scene, Options(eps, oracle, true));
    Refinement<Segment> counted = Refine<Segment>(scene, Options(eps, oracle, false));
    Refinement<Segment> again = Refine<Segment>(scene, Options(eps, oracle, false));
    REQUIRE(stored.record.counters.links > 100);  // not a trivial case
    for (const Refinement<Segment> *r : {&counted, &again}) {
        CHECK(CounterDifferences(stored.record.counters, r->record.counters) == "");
        CHECK(r->links.empty());
    }
}

TEST_CASE("Recursion limits force links and are counted", "[refine]") {
    Scene room = MakeScene("room", {{"w", 2}, {"h", 1}});
    SECTION("--min-area stops subdivision of elements shorter than A") {
        RefineOptions o = Options(0.1);
        o.minArea = 0.01;
        Refinement<Segment> r = Refine<Segment>(room, o);
        CHECK(r.record.counters.forcedLinks > 0);
        CHECK(r.record.counters.rootPairs == 6);
        CHECK(r.record.counters.culledPairs == 0);  // in a convex room every wall sees every other
        CheckInvariants(room, r, GarmannOracle<Segment>(0.1, room.Get<Segment>()));
        for (uint32_t e = 0; e < r.forest.Size(); ++e)
            if (r.forest[e].firstChild != kNoChildren)
                CHECK(r.forest[e].Size() >= 0.01);
    }
    SECTION("--max-depth bounds the depth of every element") {
        RefineOptions o = Options(0.1);
        o.maxDepth = 5;
        Refinement<Segment> r = Refine<Segment>(room, o);
        CHECK(r.record.counters.maxDepth == 5);
        CHECK(r.record.counters.forcedLinks > 0);
        CheckInvariants(room, r, GarmannOracle<Segment>(0.1, room.Get<Segment>()));
    }
}

// ---------------------------------------------------------------------------------------
// Link storage

TEST_CASE("LinkBuffer::Discard loses only whole pages inside the range it is given",
          "[refine][links]") {
    LinkBuffer links;
    const size_t n = 1 << 20;
    links.Reserve(n);
    for (uint32_t k = 0; k < n; ++k)
        links.Append({k, ~k});
    // Ranges that start and end inside pages, one of them empty of whole pages.
    links.Discard(1000, 300001);
    links.Discard(500003, 500100);
    for (size_t k = 0; k < n; ++k) {
        bool inside = (k >= 1000 && k < 300001) || (k >= 500003 && k < 500100);
        if (!inside && (links[k].i != k || links[k].j != ~uint32_t(k)))
            FAIL("link " << k << " outside the discarded ranges changed");
    }
    // What was given back reads as zero; the buffer keeps its size and stays usable.
    CHECK(links[150000].i == 0);
    CHECK(links.size() == n);
    links[150000] = {7, 8};
    CHECK(links[150000].j == 8);
}

TEST_CASE("LinkBuffer::Populate backs the pages of a range and changes no link",
          "[refine][links]") {
    LinkBuffer links;
    const size_t n = 1 << 20;  // 8 MiB: fresh pages, none backed before they are touched
    links.Reserve(n);
    for (uint32_t k = 0; k < 1000; ++k)
        links.Append({k, ~k});
    bool backed = links.Populate(500, 300001);  // from inside a page to inside another
    for (uint32_t k = 0; k < 1000; ++k)
        if (links[k].i != k || links[k].j != ~k)
            FAIL("link " << k << " changed");
#if defined(__linux__)
    if (backed) {  // every page that holds one of links [500, 300001) is in memory
        const uintptr_t page = uintptr_t(sysconf(_SC_PAGESIZE));
        uintptr_t first = reinterpret_cast<uintptr_t>(&links[500]) / page * page;
        uintptr_t last = reinterpret_cast<uintptr_t>(&links[300000]) / page * page + page;
        std::vector<unsigned char> resident((last - first) / page);
        REQUIRE(mincore(reinterpret_cast<void *>(first), last - first, resident.data()) == 0);
        for (size_t p = 0; p < resident.size(); ++p)
            if (!(resident[p] & 1))
                FAIL("page " << p << " of the range is not in memory");
    }
#endif
    (void)backed;
    links.Append({7, 8});
    CHECK(links[1000].j == 8);
}

// ---------------------------------------------------------------------------------------
// Determinism across threads

TEST_CASE("Counts, element ids and links do not depend on the number of threads",
          "[refine][threads]") {
    auto [family, params, eps] = GENERATE(table<std::string, ParamMap, double>({
        {"parallel", {{"l", 128}, {"d", 1}}, 0.05},
        {"random", {{"n", 15}, {"seed", 4}, {"size", 6}}, 0.03},
        {"array", {{"k", 4}}, 0.02},
    }));
    Scene scene = MakeScene(family, params);
    RefineOptions o = Options(eps);
    Refinement<Segment> one = Refine<Segment>(scene, o);
    REQUIRE(one.record.counters.links > 10000);  // deep enough to hand tasks to the workers
    for (int threads : {2, 3}) {
        INFO(family << " threads=" << threads);
        o.threads = threads;
        Refinement<Segment> many = Refine<Segment>(scene, o);
        CHECK(CounterDifferences(one.record.counters, many.record.counters) == "");
        CHECK(SameLinks(one.links, many.links));
        for (size_t p = 0; p < one.pairs.size(); ++p)
            CHECK(many.pairs[p].oracleCalls == one.pairs[p].oracleCalls);
        CheckInvariants(scene, many, GarmannOracle<Segment>(eps, scene.Get<Segment>()));
        CHECK(ForestDifferences(one.forest, many.forest) == "");  // canonical element ids
    }
}

TEST_CASE("Count-only counters do not depend on the number of threads, nor on which worker "
          "refines which task",
          "[refine][threads]") {
    // Several workers' trees are counted as one, not merged: the counters must be those
    // of the merged trees that store mode builds, for every scene, arity and visibility.
    auto check = [](const Scene &scene, RefineOptions o) {
        AnyRefinement reference = Refine(scene, o);  // links stored, trees merged
        const Counters &want = std::visit(
            [](const auto &r) -> const Counters & { return r.record.counters; }, reference);
        REQUIRE(want.links > 2000);  // deep enough to hand tasks to the workers
        o.storeLinks = false;
        for (int threads : {1, 2, 3, 5}) {
            INFO(scene.family << " threads=" << threads);
            o.threads = threads;
            std::visit(
                [&](const auto &r) {
                    CHECK(CounterDifferences(want, r.record.counters) == "");
                    // On several threads the result keeps only the roots.
                    CHECK(r.forest.Size() == (threads == 1 ? want.nodes : r.forest.NumRoots()));
                },
                Refine(scene, o));
        }
    };
    check(MakeScene("parallel", {{"l", 128}, {"d", 1}}), Options(0.05));
    check(MakeScene("random", {{"n", 15}, {"seed", 4}, {"size", 6}}), Options(0.03));
    check(MakeScene("array", {{"k", 4}}), Options(0.02, "hanrahan"));
    check(MakeScene("parallel3d", {{"l", 4}, {"w", 4}}), Options3D(0.05));
    check(MakeScene("parallel3d", {{"l", 4}, {"w", 4}}),
          Options3D(0.05, "garmann", Subdivision::Quadtree));
    RefineOptions visible = Options3D(0.02, "hanrahan");
    visible.minArea = 1e-2;
    visible.visibility = VisibilityMode::Fraction;
    check(MakeScene("cornell", {}), visible);
}

TEST_CASE("3D counts and links do not depend on the number of threads", "[3d][refine][threads]") {
    Scene scene = MakeScene("parallel3d", {{"l", 4}, {"w", 4}});
    for (VisibilityMode mode : {VisibilityMode::None, VisibilityMode::Fraction}) {
        RefineOptions o = Options3D(0.05);
        o.visibility = mode;
        o.raysPerSide = 2;
        Refinement<Polygon> one = Refine<Polygon>(scene, o);
        o.threads = 4;
        Refinement<Polygon> four = Refine<Polygon>(scene, o);
        CHECK(CounterDifferences(one.record.counters, four.record.counters) == "");
        CHECK(SameLinks(one.links, four.links));
        CHECK(one.record.counters.links > 1000);        // enough for tasks on several threads
        CHECK(RefinementDifferences(one, four) == "");  // tallies and element ids too
    }
}

// ---------------------------------------------------------------------------------------
// Visibility

TEST_CASE("Visibility none counts nothing; fraction on an unoccluded scene changes nothing",
          "[3d][visibility][refine]") {
    Scene scene = MakeScene("parallel3d", {{"l", 2}});
    RefineOptions o = Options3D(0.05);
    Refinement<Polygon> none = Refine<Polygon>(scene, o);
    o.visibility = VisibilityMode::Fraction;
    Refinement<Polygon> fraction = Refine<Polygon>(scene, o);
    CHECK(none.record.counters.links == fraction.record.counters.links);
    CHECK(none.record.counters.oracleCalls == fraction.record.counters.oracleCalls);
    CHECK(fraction.record.counters.visibilityQueries == fraction.record.counters.oracleCalls);
    CHECK(fraction.record.counters.rays ==
          81 * fraction.record.counters.visibilityQueries);  // k = 3
    CHECK(fraction.record.counters.occludedPairs == 0);
}

TEST_CASE("A blocker that hides everything leaves no link between the plates",
          "[3d][visibility][refine]") {
    Scene scene = MakeScene("occluded3d", {{"bl", 10}});
    RefineOptions o = Options3D(0.1);
    o.visibility = VisibilityMode::Fraction;
    Refinement<Polygon> r = Refine<Polygon>(scene, o);
    const Counters &c = r.record.counters;
    uint64_t plateLinks = 0;
    for (const Link &link : r.links)
        plateLinks += r.forest[link.i].root == 0 && r.forest[link.j].root == 1;
    CHECK(plateLinks == 0);
    CHECK(c.occludedPairs >= 1);
    // Each call links, is occluded or splits in two: calls = 2 (links + occluded) - pairs.
    CHECK(c.oracleCalls == 2 * (c.links + c.occludedPairs) - (c.rootPairs - c.culledPairs));
}

TEST_CASE("An occluder reduces the links of the plates with visibility fraction",
          "[3d][visibility][refine]") {
    RefineOptions o = Options3D(0.02);
    o.visibility = VisibilityMode::Fraction;
    Scene plates = MakeScene("parallel3d", {}), occluded = MakeScene("occluded3d", {});
    Refinement<Polygon> open = Refine<Polygon>(plates, o);
    Refinement<Polygon> blocked = Refine<Polygon>(occluded, o);
    uint64_t plateLinks = 0;
    for (const Link &link : blocked.links)
        plateLinks += blocked.forest[link.i].root == 0 && blocked.forest[link.j].root == 1;
    const Counters &c = blocked.record.counters;
    CHECK(plateLinks < open.record.counters.links);
    CHECK(c.occludedPairs > 0);
    CHECK(c.oracleCalls == 2 * (c.links + c.occludedPairs) - (c.rootPairs - c.culledPairs));
}

TEST_CASE("Visibility refine splits partially visible pairs down to the limit",
          "[3d][visibility][refine]") {
    Scene scene = MakeScene("occluded3d", {});
    RefineOptions o = Options3D(0.1);
    o.visibility = VisibilityMode::Refine;
    CHECK_THROWS_WITH(Refine(scene, o), Catch::Contains("--visibility refine"));
    o.maxDepth = 6;
    Refinement<Polygon> refine = Refine<Polygon>(scene, o);
    o.visibility = VisibilityMode::Fraction;
    Refinement<Polygon> fraction = Refine<Polygon>(scene, o);
    CHECK(refine.record.counters.forcedLinks > 0);
    CHECK(refine.record.counters.links > fraction.record.counters.links);
}

TEST_CASE("Visibility applies to 2D scenes: the occluded family", "[visibility][refine]") {
    RefineOptions o;
    o.eps = 0.05;
    o.storeLinks = true;
    Scene scene = MakeScene("occluded", {{"l", 4}});
    Refinement<Segment> none = Refine<Segment>(scene, o);
    o.visibility = VisibilityMode::Fraction;
    Refinement<Segment> fraction = Refine<Segment>(scene, o);
    const Counters &c = fraction.record.counters;
    CHECK(none.record.counters.occludedPairs == 0);
    CHECK(c.occludedPairs > 0);
    CHECK(c.rays == 9 * c.visibilityQueries);  // k = 3
    CHECK(c.oracleCalls == 2 * (c.links + c.occludedPairs) - (c.rootPairs - c.culledPairs));
    // Unoccluded 2D: the worked example is unchanged by visibility.
    Scene parallel = MakeScene("parallel", {{"l", 64}, {"d", 1}});
    o.eps = 0.25;
    Refinement<Segment> worked = Refine<Segment>(parallel, o);
    CHECK(worked.record.counters.links == 5092);
    CHECK(worked.record.counters.oracleCalls == 10183);
}

// ---------------------------------------------------------------------------------------
// Scenes from the generators and from meshes

TEST_CASE("The Cornell box refines with a recursion limit, and occlusion removes links",
          "[3d][refine]") {
    Scene scene = MakeScene("cornell", {});
    RefineOptions o = Options3D(0.02, "hanrahan");
    o.minArea = 1e-2;
    o.storeLinks = false;
    CHECK_THROWS_AS(Refine(scene, Options3D(0.02, "hanrahan")), InputError);  // touching
    Refinement<Polygon> r = Refine<Polygon>(scene, o);
    CHECK(r.record.counters.rootPairs == 17 * 16 / 2);
    CHECK(r.record.counters.culledPairs > 20);  // coplanar light and ceiling, faces of each block
    CHECK(r.record.counters.links > 1000);
    CHECK(r.record.counters.forcedLinks > 0);
    o.visibility = VisibilityMode::Fraction;
    Refinement<Polygon> visible = Refine<Polygon>(scene, o);
    CHECK(visible.record.counters.occludedPairs > 0);
    CHECK(visible.record.counters.links < r.record.counters.links);
}

TEST_CASE("An OBJ mesh refines as the family it copies", "[3d][mesh][refine]") {
    Scene mesh = LoadMesh(std::string(HRBENCH_TEST_DATA) + "/two_plates.obj");
    Refinement<Polygon> a = Refine<Polygon>(mesh, Options3D(0.03));
    Scene family = MakeScene("parallel3d", {});
    Refinement<Polygon> b = Refine<Polygon>(family, Options3D(0.03));
    CHECK(a.record.counters.links == b.record.counters.links);
    CHECK(a.record.counters.nodes == b.record.counters.nodes);
    CHECK(a.record.counters.oracleCalls == b.record.counters.oracleCalls);
}

// ---------------------------------------------------------------------------------------
// Errors

TEST_CASE("Refinement that cannot terminate is an error, not a hang", "[refine][errors]") {
    SECTION("touching patches without a recursion limit are rejected before refining") {
        Scene touching = MakeScene("perpendicular", {{"gap", 0}});
        CHECK_THROWS_AS(Refine(touching, Options(0.5)), InputError);
        CHECK_THROWS_WITH(Refine(touching, Options(0.5)), Catch::Contains("--min-area"));
    }
    SECTION("a recursion limit makes touching patches terminate") {
        RefineOptions o = Options(0.5);
        o.minArea = 1e-3;
        Scene touching = MakeScene("perpendicular", {{"gap", 0}});
        Refinement<Segment> r = Refine<Segment>(touching, o);
        CHECK(r.record.counters.forcedLinks > 0);
    }
    SECTION("a --min-area too small for the safety depth names the pair") {
        RefineOptions o = Options(0.5);
        o.minArea = 1e-300;
        Scene touching = MakeScene("perpendicular", {{"gap", 0}});
        CHECK_THROWS_AS(Refine(touching, o), LimitError);
    }
    SECTION("a memory budget too small for the links stops the run") {
        RefineOptions o = Options(0.01);
        o.memoryBudget = 1 << 20;
        Scene scene = MakeScene("parallel", {{"l", 1024}});
        CHECK_THROWS_AS(Refine(scene, o), LimitError);
    }
}

TEST_CASE("The memory budget counts the records kept per refined root pair", "[refine][errors]") {
    // Scenes of many patches, most pairs linked whole: their records (a PairTally of 24
    // bytes per refined pair) outweigh the trees, and in count-only mode everything else.
    struct Case {
        const char *family;
        ParamMap params;
        bool store;
        int threads;
        bool progress;
    };
    std::vector<Case> cases = {
        {"random", {{"n", 1500}, {"size", 50}}, false, 1, false},
        {"random", {{"n", 1500}, {"size", 50}}, true, 2, true},
        {"random3d", {{"n", 1500}, {"size", 30}}, false, 2, false},
        {"random3d", {{"n", 1500}, {"size", 30}}, true, 1, true},
    };
    for (const Case &c : cases) {
        INFO(c.family << (c.store ? " store" : " count-only") << ", " << c.threads << " threads"
                      << (c.progress ? ", progress" : ""));
        Scene scene = MakeScene(c.family, c.params);
        RefineProgress progress;
        RefineOptions o = Options(0.5, "garmann", c.store);
        o.threads = c.threads;
        o.progress = c.progress ? &progress : nullptr;
        o.memoryBudget = size_t(1) << 32;
        const size_t records =
            std::visit([](const auto &r) { return r.pairs.size(); }, Refine(scene, o)) *
            sizeof(PairTally);
        REQUIRE(records > (size_t(3) << 20));
        // Half the records' bytes: the records alone exceed it.
        o.memoryBudget = records / 2;
        CHECK_THROWS_WITH(Refine(scene, o), Catch::Contains("refined root pairs") &&
                                                Catch::Contains("memory budget"));
        // Where a run fits, what it keeps fits: records, trees and links.
        int fitted = 0;
        for (size_t budget : {records, 2 * records, 4 * records, 8 * records}) {
            o.memoryBudget = budget;
            try {
                std::visit(
                    [&](const auto &r) {
                        using F = std::decay_t<decltype(r.forest)>;
                        size_t kept = r.pairs.capacity() * sizeof(PairTally) +
                                      r.links.size() * sizeof(Link) +
                                      r.forest.Size() * F::kBytesPerElement;
                        CHECK(kept <= budget);
                    },
                    Refine(scene, o));
                ++fitted;
            } catch (const LimitError &) {
                CHECK(fitted == 0);  // a larger budget never fails where a smaller fits
            }
        }
        CHECK(fitted >= 1);
    }
}

TEST_CASE("A count-only run on one thread has the whole budget for its one forest",
          "[refine][errors]") {
    // One root pair: no pair records to speak of, the trees are all a run keeps.
    Scene scene = MakeScene("parallel", {{"l", 256}});
    RefineOptions o = Options(0.01, "garmann", false);
    const uint64_t nodes = Refine<Segment>(scene, o).record.counters.nodes;
    REQUIRE(nodes > 100000);
    // Room for the trees and the records' first array (1,024 pairs), with a tenth to
    // spare: more than half of it is trees, which a budget split between two forests
    // (a worker's and the pass's) would refuse.
    o.memoryBudget =
        size_t(1.1 * double(nodes * Forest<Segment>::kBytesPerElement)) + 1024 * sizeof(PairTally);
    CHECK(Refine<Segment>(scene, o).record.counters.nodes == nodes);
    // Two threads copy the trees once per worker beside the pass's: that does not fit.
    o.threads = 2;
    CHECK_THROWS_AS(Refine<Segment>(scene, o), LimitError);
}

TEST_CASE("Invalid refinement options are rejected with the option's name", "[refine][errors]") {
    Scene scene = MakeScene("parallel", {});
    double nan = std::numeric_limits<double>::quiet_NaN(),
           inf = std::numeric_limits<double>::infinity();
    for (double eps : {0.0, -1.0, nan, inf})
        CHECK_THROWS_WITH(Refine(scene, Options(eps)), Catch::Contains("--eps"));
    RefineOptions o = Options(0.5);
    o.minArea = -1;
    CHECK_THROWS_WITH(Refine(scene, o), Catch::Contains("--min-area"));
    o.minArea = 0;
    o.maxDepth = kSafetyDepth + 1;
    CHECK_THROWS_WITH(Refine(scene, o), Catch::Contains("--max-depth"));
}

TEST_CASE("Bad 3D refinement options are input errors naming the flag", "[3d][refine][errors]") {
    Scene scene3 = MakeScene("parallel3d", {});
    Scene scene2 = MakeScene("parallel", {});
    RefineOptions o = Options3D(0.1);
    o.raysPerSide = 0;
    CHECK_THROWS_WITH(Refine(scene3, o), Catch::Contains("--rays-per-side"));
    o = Options3D(0.1, "garmann", Subdivision::Quadtree);
    CHECK_THROWS_WITH(Refine(scene2, o), Catch::Contains("--subdivision quadtree"));
    Scene touching = MakeScene("perpendicular3d", {{"gap", 0}});
    CHECK_THROWS_WITH(Refine(touching, Options3D(0.1)), Catch::Contains("touch"));
}

TEST_CASE("Options are checked against the scene's dimension and the oracle registry",
          "[refine][errors]") {
    RefineOptions o = Options(0.5);
    CHECK_NOTHROW(ValidateOptions(o, 2));
    CHECK_NOTHROW(ValidateOptions(o, 3));
    o.subdivision = Subdivision::Quadtree;
    CHECK_NOTHROW(ValidateOptions(o, 3));
    CHECK_THROWS_WITH(ValidateOptions(o, 2), Catch::Contains("--subdivision quadtree"));
    for (const OracleInfo &info : OracleInfos()) {
        o = Options(0.5, info.name);
        CHECK_NOTHROW(ValidateOptions(o, 2));
        CHECK_NOTHROW(ValidateOptions(o, 3));
    }
    o = Options(0.5, "magic");
    CHECK_THROWS_WITH(ValidateOptions(o, 2),
                      "unknown oracle 'magic' (choose one of: garmann, hanrahan, bf)");
    Scene scene = MakeScene("parallel", {});
    CHECK_THROWS_WITH(Refine(scene, o), Catch::Contains("unknown oracle 'magic'"));
}
