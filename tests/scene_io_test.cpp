// Scene files: round trip and every kind of malformed input.
#include <catch2/catch.hpp>

#include "generators.h"
#include "hrbench.h"

using namespace hrbench;

TEST_CASE("Scenes survive a round trip through their JSON file", "[scene_io]") {
    Scene scene = MakeScene("random", {{"n", 8}, {"seed", 2}});
    scene.segments[3].material = {0.25, 2.0};
    Scene back = SceneFromJson(SceneToJson(scene), "mem");
    REQUIRE(back.segments.size() == scene.segments.size());
    for (size_t k = 0; k < scene.segments.size(); ++k) {
        CHECK(back.segments[k].a == scene.segments[k].a);  // exact: shortest round-trip digits
        CHECK(back.segments[k].b == scene.segments[k].b);
        CHECK(back.segments[k].material.reflectance == scene.segments[k].material.reflectance);
        CHECK(back.segments[k].material.emission == scene.segments[k].material.emission);
    }
    CHECK(back.params == scene.params);
    CHECK(back.family == "file");
}

TEST_CASE("The checked-in example scene loads and gives the worked example", "[scene_io]") {
    Scene scene = LoadScene(std::string(HRBENCH_TEST_DATA) + "/parallel_l64_d1.json");
    RefineOptions o;
    o.eps = 0.25;
    Refinement r = Refine(scene, o);
    CHECK(r.counters.links == 5092);
    CHECK(r.counters.nodes == 1022);
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
