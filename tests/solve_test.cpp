// The radiosity solve on the hierarchy: closed forms for two and three patches, closed
// rooms and boxes, energy balance, form-factor row sums, the dense uniform reference,
// determinism across threads, and the solve command with its bad input.
#include <catch2/catch.hpp>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

#include <Eigen/Dense>
#include <nlohmann/json.hpp>

#include "cli_helpers.h"
#include "generators.h"
#include "hrbench/hrbench.h"
#include "solve/form_factor.h"
#include "util/parallel_for.h"
#include "visibility/visibility.h"

using namespace hrbench;
using namespace hrbench_test;
using nlohmann::json;

namespace {

RefineOptions Refining(double eps, double minArea = 0, const std::string &oracle = "garmann") {
    RefineOptions o;
    o.eps = eps;
    o.minArea = minArea;
    o.oracle = oracle;
    o.storeLinks = true;
    return o;
}

SolveOptions Solving(double tolerance, SolveMethod method = SolveMethod::Jacobi) {
    SolveOptions o;
    o.tolerance = tolerance;
    o.method = method;
    return o;
}

// Hottel's crossed strings for two segments each wholly in front of the other: the four
// end points form a convex quadrilateral, whose diagonals (the crossed strings) are
// longer together than either pair of opposite sides (the uncrossed ones).
double CrossedStrings(const Segment &from, const Segment &to) {
    double one = (from.a - to.a).norm() + (from.b - to.b).norm();
    double other = (from.a - to.b).norm() + (from.b - to.a).norm();
    return (std::max(one, other) - std::min(one, other)) / (2 * from.Length());
}

Scene SegmentScene(const Patches<Segment> &patches) { return {"file", {}, "", patches}; }

// The closed unit cube, six quads facing inward, counter-clockwise seen from inside.
Scene ClosedBox(double emission, double reflectance) {
    auto quad = [&](Vec3 a, Vec3 b, Vec3 c, Vec3 d) {
        return Patch<Polygon>{Polygon::Quad(a, b, c, d), {reflectance, emission}};
    };
    Patches<Polygon> faces = {
        quad({0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}),  // z = 0, normal +z
        quad({0, 0, 1}, {0, 1, 1}, {1, 1, 1}, {1, 0, 1}),  // z = 1, normal -z
        quad({0, 0, 0}, {0, 1, 0}, {0, 1, 1}, {0, 0, 1}),  // x = 0, normal +x
        quad({1, 0, 0}, {1, 0, 1}, {1, 1, 1}, {1, 1, 0}),  // x = 1, normal -x
        quad({0, 0, 0}, {0, 0, 1}, {1, 0, 1}, {1, 0, 0}),  // y = 0, normal +y
        quad({0, 1, 0}, {1, 1, 0}, {1, 1, 1}, {0, 1, 1}),  // y = 1, normal -y
    };
    return {"file", {}, "", faces};
}

// The room family with every wall emitting 1 and reflecting half.
Scene UniformRoom() {
    Scene room = MakeScene("room", {{"w", 2}, {"h", 1}});
    for (auto &patch : room.Get<Segment>())
        patch.material = {0.5, 1};
    return room;
}

double MaxDeviation(const SolveResult &r, double value) {
    double worst = 0;
    for (const ElementRadiosity &leaf : r.leaves)
        worst = std::max(worst, std::abs(leaf.radiosity - value));
    return worst;
}

double RelativeImbalance(const SolveResult &r) {
    return std::abs(r.absorbedPower - r.emittedPower) / r.emittedPower;
}

std::vector<double> Radiosities(const SolveResult &r) {
    std::vector<double> b;
    for (const ElementRadiosity &leaf : r.leaves)
        b.push_back(leaf.radiosity);
    return b;
}

}  // namespace

// ---------------------------------------------------------------------------------------
// Closed forms

TEST_CASE("Two facing plates, one link: the 2x2 system in closed form", "[solve]") {
    // P (0,0)->(1,0) and Q (1,1)->(0,1): garmann with eps 1 links the roots at once.
    Scene scene = SegmentScene({{{{0, 0}, {1, 0}}, {0.3, 1}}, {{{1, 1}, {0, 1}}, {0.6, 0}}});
    SolveResult r = Solve(scene, Refining(1), Solving(1e-13));
    REQUIRE(r.record.counters.links == 1);
    REQUIRE(r.leaves.size() == 2);
    // Crossed strings: diagonals 2 sqrt(2), sides 2, so F = sqrt(2) - 1 both ways.
    double F = std::sqrt(2.0) - 1;
    double bP = 1 / (1 - 0.3 * 0.6 * F * F), bQ = 0.6 * F * bP;
    CHECK(r.leaves[0].radiosity == Approx(bP).epsilon(1e-11));
    CHECK(r.leaves[1].radiosity == Approx(bQ).epsilon(1e-11));
    CHECK(r.leaves[0].irradiance == Approx(F * bQ).epsilon(1e-11));
    CHECK(r.emittedPower == 1);
    CHECK(r.absorbedPower == Approx(0.7 * F * bQ + 0.4 * F * bP).epsilon(1e-11));
    CHECK(r.iterations > 1);
    CHECK(r.residual < 1e-13);
}

TEST_CASE("Three patches, one link each: the 3x3 system", "[solve]") {
    // P on the floor, Q above it, R a wall on the left facing +x; eps 10 links every
    // root pair at once.
    Patches<Segment> patches = {{{{0, 0}, {1, 0}}, {0.5, 1}},
                                {{{1, 2}, {0, 2}}, {0.7, 0.5}},
                                {{{-1, 1.8}, {-1, 0.2}}, {0.9, 0}}};
    Scene scene = SegmentScene(patches);
    for (SolveMethod method : {SolveMethod::Jacobi, SolveMethod::GaussSeidel}) {
        INFO(SolveMethodName(method));
        SolveResult r = Solve(scene, Refining(10), Solving(1e-13, method));
        REQUIRE(r.record.counters.links == 3);
        REQUIRE(r.leaves.size() == 3);
        Eigen::Matrix3d M = Eigen::Matrix3d::Identity();
        Eigen::Vector3d E;
        for (int i = 0; i < 3; ++i) {
            E(i) = patches[i].material.emission;
            for (int j = 0; j < 3; ++j)
                if (i != j)
                    M(i, j) = -patches[i].material.reflectance *
                              CrossedStrings(patches[i].shape, patches[j].shape);
        }
        Eigen::Vector3d B = M.partialPivLu().solve(E);
        for (int i = 0; i < 3; ++i)
            CHECK(r.leaves[i].radiosity == Approx(B(i)).epsilon(1e-11));
    }
}

// ---------------------------------------------------------------------------------------
// Closed scenes

TEST_CASE("A closed 2D room of uniform emission 1 and reflectance 0.5 has B = 2", "[solve]") {
    // Where the hierarchy resolves every pair down to the recursion limit (every link
    // joins two leaves), each leaf's form factors sum to 1 exactly, and B = E / (1 - rho)
    // = 2 up to the iteration's error, at most rho / (1 - rho) * tolerance * max B = 2e-10,
    // and the form factors' rounding (crossed strings lose about 1e-11 relative between
    // elements of length 1/128 at distance 2).
    Scene room = UniformRoom();
    const double tolerance = 1e-10, bound = 1e-9;
    struct Case {
        std::string oracle;
        double eps;
        SolveMethod method;
    };
    for (const Case &c : {Case{"garmann", 0.002, SolveMethod::Jacobi},
                          Case{"garmann", 0.002, SolveMethod::GaussSeidel},
                          Case{"hanrahan", 1e-7, SolveMethod::Jacobi},
                          Case{"hanrahan", 1e-7, SolveMethod::GaussSeidel}}) {
        INFO(c.oracle << " " << SolveMethodName(c.method));
        SolveResult r = Solve(room, Refining(c.eps, 0.01, c.oracle), Solving(tolerance, c.method));
        REQUIRE(r.leaves.size() == 768);  // 6 / 2^-7: every leaf shorter than 0.01
        CHECK(r.record.counters.links == (768 * 768 - 2 * 256 * 256 - 2 * 128 * 128) / 2);
        CHECK(MaxDeviation(r, 2) <= bound);
        CHECK(RelativeImbalance(r) <= 1e-9);
    }
    // Gauss-Seidel converges in fewer sweeps than Jacobi, to the same answer.
    SolveResult jacobi = Solve(room, Refining(0.05, 0.01), Solving(1e-10));
    SolveResult gauss = Solve(room, Refining(0.05, 0.01), Solving(1e-10, SolveMethod::GaussSeidel));
    CHECK(gauss.iterations < jacobi.iterations);
    for (size_t k = 0; k < jacobi.leaves.size(); ++k)
        CHECK(gauss.leaves[k].radiosity == Approx(jacobi.leaves[k].radiosity).epsilon(1e-8));
}

