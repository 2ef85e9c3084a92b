// What a solve says of its own accuracy (docs/solve.md): the exact form factors of its
// links, HSA91's "same precision" guarantee measured (link_form_factor_max and
// link_form_factor_above_eps, also `run --link-form-factors`), and the error against the
// dense reference split into the projection's and the hierarchy's.
#include <catch2/catch.hpp>

#include <cmath>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "cli_helpers.h"
#include "generators.h"
#include "hrbench/hrbench.h"
#include "solve/form_factor.h"

using namespace hrbench;
using namespace hrbench_test;
using nlohmann::json;

namespace {

RefineOptions Refining(double eps, int maxDepth = -1, const std::string &oracle = "garmann") {
    RefineOptions o;
    o.eps = eps;
    o.maxDepth = maxDepth;
    o.oracle = oracle;
    o.storeLinks = true;
    return o;
}

SolveOptions Solving(int referenceDepth = -1) {
    SolveOptions o;
    o.tolerance = 1e-12;
    o.emission = 1;
    o.referenceDepth = referenceDepth;
    return o;
}

// Howell's C-11: parallel opposed rectangles a x b at distance c.
double ParallelRectangles(double a, double b, double c) {
    const double pi = std::acos(-1.0);
    double X = a / c, Y = b / c;
    double X2 = 1 + X * X, Y2 = 1 + Y * Y;
    return 2 / (pi * X * Y) *
           (std::log(std::sqrt(X2 * Y2 / (X2 + Y2 - 1))) +
            X * std::sqrt(Y2) * std::atan(X / std::sqrt(Y2)) +
            Y * std::sqrt(X2) * std::atan(Y / std::sqrt(X2)) - X * std::atan(X) - Y * std::atan(Y));
}

// The measures of _refinement_'s links recomputed one by one from FormFactor.
template <typename Shape>
LinkFormFactors ByHand(const Refinement<Shape> &refinement, double eps) {
    LinkFormFactors m;
    size_t above = 0;
    for (const Link &l : refinement.links) {
        Shape i = refinement.forest.ShapeOf(l.i), j = refinement.forest.ShapeOf(l.j);
        double larger = std::max(FormFactor(i, j), FormFactor(j, i));
        m.max = std::max(m.max, larger);
        above += larger > eps;
    }
    m.aboveEps = double(above) / double(refinement.links.size());
    return m;
}

// reference_error_l2^2 against projection_error_l2^2 + hierarchy_error_l2^2.
void CheckOrthogonal(const ReferenceComparison &c) {
    double parts =
        c.projection.l2Error * c.projection.l2Error + c.hierarchy.l2Error * c.hierarchy.l2Error;
    CHECK(c.l2Error * c.l2Error == Approx(parts).epsilon(1e-9));
    CHECK(c.projection.l2Error > 0);
    CHECK(c.hierarchy.l2Error > 0);
    for (const ErrorNorms *n : {&c.projection, &c.hierarchy}) {
        CHECK(n->meanError <= n->l2Error);
        CHECK(n->l2Error <= n->maxError);
    }
}

}  // namespace

// ---------------------------------------------------------------------------------------
// The links' exact form factors

TEST_CASE("Two facing unit segments linked at the roots: sqrt(1 + d^2) - d", "[solve]") {
    for (double d : {0.25, 1.0, 3.0}) {
        INFO("d " << d);
        Scene plates = MakeScene("parallel", {{"l", 1}, {"d", d}});
        double exact = std::sqrt(1 + d * d) - d;
        // --max-depth 0 links the roots whatever eps: eps just below and above F.
        for (double eps : {exact * 0.99, exact * 1.01, 100.0}) {
            SolveResult r = Solve(plates, Refining(eps, 0), Solving());
            REQUIRE(r.record.counters.links == 1);
            CHECK(r.linkFormFactors.max == Approx(exact).margin(1e-12));
            CHECK(r.linkFormFactors.aboveEps == (eps < exact ? 1 : 0));
        }
    }
}

