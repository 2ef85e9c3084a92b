// The oracles (oracles/garmann.h, oracles/hanrahan.h) against their definitions and
// closed-form references, in 2D and 3D, the form-factor estimates of hanrahan and bf
// (oracles/ff_estimate.h) computed by hand, and the registry that lists them.
#include <catch2/catch.hpp>

#include <cmath>
#include <random>
#include <set>

#include "generators.h"
#include "hrbench/hrbench.h"

using namespace hrbench;

namespace {

constexpr double kPi = 3.14159265358979323846;

// An element of size _size_ (its hot record holds size^2; Size() gives _size_ back, as
// sqrt(x * x) == x in double precision without overflow or underflow).
Element<2> At(double x, double y, double size, uint32_t root = 0) {
    return {Vec2(x, y), size * size, kNoChildren, root};
}

double Sq(double x) { return x * x; }

// Two segments whose front normals are _n0_ and _n1_ (unit, axis-aligned or not).
Patches<Segment> WithNormals(const Vec2 &n0, const Vec2 &n1) {
    auto facing = [](const Vec2 &n) {
        Vec2 dir(n.y(), -n.x());  // the normal is the direction rotated by +90 degrees
        return Patch<Segment>{{Vec2(0, 0), dir}, {}};
    };
    return {facing(n0), facing(n1)};
}

// Two unit squares in z = 0 whose front normals are +z or -z as _up0_, _up1_ say.
Patches<Polygon> SquaresFacing(bool up0, bool up1) {
    auto square = [](bool up) {
        Vec3 a(0, 0, 0), b(1, 0, 0), c(1, 1, 0), d(0, 1, 0);
        return Patch<Polygon>{up ? Polygon::Quad(a, b, c, d) : Polygon::Quad(a, d, c, b), {}};
    };
    return {square(up0), square(up1)};
}

}  // namespace

TEST_CASE("The garmann oracle accepts exactly when max(A_i, A_j) <= eps * r", "[oracle][2d]") {
    SECTION("ties are acceptable") {
        // r = 1, max size 0.25, eps 0.25: 0.25 <= 0.25 * 1.
        CHECK(GarmannOracle<Segment>(0.25, {}).Acceptable(At(0, 0, 0.25), At(0, 1, 0.125)));
        CHECK_FALSE(GarmannOracle<Segment>(0.25, {}).Acceptable(At(0, 0, 0.25000000000000006),
                                                                At(0, 1, 0.1)));
    }
    SECTION("the squared fast path decides like the exact form on random pairs") {
        std::mt19937_64 rng(42);
        std::uniform_real_distribution<double> u(-4, 4), s(1e-3, 2);
        int accepted = 0;
        for (int k = 0; k < 200000; ++k) {
            Element<2> a = At(u(rng), u(rng), s(rng)), b = At(u(rng), u(rng), s(rng));
            double eps = s(rng);
            bool exact = std::max(a.Size(), b.Size()) <= eps * (a.center - b.center).norm();
            REQUIRE(GarmannOracle<Segment>(eps, {}).Acceptable(a, b) == exact);
            accepted += exact;
        }
        CHECK(accepted > 10000);  // both outcomes are exercised
        CHECK(accepted < 190000);
    }
}

TEST_CASE("The hanrahan oracle estimates the flatland form factor", "[oracle][2d]") {
    // A short element facing the centre of a segment of length a at distance r:
    // Hottel's crossed strings give F -> a / sqrt(4 r^2 + a^2) as the element shrinks
    // (docs/conventions.md), which is the centre-cosine estimate F(i<-j) with both
    // cosines 1.
    const FfEstimate centre = FfEstimate::CentreCosine;
    double a = 2, r = 1.5, delta = 1e-6;
    Segment small{Vec2(-delta / 2, 0), Vec2(delta / 2, 0)};
    Segment big{Vec2(a / 2, r), Vec2(-a / 2, r)};
    double crossed = 2 * std::hypot(a / 2 + delta / 2, r),
           uncrossed = 2 * std::hypot(a / 2 - delta / 2, r);
    double hottel = (crossed - uncrossed) / (2 * delta);
    double estimate = a / std::sqrt(4 * r * r + a * a);
    REQUIRE_THAT(estimate, Catch::Matchers::WithinRel(hottel, 1e-6));

    Patches<Segment> roots{{small, {}}, {big, {}}};
    Element<2> i = At(0, 0, delta, 0), j = At(0, r, a, 1);
    CHECK(HanrahanOracle<Segment>(estimate * (1 + 1e-9), roots, centre).Acceptable(i, j));
    CHECK_FALSE(HanrahanOracle<Segment>(estimate * (1 - 1e-9), roots, centre).Acceptable(i, j));

    SECTION("cosines are clamped: an element behind the other's front contributes nothing") {
        Element<2> behind = At(0, -1, 1, 1);  // below the x axis, normal of root 1 faces -y
        CHECK(HanrahanOracle<Segment>(1e-12, WithNormals(Vec2(0, 1), Vec2(0, -1)), centre)
                  .Acceptable(i, behind));
    }
}