TEST_CASE("In the closed room the consistent gather gives B = 2 at every eps, HSA91's plain "
          "gather only as eps falls",
          "[solve]") {
    // HSA91's approximation: a leaf gathers through its ancestors' links, whose form
    // factors are averages over the ancestor, so a leaf's row sum is 1 only on average.
    // The consistency scale restores each leaf's exact sum, so a uniform B is exact; the
    // plain gather's error falls with eps, and the energy balance with it (second order).
    Scene room = UniformRoom();
    SolveOptions plain = Solving(1e-12);
    plain.plainGather = true;
    double last = INFINITY, lastImbalance = INFINITY;
    for (double eps : {0.2, 0.05, 0.01}) {
        INFO("eps " << eps);
        SolveResult consistent = Solve(room, Refining(eps, 0.01), Solving(1e-12));
        CHECK(MaxDeviation(consistent, 2) <= 1e-9);
        CHECK(RelativeImbalance(consistent) <= 1e-9);
        SolveResult r = Solve(room, Refining(eps, 0.01), plain);
        double deviation = MaxDeviation(r, 2), imbalance = RelativeImbalance(r);
        CHECK(deviation > 1e-4);
        CHECK(deviation < last);
        CHECK(imbalance < lastImbalance);
        last = deviation, lastImbalance = imbalance;
    }
    CHECK(last < 1e-3);           // measured 5.8e-4
    CHECK(lastImbalance < 1e-6);  // measured 1.3e-7
    // The hanrahan oracle accepts grazing pairs earlier: larger errors at one eps, falling too.
    SolveResult coarse = Solve(room, Refining(0.002, 0.01, "hanrahan"), plain);
    SolveResult fine = Solve(room, Refining(0.0005, 0.01, "hanrahan"), plain);
    CHECK(MaxDeviation(fine, 2) < MaxDeviation(coarse, 2));
    CHECK(MaxDeviation(fine, 2) < 0.02);  // measured 1.1e-2
    CHECK(MaxDeviation(Solve(room, Refining(0.002, 0.01, "hanrahan"), Solving(1e-12)), 2) <= 1e-9);
}

TEST_CASE("The consistency scale is 1 where the links are exact, and never with visibility",
          "[solve]") {
    // Two facing plates, unrefined: the root link's coefficient is the exact form factor.
    Scene plates = MakeScene("parallel", {{"l", 1}, {"d", 1}});
    RefineOptions whole = Refining(100, 0);
    Refinement<Segment> r = Refine<Segment>(plates, whole);
    std::vector<LinkCoefficients> c = ComputeCoefficients(r.forest, r.links, whole);
    std::vector<double> s = ConsistencyScales(plates.Get<Segment>(), r.forest, r.links, c, whole);
    REQUIRE(s.size() == 2);
    CHECK(s[0] == Approx(1).epsilon(1e-14));
    CHECK(s[1] == Approx(1).epsilon(1e-14));
    // Refined: a leaf's scale is its exact form factor over its chain's coefficients.
    RefineOptions split = Refining(0.3, 0);
    r = Refine<Segment>(plates, split);
    c = ComputeCoefficients(r.forest, r.links, split);
    s = ConsistencyScales(plates.Get<Segment>(), r.forest, r.links, c, split);
    for (uint32_t e = 0; e < r.forest.Size(); ++e) {
        if (r.forest[e].firstChild != kNoChildren) {
            CHECK(s[e] == 1);
            continue;
        }
        double chain = 0;
        for (uint32_t a = e;; a = r.forest.Parent(a)) {
            for (size_t k = 0; k < r.links.size(); ++k)
                chain += r.links[k].i == a ? c[k].ij : r.links[k].j == a ? c[k].ji : 0;
            if (r.forest.Parent(a) == a)
                break;
        }
        const Segment &other = plates.Get<Segment>()[1 - r.forest[e].root].shape;
        CHECK(s[e] == Approx(FormFactor(r.forest.ShapeOf(e), other) / chain).epsilon(1e-13));
    }
    split.visibility = VisibilityMode::Fraction;
    for (double v : ConsistencyScales(plates.Get<Segment>(), r.forest, r.links, c, split))
        CHECK(v == 1);
}

TEST_CASE("The solve weighs links by the visible fractions the refinement sampled",
          "[solve][visibility]") {
    // The Cornell box's blocks occlude: many links are partly visible. The refinement keeps
    // each link's fraction, on any number of threads; weighing by them gives exactly the
    // coefficients of sampling the links' rays again.
    Scene cornell = MakeScene("cornell", {});
    RefineOptions o = Refining(0.05, 5e-3, "hanrahan");
    o.visibility = VisibilityMode::Fraction;
    Refinement<Polygon> r = Refine<Polygon>(cornell, o);
    REQUIRE(r.links.size() > 1000);
    // Links at depth sums of 10 and more (kTaskDepth): on several threads, workers make them.
    REQUIRE(r.record.counters.linksPerDepth.size() > 10);
    REQUIRE(r.visible.size() == r.links.size());
    size_t partial =
        std::count_if(r.visible.begin(), r.visible.end(), [](double v) { return v > 0 && v < 1; });
    CHECK(partial > 50);
    CHECK(std::none_of(r.visible.begin(), r.visible.end(), [](double v) { return v <= 0; }));
    Occluders occluders(cornell.Get<Polygon>());
    std::vector<LinkCoefficients> sampled =
        ComputeCoefficients(r.forest, r.links, o, &occluders, nullptr);
    std::vector<LinkCoefficients> kept =
        ComputeCoefficients(r.forest, r.links, o, &occluders, nullptr, &r.visible);
    REQUIRE(kept.size() == sampled.size());
    for (size_t k = 0; k < kept.size(); ++k)
        CHECK((kept[k].ij == sampled[k].ij && kept[k].ji == sampled[k].ji));
    for (int threads : {2, 3}) {
        o.threads = threads;
        CHECK(Refine<Polygon>(cornell, o).visible == r.visible);
    }
    // Without visibility, and without stored links, none is kept.
    o.visibility = VisibilityMode::None;
    CHECK(Refine<Polygon>(cornell, o).visible.empty());
    o.visibility = VisibilityMode::Fraction;
    o.storeLinks = false;
    CHECK(Refine<Polygon>(cornell, o).visible.empty());
}

TEST_CASE("The closed 3D box has B = E / (1 - rho)", "[solve][3d]") {
    // Elements of area 1/32 (--min-area 0.05) linked pairwise: every row sum is 1 up to
    // the form factors' accuracy (docs/solve.md: better than 2e-8 for shared edges).
    Scene box = ClosedBox(1, 0.5);
    SolveResult r = Solve(box, Refining(0.001, 0.05), Solving(1e-10));
    REQUIRE(r.leaves.size() == 6 * 32);
    CHECK(r.record.counters.links == (192 * 192 - 6 * 32 * 32) / 2);
    CHECK(MaxDeviation(r, 2) <= 1e-6);    // measured 2.3e-10
    CHECK(RelativeImbalance(r) <= 1e-6);  // measured 1.3e-10
    // Coarser: links between inner elements, which the consistency scale makes exact too.
    SolveResult coarse = Solve(box, Refining(0.1, 0.05), Solving(1e-10));
    CHECK(coarse.record.counters.links < r.record.counters.links / 2);  // 6510 of 15360
    CHECK(MaxDeviation(coarse, 2) <= 1e-6);
    SolveOptions plain = Solving(1e-10);
    plain.plainGather = true;
    CHECK(MaxDeviation(Solve(box, Refining(0.1, 0.05), plain), 2) > 1e-3);
    // Another emission and reflectance: B = 0.5 / (1 - 0.8) = 2.5.
    SolveResult bright = Solve(ClosedBox(0.5, 0.8), Refining(0.001, 0.05), Solving(1e-10));
    CHECK(MaxDeviation(bright, 2.5) <= 1e-6);  // measured 1.3e-9
}

