// Scene families, 2D and 3D: geometry as documented, orientation, defaults, ranges and
// determinism.
#include <catch2/catch.hpp>

#include <array>
#include <cmath>
#include <map>
#include <set>
#include <variant>

#include "generators.h"
#include "hrbench/hrbench.h"
#include "visibility/culling.h"

using namespace hrbench;

namespace {

// The shapes of a scene's patches, for short assertions.
template <typename Shape>
std::vector<Shape> ShapesOf(const Scene &scene) {
    std::vector<Shape> shapes;
    for (const Patch<Shape> &p : scene.Get<Shape>())
        shapes.push_back(p.shape);
    return shapes;
}

}  // namespace

// ---------------------------------------------------------------------------------------
// Every family

TEST_CASE("Every family builds a valid scene from its defaults", "[generators]") {
    for (const Family &family : Families()) {
        INFO(family.name);
        Scene scene = MakeScene(family.name, {});
        CHECK(scene.family == family.name);
        // Every parameter but the optional ones without a default (NaN) is in the record.
        size_t withDefault = 0;
        for (const ParamSpec &spec : family.params)
            withDefault += !spec.defaultFrom.empty() || !std::isnan(spec.defaultValue);
        CHECK(scene.params.size() == withDefault);
        CHECK_NOTHROW(ValidateScene(scene));
    }
}