TEST_CASE("The 3D garmann oracle decides max(A_i, A_j) <= eps r^2 exactly", "[oracle][3d]") {
    Element<3> a{Vec3(0, 0, 0), Sq(0.25), kNoChildren, 0}, b{Vec3(0, 0, 2), Sq(1), kNoChildren, 1};
    CHECK(GarmannOracle<Polygon>(0.25, {}).Acceptable(a, b));  // 1 <= 0.25 * 4: the tie is accepted
    CHECK(!GarmannOracle<Polygon>(0.2499, {}).Acceptable(a, b));
    CHECK(GarmannOracle<Polygon>(0.2499, {}).AcceptableVisible(a, b, 0.5));  // 0.5 <= 0.9996
    CHECK(!GarmannOracle<Polygon>(0.1, {}).AcceptableVisible(a, b, 0.5));
}

TEST_CASE("garmann decides on A^2 as the exact form on A = sqrt(A^2), at any magnitude",
          "[oracle]") {
    // The exact forms: sqrt(max A^2) <= eps * sqrt(r^2) (2D), <= eps * r^2 (3D). Squared
    // sizes, distances and eps over the whole double range, and pairs placed within a
    // few ulps of the threshold, where the decision on squares must defer to them.
    std::mt19937_64 rng(3);
    std::uniform_real_distribution<double> u(0.5, 1), e2(-1000, 1000), e1(-500, 500),
        eE(-600, 600);  // eps^2 below and above the normal doubles too
    std::uniform_int_distribution<int> ulps(-6, 6);
    int accepted = 0, total = 0;
    for (int k = 0; k < 200000; ++k) {
        double eps = std::ldexp(u(rng), int(eE(rng)));
        double x = std::ldexp(u(rng), int(e1(rng))), y = std::ldexp(u(rng), int(e1(rng)));
        double s1 = std::ldexp(u(rng), int(e2(rng))), s2 = std::ldexp(u(rng), int(e2(rng)));
        {
            Element<2> a{Vec2(0, 0), s1, kNoChildren, 0}, b{Vec2(x, y), s2, kNoChildren, 1};
            double r2 = (a.center - b.center).squaredNorm();
            if (k % 2) {  // near the threshold: A = eps r, give or take a few ulps
                double m = eps * std::sqrt(r2);
                a.sizeSquared = std::nextafter(m * m, ulps(rng) > 0 ? HUGE_VAL : 0.0);
            }
            double m = std::sqrt(std::max(a.sizeSquared, b.sizeSquared));
            bool exact = m <= eps * std::sqrt(r2);
            GarmannOracle<Segment> g(eps, {});
            INFO("2D eps=" << eps << " s=" << a.sizeSquared << "," << b.sizeSquared
                           << " r2=" << r2);
            REQUIRE(g.Acceptable(a, b) == exact);
            REQUIRE(g.AcceptableVisible(a, b, 1.0) == exact);
            accepted += exact, ++total;
        }
        {
            double z = std::ldexp(u(rng), int(e1(rng)));
            Element<3> a{Vec3(0, 0, 0), s1, kNoChildren, 0}, b{Vec3(x, y, z), s2, kNoChildren, 1};
            double r2 = (a.center - b.center).squaredNorm();
            if (k % 2) {  // near the threshold: A = eps r^2, give or take a few ulps
                double m = eps * r2;
                double s = m * m;
                for (int step = ulps(rng); step != 0; step += step > 0 ? -1 : 1)
                    s = std::nextafter(s, step > 0 ? HUGE_VAL : 0.0);
                a.sizeSquared = s;
            }
            double m = std::sqrt(std::max(a.sizeSquared, b.sizeSquared));
            bool exact = m <= eps * r2;
            GarmannOracle<Polygon> g(eps, {});
            INFO("3D eps=" << eps << " s=" << a.sizeSquared << "," << b.sizeSquared
                           << " r2=" << r2);
            REQUIRE(g.Acceptable(a, b) == exact);
            REQUIRE(g.AcceptableVisible(a, b, 1.0) == exact);
            accepted += exact, ++total;
        }
    }
    CHECK(accepted > total / 10);  // both outcomes are exercised
    CHECK(accepted < total * 9 / 10);
}

