// The 3D scene families: geometry as documented, orientation, determinism, bad values,
// and their JSON scene files.
#include <catch2/catch.hpp>

#include "generators.h"
#include "hrbench.h"

using namespace hrbench;

TEST_CASE("Every 3D family builds a valid 3D scene from its defaults", "[3d][generators]") {
    int families3d = 0;
    for (const Family &family : Families()) {
        if (family.dimension != 3)
            continue;
        INFO(family.name);
        ++families3d;
        Scene scene = MakeScene(family.name, {});
        CHECK(scene.dimension == 3);
        CHECK(scene.segments.empty());
        CHECK(scene.NumPatches() == scene.faces.size());
        CHECK_NOTHROW(ValidateScene(scene));
    }
    CHECK(families3d == 7);
}

TEST_CASE("parallel3d places its plates as documented, first edges along x", "[3d][generators]") {
    Scene s = MakeScene("parallel3d", {{"l", 4}, {"w", 2}, {"d", 3}, {"ox", 1}, {"oy", -1}});
    REQUIRE(s.faces.size() == 2);
    const Polygon &p = s.faces[0].polygon, &q = s.faces[1].polygon;
    CHECK(p.v[0] == Vec3(0, 0, 0));
    CHECK(p.v[1] == Vec3(4, 0, 0));
    CHECK(p.v[2] == Vec3(4, 2, 0));
    CHECK(p.Normal() == Vec3(0, 0, 1));
    CHECK(q.Normal() == Vec3(0, 0, -1));
    CHECK((q.v[1] - q.v[0]) == Vec3(4, 0, 0));
    CHECK(q.Centroid().isApprox(Vec3(3, 0, 3)));
    CHECK(MakeScene("parallel3d", {{"l", 5}}).params.at("w") == 5);  // w defaults to l
}

TEST_CASE("The corner families face into their wedge", "[3d][generators]") {
    Scene s = MakeScene("perpendicular3d", {{"gap", 0.5}, {"h", 2}});
    const Polygon &q = s.faces[1].polygon;
    CHECK(q.Normal() == Vec3(0, 1, 0));
    CHECK(q.v[0] == Vec3(0, 0, 2.5));
    CHECK(q.v[3] == Vec3(0, 0, 0.5));
    for (double angle : {30.0, 90.0, 150.0}) {
        Scene a = MakeScene("angled3d", {{"angle", angle}});
        CHECK(ClassifyPair(a.faces[0].polygon, a.faces[1].polygon) == PairRelation::Interacting);
    }
}

TEST_CASE("The Cornell box has its measured size and faces the right way", "[3d][generators]") {
    Scene s = MakeScene("cornell", {});
    REQUIRE(s.faces.size() == 17);
    // The box: walls face its centre, the light faces down, the blocks face out.
    Vec3 boxCentre(0.278, 0.2744, 0.2796);
    Vec3 shortCentre(0.186, 0.0825, 0.1685), tallCentre(0.3685, 0.165, 0.3515);
    for (size_t k = 0; k < s.faces.size(); ++k) {
        INFO("face " << k);
        const Polygon &p = s.faces[k].polygon;
        Vec3 c = p.Centroid(), n = p.Normal();
        if (k < 6)
            CHECK(n.dot(boxCentre - c) > 0);
        else if (k == 6)
            CHECK(n.isApprox(Vec3(0, -1, 0)));
        else
            CHECK(n.dot(c - (k < 12 ? shortCentre : tallCentre)) > 0);
    }
    CHECK(s.faces[6].material.emission > 0);
    int emitters = 0;
    for (const Face &f : s.faces)
        emitters += f.material.emission > 0;
    CHECK(emitters == 1);
    CHECK(s.faces[3].material.reflectance < s.faces[0].material.reflectance);  // green < white
    CHECK_THAT(s.faces[0].polygon.Area(), Catch::Matchers::WithinRel(0.5528 * 0.5592, 0.01));
    CHECK(MakeScene("cornell", {{"scale", 1}}).faces[1].polygon.v[0] == Vec3(556, 548.8, 0));
}

TEST_CASE("random3d is deterministic, disjoint and not trivial", "[3d][generators]") {
    Scene a = MakeScene("random3d", {{"n", 30}, {"seed", 7}});
    Scene b = MakeScene("random3d", {{"n", 30}, {"seed", 7}});
    Scene c = MakeScene("random3d", {{"n", 30}, {"seed", 8}});
    REQUIRE(a.faces.size() == 30);
    for (size_t k = 0; k < a.faces.size(); ++k)
        for (int v = 0; v < 3; ++v)
            CHECK(a.faces[k].polygon.v[v] == b.faces[k].polygon.v[v]);
    CHECK(a.faces[0].polygon.v[0] != c.faces[0].polygon.v[0]);
    int touching = 0, interacting = 0;
    for (uint32_t p = 0; p < 30; ++p)
        for (uint32_t q = p + 1; q < 30; ++q) {
            PairRelation r = ClassifyRootPair(a, p, q);
            touching += r == PairRelation::Touching;
            interacting += r == PairRelation::Interacting;
        }
    CHECK(touching == 0);
    CHECK(interacting > 50);
    CHECK_THROWS_AS(MakeScene("random3d", {{"n", 100}, {"size", 0.001}}), InputError);  // crowded
}