TEST_CASE("Two facing unit squares linked at the roots: Howell's C-11", "[solve]") {
    Scene squares = MakeScene("parallel3d", {{"l", 1}, {"d", 1}});
    double exact = ParallelRectangles(1, 1, 1);
    REQUIRE(exact == Approx(0.19982).margin(1e-5));
    SolveResult r = Solve(squares, Refining(0.1, 0), Solving());
    REQUIRE(r.record.counters.links == 1);
    CHECK(r.linkFormFactors.max == Approx(exact).epsilon(1e-9));
    CHECK(r.linkFormFactors.aboveEps == 1);
    RefineOptions o = Refining(0.3, 0);
    CHECK(MeasureLinkFormFactors(Refine(squares, o), o).aboveEps == 0);
}

TEST_CASE("The link form factors are every link's larger direction, on any thread count",
          "[solve]") {
    // Unequal plates, so that the two directions of a link differ; occluded plates with
    // visibility, where the coefficients are weighed by the visible fraction but the
    // measure is of the exact form factors.
    struct Case {
        Scene scene;
        RefineOptions options;
    };
    // garmann keeps every link within eps here; the others keep a few above it.
    RefineOptions visible = Refining(0.02);
    visible.visibility = VisibilityMode::Fraction;
    std::vector<Case> cases = {
        {MakeScene("parallel", {{"l", 4}, {"l2", 1}, {"d", 1}}), Refining(0.05)},
        {MakeScene("parallel", {{"l", 4}, {"d", 1}}), Refining(0.05, -1, "hanrahan")},
        {MakeScene("occluded", {}), visible},
        {MakeScene("parallel3d", {{"l", 2}, {"w", 1}, {"d", 1}}), Refining(0.05, -1, "hanrahan")},
    };
    for (const Case &c : cases) {
        INFO(c.scene.family << " eps " << c.options.eps);
        auto shaped = [&](auto shape) {
            using Shape = decltype(shape);
            AnyRefinement refinement = Refine(c.scene, c.options);
            LinkFormFactors hand = ByHand(std::get<Refinement<Shape>>(refinement), c.options.eps);
            CHECK(hand.max > 0);
            CHECK((hand.aboveEps > 0) ==
                  (c.options.oracle == "hanrahan" || c.options.visibility != VisibilityMode::None));
            CHECK(hand.aboveEps < 0.05);
            for (int threads : {1, 3}) {
                RefineOptions o = c.options;
                o.threads = threads;
                LinkFormFactors measured = MeasureLinkFormFactors(refinement, o);
                CHECK(measured.max == Approx(hand.max).epsilon(1e-12));
                CHECK(measured.aboveEps == hand.aboveEps);
                SolveResult solved = Solve(c.scene, o, Solving());
                CHECK(solved.linkFormFactors.max == measured.max);
                CHECK(solved.linkFormFactors.aboveEps == measured.aboveEps);
            }
        };
        if (c.scene.Dimension() == 2)
            shaped(Segment{});
        else
            shaped(Polygon{});
    }
}