TEST_CASE("Energy balances in a closed room with one emitting wall", "[solve]") {
    // Emitted sum E A against absorbed sum (1 - rho) H A, with rho differing by wall.
    Scene room = MakeScene("room", {{"w", 2}, {"h", 1}});
    auto &walls = room.Get<Segment>();
    walls[0].material = {0.2, 1};
    walls[1].material = {0.5, 0};
    walls[2].material = {0.8, 0};
    walls[3].material = {0.5, 0};
    SolveResult r = Solve(room, Refining(0.002, 0.01), Solving(1e-12));
    CHECK(r.emittedPower == 2);
    CHECK(RelativeImbalance(r) <= 1e-9);  // every link joins two leaves; measured 8e-13
    SolveResult coarse = Solve(room, Refining(0.01, 0.01), Solving(1e-12));
    CHECK(RelativeImbalance(coarse) <= 1e-6);  // measured 2.2e-7
}

TEST_CASE("The iteration approaches the balance from below: stopping early makes no energy",
          "[solve][energy]") {
    // B starts at E and every coefficient is >= 0, so B and H grow toward the solution:
    // the absorbed power of any sweep is at most the solution's. (The solution's own
    // exceeds the emitted power by 1.2e-5 here: the consistent gather is exact for a
    // uniform radiosity, and this room is lit by its ceiling alone.)
    Scene room = MakeScene("room", {{"w", 2}, {"h", 1}, {"lamp", 1}});
    double solution = Solve(room, Refining(0.05, 0.01), Solving(1e-13)).absorbedPower;
    CHECK(solution == Approx(2 * (1 + 1.21e-5)).epsilon(1e-7));
    for (SolveMethod method : {SolveMethod::Jacobi, SolveMethod::GaussSeidel}) {
        double previous = 0;
        for (double tolerance : {0.3, 0.1, 1e-2, 1e-4, 1e-8}) {
            SolveResult r = Solve(room, Refining(0.05, 0.01), Solving(tolerance, method));
            INFO(SolveMethodName(method) << " tolerance " << tolerance);
            CHECK(r.absorbedPower <= solution);
            CHECK(r.absorbedPower >= previous);
            CHECK(r.energyWarning.empty());  // within the discretisation's allowance
            previous = r.absorbedPower;
        }
        CHECK(previous == Approx(solution).epsilon(1e-7));
    }
}

TEST_CASE("Occlusion ignored, or energy made beyond the discretisation's, is warned about",
          "[solve][energy]") {
    Scene plates = MakeScene("parallel", {}), box = LoadScene(HRBENCH_TEST_DATA "/room_box.json");
    SolveResult r;
    r.emittedPower = 2;
    r.absorbedPower = 2 * 1.049;  // within the allowance
    CHECK(EnergyBalanceWarning(plates, Refining(0.5), r).empty());
    r.absorbedPower = 2 * 1.051;
    CHECK(EnergyBalanceWarning(plates, Refining(0.5), r) ==
          "absorbed power 2.1 against emitted power 2 (+5.1%), beyond the 5% a discretisation "
          "may account for: refine further (a smaller eps or --min-area; docs/solve.md, Energy "
          "balance)");
    RefineOptions fraction = Refining(0.5);
    fraction.visibility = VisibilityMode::Fraction;
    CHECK_THAT(EnergyBalanceWarning(box, fraction, r),
               Catch::Contains("--min-area, more --rays-per-side;"));
    // A deficit (light escaping an open scene) is never warned about by itself...
    r.absorbedPower = 1;
    CHECK(EnergyBalanceWarning(plates, Refining(0.5), r).empty());
    CHECK(EnergyBalanceWarning(box, fraction, r).empty());
    // ... but ignoring occlusion where a patch can block the light between others always
    // is: an open scene may lose more than it makes. A deficit is quoted as not showing
    // the light let through, never as if it were that excess.
    CHECK(EnergyBalanceWarning(box, Refining(0.5), r) ==
          "--visibility none lets light pass through the patches between others, which this "
          "scene has (without --visibility, solve weighs each link by its visible fraction; "
          "docs/solve.md, Occlusion); the energy balance alone does not show it here (absorbed "
          "power 1 against emitted power 2 (-50%): the discretisation's error outweighs it)");
}

TEST_CASE("Form-factor row sums in the closed room", "[solve]") {
    // A leaf's row sum: the coefficients of the links of the leaf and of its ancestors.
    // Its area-weighted mean over a wall is exactly 1 (the links of each root pair tile
    // it); each leaf's is 1 to within the hierarchy's error.
    Scene room = MakeScene("room", {{"w", 2}, {"h", 1}});
    for (double eps : {0.05, 0.002}) {
        INFO("eps " << eps);
        Refinement<Segment> r = Refine<Segment>(room, Refining(eps, 0.01));
        std::vector<LinkCoefficients> c =
            ComputeCoefficients(r.forest, r.links, Refining(eps, 0.01));
        std::vector<double> own(r.forest.Size(), 0);
        for (size_t k = 0; k < r.links.size(); ++k) {
            own[r.links[k].i] += c[k].ij;
            own[r.links[k].j] += c[k].ji;
        }
        std::vector<double> mean(4, 0), length(4, 0);
        double worst = 0;
        for (uint32_t e = 0; e < r.forest.Size(); ++e) {
            if (r.forest[e].firstChild != kNoChildren)
                continue;
            double sum = 0;
            for (uint32_t a = e;; a = r.forest.Parent(a)) {
                sum += own[a];
                if (r.forest.Parent(a) == a)
                    break;
            }
            worst = std::max(worst, std::abs(sum - 1));
            mean[r.forest[e].root] += r.forest[e].Size() * sum;
            length[r.forest[e].root] += r.forest[e].Size();
        }
        for (int wall = 0; wall < 4; ++wall)
            CHECK(mean[wall] / length[wall] == Approx(1).epsilon(1e-12));
        CHECK(worst <= (eps == 0.002 ? 1e-10 : 0.05));  // measured 1e-12 and 1.7e-2
    }
}

// ---------------------------------------------------------------------------------------
// The dense reference

TEST_CASE("The hierarchy converges to the dense uniform reference on parallel plates", "[solve]") {
    Scene plates = MakeScene("parallel", {{"l", 2}, {"d", 1}});
    plates.Get<Segment>()[0].material = {0.5, 1};
    plates.Get<Segment>()[1].material = {0.8, 0};
    SolveOptions options = Solving(1e-10);
    options.referenceDepth = 9;
    double last = INFINITY;
    for (double eps : {0.5, 0.1, 0.02}) {
        INFO("eps " << eps);
        SolveResult r = Solve(plates, Refining(eps), options);
        REQUIRE(r.reference);
        CHECK(r.reference->elements.size() == 1024);
        CHECK(r.comparison->meanError < last);
        last = r.comparison->meanError;
        CHECK(r.comparison->maxError >= r.comparison->meanError);
    }
    CHECK(last < 2e-3);
    // SolveUniform alone gives the same reference, in position order.
    UniformSolution ref = SolveUniform(plates, 9, Refining(1), Solving(1e-6));
    REQUIRE(ref.elements.size() == 1024);
    for (size_t k = 0; k < ref.elements.size(); ++k) {
        CHECK(ref.elements[k].root == k / 512);
        CHECK(ref.elements[k].position == k % 512);
        CHECK(ref.elements[k].depth == 9);
    }
    // The reference of a uniform closed room: B = 2 to rounding, energy balanced.
    UniformSolution room = SolveUniform(UniformRoom(), 6, Refining(1), Solving(1e-6));
    for (const ElementRadiosity &e : room.elements)
        CHECK(e.radiosity == Approx(2).epsilon(1e-10));
    CHECK(room.absorbedPower == Approx(room.emittedPower).epsilon(1e-10));
}

