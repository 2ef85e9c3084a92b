// The bf oracle (oracles/bf.h) against hand-computed cases in 2D and 3D, the radiosity
// estimate it reads (radiosity_estimate.h) on hand-built previous forests, and whole
// runs of it: the per pair invariant, determinism across threads, the command line.
#include <catch2/catch.hpp>

#include <cmath>
#include <functional>
#include <map>
#include <random>
#include <stdexcept>
#include <thread>
#include <tuple>

#include "cli_helpers.h"
#include "generators.h"
#include "hrbench/hrbench.h"
#include "hrbench/oracles/registry.h"
#include "hrbench/radiosity_estimate.h"
#include "refinement_helpers.h"

#include <nlohmann/json.hpp>

using namespace hrbench;
using hrbench_test::Cli;
using hrbench_test::RefinementDifferences;
using hrbench_test::TilingViolations;
using nlohmann::json;

namespace {

constexpr double kPi = 3.14159265358979323846;

double Sq(double x) { return x * x; }
double Below(double x) { return std::nextafter(x, 0.0); }

Element<2> At(double x, double y, double size, uint32_t root) {
    return {Vec2(x, y), size * size, kNoChildren, root};
}

// Two horizontal segments of length 4 facing each other at distance 1.5: P on y = 0
// (normal +y), Q on y = 1.5 (normal -y), with emissions _eP_ and _eQ_.
Patches<Segment> FacingSegments(double eP, double eQ) {
    return {{{Vec2(-2, 0), Vec2(2, 0)}, {0.5, eP}}, {{Vec2(2, 1.5), Vec2(-2, 1.5)}, {0.5, eQ}}};
}

// Two unit squares facing each other: P in z = 0 (normal +z), Q in z = 1 (normal -z).
Patches<Polygon> FacingSquares(double eP, double eQ) {
    Vec3 a(0, 0, 0), b(1, 0, 0), c(1, 1, 0), d(0, 1, 0), up(0, 0, 1);
    return {{Polygon::Quad(a, b, c, d), {0.5, eP}},
            {Polygon::Quad(a + up, d + up, c + up, b + up), {0.5, eQ}}};
}

Scene SceneOf(AnyPatches patches) {
    Scene scene;
    scene.family = "test";
    scene.patches = std::move(patches);
    return scene;
}

// bf with the centre-cosine estimate (oracles/ff_estimate.h), whose values the cases
// below compute by hand: A_j cos_i cos_j / sqrt(4 r^2 + A_j^2), resp. / (pi r^2 + A_j).
template <typename Shape>
BFOracle<Shape> CentreBF(double eps, const Patches<Shape> &roots) {
    return BFOracle<Shape>(eps, roots, nullptr, FfEstimate::CentreCosine);
}

RefineOptions BF(double eps, double minArea = 0) {
    RefineOptions o;
    o.oracle = "bf";
    o.eps = eps;
    o.minArea = minArea;
    o.storeLinks = true;
    return o;
}

}  // namespace

