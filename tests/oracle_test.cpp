// The flatland oracles against their definitions and closed-form references.
#include <catch2/catch.hpp>

#include <cmath>
#include <random>

#include "hrbench.h"
#include "oracles.h"

using namespace hrbench;

namespace {

Element<2> At(double x, double y, double size, uint32_t root = 0) {
    return {Vec2(x, y), size, kNoChildren, root};
}

}  // namespace

TEST_CASE("The garmann oracle accepts exactly when max(A_i, A_j) <= eps * r", "[oracle]") {
    SECTION("ties are acceptable") {
        // r = 1, max size 0.25, eps 0.25: 0.25 <= 0.25 * 1.
        CHECK(GarmannOracle(0.25).Acceptable(At(0, 0, 0.25), At(0, 1, 0.125)));
        CHECK_FALSE(GarmannOracle(0.25).Acceptable(At(0, 0, 0.25000000000000006), At(0, 1, 0.1)));
    }
    SECTION("the squared fast path decides like the exact form on random pairs") {
        std::mt19937_64 rng(42);
        std::uniform_real_distribution<double> u(-4, 4), s(1e-3, 2);
        int accepted = 0;
        for (int k = 0; k < 200000; ++k) {
            Element<2> a = At(u(rng), u(rng), s(rng)), b = At(u(rng), u(rng), s(rng));
            double eps = s(rng);
            bool exact = std::max(a.size, b.size) <= eps * (a.center - b.center).norm();
            REQUIRE(GarmannOracle(eps).Acceptable(a, b) == exact);
            accepted += exact;
        }
        CHECK(accepted > 10000);  // both outcomes are exercised
        CHECK(accepted < 190000);
    }
}

TEST_CASE("The hanrahan oracle estimates the flatland form factor", "[oracle]") {
    // A short element facing the centre of a segment of length a at distance r:
    // Hottel's crossed strings give F -> a / sqrt(4 r^2 + a^2) as the element shrinks
    // (DESIGN section 4), which is the estimate F(i<-j) with both cosines 1.
    double a = 2, r = 1.5, delta = 1e-6;
    Segment small{Vec2(-delta / 2, 0), Vec2(delta / 2, 0), {}};
    Segment big{Vec2(a / 2, r), Vec2(-a / 2, r), {}};
    double crossed = 2 * std::hypot(a / 2 + delta / 2, r), uncrossed = 2 * std::hypot(a / 2 - delta / 2, r);
    double hottel = (crossed - uncrossed) / (2 * delta);
    double estimate = a / std::sqrt(4 * r * r + a * a);
    REQUIRE_THAT(estimate, Catch::Matchers::WithinRel(hottel, 1e-6));

    HanrahanOracle oracle(0, {small.Normal(), big.Normal()});
    Element<2> i = At(0, 0, delta, 0), j = At(0, r, a, 1);
    CHECK(HanrahanOracle(estimate * (1 + 1e-9), {small.Normal(), big.Normal()}).Acceptable(i, j));
    CHECK_FALSE(HanrahanOracle(estimate * (1 - 1e-9), {small.Normal(), big.Normal()}).Acceptable(i, j));

    SECTION("cosines are clamped: an element behind the other's front contributes nothing") {
        Element<2> behind = At(0, -1, 1, 1);  // below the x axis, normal of root 1 faces -y
        CHECK(HanrahanOracle(1e-12, {Vec2(0, 1), Vec2(0, -1)}).Acceptable(i, behind));
    }
}

TEST_CASE("Oracle names parse and print", "[oracle]") {
    for (const std::string &name : OracleNames())
        CHECK(OracleName(ParseOracle(name)) == name);
    CHECK_THROWS_WITH(ParseOracle("bogus"), Catch::Contains("garmann"));
}