TEST_CASE("The hierarchy with one link per root pair is the reference of depth 0", "[solve]") {
    Scene plates = MakeScene("parallel", {{"l", 1}, {"d", 1}});
    plates.Get<Segment>()[0].material = {0.3, 1};
    SolveOptions options = Solving(1e-13);
    options.referenceDepth = 0;
    SolveResult r = Solve(plates, Refining(1), options);
    CHECK(r.comparison->maxError < 1e-12);
}

TEST_CASE("The L2 error is taken over the reference's elements", "[solve]") {
    Scene plates = MakeScene("parallel", {{"l", 1}, {"d", 1}});
    plates.Get<Segment>()[0].material = {0.3, 1};
    plates.Get<Segment>()[1].material = {0.6, 0};
    // sqrt(sum A (B_h - B_ref)^2 / sum A) / max B_ref (docs/solve.md).
    auto l2 = [](const std::vector<double> &b, const std::vector<ElementRadiosity> &ref) {
        double error = 0, measure = 0, largest = 0;
        for (size_t k = 0; k < ref.size(); ++k) {
            error += ref[k].measure * (b[k] - ref[k].radiosity) * (b[k] - ref[k].radiosity);
            measure += ref[k].measure;
            largest = std::max(largest, ref[k].radiosity);
        }
        return std::sqrt(error / measure) / largest;
    };
    SECTION("leaves coarser than the reference: each reference element takes its leaf's B") {
        // One link: the leaves are the two roots; the reference of depth 1 halves each.
        SolveOptions options = Solving(1e-13);
        options.referenceDepth = 1;
        SolveResult r = Solve(plates, Refining(1), options);
        REQUIRE(r.leaves.size() == 2);
        const std::vector<ElementRadiosity> &ref = r.reference->elements;
        REQUIRE(ref.size() == 4);
        double bP = r.leaves[0].radiosity, bQ = r.leaves[1].radiosity;
        CHECK(r.comparison->l2Error == Approx(l2({bP, bP, bQ, bQ}, ref)).epsilon(1e-12));
        CHECK(r.comparison->l2Error > 0);
    }
    SECTION("leaves finer than the reference: their area-weighted mean per element") {
        SolveOptions options = Solving(1e-13);
        options.referenceDepth = 0;
        SolveResult r = Solve(plates, Refining(0.05), options);
        REQUIRE(r.leaves.size() > 2);
        std::vector<double> power(2, 0), length(2, 0);
        for (const ElementRadiosity &leaf : r.leaves)
            power[leaf.root] += leaf.measure * leaf.radiosity, length[leaf.root] += leaf.measure;
        std::vector<double> mean = {power[0] / length[0], power[1] / length[1]};
        CHECK(r.comparison->l2Error == Approx(l2(mean, r.reference->elements)).epsilon(1e-12));
        CHECK(r.comparison->l2Error > 0);
    }
}

TEST_CASE("The reference errors are the same at every scale of the emission", "[solve]") {
    // Two emitters of different strength: the errors are relative, so scaling every
    // emission by s leaves them unchanged, from just above the smallest normal double
    // (2.2e-308) to just below the largest (1.8e308), where sums of B^2 underflowed or
    // overflowed before the solve worked in units of the largest emission.
    auto solveAt = [](double scale) {
        Scene plates = MakeScene("parallel", {{"l", 2}, {"d", 1}});
        plates.Get<Segment>()[0].material = {0.5, 1 * scale};
        plates.Get<Segment>()[1].material = {0.7, 0.25 * scale};
        SolveOptions options = Solving(1e-10);
        options.referenceDepth = 6;
        return Solve(plates, Refining(0.2), options);
    };
    SolveResult one = solveAt(1);
    const ReferenceComparison &c1 = *one.comparison;
    REQUIRE(c1.maxError > 1e-3);
    for (double scale : {1e-200, 1e-160, 1e-300, 1e155, 1e300}) {
        INFO("scale " << scale);
        SolveResult r = solveAt(scale);
        CHECK(r.comparison->maxError == Approx(c1.maxError).epsilon(1e-12));
        CHECK(r.comparison->meanError == Approx(c1.meanError).epsilon(1e-12));
        CHECK(r.comparison->l2Error == Approx(c1.l2Error).epsilon(1e-12));
        CHECK(*r.reference->change == Approx(*one.reference->change).epsilon(1e-12));
        // The solutions themselves scale.
        CHECK(r.leaves.back().radiosity / scale ==
              Approx(one.leaves.back().radiosity).epsilon(1e-12));
        CHECK(r.reference->elements[7].radiosity / scale ==
              Approx(one.reference->elements[7].radiosity).epsilon(1e-12));
        CHECK(r.emittedPower / scale == Approx(one.emittedPower).epsilon(1e-12));
        CHECK(r.reference->absorbedPower / scale ==
              Approx(one.reference->absorbedPower).epsilon(1e-12));
    }
    // A solution beyond the largest double is refused, not reported as inf or null.
    CHECK_THROWS_AS(solveAt(1e308), LimitError);
    UniformSolution tiny =
        SolveUniform(MakeScene("parallel", {{"l", 2}, {"d", 1}}), 4, Refining(1), [] {
            SolveOptions o = Solving(1e-6);
            o.emission = 1e-300;
            return o;
        }());
    for (const ElementRadiosity &e : tiny.elements)
        CHECK(e.radiosity > 1e-300);
}

TEST_CASE("The mean error never exceeds the L2 error nor the L2 error the max", "[solve]") {
    // Lit scenes where B varies a lot (a bright lamp, dark walls), where the mean once
    // exceeded the max: it was relative to the mean B, the max to the largest.
    struct Case {
        const char *family;
        ParamMap params;
        double eps, reflectance;
        int maxDepth, reference;
    };
    std::vector<Case> cases = {
        {"cornell", {}, 0.5, 0.1, 2, 2},
        {"cornell", {}, 0.5, 0.5, 2, 2},
        {"room", {{"lamp", 1}}, 1, 0.1, 2, 6},
        {"room", {{"w", 8}, {"lamp", 1}}, 0.5, 0.5, 4, 6},
        {"parallel", {{"l", 4}}, 0.3, 0.5, -1, 5},
        {"angled", {{"angle", 30}}, 0.1, 0.8, -1, 6},
    };
    for (const Case &c : cases) {
        INFO(c.family << " eps " << c.eps << " rho " << c.reflectance);
        Scene scene = MakeScene(c.family, c.params);
        RefineOptions refine = Refining(c.eps);
        refine.maxDepth = c.maxDepth;
        SolveOptions options = Solving(1e-10);
        options.reflectance = c.reflectance;
        if (std::string(c.family) != "cornell" && std::string(c.family) != "room")
            options.emission = 1;
        options.referenceDepth = c.reference;
        SolveResult r = Solve(scene, refine, options);
        const ReferenceComparison &e = *r.comparison;
        CHECK(e.meanError > 0);
        CHECK(e.meanError <= e.l2Error);
        CHECK(e.l2Error <= e.maxError);
        CHECK(e.maxError < 1);
    }
}

TEST_CASE("The reference's change from the mesh one level coarser estimates its own error",
          "[solve]") {
    Scene plates = MakeScene("parallel", {{"l", 4}, {"d", 1}});
    for (auto &patch : plates.Get<Segment>())
        patch.material = {0.5, 1};
    auto reference = [](const Scene &scene, int depth) {
        SolveOptions options = Solving(1e-8);
        options.referenceDepth = depth;
        return *Solve(scene, Refining(0.05, 0.01), options).reference;
    };
    UniformSolution six = reference(plates, 6), eight = reference(plates, 8);
    REQUIRE(six.change);
    REQUIRE(eight.change);
    CHECK(*six.change > 0);
    CHECK(*eight.change < *six.change / 4);  // second order: 16 times smaller, measured
    // By hand: the depth-6 solution averaged onto depth 5, pairs of elements in order.
    UniformSolution five = SolveUniform(plates, 5, Refining(1), Solving(1e-6));
    double largest = 0, change = 0;
    for (const ElementRadiosity &e : six.elements)
        largest = std::max(largest, e.radiosity);
    for (size_t k = 0; k < five.elements.size(); ++k) {
        const ElementRadiosity &a = six.elements[2 * k], &b = six.elements[2 * k + 1];
        REQUIRE(a.root == five.elements[k].root);
        double mean = (a.measure * a.radiosity + b.measure * b.radiosity) / (a.measure + b.measure);
        change = std::max(change, std::abs(mean - five.elements[k].radiosity));
    }
    CHECK(*six.change == Approx(change / largest).epsilon(1e-12));
    // B = E / (1 - rho) on every mesh of a closed room with uniform emission: no change.
    UniformSolution room = reference(UniformRoom(), 6);
    REQUIRE(room.change);
    CHECK(*room.change < 1e-12);  // measured 1.2e-13
    // Depth 0 has no coarser mesh.
    CHECK_FALSE(reference(plates, 0).change);
}