TEST_CASE("bf accepts iff B_j F(i<-j) and B_i F(j<-i) are within eps, in 2D", "[bf][2d]") {
    // i: length 1 at the origin, on P; j: length 2 at (0, 1.5), on Q. Both cosines are 1
    // (n . d / r = 1.5 / 1.5), so the hanrahan estimates are, as the oracle rounds them,
    // F(i<-j) = 2 / sqrt(4 * 2.25 + 2 * 2) = 2 / sqrt(13), F(j<-i) = 1 / sqrt(10).
    Element<2> i = At(0, 0, 1, 0), j = At(0, 1.5, 2, 1);
    double fij = 2 / std::sqrt(13.0), fji = 1 / std::sqrt(10.0);

    SECTION("only Q emits: B_i = 0, the threshold is B_Q F(i<-j)") {
        Patches<Segment> roots = FacingSegments(0, 3);
        double t = 3 * fij;  // 1.664...
        CHECK(CentreBF<Segment>(t, roots).Acceptable(i, j));
        CHECK_FALSE(CentreBF<Segment>(Below(t), roots).Acceptable(i, j));
        // hanrahan decides on F alone: at eps = F(i<-j) it accepts, bf's 3 F(i<-j) does not.
        CHECK_FALSE(HanrahanOracle<Segment>(0.5, roots, FfEstimate::CentreCosine).Acceptable(i, j));
        CHECK(HanrahanOracle<Segment>(fij, roots, FfEstimate::CentreCosine).Acceptable(i, j));
        CHECK_FALSE(CentreBF<Segment>(fij, roots).Acceptable(i, j));
    }
    SECTION("both emit: the larger of the two products decides") {
        Patches<Segment> weak = FacingSegments(5, 3);  // 5 / sqrt(10) = 1.58 < 1.66
        CHECK(CentreBF<Segment>(3 * fij, weak).Acceptable(i, j));
        CHECK_FALSE(CentreBF<Segment>(Below(3 * fij), weak).Acceptable(i, j));
        Patches<Segment> strong = FacingSegments(10, 3);  // 10 / sqrt(10) = 3.16 > 1.66
        CHECK(CentreBF<Segment>(10 * fji, strong).Acceptable(i, j));
        CHECK_FALSE(CentreBF<Segment>(Below(10 * fji), strong).Acceptable(i, j));
    }
    SECTION("the visible fraction weighs the products, (V * B) * F") {
        Patches<Segment> roots = FacingSegments(0, 3);
        CHECK(CentreBF<Segment>(0.5 * 3 * fij, roots).AcceptableVisible(i, j, 0.5));
        CHECK_FALSE(CentreBF<Segment>(Below(0.5 * 3 * fij), roots).AcceptableVisible(i, j, 0.5));
    }
    SECTION("the default clamped-cosine estimate: 2f > 1 raises both cosines to 2f") {
        // f(i<-j) = 2 / sqrt(13) = 0.555, so F(i<-j) = f 2f 2f = 0.683 (the receiver's
        // factor first); F(j<-i) = 1 / sqrt(10) with both cosines 1 > 2f = 0.632.
        Patches<Segment> roots = FacingSegments(0, 3);
        double t = 3 * (fij * (2 * fij) * (2 * fij));
        CHECK(BFOracle<Segment>(t, roots).Acceptable(i, j));
        CHECK_FALSE(BFOracle<Segment>(Below(t), roots).Acceptable(i, j));
        Patches<Segment> strong = FacingSegments(10, 0);
        CHECK(BFOracle<Segment>(10 * fji, strong).Acceptable(i, j));
        CHECK_FALSE(BFOracle<Segment>(Below(10 * fji), strong).Acceptable(i, j));
    }
}

TEST_CASE("bf accepts iff B_j F(i<-j) and B_i F(j<-i) are within eps, in 3D", "[bf][3d]") {
    // Directly opposed elements at distance 1: cosines 1, F = A / (pi r^2 + A) with the
    // other element's area: F(a<-b) = 2 / (pi + 2), F(b<-a) = 1 / (pi + 1).
    Element<3> a{Vec3(0.5, 0.5, 0), Sq(1), kNoChildren, 0};
    Element<3> b{Vec3(0.5, 0.5, 1), Sq(2), kNoChildren, 1};
    double fab = 2 / (kPi * 1 + 2), fba = 1 / (kPi * 1 + 1);

    Patches<Polygon> lamp = FacingSquares(0, 4);  // Q emits 4: 4 F(a<-b) = 1.556
    CHECK(CentreBF<Polygon>(4 * fab, lamp).Acceptable(a, b));
    CHECK_FALSE(CentreBF<Polygon>(Below(4 * fab), lamp).Acceptable(a, b));
    Patches<Polygon> both = FacingSquares(7, 4);  // 7 F(b<-a) = 1.690 > 1.556
    CHECK(CentreBF<Polygon>(7 * fba, both).Acceptable(a, b));
    CHECK_FALSE(CentreBF<Polygon>(Below(7 * fba), both).Acceptable(a, b));
    CHECK(CentreBF<Polygon>(0.25 * 7 * fba, both).AcceptableVisible(a, b, 0.25));
    CHECK_FALSE(CentreBF<Polygon>(Below(0.25 * 7 * fba), both).AcceptableVisible(a, b, 0.25));
    // Facing away: both estimates are 0 whatever B is.
    Patches<Polygon> away = FacingSquares(7, 4);
    std::swap(away[0].shape.v[1], away[0].shape.v[3]);  // P now faces -z
    std::swap(away[1].shape.v[1], away[1].shape.v[3]);  // Q +z
    CHECK(CentreBF<Polygon>(1e-300, away).Acceptable(a, b));
}