TEST_CASE("run --link-form-factors and solve agree; run refuses it without stored links",
          "[solve][cli]") {
    for (std::string scene :
         {"parallel l=8 d=1 --eps 0.02 --oracle hanrahan",
          "occluded --eps 0.05 --visibility fraction", "parallel3d l=2 d=1 --eps 0.2"}) {
        INFO(scene);
        CliResult run = Cli("run " + scene + " --link-form-factors --json");
        CliResult solve = Cli("solve " + scene + " --emission 1 --json");
        REQUIRE(run.exitCode == 0);
        REQUIRE(solve.exitCode == 0);
        json r = json::parse(run.out), s = json::parse(solve.out);
        CHECK(r["links"] == s["links"]);
        CHECK(r["link_form_factor_max"].get<double>() > 0);
        CHECK(r["link_form_factor_max"] == s["link_form_factor_max"]);
        CHECK(r["link_form_factor_above_eps"] == s["link_form_factor_above_eps"]);
    }
    // bf: one pass is run's refinement with E; with more, the measures are the last pass's.
    std::string bf = "cornell --oracle bf --eps 0.1 --min-area 0.01 --visibility fraction";
    json run = json::parse(Cli("run " + bf + " --link-form-factors --json").out);
    json once = json::parse(Cli("solve " + bf + " --passes 1 --json").out);
    json passes = json::parse(Cli("solve " + bf + " --json").out);
    CHECK(once["link_form_factor_max"] == run["link_form_factor_max"]);
    CHECK(once["link_form_factor_above_eps"] == run["link_form_factor_above_eps"]);
    REQUIRE(passes["passes"].get<int>() > 1);
    CHECK(passes["pass_links"].front() != passes["links"]);  // 133 and 134 links
    CHECK(passes["pass_links"].back() == passes["links"]);
    double above =
        passes["link_form_factor_above_eps"].get<double>() * passes["links"].get<double>();
    CHECK(above == Approx(std::round(above)).margin(1e-9));  // a count of the last links
    CHECK(above > 0);
    // The tables: run's rows only when asked.
    CliResult plain = Cli("run parallel l=1 d=1 --eps 0.5");
    CliResult asked = Cli("run parallel l=1 d=1 --eps 0.5 --max-depth 0 --link-form-factors");
    CHECK_THAT(plain.out, !Catch::Contains("link_form_factor"));
    CHECK_THAT(Cli("run parallel l=1 d=1 --eps 0.5 --json").out,
               !Catch::Contains("link_form_factor"));
    CHECK_THAT(asked.out, Catch::Contains("link_form_factor_max       0.41421356237309") &&
                              Catch::Contains("link_form_factor_above_eps 0\n"));
    CHECK_THAT(Cli("solve parallel l=1 d=1 --eps 0.5 --emission 1").out,
               Catch::Contains("link_form_factor_max") &&
                   Catch::Contains("link_form_factor_above_eps"));
    for (auto [other, named] :
         {std::pair<std::string, std::string>{"--count-only --eps 0.5", "--count-only"},
          {"--method translation --eps 0.5", "--method translation"},
          {"--sweep eps=0.5,0.2", "--sweep"}})
        CheckError("run parallel l=1 d=1 --link-form-factors " + other, 2,
                   "hrbench: error: --link-form-factors needs every link stored, which " + named +
                       " does not: drop one of them\n");
    CheckError("solve parallel l=1 d=1 --eps 0.5 --link-form-factors", 2,
               "hrbench: error: --link-form-factors does not apply to solve\n");
}

// ---------------------------------------------------------------------------------------
// The error against the reference, in parts

TEST_CASE("Leaves equal to the reference's elements have no projection error", "[solve]") {
    // parallel l=4 d=1 at eps 0.3: every leaf at depth 4, as the reference's elements.
    Scene plates = MakeScene("parallel", {{"l", 4}, {"d", 1}});
    SolveResult r = Solve(plates, Refining(0.3), Solving(4));
    for (const ElementRadiosity &leaf : r.leaves)
        REQUIRE(leaf.depth == 4);
    const ReferenceComparison &c = *r.comparison;
    CHECK(c.projection.maxError == 0);
    CHECK(c.projection.l2Error == 0);
    CHECK(c.hierarchy.maxError == c.maxError);
    CHECK(c.hierarchy.meanError == c.meanError);
    CHECK(c.hierarchy.l2Error == c.l2Error);
    CHECK(c.l2Error > 0);
}

