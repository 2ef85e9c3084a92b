// The oracles (oracles/garmann.h, oracles/hanrahan.h) against their definitions and
// closed-form references, in 2D and 3D, and the registry that lists them.
#include <catch2/catch.hpp>

#include <cmath>
#include <random>
#include <set>

#include "hrbench/generators/generators.h"
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
    // (docs/conventions.md), which is the estimate F(i<-j) with both cosines 1.
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
    CHECK(HanrahanOracle<Segment>(estimate * (1 + 1e-9), roots).Acceptable(i, j));
    CHECK_FALSE(HanrahanOracle<Segment>(estimate * (1 - 1e-9), roots).Acceptable(i, j));

    SECTION("cosines are clamped: an element behind the other's front contributes nothing") {
        Element<2> behind = At(0, -1, 1, 1);  // below the x axis, normal of root 1 faces -y
        CHECK(HanrahanOracle<Segment>(1e-12, WithNormals(Vec2(0, 1), Vec2(0, -1)))
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
    // Directly opposed elements: cosines 1, F = A / (pi r^2 + A).
    Patches<Polygon> normals = SquaresFacing(true, false);  // +z, -z
    REQUIRE(normals[0].shape.Normal() == Vec3(0, 0, 1));
    REQUIRE(normals[1].shape.Normal() == Vec3(0, 0, -1));
    Element<3> a{Vec3(0, 0, 0), Sq(1), kNoChildren, 0}, b{Vec3(0, 0, 1), Sq(2), kNoChildren, 1};
    double fAB = 2 / (kPi + 2), fBA = 1 / (kPi + 1);
    CHECK(HanrahanOracle<Polygon>(fAB, normals).Acceptable(a, b));
    CHECK(!HanrahanOracle<Polygon>(fAB * (1 - 1e-9), normals).Acceptable(a, b));
    CHECK(!HanrahanOracle<Polygon>(fBA, normals).Acceptable(a, b));  // F(a<-b) > F(b<-a)
    CHECK(HanrahanOracle<Polygon>(fAB / 2, normals).AcceptableVisible(a, b, 0.5));
    // Facing away: cosines clamped at 0, always acceptable.
    Patches<Polygon> away = SquaresFacing(false, true);  // -z, +z
    CHECK(HanrahanOracle<Polygon>(1e-9, away).Acceptable(a, b));
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
        CHECK(std::string(info.parameters) == "eps");
        CHECK(std::string(FindOracle(info.name).name) == info.name);
        CHECK(info.Supports(2));
        CHECK(info.Supports(3));
        CHECK_FALSE(info.Supports(1));
        CHECK_FALSE(info.Supports(4));
    }
    CHECK(names == std::set<std::string>{"garmann", "hanrahan", "bf"});
    CHECK(std::string(infos.front().name) == "garmann");  // the default comes first
    CHECK(RefineOptions().oracle == infos.front().name);
}

TEST_CASE("Every oracle of the registry rejects large close pairs and accepts small far ones",
          "[oracle][registry]") {
    // Facing unit plates at distance 1, eps 0.1: the root pair is rejected by every
    // oracle (garmann 1 > 0.1; hanrahan 1/sqrt(5) in 2D, 1/(pi+1) in 3D; bf, with both
    // plates emitting 1, as hanrahan), and elements of size 1e-3 at the same centres are
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