TEST_CASE("The 3D hanrahan oracle estimates both form factors at the centroids", "[oracle][3d]") {
    // Directly opposed elements: cosines 1, F = A / (pi r^2 + A) (centre-cosine).
    const FfEstimate centre = FfEstimate::CentreCosine;
    Patches<Polygon> normals = SquaresFacing(true, false);  // +z, -z
    REQUIRE(normals[0].shape.Normal() == Vec3(0, 0, 1));
    REQUIRE(normals[1].shape.Normal() == Vec3(0, 0, -1));
    Element<3> a{Vec3(0, 0, 0), Sq(1), kNoChildren, 0}, b{Vec3(0, 0, 1), Sq(2), kNoChildren, 1};
    double fAB = 2 / (kPi + 2), fBA = 1 / (kPi + 1);
    CHECK(HanrahanOracle<Polygon>(fAB, normals, centre).Acceptable(a, b));
    CHECK(!HanrahanOracle<Polygon>(fAB * (1 - 1e-9), normals, centre).Acceptable(a, b));
    CHECK(!HanrahanOracle<Polygon>(fBA, normals, centre).Acceptable(a, b));  // F(a<-b) > F(b<-a)
    CHECK(HanrahanOracle<Polygon>(fAB / 2, normals, centre).AcceptableVisible(a, b, 0.5));
    // Facing away: cosines clamped at 0, always acceptable.
    Patches<Polygon> away = SquaresFacing(false, true);  // -z, +z
    CHECK(HanrahanOracle<Polygon>(1e-9, away, centre).Acceptable(a, b));
}

TEST_CASE("The weighted oracles decide as the plain ones when all is visible", "[oracle]") {
    SECTION("2D: pairs near the threshold of the worked example and elsewhere") {
        Scene scene = MakeScene("angled", {{"angle", 50}});
        const Patches<Segment> &roots = scene.Get<Segment>();
        GarmannOracle<Segment> g(0.25, roots);
        HanrahanOracle<Segment> h(0.05, roots);
        int disagreements = 0, accepted = 0;
        for (int a = 0; a < 40; ++a)
            for (int b = 0; b < 40; ++b) {
                Element<2> ei = At(a * 0.1, 0, 0.05 * (1 + a % 7), 0);
                Element<2> ej = At(b * 0.07, 1 + b * 0.03, 0.05 * (1 + b % 5), 1);
                disagreements += g.Acceptable(ei, ej) != g.AcceptableVisible(ei, ej, 1.0);
                disagreements += h.Acceptable(ei, ej) != h.AcceptableVisible(ei, ej, 1.0);
                accepted += g.Acceptable(ei, ej) + h.Acceptable(ei, ej);
            }
        CHECK(disagreements == 0);
        CHECK(accepted > 100);  // not trivial
        CHECK(accepted < 3000);
    }
    SECTION("3D: pairs between two facing plates") {
        Scene scene = MakeScene("parallel3d", {});
        const Patches<Polygon> &roots = scene.Get<Polygon>();
        GarmannOracle<Polygon> g(0.25, roots);
        HanrahanOracle<Polygon> h(0.02, roots);
        int disagreements = 0, accepted = 0;
        for (int a = 0; a < 30; ++a)
            for (int b = 0; b < 30; ++b) {
                Element<3> ei{Vec3(a * 0.03, 0.5, 0), Sq(0.01 * (1 + a % 7)), kNoChildren, 0};
                Element<3> ej{Vec3(b * 0.04, 0.3, 0.2 + b * 0.03), Sq(0.01 * (1 + b % 5)),
                              kNoChildren, 1};
                disagreements += g.Acceptable(ei, ej) != g.AcceptableVisible(ei, ej, 1.0);
                disagreements += h.Acceptable(ei, ej) != h.AcceptableVisible(ei, ej, 1.0);
                accepted += g.Acceptable(ei, ej) + h.Acceptable(ei, ej);
            }
        CHECK(disagreements == 0);
        CHECK(accepted > 0);  // both outcomes are exercised
        CHECK(accepted < 2 * 30 * 30);
    }
}