TEST_CASE("bf accepts a pair whose elements do not emit at once, however close", "[bf]") {
    // Root 2 emits, so the scene is accepted; roots 0 and 1 do not.
    Patches<Segment> roots = FacingSegments(0, 0);
    roots.push_back({{Vec2(0, 5), Vec2(1, 5)}, {0.5, 1}});
    BFOracle<Segment> oracle = CentreBF<Segment>(1e-300, roots);
    CHECK(oracle.Acceptable(At(0, 0, 4, 0), At(0, 1e-9, 4, 1)));
    CHECK(oracle.AcceptableVisible(At(0, 0, 4, 0), At(0, 1e-9, 4, 1), 0.5));
    // One-sided: only the product with the emitter's B counts. A tiny i under a long j:
    // F(i<-j) = 4 / sqrt(9 + 16) = 0.8, F(j<-i) = 1e-6 / sqrt(9 + 1e-12).
    Element<2> i = At(0, 0, 1e-6, 0), j = At(0, 1.5, 4, 1);
    double fji = 1e-6 / std::sqrt(4 * 2.25 + 1e-6 * 1e-6);
    CHECK_FALSE(CentreBF<Segment>(0.5, FacingSegments(0, 1)).Acceptable(i, j));  // 0.8 > 0.5
    CHECK(CentreBF<Segment>(fji, FacingSegments(1, 0)).Acceptable(i, j));
    CHECK_FALSE(CentreBF<Segment>(Below(fji), FacingSegments(1, 0)).Acceptable(i, j));

    SECTION("a run where nothing emits is refused") {
        CHECK_THROWS_AS(CentreBF<Segment>(0.1, FacingSegments(0, 0)), InputError);
        Scene dark = SceneOf(FacingSquares(0, 0));
        CHECK_THROWS_WITH(Refine(dark, BF(0.1)),
                          Catch::StartsWith("the bf oracle needs an emitter: "));
    }
}

TEST_CASE("Doubling B halves the threshold bf puts on F, exactly", "[bf]") {
    // (2B) F <= eps iff B F <= eps / 2: scaling by 2 is exact in doubles, so with every
    // emission doubled bf decides at eps as it did at eps / 2, pair by pair.
    std::mt19937_64 rng(91);
    std::uniform_real_distribution<double> u(0, 4), s(0.01, 2), e(0.001, 0.5);
    Patches<Segment> flat = FacingSegments(1.5, 0.75), flat2 = FacingSegments(3, 1.5);
    Patches<Polygon> space = FacingSquares(1.5, 0.75), space2 = FacingSquares(3, 1.5);
    int accepted = 0, total = 0;
    for (int k = 0; k < 20000; ++k) {
        double eps = e(rng);
        Element<2> i = At(u(rng) - 2, 0, s(rng), 0), j = At(u(rng) - 2, u(rng), s(rng), 1);
        bool once = CentreBF<Segment>(eps / 2, flat).Acceptable(i, j);
        REQUIRE(CentreBF<Segment>(eps, flat2).Acceptable(i, j) == once);
        Element<3> a{Vec3(u(rng), u(rng), 0), Sq(s(rng)), kNoChildren, 0};
        Element<3> b{Vec3(u(rng), u(rng), u(rng)), Sq(s(rng)), kNoChildren, 1};
        bool once3 = CentreBF<Polygon>(eps / 2, space).Acceptable(a, b);
        REQUIRE(CentreBF<Polygon>(eps, space2).Acceptable(a, b) == once3);
        accepted += once + once3, total += 2;
    }
    CHECK(accepted > total / 10);  // both outcomes are exercised
    CHECK(accepted < total * 9 / 10);
    // At the threshold itself: the least accepting eps doubles with B.
    Element<2> i = At(0, 0, 1, 0), j = At(0, 1.5, 2, 1);
    double t = 1.5 * (1 / std::sqrt(10.0));  // B_P F(j<-i) = 0.474 > B_Q F(i<-j) = 0.416
    CHECK(CentreBF<Segment>(t, flat).Acceptable(i, j));
    CHECK_FALSE(CentreBF<Segment>(Below(t), flat).Acceptable(i, j));
    CHECK(CentreBF<Segment>(2 * t, flat2).Acceptable(i, j));
    CHECK_FALSE(CentreBF<Segment>(Below(2 * t), flat2).Acceptable(i, j));
}

