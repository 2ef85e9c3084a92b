// Scene families: geometry as documented, defaults, ranges and determinism.
#include <catch2/catch.hpp>

#include "generators.h"
#include "hrbench.h"

using namespace hrbench;

TEST_CASE("Every family builds a valid scene from its defaults", "[generators]") {
    for (const Family &family : Families()) {
        INFO(family.name);
        Scene scene = MakeScene(family.name, {});
        CHECK(scene.family == family.name);
        CHECK(scene.params.size() == family.params.size());
        CHECK_NOTHROW(ValidateScene(scene));
    }
}

TEST_CASE("The parallel family places the plates as DESIGN section 2 says", "[generators]") {
    Scene s = MakeScene("parallel", {{"l", 4}, {"d", 2}, {"offset", 1}, {"l2", 3}});
    REQUIRE(s.segments.size() == 2);
    CHECK(s.segments[0].a == Vec2(0, 0));
    CHECK(s.segments[0].b == Vec2(4, 0));
    CHECK(s.segments[1].a == Vec2(4, 2));  // offset + l2
    CHECK(s.segments[1].b == Vec2(1, 2));  // offset
    CHECK(s.segments[0].Normal() == Vec2(0, 1));
    CHECK(s.segments[1].Normal() == Vec2(0, -1));
    CHECK(MakeScene("parallel", {{"l", 5}}).params.at("l2") == 5);  // l2 defaults to l
}

TEST_CASE("Plates of the corner families face each other", "[generators]") {
    Scene perpendicular = MakeScene("perpendicular", {{"gap", 0.5}});
    CHECK(perpendicular.segments[1].a == Vec2(0, 1.5));
    CHECK(perpendicular.segments[1].b == Vec2(0, 0.5));
    CHECK(perpendicular.segments[1].Normal().isApprox(Vec2(1, 0)));
    for (double angle : {30.0, 90.0, 170.0}) {
        Scene s = MakeScene("angled", {{"angle", angle}});
        CHECK(ClassifyPair(s.segments[0], s.segments[1]) == PairRelation::Interacting);
    }
    CHECK(ClassifyPair(MakeScene("perpendicular", {{"gap", 0}}).segments[0],
                       MakeScene("perpendicular", {{"gap", 0}}).segments[1]) ==
          PairRelation::Touching);
}

TEST_CASE("Enclosures are closed with normals pointing inward", "[generators]") {
    for (const Scene &s : {MakeScene("enclosure", {{"n", 7}}), MakeScene("room", {})}) {
        Vec2 centroid = Vec2::Zero();
        for (const Segment &seg : s.segments)
            centroid += seg.Midpoint() / double(s.segments.size());
        for (size_t k = 0; k < s.segments.size(); ++k) {
            const Segment &seg = s.segments[k];
            CHECK(seg.b == s.segments[(k + 1) % s.segments.size()].a);  // closed
            CHECK(seg.Normal().dot(centroid - seg.Midpoint()) > 0);       // inward
        }
    }
}

TEST_CASE("The array family repeats the same facing pair k times", "[generators]") {
    Scene s = MakeScene("array", {{"k", 5}, {"l", 2}, {"d", 1}, {"spacing", 1}});
    REQUIRE(s.segments.size() == 10);
    for (int i = 0; i < 5; ++i) {
        CHECK(s.segments[i].a == Vec2(3 * i, 0));
        CHECK(s.segments[5 + i].b == Vec2(3 * i, 1));
    }
}

TEST_CASE("Random scenes depend only on their seed and never cross", "[generators]") {
    ParamMap p{{"n", 30}, {"seed", 5}, {"size", 10}};
    Scene a = MakeScene("random", p), b = MakeScene("random", p);
    REQUIRE(a.segments.size() == 30);
    for (size_t k = 0; k < a.segments.size(); ++k) {
        CHECK(a.segments[k].a == b.segments[k].a);
        CHECK(a.segments[k].b == b.segments[k].b);
        CHECK(a.segments[k].Length() == Approx(1));
    }
    p["seed"] = 6;
    CHECK(MakeScene("random", p).segments[0].a != a.segments[0].a);
    for (size_t i = 0; i < a.segments.size(); ++i)
        for (size_t j = i + 1; j < a.segments.size(); ++j)
            CHECK(ClassifyPair(a.segments[i], a.segments[j]) != PairRelation::Touching);
    // The scene of a seed is fixed for good: a changed generator breaks saved sweeps.
    Scene one = MakeScene("random", {{"n", 1}, {"seed", 1}, {"size", 10}});
    CHECK_THAT(one.segments[0].a.x(), Catch::Matchers::WithinRel(1.8407641913114348, 1e-12));
    CHECK_THAT(one.segments[0].b.y(), Catch::Matchers::WithinRel(1.4896405422134733, 1e-12));
    CHECK_THROWS_WITH(MakeScene("random", {{"n", 500}, {"size", 1}, {"length", 1}}),
                      Catch::Contains("enlarge size"));
}

TEST_CASE("Bad scene parameters are rejected with a clear message", "[generators][errors]") {
    CHECK_THROWS_WITH(MakeScene("bogus", {}), Catch::Contains("unknown scene 'bogus'"));
    CHECK_THROWS_WITH(MakeScene("parallel", {{"x", 1}}), Catch::Contains("no parameter 'x'"));
    CHECK_THROWS_WITH(MakeScene("parallel", {{"d", 0}}), Catch::Contains("d=0 is out of range"));
    CHECK_THROWS_WITH(MakeScene("parallel", {{"l", -1}}), Catch::Contains("> 0"));
    CHECK_THROWS_AS(MakeScene("angled", {{"angle", 180}}), InputError);
    CHECK_THROWS_AS(MakeScene("enclosure", {{"n", 2}}), InputError);
    CHECK_THROWS_AS(MakeScene("enclosure", {{"n", 4.5}}), InputError);
    CHECK_THROWS_AS(MakeScene("perpendicular", {{"gap", -0.1}}), InputError);
}