// ---------------------------------------------------------------------------------------
// Determinism

TEST_CASE("Radiosity is the same bit for bit on 1 and 2 threads", "[solve]") {
    Scene occluded = MakeScene("occluded", {});
    for (auto &patch : occluded.Get<Segment>())
        patch.material = {0.6, 0};
    occluded.Get<Segment>()[0].material.emission = 1;
    RefineOptions one = Refining(0.05), two = Refining(0.05);
    one.visibility = two.visibility = VisibilityMode::Fraction;
    two.threads = 2;
    SolveResult a = Solve(occluded, one, Solving(1e-8)), b = Solve(occluded, two, Solving(1e-8));
    REQUIRE(a.record.counters.occludedPairs > 0);
    CHECK(Radiosities(a) == Radiosities(b));
    CHECK(a.iterations == b.iterations);
    CHECK(a.absorbedPower == b.absorbedPower);
    // And in 3D, where the form factors cost the most.
    RefineOptions one3 = Refining(0.05, 0.05), two3 = Refining(0.05, 0.05);
    two3.threads = 2;
    Scene box = ClosedBox(1, 0.5);
    CHECK(Radiosities(Solve(box, one3, Solving(1e-8))) ==
          Radiosities(Solve(box, two3, Solving(1e-8))));
}

TEST_CASE("ParallelFor visits every index once and rethrows the earliest failure", "[solve]") {
    for (int threads : {1, 2, 4}) {
        std::vector<int> visits(1000, 0);
        std::atomic<int> states{0};
        ParallelFor(
            visits.size(), 7, threads, [&] { return ++states; },
            [&](int, size_t k) { ++visits[k]; });
        CHECK(std::count(visits.begin(), visits.end(), 1) == 1000);
        CHECK(states == threads);  // one state per worker
        // Chunks are taken in order and finish once taken, so 300 fails whenever 600 does.
        for (int run = 0; run < 20; ++run)
            CHECK_THROWS_WITH(ParallelFor(
                                  1000, 7, threads, [] { return 0; },
                                  [](int, size_t k) {
                                      if (k == 300 || k == 600)
                                          throw std::runtime_error(std::to_string(k));
                                  }),
                              "300");
    }
    bool ran = false;
    ParallelFor(
        0, 4, 2, [] { return 0; }, [&](int, size_t) { ran = true; });
    CHECK_FALSE(ran);
}

TEST_CASE("ParallelFor makes each worker's state with its index, once", "[solve]") {
    // 3 chunks of 7 indices: at most 3 workers, whatever the thread count.
    for (int threads : {1, 2, 4}) {
        std::vector<std::atomic<int>> made(4);
        ParallelFor(
            21, 7, threads,
            [&](size_t w) {
                ++made[w];
                return w;
            },
            [](size_t, size_t) {});
        for (size_t w = 0; w < made.size(); ++w)
            CHECK(made[w] == (w < size_t(std::min(threads, 3)) ? 1 : 0));
    }
}

// ---------------------------------------------------------------------------------------
// BF refinement in passes

namespace {

SolveOptions Passes(int passes) {
    SolveOptions o = Solving(1e-6);
    o.passes = passes;
    return o;
}

// Whether the passes of _r_ stopped by the rule: every pass but the last differs from
// the one before in links or nodes, and the last repeats its predecessor or hits _cap_.
bool StoppedByTheRule(const SolveResult &r, int cap) {
    auto same = [&](size_t k) {
        return r.passLinks[k] == r.passLinks[k - 1] && r.passNodes[k] == r.passNodes[k - 1];
    };
    size_t n = r.passLinks.size();
    if (n != size_t(r.passes) || r.passNodes.size() != n || n < 1 || r.passes > cap)
        return false;
    for (size_t k = 1; k + 1 < n; ++k)
        if (same(k))
            return false;
    return r.passes == cap || (n > 1 && same(n - 1));
}

// The solution's B is E + rho H >= E on every element and bf accepts less as B grows, so
// pass 2 splits every pair pass 1 split (nodes do not fall); and pass 1 linked every pair
// of non-emitting roots at once (B = 0 there), which pass 2, with lit walls, refines.
void CheckSecondPassRefinesMore(const Scene &scene, const RefineOptions &refine) {
    SolveResult one = Solve(scene, refine, Passes(1));
    SolveResult two = Solve(scene, refine, Passes(2));
    SolveResult all = Solve(scene, refine, Passes(kMaxPasses));
    REQUIRE(one.passes == 1);
    CHECK(one.passLinks == std::vector<uint64_t>{one.record.counters.links});
    CHECK(one.passNodes == std::vector<uint64_t>{one.record.counters.nodes});
    REQUIRE(two.passes == 2);
    CHECK(two.passLinks[0] == one.passLinks[0]);
    CHECK(two.passNodes[0] == one.passNodes[0]);
    CHECK(two.passLinks[1] > two.passLinks[0]);
    CHECK(two.passNodes[1] >= two.passNodes[0]);
    CHECK(two.record.counters.links == two.passLinks[1]);
    // Every run's passes begin alike and stop by the rule.
    CHECK(StoppedByTheRule(one, 1));
    CHECK(StoppedByTheRule(two, 2));
    CHECK(StoppedByTheRule(all, kMaxPasses));
    REQUIRE(all.passes >= 2);
    CHECK(std::equal(two.passLinks.begin(), two.passLinks.end(), all.passLinks.begin()));
    CHECK(all.record.counters.links == all.passLinks.back());
    CHECK(all.record.counters.nodes == all.passNodes.back());
    CHECK(all.leaves.size() == all.record.counters.leaves);
}

}  // namespace

TEST_CASE("bf refines again with the solution's B until links and nodes repeat, in 3D",
          "[solve][bf][3d]") {
    Scene cornell = MakeScene("cornell", {});
    RefineOptions bf = Refining(0.05, 0.001, "bf");
    CheckSecondPassRefinesMore(cornell, bf);
    // --passes 1 is the one refinement with the roots' emission: the refinement alone.
    Refinement<Polygon> single = Refine<Polygon>(cornell, bf);
    SolveResult one = Solve(cornell, bf, Passes(1));
    CHECK(one.record.counters.links == single.record.counters.links);
    CHECK(one.record.counters.nodes == single.record.counters.nodes);
    CHECK(one.record.counters.leaves == single.record.counters.leaves);
    // The default is at most kDefaultPasses.
    SolveResult byDefault = Solve(cornell, bf, Solving(1e-6));
    CHECK(StoppedByTheRule(byDefault, kDefaultPasses));
}

TEST_CASE("bf refines again with the solution's B, in 2D", "[solve][bf][2d]") {
    // The closed room, one wall emitting: in pass 1 the three dark walls link pairwise at
    // the roots.
    Scene room = MakeScene("room", {{"w", 2}, {"h", 1}});
    for (auto &patch : room.Get<Segment>())
        patch.material = {0.5, 0};
    room.Get<Segment>()[0].material.emission = 1;
    RefineOptions bf = Refining(0.05, 0.01, "bf");
    CheckSecondPassRefinesMore(room, bf);
    Refinement<Segment> single = Refine<Segment>(room, bf);
    CHECK(Solve(room, bf, Passes(1)).record.counters.links == single.record.counters.links);
}