TEST_CASE("The estimate looks an element up in a previous forest, in 2D", "[bf][estimate][2d]") {
    // P from (0,0) to (8,0), Q above it. The previous forest splits P into [0,4] (2) and
    // [4,8] (3), [4,8] into [4,6] (4) and [6,8] (5), [4,6] into [4,5] (6) and [5,6] (7);
    // Q is not split. Element e holds the value e + 1.
    Patches<Segment> roots = {{{Vec2(0, 0), Vec2(8, 0)}, {}}, {{Vec2(8, 2), Vec2(0, 2)}, {}}};
    Forest<Segment> previous(roots, 100, Subdivision::Binary);
    REQUIRE(previous.Children(0) == 2);
    REQUIRE(previous.Children(3) == 4);
    REQUIRE(previous.Children(4) == 6);
    REQUIRE(previous.Size() == 8);
    RadiosityEstimate<Segment> b(previous, {1, 2, 3, 4, 5, 6, 7, 8});
    // The same element: its value.
    CHECK(b(At(2, 0, 4, 0)) == 3);    // [0,4]
    CHECK(b(At(5, 0, 2, 0)) == 5);    // [4,6]
    CHECK(b(At(7, 0, 2, 0)) == 6);    // [6,8]
    CHECK(b(At(4.5, 0, 1, 0)) == 7);  // [4,5]
    CHECK(b(At(5.5, 0, 1, 0)) == 8);  // [5,6]
    // Deeper than the previous forest: the value of the leaf above it.
    CHECK(b(At(1, 0, 2, 0)) == 3);           // [0,2] under [0,4]
    CHECK(b(At(3.75, 0, 0.5, 0)) == 3);      // [3.5,4]
    CHECK(b(At(5.75, 0, 0.5, 0)) == 8);      // [5.5,6] under [5,6]
    CHECK(b(At(6.25, 0, 0.5, 0)) == 6);      // [6,6.5] under [6,8]
    CHECK(b(At(1.0625, 2, 0.125, 1)) == 2);  // deep in Q, which was not split
    // Coarser than the previous forest's leaves: the coarser element's own value.
    CHECK(b(At(4, 0, 8, 0)) == 1);  // P itself
    CHECK(b(At(6, 0, 4, 0)) == 4);  // [4,8]
    CHECK(b(At(4, 2, 8, 1)) == 2);  // Q

    SECTION("per root, every element gets its root's value") {
        RadiosityEstimate<Segment> e = RadiosityEstimate<Segment>::FromEmission(
            {{{Vec2(0, 0), Vec2(8, 0)}, {0.5, 2.5}}, {{Vec2(8, 2), Vec2(0, 2)}, {0.5, 0}}});
        CHECK(e(At(5.75, 0, 0.5, 0)) == 2.5);
        CHECK(e(At(4, 2, 8, 1)) == 0);
        CHECK(e.Max() == 2.5);
    }
    SECTION("malformed estimates are refused") {
        CHECK_THROWS_AS(RadiosityEstimate<Segment>(previous, {1, 2, 3}), std::invalid_argument);
        CHECK_THROWS_AS(RadiosityEstimate<Segment>(std::vector<double>{1, -1}),
                        std::invalid_argument);
        CHECK_THROWS_AS(RadiosityEstimate<Segment>(std::vector<double>{1, NAN}),
                        std::invalid_argument);
    }
}

