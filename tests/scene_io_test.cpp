// Scene files, 2D and 3D: round trip and every kind of malformed input.
#include <catch2/catch.hpp>

#include <cmath>

#include "generators.h"
#include "hrbench/hrbench.h"
#include "util/sha256.h"

using namespace hrbench;

TEST_CASE("Scenes survive a round trip through their JSON file", "[scene_io][2d]") {
    Scene scene = MakeScene("random", {{"n", 8}, {"seed", 2}});
    scene.Get<Segment>()[3].material = {0.25, 2.0};
    Scene back = SceneFromJson(SceneToJson(scene), "mem");
    CHECK(back.Dimension() == 2);
    const Patches<Segment> &s = scene.Get<Segment>(), &b = back.Get<Segment>();
    REQUIRE(b.size() == s.size());
    for (size_t k = 0; k < s.size(); ++k) {
        CHECK(b[k].shape.a == s[k].shape.a);  // exact: shortest round-trip digits
        CHECK(b[k].shape.b == s[k].shape.b);
        CHECK(b[k].material.reflectance == s[k].material.reflectance);
        CHECK(b[k].material.emission == s[k].material.emission);
    }
    CHECK(back.params == scene.params);
    CHECK(back.family == "file");
}

TEST_CASE("The checked-in example scene loads and gives the worked example", "[scene_io]") {
    Scene scene = LoadScene(std::string(HRBENCH_TEST_DATA) + "/parallel_l64_d1.json");
    RefineOptions o;
    o.eps = 0.25;
    Refinement<Segment> r = Refine<Segment>(scene, o);
    CHECK(r.record.counters.links == 5092);
    CHECK(r.record.counters.nodes == 1022);
}

TEST_CASE("Malformed scene files give one line naming the problem", "[scene_io][errors]") {
    std::string good = SceneToJson(MakeScene("parallel", {}));
    auto error = [](const std::string &text) {
        try {
            SceneFromJson(text, "f.json");
        } catch (const InputError &e) {
            return std::string(e.what());
        }
        return std::string("no error");
    };
    CHECK_THAT(error(good.substr(0, good.size() / 2)), Catch::Contains("f.json: malformed JSON"));
    CHECK_THAT(error(""), Catch::Contains("malformed JSON"));
    CHECK_THAT(error("[1,2]"), Catch::Contains("not an hrbench scene"));
    CHECK_THAT(error(R"({"format":"hrbench-scene","schema_version":9,"patches":[]})"),
               Catch::Contains("schema_version"));
    std::string head = R"({"format":"hrbench-scene","schema_version":1,"patches":)";
    CHECK_THAT(error(head + "[]}"), Catch::Contains("no patches"));
    CHECK_THAT(error(head + "{}}"), Catch::Contains("\"patches\" must be an array"));
    CHECK_THAT(error(head + R"([{"a":[0,0]}]})"), Catch::Contains("patches[0] has no \"b\""));
    CHECK_THAT(error(head + R"([{"a":[0,0],"b":[1]}]})"), Catch::Contains("patches[0].b"));
    CHECK_THAT(error(head + R"([{"a":[0,"x"],"b":[1,0]}]})"), Catch::Contains("must be a number"));
    CHECK_THAT(error(head + R"([{"a":[1,1],"b":[1,1]}]})"), Catch::Contains("degenerate"));
    CHECK_THAT(error(head + R"([{"a":[0,0],"b":[1e999,0]}]})"), Catch::Contains("number overflow"));
    CHECK_THAT(error(head + R"([{"a":[0,0],"b":[1,0],"reflectance":1.5}]})"),
               Catch::Contains("reflectance"));
    CHECK_THROWS_WITH(LoadScene("/nonexistent/scene.json"), Catch::Contains("cannot read"));
}