TEST_CASE("The registry lists every oracle once, for both dimensions", "[oracle][registry]") {
    std::vector<OracleInfo> infos = OracleInfos();
    REQUIRE(infos.size() >= 2);
    std::set<std::string> names;
    for (const OracleInfo &info : infos) {
        INFO(info.name);
        CHECK(names.insert(info.name).second);  // unique
        CHECK(std::string(info.doc).size() > 0);
        // garmann reads eps; hanrahan and bf the form-factor estimate too.
        bool estimates = std::string(info.name) != "garmann";
        CHECK(std::string(info.parameters) == (estimates ? "eps ff_estimate" : "eps"));
        CHECK(info.Reads("eps"));
        CHECK(info.Reads("ff_estimate") == estimates);
        CHECK_FALSE(info.Reads("ff"));
        CHECK(std::string(FindOracle(info.name).name) == info.name);
        CHECK(info.Supports(2));
        CHECK(info.Supports(3));
        CHECK_FALSE(info.Supports(1));
        CHECK_FALSE(info.Supports(4));
    }
    CHECK(names == std::set<std::string>{"garmann", "hanrahan", "bf"});
    CHECK(std::string(infos.front().name) == "garmann");  // the default comes first
    CHECK(RefineOptions().oracle == infos.front().name);
    CHECK(OraclesReading("ff_estimate") == std::vector<std::string>{"hanrahan", "bf"});
    CHECK(OraclesReading("eps") == std::vector<std::string>{"garmann", "hanrahan", "bf"});
}

TEST_CASE("Every oracle of the registry rejects large close pairs and accepts small far ones",
          "[oracle][registry]") {
    // Facing unit plates at distance 1, eps 0.1: the root pair is rejected by every
    // oracle (garmann 1 > 0.1; hanrahan 1/sqrt(5) in 2D, 1/(pi+1) in 3D with its default
    // estimate, as with each, the cosines being 1 and 2f < 1; bf, with both plates
    // emitting 1, as hanrahan), and elements of size 1e-3 at the same centres are
    // accepted.
    Scene flat = MakeScene("parallel", {{"l", 1}, {"d", 1}});
    Scene space = MakeScene("parallel3d", {});
    for (auto &patch : flat.Get<Segment>())
        patch.material.emission = 1;
    for (auto &patch : space.Get<Polygon>())
        patch.material.emission = 1;
    int oracles = 0;
    AllOracles::ForEach([&](auto tag) {
        using Tag = decltype(tag);
        INFO(Tag::Info().name);
        ++oracles;
        typename Tag::template Type<Segment> o2(0.1, flat.Get<Segment>());
        CHECK_FALSE(o2.Acceptable(At(0.5, 0, 1, 0), At(0.5, 1, 1, 1)));
        CHECK(o2.Acceptable(At(0.5, 0, 1e-3, 0), At(0.5, 1, 1e-3, 1)));
        typename Tag::template Type<Polygon> o3(0.1, space.Get<Polygon>());
        Element<3> p{Vec3(0.5, 0.5, 0), Sq(1), kNoChildren, 0},
            q{Vec3(0.5, 0.5, 1), Sq(1), kNoChildren, 1};
        CHECK_FALSE(o3.Acceptable(p, q));
        p.sizeSquared = q.sizeSquared = Sq(1e-3);
        CHECK(o3.Acceptable(p, q));
    });
    CHECK(oracles == int(OracleInfos().size()));
}

TEST_CASE("An unknown oracle name is refused with the list of names", "[oracle][registry]") {
    CHECK_THROWS_AS(FindOracle("bogus"), InputError);
    CHECK_THROWS_WITH(FindOracle("bogus"), Catch::Contains("garmann"));
    CHECK_THROWS_WITH(FindOracle("magic"),
                      "unknown oracle 'magic' (choose one of: garmann, hanrahan, bf)");
    for (const OracleInfo &info : OracleInfos())
        CHECK_THROWS_WITH(FindOracle("bogus"), Catch::Contains(info.name));
    CHECK_THROWS_AS(FindOracle("Garmann"), InputError);  // names are case-sensitive
    CHECK_THROWS_AS(FindOracle(""), InputError);
}