TEST_CASE("bf's passes are the same bit for bit on 1 and 2 threads", "[solve][bf]") {
    Scene cornell = MakeScene("cornell", {});
    RefineOptions one = Refining(0.05, 0.001, "bf"), two = one;
    two.threads = 2;
    SolveResult a = Solve(cornell, one, Passes(3)), b = Solve(cornell, two, Passes(3));
    CHECK(a.passLinks == b.passLinks);
    CHECK(a.passNodes == b.passNodes);
    CHECK(Radiosities(a) == Radiosities(b));
    CHECK(a.iterations == b.iterations);
}

TEST_CASE("Passes apply to bf only; other oracles refine once", "[solve][bf][errors]") {
    Scene room = UniformRoom();
    SolveResult r = Solve(room, Refining(0.1, 0.01), Solving(1e-6));
    CHECK(r.passes == 1);
    CHECK(r.passLinks == std::vector<uint64_t>{r.record.counters.links});
    CHECK_THROWS_WITH(Solve(room, Refining(0.1, 0.01), Passes(2)),
                      Catch::StartsWith("--passes applies to the bf oracle only"));
    CHECK_THROWS_WITH(Solve(room, Refining(0.1, 0.01, "bf"), Passes(0)),
                      "--passes must be between 1 and 100");
    CHECK_THROWS_WITH(Solve(room, Refining(0.1, 0.01, "bf"), Passes(101)),
                      "--passes must be between 1 and 100");
}

TEST_CASE("The memory budget counts the previous bf pass's solution", "[solve][bf][errors]") {
    // With rho = 0 the solution is B = E, so pass 2 refines exactly as pass 1 did: the
    // smallest budget that fits one pass does not fit a second beside the first's forest.
    Scene plates = MakeScene("parallel", {{"l", 4}, {"d", 1}});
    for (auto &patch : plates.Get<Segment>())
        patch.material = {0, 1};
    RefineOptions bf = Refining(0.05, 0, "bf");
    auto fits = [&](size_t budget, int passes) {
        RefineOptions within = bf;
        within.memoryBudget = budget;
        try {
            Solve(plates, within, Passes(passes));
            return true;
        } catch (const LimitError &e) {
            CHECK_THAT(e.what(), Catch::Contains("memory budget"));
            return false;
        }
    };
    SolveResult two = Solve(plates, bf, Passes(2));
    REQUIRE(two.passes == 2);
    REQUIRE(two.passNodes[1] == two.passNodes[0]);
    REQUIRE(two.passLinks[1] == two.passLinks[0]);
    size_t low = 1, high = size_t(64) << 20;  // fails, fits
    REQUIRE(fits(high, 1));
    while (high - low > 1) {
        size_t middle = low + (high - low) / 2;
        (fits(middle, 1) ? high : low) = middle;
    }
    CHECK_FALSE(fits(high, 2));
    CHECK(fits(2 * high, 2));
}

// ---------------------------------------------------------------------------------------
// Bad input (library)

TEST_CASE("Solve refuses what it cannot solve", "[solve][errors]") {
    Scene dark = MakeScene("parallel", {});
    CHECK_THROWS_WITH(Solve(dark, Refining(0.5), Solving(1e-6)),
                      "nothing emits: give --emission or a scene with an emitter");
    Scene lit = UniformRoom();
    SolveOptions few = Solving(1e-12);
    few.maxIterations = 3;
    try {
        Solve(lit, Refining(0.1, 0.01), few);
        FAIL("no LimitError");
    } catch (const LimitError &e) {
        CHECK_THAT(e.what(),
                   Catch::StartsWith("solve did not converge in 3 iterations (residual "));
    }
    SolveOptions deep = Solving(1e-6);
    deep.referenceDepth = 20;
    CHECK_THROWS_AS(Solve(lit, Refining(0.1, 0.01), deep), InputError);
}

// ---------------------------------------------------------------------------------------
// The solve command

TEST_CASE("solve --json reports the run record and the solution", "[solve][cli]") {
    std::string csvPath = Scratch("solve.csv");
    CliResult r = Cli("solve room w=2 h=1 --eps 0.05 --min-area 0.01 --emission 1 "
                      "--reflectance 0.5 --json --out " +
                      csvPath);
    REQUIRE(r.exitCode == 0);
    CHECK(r.err.empty());
    json j = json::parse(r.out);
    CHECK(j["scene"] == "room");
    CHECK(j["mode"] == "store");
    CHECK(j["method"] == "enumerate");
    CHECK(j["solver"] == "jacobi");
    CHECK(j["tolerance"] == 1e-6);
    CHECK(j["max_iterations"] == 1000);
    CHECK(j["emission"] == 1.0);
    CHECK(j["reflectance"] == 0.5);
    CHECK(j["radiosity"].size() == j["leaves"].get<size_t>());
    CHECK(j["iterations"].get<int>() > 1);
    CHECK(j["residual"].get<double>() < 1e-6);
    CHECK(j["emitted_power"] == 6.0);
    CHECK(j["absorbed_power"].get<double>() == Approx(6).epsilon(1e-4));
    for (const char *stage : {"refine", "coefficients", "solve"}) {
        CHECK(j[std::string("seconds_") + stage].get<double>() >= 0);
        CHECK(j[std::string("cpu_seconds_") + stage].get<double>() >= 0);
    }
    for (const json &b : j["radiosity"])
        CHECK(std::abs(b.get<double>() - 2) < 0.05);
    // The CSV: a header and one row per leaf, in the JSON's order.
    std::istringstream csv(ReadFile(csvPath));
    std::string line;
    std::getline(csv, line);
    CHECK(line == "element,root,depth,position,x,y,measure,radiosity,irradiance,reflectance,"
                  "emission,red,green,blue,x0,y0,x1,y1");
    size_t rows = 0;
    double length = 0;
    while (std::getline(csv, line)) {
        std::vector<std::string> cells;
        std::stringstream fields(line);
        for (std::string cell; std::getline(fields, cell, ',');)
            cells.push_back(cell);
        REQUIRE(cells.size() == 18);
        CHECK(std::stod(cells[7]) == j["radiosity"][rows].get<double>());
        length += std::stod(cells[6]);
        ++rows;
    }
    CHECK(rows == j["leaves"].get<size_t>());
    CHECK(length == Approx(6));
    // The same run as a table, and with --reference.
    CliResult table = Cli("solve room --eps 0.05 --min-area 0.01 --emission 1 --solver "
                          "gauss-seidel --reference 4");
    CHECK(table.exitCode == 0);
    CHECK_THAT(table.out, Catch::Contains("gauss-seidel") && Catch::Contains("radiosity_max") &&
                              Catch::Contains("reference_error_max") &&
                              Catch::Contains("reference_error_l2") &&
                              Catch::Contains("reference_change"));
    json withReference = json::parse(
        Cli("solve room --eps 0.05 --min-area 0.01 --emission 1 --reference 4 --json").out);
    CHECK(withReference["reference_error_l2"].get<double>() > 0);
    CHECK(withReference["reference_change"].get<double>() < 1e-12);  // B = 2 on both meshes
    json depth0 = json::parse(
        Cli("solve room --eps 0.05 --min-area 0.01 --emission 1 --reference 0 --json").out);
    CHECK(depth0.contains("reference_error_l2"));
    CHECK_FALSE(depth0.contains("reference_change"));
}

namespace {

// The rows of a CSV file after its header, each split at its commas (empty cells kept).
std::vector<std::vector<std::string>> CsvRows(const std::string &path, std::string &header) {
    std::istringstream csv(ReadFile(path));
    std::getline(csv, header);
    std::vector<std::vector<std::string>> rows;
    for (std::string line; std::getline(csv, line);) {
        std::vector<std::string> cells;
        size_t start = 0;
        for (size_t comma; (comma = line.find(',', start)) != std::string::npos; start = comma + 1)
            cells.push_back(line.substr(start, comma - start));
        cells.push_back(line.substr(start));
        rows.push_back(cells);
    }
    return rows;
}

}  // namespace