TEST_CASE("Hostile scene files are refused with one line, never read without bound",
          "[scene_io][errors]") {
    auto error = [](const std::string &text) {
        try {
            SceneFromJson(text, "f.json");
        } catch (const InputError &e) {
            return std::string(e.what());
        }
        return std::string("no error");
    };
    std::string head = R"({"format":"hrbench-scene","schema_version":1,"patches":)";
    SECTION("types, keys and nesting") {
        CHECK(error(R"({"format":"hrbench-scene","schema_version":"1","patches":[]})") ==
              "f.json: \"schema_version\" must be the integer 1");
        CHECK(error(R"({"format":"hrbench-scene","schema_version":1.5,"patches":[]})") ==
              "f.json: \"schema_version\" must be the integer 1");
        CHECK(error(R"({"format":7,"schema_version":1,"patches":[]})") ==
              "f.json: not an hrbench scene (\"format\": \"hrbench-scene\" missing)");
        CHECK(error(R"({"format":"hrbench-scene","schema_version":1,"params":[1],"patches":[]})") ==
              "f.json: \"params\" must be an object of numbers");
        CHECK(error(head + R"([{"a":[0,0],"b":[1,0],"a":[2,2]}]})") ==
              "f.json: key \"a\" appears twice in one object");
        CHECK(error(R"({"format":"hrbench-scene","schema_version":1,"schema_version":1})") ==
              "f.json: key \"schema_version\" appears twice in one object");
        CHECK(error(head + R"([{"a":[0,0],"b":[1,0],"emmission":1}]})") ==
              "f.json: patches[0] has an unknown key \"emmission\"");
        CHECK(error(R"({"format":"hrbench-scene","schema_version":1,"patchs":[]})") ==
              "f.json: has an unknown key \"patchs\"");
        CHECK(error(std::string(100000, '[') + std::string(100000, ']')) ==
              "f.json: JSON nested deeper than 32 levels");
    }
    SECTION("numbers beyond double precision") {
        CHECK(error(head + R"([{"a":[0,0],"b":[1e155,0]},{"a":[0,1],"b":[1,1]}]})") ==
              "f.json: patch 0 is too long for double precision (its length overflows)");
        CHECK(error(head + R"([{"a":[0,0],"b":[1e-300,0]},{"a":[0,1],"b":[1,1]}]})") ==
              "f.json: patch 0 is too short for double precision (its squared length underflows)");
        std::string tiny = R"({"format":"hrbench-scene","schema_version":1,"dimension":3,)"
                           R"("patches":[{"vertices":[[0,0,0],[1e-200,0,0],[0,1e-200,0]]}]})";
        CHECK(error(tiny) ==
              "f.json: patch 0 is too small for double precision (its squared size underflows)");
    }
    SECTION("files that are no scene file") {
        CHECK_THROWS_WITH(LoadScene("/tmp"), "cannot read scene file '/tmp': it is a directory");
        CHECK_THROWS_WITH(LoadScene("/dev/zero", size_t(1) << 20),
                          "scene file '/dev/zero' is larger than the input limit of 1 MiB; raise "
                          "it with --max-input MIB");
        CHECK_THROWS_WITH(LoadScene(HRBENCH_TEST_DATA "/parallel_l64_d1.json", 100),
                          Catch::Contains("bytes, more than the input limit"));
        CHECK(LoadScene(HRBENCH_TEST_DATA "/parallel_l64_d1.json").NumPatches() == 2);
    }
}

TEST_CASE("3D scenes survive a round trip through their JSON file", "[3d][scene_io]") {
    Scene scene = MakeScene("cornell", {});
    Scene back = SceneFromJson(SceneToJson(scene), "mem");
    CHECK(back.Dimension() == 3);
    const Patches<Polygon> &s = scene.Get<Polygon>(), &b = back.Get<Polygon>();
    REQUIRE(b.size() == s.size());
    for (size_t k = 0; k < s.size(); ++k) {
        CHECK(b[k].shape.n == s[k].shape.n);
        for (int v = 0; v < s[k].shape.n; ++v)
            CHECK(b[k].shape.v[v] == s[k].shape.v[v]);
        CHECK(b[k].material.reflectance == s[k].material.reflectance);
        CHECK(b[k].material.emission == s[k].material.emission);
        CHECK(b[k].material.colour == s[k].material.colour);  // the light has none
    }
    CHECK(b[0].material.colour == Rgb{0.725, 0.71, 0.68});
    CHECK_FALSE(b[6].material.colour);
}

TEST_CASE("A patch's display colour is an optional [r, g, b] in [0, 1]", "[scene_io]") {
    auto load = [](const std::string &colour) {
        return SceneFromJson(R"({"format":"hrbench-scene","schema_version":1,"patches":[)"
                             R"({"a":[0,0],"b":[1,0],"reflectance":0.4)" +
                                 colour + "}]}",
                             "f.json")
            .Get<Segment>()[0]
            .material;
    };
    CHECK(load(R"(,"colour":[0.25,1,0])").colour == Rgb{0.25, 1, 0});
    CHECK_FALSE(load("").colour);
    CHECK(load("").DisplayColour() == Rgb{0.4, 0.4, 0.4});  // grey of the reflectance
    auto error = [&](const std::string &colour) {
        try {
            load(colour);
        } catch (const InputError &e) {
            return std::string(e.what());
        }
        return std::string("no error");
    };
    CHECK(error(R"(,"colour":[0.5,-0.1,0])") ==
          "f.json: patch 0 has a colour component outside [0, 1]");
    CHECK(error(R"(,"colour":[0.5,1.5,0])") ==
          "f.json: patch 0 has a colour component outside [0, 1]");
    CHECK(error(R"(,"colour":[0.5,0.5])") ==
          "f.json: patches[0].colour must be an array of 3 numbers [r, g, b]");
    CHECK(error(R"(,"colour":[0.5,0.5,0.5,1])") ==
          "f.json: patches[0].colour must be an array of 3 numbers [r, g, b]");
    CHECK(error(R"(,"colour":"red")") ==
          "f.json: patches[0].colour must be an array of 3 numbers [r, g, b]");
    CHECK(error(R"(,"colour":[0.5,null,0])") == "f.json: patches[0].colour[1] must be a number");
    CHECK_THAT(error(R"(,"colour":[0.5,1e999,0])"), Catch::Contains("number overflow"));
    CHECK_THAT(error(R"(,"colour":[NaN,0,0])"), Catch::Contains("malformed JSON"));
    // A colour survives a round trip; a patch without one stays without.
    Scene scene = MakeScene("parallel", {});
    scene.Get<Segment>()[1].material.colour = Rgb{0.1, 0.2, 0.3};
    Scene back = SceneFromJson(SceneToJson(scene), "mem");
    CHECK(back.Get<Segment>()[1].material.colour == Rgb{0.1, 0.2, 0.3});
    CHECK_FALSE(back.Get<Segment>()[0].material.colour);
}