TEST_CASE("array3d and occluded3d build the documented patches", "[3d][generators]") {
    CHECK(MakeScene("array3d", {{"k", 3}}).faces.size() == 18);
    Scene o = MakeScene("occluded3d", {{"bl", 0.4}, {"bw", 0.2}, {"h", 0.3}});
    REQUIRE(o.faces.size() == 4);
    CHECK(o.faces[2].polygon.Normal() == Vec3(0, 0, -1));  // facing P
    CHECK(o.faces[3].polygon.Normal() == Vec3(0, 0, 1));   // facing Q
    CHECK(o.faces[2].polygon.Centroid().isApprox(Vec3(0.5, 0.5, 0.3)));
    CHECK_THAT(o.faces[3].polygon.Area(), Catch::Matchers::WithinRel(0.08, 1e-12));
    CHECK_THROWS_AS(MakeScene("occluded3d", {{"h", 1}}), InputError);
    CHECK_THROWS_AS(MakeScene("occluded", {{"h", 2}}), InputError);
    Scene o2 = MakeScene("occluded", {});
    REQUIRE(o2.segments.size() == 4);
    CHECK(o2.segments[2].Normal() == Vec2(0, -1));
    CHECK(o2.segments[3].Normal() == Vec2(0, 1));
}

TEST_CASE("3D scenes survive a round trip through their JSON file", "[3d][scene_io]") {
    Scene scene = MakeScene("cornell", {});
    Scene back = SceneFromJson(SceneToJson(scene), "mem");
    CHECK(back.dimension == 3);
    REQUIRE(back.faces.size() == scene.faces.size());
    for (size_t k = 0; k < scene.faces.size(); ++k) {
        CHECK(back.faces[k].polygon.n == scene.faces[k].polygon.n);
        for (int v = 0; v < scene.faces[k].polygon.n; ++v)
            CHECK(back.faces[k].polygon.v[v] == scene.faces[k].polygon.v[v]);
        CHECK(back.faces[k].material.reflectance == scene.faces[k].material.reflectance);
        CHECK(back.faces[k].material.emission == scene.faces[k].material.emission);
    }
}

TEST_CASE("Bad 3D scene files are rejected with one line naming the problem",
          "[3d][scene_io]") {
    auto load = [](const std::string &patches, int dimension = 3) {
        return SceneFromJson(R"({"format":"hrbench-scene","schema_version":1,"dimension":)" +
                                 std::to_string(dimension) + R"(,"patches":[)" + patches + "]}",
                             "mem");
    };
    CHECK_NOTHROW(load(R"({"vertices":[[0,0,0],[1,0,0],[0,1,0]]})"));
    auto fails = [&](const std::string &patches, const std::string &fragment, int dimension = 3) {
        INFO(patches);
        try {
            load(patches, dimension);
            FAIL("no error");
        } catch (const InputError &e) {
            CHECK_THAT(e.what(), Catch::Contains(fragment));
            CHECK(std::string(e.what()).find('\n') == std::string::npos);
        }
    };
    fails(R"({"vertices":[[0,0,0],[1,0,0],[1,1,0.5],[0,1,0]]})", "not planar");
    fails(R"({"vertices":[[0,0,0],[1,0,0],[0.1,0.1,0],[0,1,0]]})", "not a convex quad");
    fails(R"({"vertices":[[0,0,0],[1,1,1],[2,2,2]]})", "degenerate");
    fails(R"({"vertices":[[0,0,0],[1,0,0]]})", "3 or 4 points");
    fails(R"({"vertices":[[0,0,0],[1,0,0],[0,1]]})", "3 numbers");
    fails(R"({"vertices":[[0,0,0],[1e999,0,0],[0,1,0]]})", "malformed JSON");
    fails(R"({"a":[0,0],"b":[1,0]})", "no \"vertices\"");
    fails("", "no patches");
    fails(R"({"vertices":[[0,0,0],[1,0,0],[0,1,0]],"reflectance":1})", "reflectance");
    fails(R"({"vertices":[[0,0,0],[1,0,0],[0,1,0]]})", "dimension", 4);
}
