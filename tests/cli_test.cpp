// End-to-end tests of the hrbench command: its JSON, its files and its exit codes.
#include <catch2/catch.hpp>

#include "cli_helpers.h"

#include <nlohmann/json.hpp>

using nlohmann::json;

using namespace hrbench_test;

TEST_CASE("run --json reports every field the analysis reads", "[cli]") {
    CliResult r = Cli("run parallel l=64 d=1 --eps 0.25 --json");
    REQUIRE(r.exitCode == 0);
    json j = json::parse(r.out);
    CHECK(j["schema_version"] == 1);
    CHECK(j["version"].is_string());
    CHECK(j["context"]["build_type"].is_string());
    CHECK(j["scene"] == "parallel");
    CHECK(j["params"] == json({{"l", 64.0}, {"d", 1.0}, {"offset", 0.0}, {"l2", 64.0}}));
    CHECK(j["eps"] == 0.25);
    CHECK(j["oracle"] == "garmann");
    CHECK(j["mode"] == "store");
    CHECK(j["min_area"].is_null());
    CHECK(j["max_depth_limit"].is_null());
    CHECK(j["nodes"] == 1022);
    CHECK(j["leaves"] == 512);
    CHECK(j["links"] == 5092);
    CHECK(j["oracle_calls"] == 10183);
    CHECK(j["max_depth"] == 8);
    CHECK(j["forced_links"] == 0);
    CHECK(j["culled_pairs"] == 0);
    CHECK(j["root_pairs"] == 1);
    CHECK(j["nodes_per_depth"].size() == 9);
    CHECK(j["links_per_depth"].back() == 3536);
    CHECK(j["seconds"].get<double>() >= 0);
}

TEST_CASE("run options reach the engine", "[cli]") {
    json j = json::parse(
        Cli("run room --eps 0.1 --oracle hanrahan --min-area 0.01 --max-depth 6 --count-only --json").out);
    CHECK(j["oracle"] == "hanrahan");
    CHECK(j["mode"] == "count-only");
    CHECK(j["min_area"] == 0.01);
    CHECK(j["max_depth_limit"] == 6);
    CHECK(j["forced_links"].get<int>() > 0);
    CHECK(j["oracle_calls"] == 2 * j["links"].get<int>() - 6);  // 6 root pairs, none culled
}

TEST_CASE("The human table, the scene list and the help print", "[cli]") {
    CliResult table = Cli("run parallel --eps 0.25");
    CHECK(table.exitCode == 0);
    CHECK_THAT(table.out, Catch::Contains("oracle_calls") && Catch::Contains("10183"));
    CliResult scenes = Cli("scenes");
    CHECK(scenes.exitCode == 0);
    for (const char *family : {"parallel", "perpendicular", "angled", "enclosure", "room", "array", "random"})
        CHECK_THAT(scenes.out, Catch::Contains(std::string(family) + ":"));
    CHECK(Cli("--help").exitCode == 0);
    CHECK_THAT(Cli("run --help").out, Catch::Contains("--min-area"));
    CHECK_THAT(Cli("--version").out, Catch::StartsWith("hrbench "));
}

TEST_CASE("links writes one CSV row per link that tiles the parameter square", "[cli]") {
    std::string csvPath = Scratch("links.csv");
    REQUIRE(Cli("links parallel l=8 d=1 --eps 0.5 --out " + csvPath).exitCode == 0);
    json j = json::parse(Cli("run parallel l=8 d=1 --eps 0.5 --json").out);
    std::ifstream csv(csvPath);
    std::string header, line;
    std::getline(csv, header);
    CHECK(header == "root_i,elem_i,t0_i,t1_i,depth_i,root_j,elem_j,t0_j,t1_j,depth_j");
    int rows = 0;
    double area = 0;
    while (std::getline(csv, line)) {
        double v[10];
        char comma;
        std::istringstream fields(line);
        for (int k = 0; k < 10; ++k)
            fields >> v[k] >> comma;
        CHECK(v[0] == 0);
        CHECK(v[5] == 1);
        area += (v[3] - v[2]) * (v[8] - v[7]);
        ++rows;
    }
    CHECK(rows == j["links"].get<int>());
    CHECK_THAT(area, Catch::Matchers::WithinRel(64.0, 1e-12));
}

TEST_CASE("Saved scenes run the same as the family they came from", "[cli]") {
    std::string scenePath = Scratch("scene.json");
    REQUIRE(Cli("save parallel l=16 d=2 offset=1 --out " + scenePath).exitCode == 0);
    json a = json::parse(Cli("run --scene-file " + scenePath + " --eps 0.2 --json").out);
    json b = json::parse(Cli("run parallel l=16 d=2 offset=1 --eps 0.2 --json").out);
    CHECK(a["scene"] == "file");
    CHECK(a["scene_file"] == scenePath);
    for (const char *key : {"nodes", "leaves", "links", "oracle_calls"})
        CHECK(a[key] == b[key]);
}

TEST_CASE("Bad input gives one line on stderr and exit code 2", "[cli][errors]") {
    CheckError("", 2, "no command");
    CheckError("frobnicate parallel --eps 1", 2, "unknown command");
    CheckError("run bogus --eps 1", 2, "unknown scene 'bogus'");
    CheckError("run parallel q=1 --eps 1", 2, "no parameter 'q'");
    CheckError("run parallel d=-1 --eps 1", 2, "out of range");
    CheckError("run parallel l=abc --eps 1", 2, "not a number");
    CheckError("run parallel", 2, "needs --eps");
    CheckError("run parallel --eps", 2, "--eps needs a value");
    CheckError("run parallel --eps 0", 2, "--eps must be");
    CheckError("run parallel --eps -1", 2, "--eps must be");
    CheckError("run parallel --eps nan", 2, "not a finite number");
    CheckError("run parallel --eps inf", 2, "not a finite number");
    CheckError("run parallel --eps 1 --oracle magic", 2, "unknown oracle");
    CheckError("run parallel --eps 1 --max-depth 99", 2, "--max-depth");
    CheckError("run parallel --eps 1 --bogus", 2, "unknown option '--bogus'");
    CheckError("run perpendicular gap=0 --eps 0.5", 2, "touch");
    CheckError("run enclosure --eps 0.5", 2, "touch");
    CheckError("run --scene-file /nonexistent.json --eps 1", 2, "cannot read");
    CheckError("run --scene-file " HRBENCH_TEST_DATA "/truncated.json --eps 1", 2, "malformed JSON");
    CheckError("run --scene-file " HRBENCH_TEST_DATA "/degenerate.json --eps 1", 2, "degenerate");
    CheckError("run parallel --scene-file x.json --eps 1", 2, "either");
    CheckError("links parallel --eps 1", 2, "needs --out");
}

TEST_CASE("Limits reached during refinement give exit code 3", "[cli][errors]") {
    CheckError("run parallel l=1024 --eps 0.01 --max-memory 1", 3, "memory budget");
    CheckError("run perpendicular gap=0 --eps 0.5 --min-area 1e-300", 3, "safety depth");
}