TEST_CASE("Bad 3D scene files are rejected with one line naming the problem", "[3d][scene_io]") {
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

TEST_CASE("SHA-256 gives the FIPS 180-4 digests at every padding boundary", "[scene_io][digest]") {
    CHECK(Sha256Hex("") == "e3b0c44298fc1c149afbf4c8996fb92427ae41e4649b934ca495991b7852b855");
    CHECK(Sha256Hex("abc") == "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad");
    // Lengths around the 56- and 64-byte boundaries, where the length field moves on.
    const std::pair<size_t, const char *> cases[] = {
        {55, "9f4390f8d30c2dd92ec9f095b65e2b9ae9b0a925a5258e241c9f1e910f734318"},
        {56, "b35439a4ac6f0948b6d6f9e3c6af0f5f590ce20f1bde7090ef7970686ec6738a"},
        {63, "7d3e74a05d7db15bce4ad9ec0658ea98e3f06eeecf16b4c6fff2da457ddc2f34"},
        {64, "ffe054fe7ae0cb6dc65c3af9b61d5209f439851db43d0ba5997337df154668eb"},
        {65, "635361c48bb9eab14198e76ea8ab7f1a41685d6ad62aa9146d301d4f17eb0ae0"},
        {200, "c2a908d98f5df987ade41b5fce213067efbcc21ef2240212a41e54b5e7c28ae5"}};
    for (const auto &[n, digest] : cases) {
        INFO(n);
        CHECK(Sha256Hex(std::string(n, 'a')) == digest);
        // Piece by piece, split anywhere, the same digest.
        for (size_t cut : {size_t(0), size_t(1), n / 2, n}) {
            Sha256 sha;
            sha.Update(std::string(cut, 'a'));
            sha.Update(std::string(n - cut, 'a'));
            CHECK(sha.Hex() == digest);
        }
    }
}

TEST_CASE("The digest of a scene larger than a piece is that of its whole text",
          "[scene_io][digest]") {
    // 8 * 40^2 triangles: about 2.3 MB of text, digested in pieces of 1 MiB.
    Scene sphere = MakeScene("sphere", {{"n", 40}});
    REQUIRE(SceneGeometryText(sphere).size() > (size_t(2) << 20));
    CHECK(SceneSha256(sphere) == Sha256Hex(SceneGeometryText(sphere)));
}

TEST_CASE("The scene digest hashes the corners in order, and only them", "[scene_io][digest]") {
    Scene plates = MakeScene("parallel3d", {});
    CHECK(SceneGeometryText(plates) == "0 0 0 1 0 0 1 1 0 0 1 0\n0 1 1 1 1 1 1 0 1 0 0 1\n");
    CHECK(SceneSha256(plates) ==
          "08f184efc2701867f8585bb1ccb33c2ce1dadb3a79a7f8973ab01e357f36a6e4");
    Scene segments = MakeScene("parallel", {{"l", 0.1}, {"d", 1}});
    CHECK(SceneGeometryText(segments) == "0 0 0.10000000000000001 0\n0.10000000000000001 1 0 1\n");
    // Materials do not count; a corner moved by one ulp, the order of corners, and -0 do.
    Scene other = plates;
    other.Get<Polygon>()[0].material = {0.25, 3.0};
    CHECK(SceneSha256(other) == SceneSha256(plates));
    other.Get<Polygon>()[0].shape.v[2].x() = std::nextafter(1.0, 2.0);
    CHECK(SceneSha256(other) != SceneSha256(plates));
    other = plates;
    Polygon &p = other.Get<Polygon>()[0].shape;
    p = Polygon::Quad(p.v[1], p.v[2], p.v[3], p.v[0]);
    CHECK(SceneSha256(other) != SceneSha256(plates));
    other = plates;
    other.Get<Polygon>()[0].shape.v[0].x() = -0.0;
    CHECK(SceneSha256(other) == SceneSha256(plates));
}