// Grows _forest_: splits every element of depth below _depth_ for which _split_ says so,
// parents before children.
template <typename Shape, typename Split>
void Grow(Forest<Shape> &forest, int depth, Split split) {
    for (uint32_t e = 0; e < forest.Size(); ++e)
        if (forest.Depth(e) < depth && split(e))
            forest.Children(e);
}

// The lookup rule by tree positions: the value of the deepest element of _previous_ that
// is the query or an ancestor of it (same root, its depth's position prefix).
template <typename Shape>
void CheckAgainstPositions(const Forest<Shape> &previous, const Forest<Shape> &current,
                           const std::vector<double> &values) {
    std::map<std::tuple<uint32_t, int, uint64_t>, uint32_t> byPosition;
    for (uint32_t e = 0; e < previous.Size(); ++e)
        byPosition[{previous[e].root, previous.Depth(e), previous.Position(e)}] = e;
    RadiosityEstimate<Shape> b(previous, values);
    uint64_t arity = uint64_t(current.Arity());
    int deeper = 0, coarser = 0;
    for (uint32_t e = 0; e < current.Size(); ++e) {
        int depth = current.Depth(e);
        uint64_t position = current.Position(e);
        auto found = byPosition.end();
        for (; (found = byPosition.find({current[e].root, depth, position})) == byPosition.end();
             --depth)
            position /= arity;
        INFO("element " << e << " at depth " << current.Depth(e));
        REQUIRE(b(current[e]) == values[found->second]);
        deeper += depth < current.Depth(e);
        coarser += previous[found->second].firstChild != kNoChildren;
    }
    CHECK(deeper > 10);   // queries finer than the previous forest
    CHECK(coarser > 10);  // and coarser than its leaves
}

TEST_CASE("The estimate looks an element up in a previous forest, in 3D", "[bf][estimate][3d]") {
    // A tilted trapezoid and a triangle (corners in a plane spanned by u and v).
    Vec3 o(0.3, -0.2, 1), u(1, 0, 0.25), v(0.1, 1, 0.5);
    auto at = [&](double x, double y) { return Vec3(o + x * u + y * v); };
    Patches<Polygon> roots = {{Polygon::Quad(at(0, 0), at(2, 0), at(1.6, 1.2), at(0.3, 1)), {}},
                              {Polygon::Triangle(at(3, 0), at(5, 0.5), at(3.5, 2)), {}}};
    for (Subdivision mode : {Subdivision::Binary, Subdivision::Quadtree}) {
        INFO(SubdivisionName(mode));
        int depth = mode == Subdivision::Binary ? 7 : 4;
        // The previous forest: split irregularly, to depth - 1; the current one: uniformly.
        Forest<Polygon> previous(roots, 100000, mode), current(roots, 100000, mode);
        Grow(previous, depth - 1, [](uint32_t e) { return e % 3 != 1; });
        Grow(current, depth, [](uint32_t) { return true; });
        std::vector<double> values;
        for (uint32_t e = 0; e < previous.Size(); ++e)
            values.push_back(0.5 + e);
        CheckAgainstPositions(previous, current, values);
    }
    SECTION("2D, the same rule") {
        Patches<Segment> flat = {{{Vec2(0, 0), Vec2(3, 1)}, {}}, {{Vec2(3, 2), Vec2(-1, 2)}, {}}};
        Forest<Segment> previous(flat, 100000, Subdivision::Binary),
            current(flat, 100000, Subdivision::Binary);
        Grow(previous, 9, [](uint32_t e) { return e % 3 != 1; });
        Grow(current, 10, [](uint32_t) { return true; });
        std::vector<double> values;
        for (uint32_t e = 0; e < previous.Size(); ++e)
            values.push_back(0.5 + e);
        CheckAgainstPositions(previous, current, values);
    }
}