TEST_CASE("solve --out gives each leaf's material, display colour and segment in 2D",
          "[solve][cli]") {
    // parallel l=4 d=1: P from (0,0) to (4,0), Q from (4,1) to (0,1); eps 0.3 splits
    // both plates uniformly, to depth 4, so each leaf's end points are multiples of 4/16.
    std::string csvPath = Scratch("solve2d.csv");
    REQUIRE(Cli("solve parallel l=4 d=1 --eps 0.3 --emission 1 --reflectance 0.25 --out " + csvPath)
                .exitCode == 0);
    std::string header;
    std::vector<std::vector<std::string>> rows = CsvRows(csvPath, header);
    CHECK(header == "element,root,depth,position,x,y,measure,radiosity,irradiance,reflectance,"
                    "emission,red,green,blue,x0,y0,x1,y1");
    REQUIRE(rows.size() == 32);
    for (const std::vector<std::string> &row : rows) {
        INFO(row[0]);
        REQUIRE(row.size() == 18);
        int root = std::stoi(row[1]), depth = std::stoi(row[2]), position = std::stoi(row[3]);
        CHECK(depth == 4);
        double h = 4.0 / (1 << depth);
        // The overrides, and grey of the reflectance: the scene gives no colour.
        for (int c = 9; c <= 13; ++c)
            CHECK(std::stod(row[size_t(c)]) == (c == 10 ? 1 : 0.25));
        double along = root == 0 ? position * h : 4 - position * h;
        double next = root == 0 ? (position + 1) * h : 4 - (position + 1) * h;
        CHECK(std::stod(row[14]) == along);
        CHECK(std::stod(row[15]) == root);
        CHECK(std::stod(row[16]) == next);
        CHECK(std::stod(row[17]) == root);
        CHECK(std::stod(row[6]) == h);
        CHECK(std::stod(row[4]) == (along + next) / 2);
    }
}

TEST_CASE("solve --out gives each leaf's corners and display colour in 3D", "[solve][cli][3d]") {
    std::string csvPath = Scratch("solve3d.csv");
    REQUIRE(Cli("solve cornell --eps 0.05 --min-area 0.01 --out " + csvPath).exitCode == 0);
    std::string header;
    std::vector<std::vector<std::string>> rows = CsvRows(csvPath, header);
    CHECK(header == "element,root,depth,position,x,y,z,measure,radiosity,irradiance,reflectance,"
                    "emission,red,green,blue,corners,x0,y0,z0,x1,y1,z1,x2,y2,z2,x3,y3,z3");
    const Patches<Polygon> roots = MakeScene("cornell", {}).Get<Polygon>();
    std::vector<double> area(roots.size(), 0);
    for (const std::vector<std::string> &row : rows) {
        INFO(row[0]);
        REQUIRE(row.size() == 28);
        size_t root = std::stoul(row[1]);
        REQUIRE(root < roots.size());
        const Polygon &patch = roots[root].shape;
        const Material &material = roots[root].material;
        CHECK(std::stod(row[10]) == material.reflectance);
        CHECK(std::stod(row[11]) == material.emission);
        for (size_t c = 0; c < 3; ++c)
            CHECK(std::stod(row[12 + c]) == material.DisplayColour()[c]);
        // A leaf has its root's number of corners (a triangle's fourth is empty), each in
        // the root's plane and inside it, and its area is the measure.
        int n = std::stoi(row[15]);
        CHECK(n == patch.n);
        std::array<Vec3, 4> corner;
        for (int k = 0; k < n; ++k) {
            for (int d = 0; d < 3; ++d)
                corner[size_t(k)][d] = std::stod(row[16 + 3 * size_t(k) + size_t(d)]);
            Vec3 normal = patch.Normal();
            CHECK(std::abs((corner[size_t(k)] - patch.v[0]).dot(normal)) < 1e-12);
            for (int e = 0; e < patch.n; ++e) {
                const Vec3 &from = patch.v[size_t(e)], &to = patch.v[size_t((e + 1) % patch.n)];
                CHECK((to - from).cross(corner[size_t(k)] - from).dot(normal) > -1e-12);
            }
        }
        if (n == 3)
            CHECK((row[25].empty() && row[26].empty() && row[27].empty()));
        Polygon leaf = n == 3 ? Polygon::Triangle(corner[0], corner[1], corner[2])
                              : Polygon::Quad(corner[0], corner[1], corner[2], corner[3]);
        CHECK(leaf.Area() == Approx(std::stod(row[7])).epsilon(1e-12));
        area[root] += std::stod(row[7]);
    }
    for (size_t root = 0; root < roots.size(); ++root)
        CHECK(area[root] == Approx(roots[root].shape.Area()).epsilon(1e-12));
    // The measured RGB of the walls; the light is grey of its reflectance.
    CHECK(roots[0].material.DisplayColour() == Rgb{0.725, 0.71, 0.68});
    CHECK(roots[3].material.DisplayColour() == Rgb{0.14, 0.45, 0.091});
    CHECK(roots[4].material.DisplayColour() == Rgb{0.63, 0.065, 0.05});
    CHECK(roots[6].material.DisplayColour() == Rgb{0.78, 0.78, 0.78});
}

TEST_CASE("solve reads scene files and meshes, and lists itself", "[solve][cli]") {
    std::string scenePath = Scratch("lit_plates.json");
    REQUIRE(Cli("save parallel l=1 d=1 --out " + scenePath).exitCode == 0);
    json file = json::parse(
        Cli("solve --scene-file " + scenePath + " --eps 0.5 --emission 2 --reflectance 0 --json")
            .out);
    CHECK(file["scene_file"] == scenePath);
    for (const json &b : file["radiosity"])
        CHECK(b == 2.0);  // nothing reflects
    CHECK(file["iterations"] == 1);
    json mesh = json::parse(
        Cli("solve --mesh " HRBENCH_TEST_DATA "/two_plates.obj --eps 0.5 --emission 1 --json").out);
    CHECK(mesh["dimension"] == 3);
    CHECK(mesh["radiosity"].size() == mesh["leaves"].get<size_t>());
    json caps = json::parse(Cli("capabilities --json").out);
    bool listed = false;
    for (const json &c : caps["commands"])
        listed |= c["name"] == "solve";
    CHECK(listed);
    CHECK(caps["solvers"].size() == SolveMethods().size());
    for (const json &o : caps["options"])
        if (o["name"] == "emission")
            CHECK(o["commands"] == json({"solve"}));
        else if (o["name"] == "tolerance")  // dump-paths' matching tolerance too
            CHECK(o["commands"] == json({"solve", "dump-paths"}));
    CHECK_THAT(Cli("--help").out,
               Catch::Contains("solve SCENE") && Catch::Contains("--max-iterations"));
}