// ---------------------------------------------------------------------------------------
// The form-factor estimates of hanrahan and bf (--ff-estimate), computed by hand.

namespace {

// F(i<-j), F(j<-i) of _estimate_ for a pair on two roots with front normals _ni_, _nj_.
template <typename Shape>
Eigen::Array2d Estimates(FfEstimate estimate, const Element<Shape::kDimension> &i,
                         const Element<Shape::kDimension> &j, const typename Shape::Vec &ni,
                         const typename Shape::Vec &nj) {
    return FormFactorEstimates<Shape>(i, j, ni, nj, estimate);
}

// Checks that _estimate_ gives (_fij_, _fji_) to within a few ulps, and that the hanrahan
// oracle with it accepts the pair at eps = max(fij, fji) (up to 1e-12) and not below.
template <typename Shape>
void CheckEstimate(FfEstimate estimate, const Patches<Shape> &roots,
                   const Element<Shape::kDimension> &i, const Element<Shape::kDimension> &j,
                   double fij, double fji) {
    INFO(FfEstimateName(estimate));
    Eigen::Array2d f = Estimates<Shape>(estimate, i, j, roots[i.root].shape.Normal(),
                                        roots[j.root].shape.Normal());
    CHECK_THAT(f[0], Catch::Matchers::WithinRel(fij, 1e-14) || Catch::Matchers::WithinAbs(fij, 0));
    CHECK_THAT(f[1], Catch::Matchers::WithinRel(fji, 1e-14) || Catch::Matchers::WithinAbs(fji, 0));
    double threshold = std::max(fij, fji);
    if (threshold > 0) {
        CHECK(HanrahanOracle<Shape>(threshold * (1 + 1e-12), roots, estimate).Acceptable(i, j));
        CHECK_FALSE(
            HanrahanOracle<Shape>(threshold * (1 - 1e-12), roots, estimate).Acceptable(i, j));
    } else {
        CHECK(HanrahanOracle<Shape>(1e-300, roots, estimate).Acceptable(i, j));
    }
}

const std::vector<FfEstimate> kAllEstimates = {FfEstimate::CentreCosine, FfEstimate::SolidAngle,
                                               FfEstimate::ClampedCosine};

// Which of centre-cosine, solid-angle and clamped-cosine accept the pair at _eps_.
template <typename Shape>
std::vector<bool> Decisions(double eps, const Patches<Shape> &roots,
                            const Element<Shape::kDimension> &i,
                            const Element<Shape::kDimension> &j) {
    std::vector<bool> accepted;
    for (FfEstimate e : kAllEstimates)
        accepted.push_back(HanrahanOracle<Shape>(eps, roots, e).Acceptable(i, j));
    return accepted;
}

}  // namespace

TEST_CASE("Facing unit elements at distance 1: the three estimates agree", "[oracle][estimate]") {
    // Both cosines 1 and 2f < 1, so every estimate is the point-to-disc factor f:
    // 1 / sqrt(4 + 1) in 2D, 1 / (pi + 1) in 3D.
    Patches<Segment> flat = WithNormals(Vec2(0, 1), Vec2(0, -1));
    Element<2> i = At(0, 0, 1, 0), j = At(0, 1, 1, 1);
    Patches<Polygon> space = SquaresFacing(true, false);
    Element<3> a{Vec3(0, 0, 0), 1, kNoChildren, 0}, b{Vec3(0, 0, 1), 1, kNoChildren, 1};
    for (FfEstimate e : kAllEstimates) {
        CheckEstimate(e, flat, i, j, 1 / std::sqrt(5.0), 1 / std::sqrt(5.0));
        CheckEstimate(e, space, a, b, 1 / (kPi + 1), 1 / (kPi + 1));
    }
}