TEST_CASE("Every family builds patches of the dimension it declares", "[generators]") {
    int families2d = 0, families3d = 0;
    for (const Family &family : Families()) {
        INFO(family.name);
        Scene scene = MakeScene(family.name, {});
        CHECK(scene.Dimension() == family.dimension);
        if (family.dimension == 2) {
            ++families2d;
            CHECK(std::holds_alternative<Patches<Segment>>(scene.patches));
            CHECK(scene.NumPatches() == scene.Get<Segment>().size());
        } else {
            ++families3d;
            CHECK(std::holds_alternative<Patches<Polygon>>(scene.patches));
            CHECK(scene.NumPatches() == scene.Get<Polygon>().size());
        }
    }
    CHECK(families2d == 8);
    CHECK(families3d == 8);
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

// ---------------------------------------------------------------------------------------
// 2D families

TEST_CASE("The parallel family places the plates as docs/conventions.md says", "[generators][2d]") {
    Scene scene = MakeScene("parallel", {{"l", 4}, {"d", 2}, {"offset", 1}, {"l2", 3}});
    std::vector<Segment> s = ShapesOf<Segment>(scene);
    REQUIRE(s.size() == 2);
    CHECK(s[0].a == Vec2(0, 0));
    CHECK(s[0].b == Vec2(4, 0));
    CHECK(s[1].a == Vec2(4, 2));  // offset + l2
    CHECK(s[1].b == Vec2(1, 2));  // offset
    CHECK(s[0].Normal() == Vec2(0, 1));
    CHECK(s[1].Normal() == Vec2(0, -1));
    CHECK(MakeScene("parallel", {{"l", 5}}).params.at("l2") == 5);  // l2 defaults to l
}

TEST_CASE("Plates of the corner families face each other", "[generators][2d]") {
    std::vector<Segment> perpendicular =
        ShapesOf<Segment>(MakeScene("perpendicular", {{"gap", 0.5}}));
    CHECK(perpendicular[1].a == Vec2(0, 1.5));
    CHECK(perpendicular[1].b == Vec2(0, 0.5));
    CHECK(perpendicular[1].Normal().isApprox(Vec2(1, 0)));
    for (double angle : {30.0, 90.0, 170.0}) {
        std::vector<Segment> s = ShapesOf<Segment>(MakeScene("angled", {{"angle", angle}}));
        CHECK(ClassifyPair(s[0], s[1]) == PairRelation::Interacting);
    }
    std::vector<Segment> touching = ShapesOf<Segment>(MakeScene("perpendicular", {{"gap", 0}}));
    CHECK(ClassifyPair(touching[0], touching[1]) == PairRelation::Touching);
}

TEST_CASE("Enclosures are closed with normals pointing inward", "[generators][2d]") {
    for (const Scene &scene : {MakeScene("enclosure", {{"n", 7}}), MakeScene("room", {})}) {
        std::vector<Segment> s = ShapesOf<Segment>(scene);
        Vec2 centroid = Vec2::Zero();
        for (const Segment &seg : s)
            centroid += seg.Midpoint() / double(s.size());
        for (size_t k = 0; k < s.size(); ++k) {
            const Segment &seg = s[k];
            CHECK(seg.b == s[(k + 1) % s.size()].a);                 // closed
            CHECK(seg.Normal().dot(centroid - seg.Midpoint()) > 0);  // inward
        }
    }
}

TEST_CASE("The room's lamp is its ceiling's emission, and nothing else emits", "[generators][2d]") {
    const Scene lit = MakeScene("room", {{"w", 3}, {"h", 2}, {"lamp", 1.5}});
    const Patches<Segment> &walls = lit.Get<Segment>();
    REQUIRE(walls.size() == 4);
    for (const Patch<Segment> &wall : walls) {
        bool ceiling = wall.shape.a.y() == 2 && wall.shape.b.y() == 2;
        CHECK(wall.material.emission == (ceiling ? 1.5 : 0.0));
        CHECK(wall.material.reflectance == 0.5);
    }
    const Scene dark = MakeScene("room", {});
    for (const Patch<Segment> &wall : dark.Get<Segment>())
        CHECK(wall.material.emission == 0);
}

TEST_CASE("The array family repeats the same facing pair k times", "[generators][2d]") {
    std::vector<Segment> s =
        ShapesOf<Segment>(MakeScene("array", {{"k", 5}, {"l", 2}, {"d", 1}, {"spacing", 1}}));
    REQUIRE(s.size() == 10);
    for (int i = 0; i < 5; ++i) {
        CHECK(s[i].a == Vec2(3 * i, 0));
        CHECK(s[5 + i].b == Vec2(3 * i, 1));
    }
}

TEST_CASE("Random scenes depend only on their seed and never cross", "[generators][2d]") {
    ParamMap p{{"n", 30}, {"seed", 5}, {"size", 10}};
    std::vector<Segment> a = ShapesOf<Segment>(MakeScene("random", p)),
                         b = ShapesOf<Segment>(MakeScene("random", p));
    REQUIRE(a.size() == 30);
    for (size_t k = 0; k < a.size(); ++k) {
        CHECK(a[k].a == b[k].a);
        CHECK(a[k].b == b[k].b);
        CHECK(a[k].Length() == Approx(1));
    }
    p["seed"] = 6;
    CHECK(MakeScene("random", p).Get<Segment>()[0].shape.a != a[0].a);
    for (size_t i = 0; i < a.size(); ++i)
        for (size_t j = i + 1; j < a.size(); ++j)
            CHECK(ClassifyPair(a[i], a[j]) != PairRelation::Touching);
    // The scene of a seed is fixed for good: a changed generator breaks saved sweeps.
    Segment one =
        MakeScene("random", {{"n", 1}, {"seed", 1}, {"size", 10}}).Get<Segment>()[0].shape;
    CHECK_THAT(one.a.x(), Catch::Matchers::WithinRel(1.8407641913114348, 1e-12));
    CHECK_THAT(one.b.y(), Catch::Matchers::WithinRel(1.4896405422134733, 1e-12));
    CHECK_THROWS_WITH(MakeScene("random", {{"n", 500}, {"size", 1}, {"length", 1}}),
                      Catch::Contains("enlarge size"));
}

TEST_CASE("A random soup of a given density has the box side sqrt(n / density)",
          "[generators][2d]") {
    // n = 400 at density 1 is the box of side 20: the same draws, the same scene, as
    // size = 20; the record holds density and leaves size out, which does not apply.
    Scene dense = MakeScene("random", {{"n", 400}, {"density", 1}, {"seed", 3}});
    Scene sized = MakeScene("random", {{"n", 400}, {"size", 20}, {"seed", 3}});
    std::vector<Segment> a = ShapesOf<Segment>(dense), b = ShapesOf<Segment>(sized);
    REQUIRE(a.size() == 400);
    for (size_t k = 0; k < a.size(); ++k) {
        CHECK(a[k].a == b[k].a);
        CHECK(a[k].b == b[k].b);
    }
    CHECK(dense.params.at("density") == 1);
    CHECK(dense.params.count("size") == 0);
    // Without density nothing changes: no density in the record, size at its default.
    Scene plain = MakeScene("random", {{"n", 5}});
    CHECK(plain.params.count("density") == 0);
    CHECK(plain.params.at("size") == 10);
    // The centres of n = 4 at density 0.25 lie in the box of side 4 = sqrt(4 / 0.25).
    for (const Segment &s : ShapesOf<Segment>(MakeScene("random", {{"n", 4}, {"density", 0.25}}))) {
        Vec2 c = 0.5 * (s.a + s.b);
        CHECK((c.x() >= 0 && c.x() < 4 && c.y() >= 0 && c.y() < 4));
    }
    CHECK_THROWS_WITH(MakeScene("random", {{"n", 10}, {"density", 1}, {"size", 10}}),
                      "scene random: give density or size, not both");
    CHECK_THROWS_WITH(MakeScene("random", {{"n", 10}, {"density", 0}}),
                      Catch::Contains("density=0 is out of range (> 0)"));
    CHECK_THROWS_WITH(MakeScene("random", {{"n", 500}, {"density", 100}}),
                      Catch::Contains("lower density"));
}

TEST_CASE("A random 3D soup of a given density has the cube side cbrt(n / density)",
          "[generators][3d]") {
    // n = 125 at density 1 is the cube of side 5: the same draws, the same scene, as
    // size = 5 (cbrt(125) is exactly 5).
    Scene dense = MakeScene("random3d", {{"n", 125}, {"density", 1}, {"seed", 3}});
    Scene sized = MakeScene("random3d", {{"n", 125}, {"size", 5}, {"seed", 3}});
    std::vector<Polygon> a = ShapesOf<Polygon>(dense), b = ShapesOf<Polygon>(sized);
    REQUIRE(a.size() == 125);
    for (size_t k = 0; k < a.size(); ++k)
        for (int v = 0; v < 3; ++v)
            CHECK(a[k].v[v] == b[k].v[v]);
    CHECK(dense.params.count("size") == 0);
    CHECK(MakeScene("random3d", {{"n", 5}}).params.count("density") == 0);
    CHECK_THROWS_WITH(MakeScene("random3d", {{"n", 10}, {"density", 1}, {"size", 10}}),
                      "scene random3d: give density or size, not both");
    CHECK_THROWS_WITH(MakeScene("random3d", {{"n", 200}, {"density", 200000}}),
                      Catch::Contains("lower density"));
}

TEST_CASE("Random scenes are placed on a grid and stay what testing every pair gives",
          "[generators]") {
    // The last of 400 crowded segments and of 200 crowded triangles, as an earlier
    // engine placed them by testing every placed shape (hrbench 0.2.0).
    auto segments = MakeScene("random", {{"n", 400}, {"size", 12}, {"seed", 3}}).Get<Segment>();
    CHECK(segments.back().shape.a.x() == 7.083335141130152);
    CHECK(segments.back().shape.b.y() == 10.037097433110024);
    auto triangles = MakeScene("random3d", {{"n", 200}, {"size", 6}, {"seed", 2}}).Get<Polygon>();
    CHECK(triangles.back().shape.v[0].x() == 3.3875922369481275);
    CHECK(triangles.back().shape.v[2].z() == 5.615755075078493);
    for (size_t i = 0; i < segments.size(); ++i)
        for (size_t j = i + 1; j < segments.size(); ++j)
            REQUIRE(ClassifyPair(segments[i].shape, segments[j].shape) != PairRelation::Touching);
    // 100,000 shapes build in linear time (a few seconds before, minutes with every pair).
    CHECK(MakeScene("random", {{"n", 100000}, {"size", 1000}}).NumPatches() == 100000);
}

TEST_CASE("The occluded family puts two back-to-back blockers between the plates",
          "[generators][2d]") {
    std::vector<Segment> o2 = ShapesOf<Segment>(MakeScene("occluded", {}));
    REQUIRE(o2.size() == 4);
    CHECK(o2[2].Normal() == Vec2(0, -1));
    CHECK(o2[3].Normal() == Vec2(0, 1));
    CHECK_THROWS_AS(MakeScene("occluded", {{"h", 2}}), InputError);
}

// ---------------------------------------------------------------------------------------
// 3D families

TEST_CASE("parallel3d places its plates as documented, first edges along x", "[generators][3d]") {
    std::vector<Polygon> s = ShapesOf<Polygon>(
        MakeScene("parallel3d", {{"l", 4}, {"w", 2}, {"d", 3}, {"ox", 1}, {"oy", -1}}));
    REQUIRE(s.size() == 2);
    const Polygon &p = s[0], &q = s[1];
    CHECK(p.v[0] == Vec3(0, 0, 0));
    CHECK(p.v[1] == Vec3(4, 0, 0));
    CHECK(p.v[2] == Vec3(4, 2, 0));
    CHECK(p.Normal() == Vec3(0, 0, 1));
    CHECK(q.Normal() == Vec3(0, 0, -1));
    CHECK((q.v[1] - q.v[0]) == Vec3(4, 0, 0));
    CHECK(q.Centroid().isApprox(Vec3(3, 0, 3)));
    CHECK(MakeScene("parallel3d", {{"l", 5}}).params.at("w") == 5);  // w defaults to l
}

TEST_CASE("The corner families face into their wedge", "[generators][3d]") {
    std::vector<Polygon> s =
        ShapesOf<Polygon>(MakeScene("perpendicular3d", {{"gap", 0.5}, {"h", 2}}));
    const Polygon &q = s[1];
    CHECK(q.Normal() == Vec3(0, 1, 0));
    CHECK(q.v[0] == Vec3(0, 0, 2.5));
    CHECK(q.v[3] == Vec3(0, 0, 0.5));
    for (double angle : {30.0, 90.0, 150.0}) {
        std::vector<Polygon> a = ShapesOf<Polygon>(MakeScene("angled3d", {{"angle", angle}}));
        CHECK(ClassifyPair(a[0], a[1]) == PairRelation::Interacting);
    }
}

TEST_CASE("The Cornell box has its measured size and faces the right way", "[generators][3d]") {
    Scene scene = MakeScene("cornell", {});
    const Patches<Polygon> &s = scene.Get<Polygon>();
    REQUIRE(s.size() == 17);
    // The box: walls face its centre, the light faces down, the blocks face out.
    Vec3 boxCentre(0.278, 0.2744, 0.2796);
    Vec3 shortCentre(0.186, 0.0825, 0.1685), tallCentre(0.3685, 0.165, 0.3515);
    for (size_t k = 0; k < s.size(); ++k) {
        INFO("face " << k);
        const Polygon &p = s[k].shape;
        Vec3 c = p.Centroid(), n = p.Normal();
        if (k < 6)
            CHECK(n.dot(boxCentre - c) > 0);
        else if (k == 6)
            CHECK(n.isApprox(Vec3(0, -1, 0)));
        else
            CHECK(n.dot(c - (k < 12 ? shortCentre : tallCentre)) > 0);
    }
    CHECK(s[6].material.emission > 0);
    int emitters = 0;
    for (const Patch<Polygon> &f : s)
        emitters += f.material.emission > 0;
    CHECK(emitters == 1);
    CHECK(s[3].material.reflectance < s[0].material.reflectance);  // green < white
    CHECK_THAT(s[0].shape.Area(), Catch::Matchers::WithinRel(0.5528 * 0.5592, 0.01));
    CHECK(MakeScene("cornell", {{"scale", 1}}).Get<Polygon>()[1].shape.v[0] == Vec3(556, 548.8, 0));
}

TEST_CASE("random3d is deterministic, disjoint and not trivial", "[generators][3d]") {
    std::vector<Polygon> a = ShapesOf<Polygon>(MakeScene("random3d", {{"n", 30}, {"seed", 7}}));
    std::vector<Polygon> b = ShapesOf<Polygon>(MakeScene("random3d", {{"n", 30}, {"seed", 7}}));
    std::vector<Polygon> c = ShapesOf<Polygon>(MakeScene("random3d", {{"n", 30}, {"seed", 8}}));
    REQUIRE(a.size() == 30);
    for (size_t k = 0; k < a.size(); ++k)
        for (int v = 0; v < 3; ++v)
            CHECK(a[k].v[v] == b[k].v[v]);
    CHECK(a[0].v[0] != c[0].v[0]);
    int touching = 0, interacting = 0;
    for (uint32_t p = 0; p < 30; ++p)
        for (uint32_t q = p + 1; q < 30; ++q) {
            PairRelation r = ClassifyPair(a[p], a[q]);
            touching += r == PairRelation::Touching;
            interacting += r == PairRelation::Interacting;
        }
    CHECK(touching == 0);
    CHECK(interacting > 50);
    CHECK_THROWS_AS(MakeScene("random3d", {{"n", 100}, {"size", 0.001}}), InputError);  // crowded
}

TEST_CASE("array3d and occluded3d build the documented patches", "[generators][3d]") {
    CHECK(MakeScene("array3d", {{"k", 3}}).Get<Polygon>().size() == 18);
    std::vector<Polygon> o =
        ShapesOf<Polygon>(MakeScene("occluded3d", {{"bl", 0.4}, {"bw", 0.2}, {"h", 0.3}}));
    REQUIRE(o.size() == 4);
    CHECK(o[2].Normal() == Vec3(0, 0, -1));  // facing P
    CHECK(o[3].Normal() == Vec3(0, 0, 1));   // facing Q
    CHECK(o[2].Centroid().isApprox(Vec3(0.5, 0.5, 0.3)));
    CHECK_THAT(o[3].Area(), Catch::Matchers::WithinRel(0.08, 1e-12));
    CHECK_THROWS_AS(MakeScene("occluded3d", {{"h", 1}}), InputError);
}

TEST_CASE("sphere is closed, faces inward and has the sphere's area", "[generators][3d]") {
    for (int n : {1, 2, 5}) {
        INFO("n = " << n);
        const double radius = 2;
        std::vector<Polygon> s =
            ShapesOf<Polygon>(MakeScene("sphere", {{"n", n}, {"radius", radius}}));
        REQUIRE(s.size() == size_t(8 * n * n));
        // Closed: every edge a -> b of a triangle is met exactly once as b -> a, so each
        // edge is shared by two triangles of opposite orientation (corners shared exactly).
        using Corner = std::array<double, 3>;
        auto key = [](const Vec3 &v) { return Corner{v.x(), v.y(), v.z()}; };
        std::map<std::pair<Corner, Corner>, int> edges;
        std::set<Corner> corners;
        double area = 0;
        for (const Polygon &t : s) {
            REQUIRE(t.n == 3);
            for (int k = 0; k < 3; ++k) {
                ++edges[{key(t.v[k]), key(t.v[(k + 1) % 3])}];
                corners.insert(key(t.v[k]));
                CHECK_THAT(t.v[k].norm(), Catch::Matchers::WithinRel(radius, 1e-15));
            }
            CHECK(t.Normal().dot(-t.Centroid()) > 0);  // toward the centre
            area += t.Area();
        }
        for (const auto &[edge, count] : edges) {
            CHECK(count == 1);
            CHECK(edges.count({edge.second, edge.first}) == 1);
        }
        CHECK(edges.size() == 3 * s.size());
        CHECK(corners.size() == size_t(4 * n * n + 2));  // Euler: V - E + F = 2
        // Inscribed triangles: less than the sphere's area, closer as n grows.
        double sphere = 4 * 3.14159265358979323846 * radius * radius;
        CHECK(area < sphere);
        CHECK(area > sphere * (n == 1 ? 0.4 : n == 2 ? 0.75 : 0.95));
    }
    // n = 1 is the octahedron.
    std::vector<Polygon> octahedron = ShapesOf<Polygon>(MakeScene("sphere", {{"n", 1}}));
    CHECK(octahedron[0].v[0] == Vec3(1, 0, 0));
    CHECK(octahedron[0].Normal().isApprox(-Vec3(1, 1, 1).normalized()));
    std::vector<Polygon> again = ShapesOf<Polygon>(MakeScene("sphere", {{"n", 1}}));
    for (size_t k = 0; k < octahedron.size(); ++k)
        CHECK(octahedron[k].v == again[k].v);
    CHECK_THROWS_AS(MakeScene("sphere", {{"n", 0}}), InputError);
    CHECK_THROWS_AS(MakeScene("sphere", {{"n", 1001}}), InputError);
    CHECK_THROWS_AS(MakeScene("sphere", {{"n", 2.5}}), InputError);
}

TEST_CASE("Inside the sphere every pair faces the other; neighbours touch", "[generators][3d]") {
    std::vector<Polygon> s = ShapesOf<Polygon>(MakeScene("sphere", {{"n", 2}}));
    int touching = 0, sharing = 0;
    for (size_t p = 0; p < s.size(); ++p)
        for (size_t q = p + 1; q < s.size(); ++q) {
            bool shared = false;
            for (int a = 0; a < 3; ++a)
                for (int b = 0; b < 3; ++b)
                    shared = shared || s[p].v[a] == s[q].v[b];
            PairRelation r = ClassifyPair(s[p], s[q]);
            CHECK(r == (shared ? PairRelation::Touching : PairRelation::Interacting));
            touching += r == PairRelation::Touching;
            sharing += shared;
        }
    // 18 corners: the 6 of the octahedron in 4 triangles, the 12 edge midpoints in 6;
    // pairs around a corner: 6 * C(4,2) + 12 * C(6,2) = 216, less the 48 edges counted
    // twice (their two ends): 168 pairs sharing a corner.
    CHECK(sharing == 168);
    CHECK(touching == 168);
}