TEST_CASE("The estimate reads alike from several threads", "[bf][estimate]") {
    Scene scene = MakeScene("cornell", {});
    Refinement<Polygon> first = Refine<Polygon>(scene, BF(0.05, 0.001));
    std::vector<double> values;
    for (uint32_t e = 0; e < first.forest.Size(); ++e)
        values.push_back(1 + (e % 7));
    const RadiosityEstimate<Polygon> b(first.forest, values);
    Forest<Polygon> queries(scene.Get<Polygon>(), 1000000, Subdivision::Binary);
    Grow(queries, 5, [](uint32_t) { return true; });
    auto lookUp = [&](std::vector<double> &out) {
        for (uint32_t e = 0; e < queries.Size(); ++e)
            out.push_back(b(queries[e]));
    };
    std::vector<double> one, two, three;
    lookUp(one);
    std::thread a(lookUp, std::ref(two)), c(lookUp, std::ref(three));
    a.join(), c.join();
    CHECK(one == two);
    CHECK(one == three);
}

TEST_CASE("bf runs refine cornell with oracle_calls = 2L - 1 per pair, on any threads",
          "[bf][refine][3d]") {
    Scene scene = MakeScene("cornell", {});
    RefineOptions o = BF(0.05, 0.001);
    Refinement<Polygon> one = Refine<Polygon>(scene, o);
    CHECK(TilingViolations(scene, one, 1e-9) == "");
    const Counters &c = one.record.counters;
    CHECK(c.oracleCalls == 2 * c.links - c.rootPairs + c.culledPairs);
    CHECK(c.linksPerDepth.size() > 10);  // link depth kTaskDepth (kernel.h): threads had tasks
    // Pairs of roots that do not emit are linked at once: one call each.
    const Patches<Polygon> &roots = scene.Get<Polygon>();
    int dark = 0;
    for (const PairTally &pair : one.pairs)
        if (roots[pair.p].material.emission == 0 && roots[pair.q].material.emission == 0) {
            CHECK(pair.oracleCalls == 1);
            ++dark;
        }
    CHECK(dark > 0);
    CHECK(c.linksPerDepth[0] >= uint64_t(dark));
    for (int threads : {2, 3}) {
        RefineOptions t = o;
        t.threads = threads;
        CHECK(RefinementDifferences(one, Refine<Polygon>(scene, t)) == "");
    }

    SECTION("the emission as a previous forest's values refines as the emission does") {
        std::vector<double> emission;
        for (uint32_t e = 0; e < one.forest.Size(); ++e)
            emission.push_back(roots[one.forest[e].root].material.emission);
        RadiosityEstimate<Polygon> same(one.forest, emission);
        RefineOptions withForest = o;
        withForest.estimate = &same;
        CHECK(RefinementDifferences(one, Refine<Polygon>(scene, withForest)) == "");
    }
    SECTION("a second pass reads a previous solution, deterministically") {
        // Made-up values of a previous solution: every element reflects some light.
        std::vector<double> values;
        for (uint32_t e = 0; e < one.forest.Size(); ++e)
            values.push_back(roots[one.forest[e].root].material.emission + 0.1 * (1 + e % 5));
        RadiosityEstimate<Polygon> previous(one.forest, values);
        RefineOptions second = o;
        second.estimate = &previous;
        Refinement<Polygon> pass2 = Refine<Polygon>(scene, second);
        CHECK(TilingViolations(scene, pass2, 1e-9) == "");
        CHECK(pass2.record.counters.links > c.links);  // what was dark now refines
        second.threads = 2;
        CHECK(RefinementDifferences(pass2, Refine<Polygon>(scene, second)) == "");
        // An estimate of the other shape is a caller's mistake.
        RadiosityEstimate<Segment> flat(std::vector<double>{1, 1});
        second.estimate = &flat;
        CHECK_THROWS_AS(Refine<Polygon>(scene, second), std::invalid_argument);
        // So is one of another scene's roots.
        RadiosityEstimate<Polygon> fewer(std::vector<double>{1, 1});
        second.estimate = &fewer;
        CHECK_THROWS_AS(Refine<Polygon>(scene, second), std::invalid_argument);
    }
}