TEST_CASE("The estimates in 2D, where a cosine lies below the clamp", "[oracle][estimate][2d]") {
    Patches<Segment> facing = WithNormals(Vec2(0, 1), Vec2(0, -1));
    SECTION("offset elements of lengths 0.5 and 2: the clamp applies in one direction") {
        // i (length 0.5) at the origin, j (length 2) at (3, 1): r^2 = 10, both cosines
        // 1/sqrt(10). f(i<-j) = 2 / sqrt(44) = 0.302, 2f = 0.603 > 0.316 raises both
        // cosines: F = f (2f)^2; f(j<-i) = 0.5 / sqrt(40.25) = 0.0788, 2f < 0.316: F = f / 10.
        Element<2> i = At(0, 0, 0.5, 0), j = At(3, 1, 2, 1);
        double fij = 2 / std::sqrt(44.0), fji = 0.5 / std::sqrt(40.25);
        CheckEstimate(FfEstimate::CentreCosine, facing, i, j, fij / 10, fji / 10);
        CheckEstimate(FfEstimate::SolidAngle, facing, i, j, fij, fji);
        CheckEstimate(FfEstimate::ClampedCosine, facing, i, j, 4 * fij * fij * fij, fji / 10);
        // Thresholds 0.0302, 0.302 and 0.110: at eps 0.05 only centre-cosine accepts, at
        // 0.2 centre-cosine and clamped-cosine.
        CHECK(Decisions(0.05, facing, i, j) == std::vector<bool>{true, false, false});
        CHECK(Decisions(0.2, facing, i, j) == std::vector<bool>{true, false, true});
    }
    SECTION("perpendicular elements: centre-cosine 0, clamped-cosine 2f^2") {
        // j's normal (1, 0) is perpendicular to c_j - c_i = (0, 1): cos_j = 0.
        Patches<Segment> roots = WithNormals(Vec2(0, 1), Vec2(1, 0));
        Element<2> i = At(0, 0, 1, 0), j = At(0, 1, 1, 1);
        double f = 1 / std::sqrt(5.0);
        CheckEstimate(FfEstimate::CentreCosine, roots, i, j, 0, 0);
        CheckEstimate(FfEstimate::SolidAngle, roots, i, j, f, f);
        CheckEstimate(FfEstimate::ClampedCosine, roots, i, j, 2 * f * f, 2 * f * f);  // 0.4
        // The eps where they part: 0.42 rejects only solid-angle, 0.3 all but centre-cosine.
        CHECK(Decisions(0.42, roots, i, j) == std::vector<bool>{true, false, true});
        CHECK(Decisions(0.3, roots, i, j) == std::vector<bool>{true, false, false});
    }
    SECTION("facing away: centre-cosine clamps at 0, clamped-cosine takes |cos|") {
        Patches<Segment> away = WithNormals(Vec2(0, -1), Vec2(0, 1));
        Element<2> i = At(0, 0, 1, 0), j = At(0, 1, 1, 1);
        double f = 1 / std::sqrt(5.0);
        CheckEstimate(FfEstimate::CentreCosine, away, i, j, 0, 0);
        CheckEstimate(FfEstimate::SolidAngle, away, i, j, f, f);
        CheckEstimate(FfEstimate::ClampedCosine, away, i, j, f, f);
    }
    SECTION("close elements: 2f > 1, and clamped-cosine exceeds 1 (no cap)") {
        // r = 0.25: f = 1 / sqrt(1.25) = 0.894, clamped-cosine f (2f)^2 = 2.86.
        Element<2> i = At(0, 0, 1, 0), j = At(0, 0.25, 1, 1);
        double f = 1 / std::sqrt(1.25);
        CheckEstimate(FfEstimate::CentreCosine, facing, i, j, f, f);
        CheckEstimate(FfEstimate::SolidAngle, facing, i, j, f, f);
        CheckEstimate(FfEstimate::ClampedCosine, facing, i, j, 4 * f * f * f, 4 * f * f * f);
        CHECK(Decisions(1, facing, i, j) == std::vector<bool>{true, true, false});
    }
}