TEST_CASE("The projection is the reference's mean over each leaf", "[solve]") {
    Scene plates = MakeScene("parallel", {{"l", 1}, {"d", 1}});
    plates.Get<Segment>()[0].material = {0.3, 1};
    plates.Get<Segment>()[1].material = {0.6, 0};
    SolveOptions options = Solving(2);
    options.emission.reset();
    SECTION("leaves coarser than the reference: its mean over the leaf") {
        // One link: the leaves are the roots, each holding 4 reference elements of
        // length 1/4, so the projection on a root is the mean of its 4 values.
        SolveResult r = Solve(plates, Refining(10, 0), options);
        REQUIRE(r.leaves.size() == 2);
        const std::vector<ElementRadiosity> &ref = r.reference->elements;
        REQUIRE(ref.size() == 8);
        double largest = 0, projection = 0, hierarchy = 0, projectionMax = 0;
        for (const ElementRadiosity &e : ref)
            largest = std::max(largest, e.radiosity);
        for (int root = 0; root < 2; ++root) {
            double mean = 0;
            for (int k = 0; k < 4; ++k)
                mean += ref[size_t(4 * root + k)].radiosity / 4;
            double solved = r.leaves[size_t(root)].radiosity;
            for (int k = 0; k < 4; ++k) {
                double e = std::abs(mean - ref[size_t(4 * root + k)].radiosity) / largest;
                projection += 0.25 * e * e / 2;
                projectionMax = std::max(projectionMax, e);
            }
            hierarchy += 4 * 0.25 * std::pow((solved - mean) / largest, 2) / 2;
        }
        const ReferenceComparison &c = *r.comparison;
        CHECK(c.projection.l2Error == Approx(std::sqrt(projection)).epsilon(1e-12));
        CHECK(c.projection.maxError == Approx(projectionMax).epsilon(1e-12));
        CHECK(c.hierarchy.l2Error == Approx(std::sqrt(hierarchy)).epsilon(1e-12));
        CheckOrthogonal(c);
    }
    SECTION("leaves finer than the reference: the reference element's value, error 0") {
        // The reference of depth 0 is constant on each root; every leaf lies inside one.
        options.referenceDepth = 0;
        SolveResult r = Solve(plates, Refining(0.05), options);
        REQUIRE(r.leaves.size() > 2);
        const ReferenceComparison &c = *r.comparison;
        CHECK(c.projection.maxError == 0);
        CHECK(c.hierarchy.maxError == c.maxError);
        CHECK(c.hierarchy.l2Error == c.l2Error);
        CHECK(c.l2Error > 0);
    }
}

TEST_CASE("The reference error's parts are orthogonal in 2D and 3D", "[solve]") {
    SECTION("2D plates, leaves both coarser and finer than the reference") {
        Scene plates = MakeScene("parallel", {{"l", 4}, {"d", 1}});
        for (double eps : {0.2, 0.05, 0.01}) {  // leaves of depth 5, 7 and 9
            INFO("eps " << eps);
            SolveResult r = Solve(plates, Refining(eps), Solving(10));
            CheckOrthogonal(*r.comparison);
        }
        // Unequal plates: leaves of depth 5 to 7 against the reference of depth 6.
        SolveResult mixed = Solve(MakeScene("parallel", {{"l", 4}, {"l2", 1}, {"d", 1}}),
                                  Refining(0.05), Solving(6));
        int shallower = 0, deeper = 0;
        for (const ElementRadiosity &leaf : mixed.leaves)
            shallower += leaf.depth<6, deeper += leaf.depth> 6;
        CHECK(shallower > 0);
        CHECK(deeper > 0);
        CheckOrthogonal(*mixed.comparison);
    }
    SECTION("2D, plain gather") {
        SolveOptions plain = Solving(8);
        plain.plainGather = true;
        SolveResult r = Solve(MakeScene("parallel", {{"l", 4}, {"d", 1}}), Refining(0.05), plain);
        CheckOrthogonal(*r.comparison);
    }
    SECTION("3D: the Cornell box and offset plates") {
        RefineOptions o = Refining(0.5, 3);
        SolveResult cornell = Solve(MakeScene("cornell", {}), o, [] {
            SolveOptions s = Solving(2);
            s.emission.reset();
            return s;
        }());
        CheckOrthogonal(*cornell.comparison);
        SolveResult plates = Solve(MakeScene("parallel3d", {{"l", 2}, {"d", 1}, {"ox", 0.5}}),
                                   Refining(0.2), Solving(6));
        CheckOrthogonal(*plates.comparison);
    }
}