TEST_CASE("bf refines a 2D scene with an emitter", "[bf][refine][2d]") {
    Scene scene = SceneOf(FacingSegments(0, 1));
    Refinement<Segment> one = Refine<Segment>(scene, BF(0.01));
    CHECK(TilingViolations(scene, one) == "");
    REQUIRE(one.pairs.size() == 1);
    CHECK(one.pairs[0].oracleCalls == 2 * one.pairs[0].links - 1);
    CHECK(one.record.counters.links > 100);
    CHECK(one.record.counters.forcedLinks == 0);  // terminates on its own
    RefineOptions two = BF(0.01);
    two.threads = 2;
    CHECK(RefinementDifferences(one, Refine<Segment>(scene, two)) == "");
}

TEST_CASE("hrbench run --oracle bf on cornell, on 1 and 2 threads, and its errors", "[bf][cli]") {
    const std::string run = "run cornell --oracle bf --eps 0.05 --min-area 0.001 --json";
    hrbench_test::CliResult one = Cli(run + " --threads 1"), two = Cli(run + " --threads 2");
    REQUIRE(one.exitCode == 0);
    REQUIRE(two.exitCode == 0);
    json a = json::parse(one.out), b = json::parse(two.out);
    CHECK(a["oracle"] == "bf");
    for (const char *counter :
         {"nodes", "leaves", "links", "oracle_calls", "max_depth", "forced_links", "culled_pairs",
          "root_pairs", "nodes_per_depth", "links_per_depth"}) {
        INFO(counter);
        CHECK(a[counter] == b[counter]);
    }
    uint64_t links = a["links"], calls = a["oracle_calls"], refined = 136 - 55;
    CHECK(a["root_pairs"] == 136);
    CHECK(a["culled_pairs"] == 55);
    CHECK(calls == 2 * links - refined);  // 2L - 1 summed over the refined root pairs

    SECTION("a scene file in 2D") {
        Scene scene = SceneOf(FacingSegments(0, 1));
        std::string path = hrbench_test::Scratch("bf_lit.json");
        SaveScene(scene, path);
        hrbench_test::CliResult r =
            Cli("run --scene-file " + path + " --oracle bf --eps 0.01 --json --threads 2");
        REQUIRE(r.exitCode == 0);
        json j = json::parse(r.out);
        CHECK(j["oracle_calls"] == 2 * j["links"].get<uint64_t>() - 1);
        CHECK(j["links"] == Refine<Segment>(scene, BF(0.01)).record.counters.links);
    }
    SECTION("check-links validates a dump of it") {
        std::string dump = hrbench_test::Scratch("bf_cornell.links");
        const std::string scene = "cornell --oracle bf --eps 0.05 --min-area 0.001";
        REQUIRE(Cli("links " + scene + " --format probe --out " + dump).exitCode == 0);
        hrbench_test::CliResult check = Cli("check-links " + scene + " --links " + dump);
        CHECK(check.exitCode == 0);
        CHECK_THAT(check.out, Catch::Contains("with bf eps 0.05"));
    }
    SECTION("nothing emits: exit 2") {
        hrbench_test::CheckError("run parallel --eps 0.1 --oracle bf", 2,
                                 "the bf oracle needs an emitter: ");
        hrbench_test::CheckError("run parallel3d --eps 0.1 --oracle bf", 2,
                                 "the bf oracle needs an emitter: ");
    }
}