TEST_CASE("The estimates in 3D, where a cosine lies below the clamp", "[oracle][estimate][3d]") {
    // a (area 1, normal +z) at the origin, b (area 2, normal -z) at (1, 0, 0.5):
    // r^2 = 1.25, both cosines 0.5 / sqrt(1.25) = 0.447, their product 0.2.
    // f(a<-b) = 2 / (1.25 pi + 2) = 0.337, 2f = 0.675 > 0.447: F = f (2f)^2;
    // f(b<-a) = 1 / (1.25 pi + 1) = 0.203, 2f = 0.406 < 0.447: F = 0.2 f.
    Patches<Polygon> roots = SquaresFacing(true, false);
    Element<3> a{Vec3(0, 0, 0), 1, kNoChildren, 0}, b{Vec3(1, 0, 0.5), 4, kNoChildren, 1};
    double fab = 2 / (1.25 * kPi + 2), fba = 1 / (1.25 * kPi + 1);
    CheckEstimate(FfEstimate::CentreCosine, roots, a, b, 0.2 * fab, 0.2 * fba);
    CheckEstimate(FfEstimate::SolidAngle, roots, a, b, fab, fba);
    CheckEstimate(FfEstimate::ClampedCosine, roots, a, b, 4 * fab * fab * fab, 0.2 * fba);
    // Thresholds 0.0675, 0.337 and 0.154.
    CHECK(Decisions(0.1, roots, a, b) == std::vector<bool>{true, false, false});
    CHECK(Decisions(0.2, roots, a, b) == std::vector<bool>{true, false, true});
    CHECK(Decisions(0.4, roots, a, b) == std::vector<bool>{true, true, true});
    // Facing away: centre-cosine 0; clamped-cosine as facing, from the absolute values.
    Patches<Polygon> away = SquaresFacing(false, true);
    CheckEstimate(FfEstimate::CentreCosine, away, a, b, 0, 0);
    CheckEstimate(FfEstimate::ClampedCosine, away, a, b, 4 * fab * fab * fab, 0.2 * fba);
}

TEST_CASE("The run's estimate reaches hanrahan and bf; clamped-cosine is the default",
          "[oracle][estimate]") {
    CHECK(RefineOptions().ffEstimate == FfEstimate::ClampedCosine);
    CHECK(kDefaultFfEstimate == FfEstimate::ClampedCosine);
    CHECK(FfEstimates().front().estimate == kDefaultFfEstimate);  // the default comes first
    // The perpendicular pair: centre-cosine 0, clamped-cosine 0.4, solid-angle 0.447.
    Patches<Segment> roots = WithNormals(Vec2(0, 1), Vec2(1, 0));
    for (auto &patch : roots)
        patch.material.emission = 1;  // B = 1: bf decides as hanrahan
    Element<2> i = At(0, 0, 1, 0), j = At(0, 1, 1, 1);
    RefineOptions o;
    o.eps = 0.42;
    CHECK(MakeOracle<HanrahanOracle<Segment>>(o, roots).Acceptable(i, j));
    CHECK(MakeOracle<BFOracle<Segment>>(o, roots).Acceptable(i, j));
    CHECK(HanrahanOracle<Segment>(0.42, roots).Acceptable(i, j));  // the default
    o.ffEstimate = FfEstimate::SolidAngle;
    CHECK_FALSE(MakeOracle<HanrahanOracle<Segment>>(o, roots).Acceptable(i, j));
    CHECK_FALSE(MakeOracle<BFOracle<Segment>>(o, roots).Acceptable(i, j));
    o.eps = 0.3;
    o.ffEstimate = FfEstimate::CentreCosine;
    CHECK(MakeOracle<HanrahanOracle<Segment>>(o, roots).Acceptable(i, j));
    CHECK(MakeOracle<BFOracle<Segment>>(o, roots).Acceptable(i, j));
    o.ffEstimate = FfEstimate::ClampedCosine;
    CHECK_FALSE(MakeOracle<HanrahanOracle<Segment>>(o, roots).Acceptable(i, j));
    CHECK_FALSE(MakeOracle<BFOracle<Segment>>(o, roots).Acceptable(i, j));
}

TEST_CASE("The estimates are named, each with formulas and a source", "[oracle][estimate]") {
    std::vector<std::string> names;
    for (const FfEstimateInfo &info : FfEstimates()) {
        names.push_back(info.name);
        CHECK(ParseFfEstimate(info.name) == info.estimate);
        CHECK(FfEstimateName(info.estimate) == info.name);
        CHECK(std::string(info.formula2d).find("sqrt(4 r^2") != std::string::npos);
        CHECK(std::string(info.formula3d).find("pi r^2") != std::string::npos);
        CHECK(std::string(info.source).size() > 40);
    }
    CHECK(names == std::vector<std::string>{"clamped-cosine", "centre-cosine", "solid-angle"});
    CHECK_THROWS_AS(ParseFfEstimate("center-cosine"), InputError);
    CHECK_THROWS_WITH(ParseFfEstimate("hsa91"),
                      "unknown form-factor estimate 'hsa91' (choose one of: clamped-cosine, "
                      "centre-cosine, solid-angle)");
}