TEST_CASE("solve accounts for occlusion where the scene can occlude, and warns of made energy",
          "[solve][cli][energy]") {
    // A closed 2D room lit by its ceiling (emission 1, length 2) with a box in it.
    const std::string box =
        "solve --scene-file " HRBENCH_TEST_DATA "/room_box.json --eps 0.05 --min-area 0.01 --json";
    CliResult fraction = Cli(box);
    REQUIRE(fraction.exitCode == 0);
    CHECK(fraction.err.empty());
    json j = json::parse(fraction.out);
    CHECK(j["visibility"] == "fraction");
    CHECK(j["gather"] == "plain");
    CHECK(j["emitted_power"] == 2.0);
    // Closed: all but what the sampled visibility and the plain gather lose is absorbed
    // (measured 1.996).
    CHECK(j["absorbed_power"].get<double>() <= 2);
    CHECK(j["absorbed_power"].get<double>() > 1.99);
    CHECK(j["energy_balance_warning"].is_null());
    // The papers' setting, asked for: light passes through the box (measured 3.72 of 2).
    CliResult none = Cli(box + " --visibility none");
    REQUIRE(none.exitCode == 0);
    json n = json::parse(none.out);
    CHECK(n["visibility"] == "none");
    CHECK(n["absorbed_power"].get<double>() > 3.5);
    REQUIRE(n["energy_balance_warning"].is_string());
    std::string warning = n["energy_balance_warning"];
    CHECK(none.err == "hrbench: warning: " + warning + "\n");
    CHECK_THAT(warning, Catch::StartsWith("--visibility none lets light pass through the patches "
                                          "between others") &&
                            Catch::EndsWith("absorbed power 3.72 against emitted power 2 "
                                            "(+85.9%), light let through among it"));
    // The same in 3D: a room lit by its ceiling (emission 1, area 4), a box floating in it.
    const std::string room3d =
        "solve --mesh " HRBENCH_TEST_DATA "/room_box.obj --eps 0.5 --min-area 0.05 --json";
    json j3 = json::parse(Cli(room3d).out);
    CHECK(j3["visibility"] == "fraction");
    CHECK(j3["emitted_power"] == 4.0);
    CHECK(j3["absorbed_power"].get<double>() <= 4);
    CHECK(j3["energy_balance_warning"].is_null());
    CliResult none3 = Cli(room3d + " --visibility none");
    json n3 = json::parse(none3.out);
    CHECK(n3["absorbed_power"].get<double>() > 4.2);
    CHECK(n3["energy_balance_warning"].is_string());
    CHECK_THAT(none3.err, Catch::StartsWith("hrbench: warning: --visibility none lets light "
                                            "pass through") &&
                              Catch::EndsWith("absorbed power 4.88 against emitted power 4 "
                                              "(+21.9%), light let through among it\n"));
    // The open Cornell box loses more through its front than the blocks let through: the
    // powers alone would not tell, the line does.
    CliResult cornell = Cli("solve cornell --eps 0.5 --min-area 0.01 --visibility none");
    CHECK(cornell.exitCode == 0);
    CHECK_THAT(cornell.err, Catch::StartsWith("hrbench: warning: --visibility none lets light"));
    CHECK_THAT(cornell.out, Catch::Contains("visibility none"));

    // Two facing plates cannot occlude: the papers' none, exact, and nothing to warn of.
    CliResult plates = Cli("solve parallel --eps 0.1 --emission 1 --json");
    CHECK(plates.err.empty());
    json p = json::parse(plates.out);
    CHECK(p["visibility"] == "none");
    CHECK(p["gather"] == "consistent");
    CHECK(p["energy_balance_warning"].is_null());
    // Nor can the closed room; HSA91's plain gather makes energy there at a coarse eps
    // (measured 0.37%), within what a discretisation may account for.
    CliResult plain = Cli("solve room lamp=1 --eps 0.5 --min-area 0.01 --plain-gather --json");
    CHECK(plain.err.empty());
    json pj = json::parse(plain.out);
    CHECK(pj["visibility"] == "none");
    CHECK(pj["absorbed_power"].get<double>() > 2.005);
    CHECK(pj["energy_balance_warning"].is_null());
    // Counting keeps the papers' none whatever the scene.
    json run = json::parse(Cli("run --scene-file " HRBENCH_TEST_DATA
                               "/room_box.json --eps 0.05 --min-area 0.01 "
                               "--json")
                               .out);
    CHECK(run["visibility"] == "none");
}

TEST_CASE("solve --oracle bf reports its passes, and reads --emission", "[solve][bf][cli]") {
    const std::string cornell = "solve cornell --oracle bf --eps 0.05 --min-area 0.001 --json";
    json two = json::parse(Cli(cornell + " --passes 2").out);
    CHECK(two["passes"] == 2);
    REQUIRE(two["pass_links"].size() == 2);
    REQUIRE(two["pass_nodes"].size() == 2);
    CHECK(two["pass_links"][1] > two["pass_links"][0]);
    CHECK(two["links"] == two["pass_links"][1]);
    CHECK(two["nodes"] == two["pass_nodes"][1]);
    CHECK_THAT(Cli("solve cornell --oracle bf --eps 0.05 --min-area 0.001 --passes 2").out,
               Catch::Contains("pass_links") && Catch::Contains("passes"));
    // The parallel plates emit nothing: only --emission lights them, and the first pass
    // reads it. Doubling B halves bf's threshold on F exactly.
    const std::string plates = "solve parallel l=4 d=1 --oracle bf --passes 1 --json";
    json e1 = json::parse(Cli(plates + " --emission 1 --eps 0.05").out);
    json e2 = json::parse(Cli(plates + " --emission 2 --eps 0.1").out);
    CHECK(e1["links"].get<uint64_t>() > 1);
    CHECK(e1["pass_links"] == e2["pass_links"]);
    CHECK(e1["pass_nodes"] == e2["pass_nodes"]);
    json garmann = json::parse(Cli("solve parallel --eps 0.5 --emission 1 --json").out);
    CHECK(garmann["passes"] == 1);
}

TEST_CASE("solve's bad input gives one line and exit code 2, limits exit code 3",
          "[solve][cli][errors]") {
    const std::string room = "solve room --eps 0.1 --min-area 0.01 ";
    CheckError("solve parallel --eps 0.5", 2,
               "nothing emits: give --emission or a scene with an emitter");
    CheckError("solve parallel --eps 0.5 --emission 0", 2, "nothing emits");
    CheckError(room + "--reflectance 1", 2, "--reflectance must be a number in [0, 1)");
    CheckError(room + "--reflectance -0.1", 2, "--reflectance must be a number in [0, 1)");
    CheckError(room + "--reflectance nan", 2, "not a finite number");
    CheckError(room + "--emission -1", 2, "--emission must be a finite number >= 0");
    CheckError(room + "--emission inf", 2, "not a finite number");
    CheckError(room + "--emission 1 --tolerance 0", 2, "--tolerance must be a number in (0, 1)");
    CheckError(room + "--emission 1 --tolerance 1", 2, "--tolerance must be a number in (0, 1)");
    CheckError(room + "--emission 1 --max-iterations 0", 2, "--max-iterations must be between");
    CheckError(room + "--emission 1 --count-only", 2,
               "--count-only does not apply to solve: it needs every link stored");
    CheckError(room + "--emission 1 --method translation", 2,
               "--method does not apply to solve: it stores and enumerates every link");
    CheckError(room + "--emission 1 --solver newton", 2, "unknown solver 'newton'");
    CheckError("run parallel --eps 0.5 --solver jacobi", 2, "--solver does not apply to run");
    CheckError("run parallel --eps 0.5 --tolerance 0.1", 2, "--tolerance does not apply to run");
    CheckError("solve room --eps 0.1 --emission 1", 2, "touch");
    CheckError("solve parallel --emission 1", 2, "solve needs --eps");
    CheckError(room + "--emission 1 --reference 20", 2, "the most the dense reference solves");
    CheckError(room + "--emission 1 --out /dev/full", 2, "cannot write solve file '/dev/full'");
    std::string badColour = Scratch("bad_colour.json");
    std::ofstream(badColour) << R"({"format":"hrbench-scene","schema_version":1,"patches":[)"
                                R"({"a":[0,0],"b":[1,0],"emission":1,"colour":[0.5,-1,0]},)"
                                R"({"a":[1,1],"b":[0,1]}]})";
    CheckError("solve --scene-file " + badColour + " --eps 0.5", 2,
               "patch 0 has a colour component outside [0, 1]");
    CheckError(room + "--emission 1 --max-iterations 3 --tolerance 1e-9", 3,
               "solve did not converge in 3 iterations (residual ");
    CheckError("solve parallel l=1024 --eps 0.01 --emission 1 --max-memory 1", 3, "memory budget");
    // 3 MiB fit one bf pass but not a second, identical one (B = E with rho = 0) beside
    // the first's forest (with the centre-cosine estimate, whose refinement sizes this).
    const std::string bf = "solve parallel l=16 d=1 --eps 0.015 --oracle bf --emission 1 "
                           "--reflectance 0 --ff-estimate centre-cosine --max-memory 3 --passes ";
    CHECK(Cli(bf + "1").exitCode == 0);
    CheckError(bf + "2", 3, "would exceed the memory budget");
    CheckError(room + "--emission 1 --passes 2", 2, "--passes applies to the bf oracle only");
    CheckError(room + "--emission 1 --oracle garmann --passes 1", 2,
               "--passes applies to the bf oracle only");
    CheckError(room + "--emission 1 --oracle bf --passes 0", 2, "--passes must be between 1 and");
    CheckError("run parallel --eps 0.5 --passes 2", 2, "--passes does not apply to run");
}
