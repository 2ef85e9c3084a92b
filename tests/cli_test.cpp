// End-to-end tests of the hrbench command, 2D and 3D: its JSON, its files, the
// capability listing and the exit code of every kind of bad input.
#include <catch2/catch.hpp>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>

#include "cli_helpers.h"
#include "generators.h"
#include "hrbench/hrbench.h"
#include "util/format.h"

#include <nlohmann/json.hpp>

using nlohmann::json;

using namespace hrbench_test;

namespace {

const std::string kData = HRBENCH_TEST_DATA;

// The keys of a run record that describe the run rather than count it (record.h).
const std::set<std::string> kRunContextKeys = {
    "schema_version",  "version",      "context",     "scene",         "params",
    "scene_file",      "mesh_file",    "patches",     "dimension",     "eps",
    "oracle",          "ff_estimate",  "method",      "mode",          "min_area",
    "max_depth_limit", "threads",      "subdivision", "visibility",    "rays_per_side",
    "seconds",         "scene_sha256", "clusters",    "cluster_bound", "cpu_seconds",
    "linking_seconds", "linking_bytes"};

}  // namespace

// ---------------------------------------------------------------------------------------
// run, links and save

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
    json j = json::parse(Cli("run room --eps 0.1 --oracle hanrahan --min-area 0.01 --max-depth 6 "
                             "--count-only --json")
                             .out);
    CHECK(j["oracle"] == "hanrahan");
    CHECK(j["mode"] == "count-only");
    CHECK(j["min_area"] == 0.01);
    CHECK(j["max_depth_limit"] == 6);
    CHECK(j["forced_links"].get<int>() > 0);
    CHECK(j["oracle_calls"] == 2 * j["links"].get<int>() - 6);  // 6 root pairs, none culled
}

TEST_CASE("The human table, the scene list with the oracles, and the help print", "[cli]") {
    CliResult table = Cli("run parallel --eps 0.25");
    CHECK(table.exitCode == 0);
    CHECK_THAT(table.out, Catch::Contains("oracle_calls") && Catch::Contains("10183"));
    CliResult scenes = Cli("scenes");
    CHECK(scenes.exitCode == 0);
    for (const char *family :
         {"parallel", "perpendicular", "angled", "enclosure", "room", "array", "random"})
        CHECK_THAT(scenes.out, Catch::Contains(std::string(family) + ":"));
    // An optional parameter without a default (random's density) says so, not "nan".
    CHECK_THAT(scenes.out, Catch::Contains("density  default none "));
    CHECK_THAT(scenes.out, !Catch::Contains("default nan"));
    CHECK_THAT(scenes.out, Catch::Contains("oracles (--oracle):"));
    for (const hrbench::OracleInfo &info : hrbench::OracleInfos())
        CHECK_THAT(scenes.out, Catch::Contains(std::string("  ") + info.name + " "));
    CHECK(Cli("--help").exitCode == 0);
    CHECK_THAT(Cli("run --help").out, Catch::Contains("--min-area"));
    CHECK_THAT(Cli("--version").out, Catch::StartsWith("hrbench "));
}

TEST_CASE("The help states the exit code that each outcome gives", "[cli][errors]") {
    std::string help = Cli("--help").out;
    std::replace(help.begin(), help.end(), '\n', ' ');
    CHECK_THAT(help, Catch::Contains(
                         "Exit codes (docs/limits.md): 0 success, warnings and hints on stderr "
                         "included; 1 internal error (a bug); 2 usage or input error; 3 a limit "
                         "was reached (memory budget or out of memory, safety depth, an element "
                         "too small for double precision, a counter beyond 2^64, solve not "
                         "converging or diverging); 4 check-links found a violation in the link "
                         "dump."));
    CHECK(Cli("run parallel --eps 0.5 --min-area 2").exitCode == 0);  // with a warning
    CHECK(Cli("run parallel --eps 0").exitCode == 2);
    CHECK(Cli("run parallel l=1024 --eps 0.01 --max-memory 1").exitCode == 3);
    CHECK(Cli("solve room lamp=1 --eps 0.1 --min-area 0.01 --max-iterations 2").exitCode == 3);
    // check-links: a dump with one link dropped leaves a pair uncovered.
    std::string dump = Scratch("exit.dump");
    REQUIRE(Cli("links parallel --eps 0.5 --format probe --out " + dump).exitCode == 0);
    std::string text = ReadFile(dump);
    size_t second = text.find('\n') + 1;  // the first link, after the format line
    text.erase(second, text.find('\n', second) + 1 - second);
    std::ofstream(dump, std::ios::binary) << text;
    CliResult violation = Cli("check-links parallel --eps 0.5 --links " + dump);
    CHECK(violation.exitCode == 4);
    CHECK_THAT(violation.err, Catch::StartsWith("hrbench: error: " + dump));
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

TEST_CASE("Clusters on the command line: their counters, their links and the options they refuse",
          "[cli][clusters]") {
    json plain = json::parse(Cli("run random n=30 seed=1 size=40 --eps 0.2 --json").out);
    CHECK(plain["clusters"] == false);
    for (const char *key : {"cluster_nodes", "cluster_links", "element_links",
                            "cluster_oracle_calls", "opened_clusters"})
        CHECK(plain[key] == 0);
    CliResult r = Cli("run random n=30 seed=1 size=40 --eps 0.2 --clusters --json");
    REQUIRE(r.exitCode == 0);
    json j = json::parse(r.out);
    CHECK(j["clusters"] == true);
    CHECK(j["cluster_nodes"] == 29);
    CHECK(j["cluster_links"].get<uint64_t>() > 0);
    CHECK(j["links"] == j["element_links"].get<uint64_t>() + j["cluster_links"].get<uint64_t>());
    CHECK(j["cluster_oracle_calls"].get<uint64_t>() + 29 ==
          2 * j["cluster_links"].get<uint64_t>() + j["root_pairs"].get<uint64_t>());

    // The links file: the element rows, then one row per cluster link, a cluster as C<k>.
    std::string csv = Scratch("clusters.csv");
    REQUIRE(Cli("links random n=30 seed=1 size=40 --eps 0.2 --clusters --out " + csv).exitCode ==
            0);
    std::istringstream rows(ReadFile(csv));
    std::string line;
    uint64_t count = 0, clusterRows = 0;
    std::getline(rows, line);
    while (std::getline(rows, line)) {
        ++count;
        clusterRows += line[0] == 'C' || line.find(",C") != std::string::npos;
        CHECK(std::count(line.begin(), line.end(), ',') == 9);
    }
    CHECK(count == j["links"].get<uint64_t>());
    CHECK(clusterRows == j["cluster_links"].get<uint64_t>());

    for (const char *refused :
         {"run parallel --eps 0.5 --clusters --count-only --method translation",
          "run parallel --clusters --count-only --sweep eps=0.1,0.2"}) {
        CliResult bad = Cli(refused);
        INFO(refused);
        CHECK(bad.exitCode == 2);
        CHECK(bad.err.find("--clusters") != std::string::npos);
        CHECK(std::count(bad.err.begin(), bad.err.end(), '\n') == 1);
    }
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

TEST_CASE("The 2D worked example is unchanged and visibility counts stay zero", "[cli]") {
    json j = json::parse(Cli("run parallel l=64 d=1 --eps 0.25 --json").out);
    CHECK(j["nodes"] == 1022);
    CHECK(j["leaves"] == 512);
    CHECK(j["links"] == 5092);
    CHECK(j["oracle_calls"] == 10183);
    CHECK(j["dimension"] == 2);
    CHECK(j["rays"] == 0);
}

// ---------------------------------------------------------------------------------------
// 3D scenes, meshes and visibility

TEST_CASE("run --json reports the 3D and visibility fields", "[cli][3d]") {
    CliResult r = Cli("run parallel3d l=1 w=1 d=1 --eps 0.5 --json");
    REQUIRE(r.exitCode == 0);
    json j = json::parse(r.out);
    CHECK(j["dimension"] == 3);
    CHECK(j["subdivision"] == "binary");
    CHECK(j["visibility"] == "none");
    CHECK(j["rays_per_side"].is_null());
    CHECK(j["nodes"] == 6);
    CHECK(j["links"] == 4);
    CHECK(j["oracle_calls"] == 7);
    CHECK(j["rays"] == 0);
    CHECK(j["visibility_queries"] == 0);
    CHECK(j["occluded_pairs"] == 0);
    json q =
        json::parse(Cli("run occluded3d --eps 0.1 --subdivision quadtree --visibility fraction "
                        "--rays-per-side 2 --json")
                        .out);
    CHECK(q["subdivision"] == "quadtree");
    CHECK(q["visibility"] == "fraction");
    CHECK(q["rays_per_side"] == 2);
    CHECK(q["rays"] == 16 * q["visibility_queries"].get<int>());
    CHECK(q["occluded_pairs"].get<int>() > 0);
}

TEST_CASE("A mesh runs like the family it copies, and is named in the record", "[cli][mesh]") {
    json a = json::parse(Cli("run --mesh " + kData + "/two_plates.obj --eps 0.05 --json").out);
    json b = json::parse(Cli("run parallel3d --eps 0.05 --json").out);
    CHECK(a["scene"] == "mesh");
    CHECK(a["mesh_file"] == kData + "/two_plates.obj");
    for (const char *key : {"nodes", "leaves", "links", "oracle_calls"})
        CHECK(a[key] == b[key]);
}

TEST_CASE("The published Cornell boxes run with --triangulate, and fail without it",
          "[cli][mesh]") {
    const std::string original = kData + "/meshes/CornellBox-Original.obj",
                      measured = kData + "/meshes/cornell_box.obj";
    CheckError("run --mesh " + original + " --eps 0.5", 2,
               "line 62: face 5 is not planar: its corners lie 0.005 off their mean plane, "
               "0.00176 of the face's diameter 2.84 (tolerance 1e-06 of the diameter); "
               "--triangulate splits it into triangles");
    CheckError("links --mesh " + measured + " --eps 0.5 --out " + Scratch("cornell.csv"), 2,
               "line 77: face 8 is not planar: its corners lie 0.8 off their mean plane, 0.00102 "
               "of the face's diameter 784 (tolerance 1e-06 of the diameter); --triangulate");

    // Counts pinned from this engine; the same with 3 threads, and 2 L - (refined pairs)
    // oracle calls. The walls touch, so a recursion limit is needed.
    for (const char *threads : {"1", "3"}) {
        INFO("threads " << threads);
        CliResult r = Cli("run --mesh " + original +
                          " --triangulate --eps 0.5 --min-area 0.01 "
                          "--count-only --json --threads " +
                          threads);
        REQUIRE(r.exitCode == 0);
        CHECK(r.err.empty());
        json j = json::parse(r.out);
        CHECK(j["patches"] == 19);
        CHECK(j["params"] == json({{"triangulate", 1.0}}));
        CHECK(j["mesh_file"] == original);
        CHECK(j["root_pairs"] == 171);
        CHECK(j["culled_pairs"] == 78);
        CHECK(j["nodes"] == 2769);
        CHECK(j["leaves"] == 1394);
        CHECK(j["links"] == 6834);
        CHECK(j["oracle_calls"] == 13575);
        CHECK(j["forced_links"] == 1214);
        CHECK(j["oracle_calls"] == 2 * j["links"].get<int>() - (171 - 78));
    }
    json m = json::parse(Cli("run --mesh " + measured +
                             " --triangulate --scale 0.001 --eps 0.5 "
                             "--min-area 0.01 --count-only --json")
                             .out);
    CHECK(m["params"] == json({{"scale", 0.001}, {"triangulate", 1.0}}));
    CHECK(m["patches"] == 19);
    CHECK(m["culled_pairs"] == 90);
    CHECK(m["links"] == 1549);
    CHECK(m["oracle_calls"] == 3017);
    CHECK(m["nodes"] == 381);

    std::string saved = Scratch("cornell_triangulated.json");
    REQUIRE(Cli("save --mesh " + original + " --triangulate --out " + saved).exitCode == 0);
    CHECK(json::parse(Cli("run --scene-file " + saved +
                          " --eps 0.5 --min-area 0.01 --count-only "
                          "--json")
                          .out)["links"] == 6834);
}

TEST_CASE("A --min-area far from the scene's size is warned about, on one line", "[cli][mesh]") {
    // The measured Cornell box is in millimetres: its ceiling, 556 x 559.2 = 3.11e5 mm^2,
    // is 3e8 times --min-area 1e-3, which was meant in square metres.
    CliResult mm = Cli("run --mesh " + kData +
                       "/meshes/cornell_box.obj --triangulate --eps 0.5 "
                       "--min-area 1e-3 --max-depth 2 --count-only --json");
    CHECK(mm.exitCode == 0);
    // Its material library was not published with it: a warning of its own comes first.
    const std::string noLibrary = "hrbench: warning: mesh file '" + kData +
                                  "/meshes/cornell_box.obj', line 8: material library '" + kData +
                                  "/meshes/cornell_box.mtl' does not exist: the faces of its "
                                  "materials get the default reflectance 0.5 and emission 0\n";
    CHECK(mm.err == noLibrary +
                        "hrbench: warning: --min-area 0.001 is below 1e-08 of the largest patch's "
                        "area, 3.11e+05: elements may be halved 29 times before it applies (are "
                        "the scene and --min-area in the same units? --scale rescales a mesh)\n");
    CHECK(json::parse(mm.out)["patches"] == 19);
    CHECK(Cli("run --mesh " + kData +
              "/meshes/cornell_box.obj --triangulate --scale 0.001 "
              "--eps 0.5 --min-area 1e-3 --max-depth 2 --count-only")
              .err == noLibrary);
    // Larger than every patch, for any scene source.
    CliResult big = Cli("links parallel l=1 --eps 0.5 --min-area 2 --out " + Scratch("big.csv"));
    CHECK(big.exitCode == 0);
    CHECK(big.err == "hrbench: warning: --min-area 2 exceeds the largest patch's length, 1: no "
                     "element will be split (are the scene and --min-area in the same units? "
                     "--scale rescales a mesh)\n");
    CHECK(Cli("run cornell --eps 0.5 --min-area 1e-3").err.empty());
}

TEST_CASE("A missing material library and an undefined material are warned about, on one "
          "line each",
          "[cli][mesh]") {
    // Counting reads the geometry only: it runs, and says what the surfaces fell back to.
    CliResult missing = Cli("run --mesh " + kData + "/missing_library.obj --eps 0.5 --json");
    CHECK(missing.exitCode == 0);
    CHECK(missing.err == "hrbench: warning: mesh file '" + kData +
                             "/missing_library.obj', line 2: material library '" + kData +
                             "/no_such_library.mtl' does not exist: the faces of its materials "
                             "get the default reflectance 0.5 and emission 0\n");
    CHECK(
        json::parse(missing.out)["links"] ==
        json::parse(Cli("run --mesh " + kData + "/two_plates.obj --eps 0.5 --json").out)["links"]);
    // solve then finds nothing emitting: the warning before the error names the cause.
    CliResult dark = Cli("solve --mesh " + kData + "/undefined_material.obj --eps 0.5");
    CHECK(dark.exitCode == 2);
    CHECK(dark.err == "hrbench: warning: mesh file '" + kData +
                          "/undefined_material.obj', line 14: material 'lmap' is not defined by "
                          "the material libraries read so far: its faces get the default "
                          "reflectance 0.5 and emission 0\nhrbench: error: nothing emits: give "
                          "--emission or a scene with an emitter\n");
    CHECK(Cli("save --mesh " + kData + "/missing_library.obj --out " + Scratch("m.json"))
              .err.find("does not exist") != std::string::npos);
    CHECK(Cli("run --mesh " + kData + "/two_plates.obj --eps 0.5").err.empty());
}

TEST_CASE("A mesh whose faces mostly exchange no light draws a hint, on one line", "[cli][mesh]") {
    // Every face reversed: the room's walls, 16 of the 17.5 units of area, now face out.
    CliResult flipped = Cli("run --mesh " + kData +
                            "/room_box_flipped.obj --eps 0.5 "
                            "--min-area 0.05 --json");
    CHECK(flipped.exitCode == 0);
    CHECK(flipped.err == "hrbench: hint: faces holding 100% of the area of one of the mesh's 2 "
                         "connected parts (6 of its 6 faces) have every other face behind them "
                         "and exchange no light; faces are counter-clockwise seen from their "
                         "front (docs/3d.md): a room seen from inside, or a face of a part, may "
                         "be the wrong way round\n");
    // The walls' root pairs are all culled: 15 among them and 36 with the box.
    CHECK(json::parse(flipped.out)["culled_pairs"] == 51);
    CHECK_THAT(Cli("links --mesh " + kData +
                   "/room_box_flipped.obj --eps 0.5 --min-area 0.05 "
                   "--out " +
                   Scratch("flipped.csv"))
                   .err,
               Catch::StartsWith("hrbench: hint: faces holding 100% of the area of one"));
    CHECK(Cli("run --mesh " + kData + "/room_box.obj --eps 0.5 --min-area 0.05").err.empty());
}

TEST_CASE("Option --scale and --triangulate are checked and apply to meshes only", "[cli][mesh]") {
    const std::string mesh = " --mesh " + kData + "/two_plates.obj --eps 0.5";
    CheckError("run" + mesh + " --scale 0", 2, "--scale must be a finite number greater than 0");
    CheckError("run" + mesh + " --scale -2", 2, "--scale must be a finite number greater than 0");
    CheckError("run" + mesh + " --scale inf", 2, "--scale");
    CheckError("run" + mesh + " --scale 1e308", 2,
               "line 12: face 1 is too large for double precision (its size or area overflows)");
    CheckError("run parallel --eps 0.5 --triangulate", 2, "--triangulate applies to --mesh only");
    CheckError("save room --scale 2", 2, "--scale applies to --mesh only");
    json j = json::parse(Cli("run" + mesh + " --scale 2 --json").out);
    CHECK(j["params"] == json({{"scale", 2.0}}));
}

TEST_CASE("3D scenes save, load and write links with areas and centroids", "[cli][3d]") {
    std::string scenePath = Scratch("plates.json"), csvPath = Scratch("links3d.csv");
    REQUIRE(Cli("save parallel3d l=2 --out " + scenePath).exitCode == 0);
    json a = json::parse(Cli("run --scene-file " + scenePath + " --eps 0.1 --json").out);
    json b = json::parse(Cli("run parallel3d l=2 --eps 0.1 --json").out);
    CHECK(a["links"] == b["links"]);
    REQUIRE(Cli("links parallel3d --eps 0.5 --out " + csvPath).exitCode == 0);
    std::ifstream csv(csvPath);
    std::string header, line;
    std::getline(csv, header);
    CHECK(header == "root_i,elem_i,area_i,cx_i,cy_i,cz_i,depth_i,root_j,elem_j,area_j,cx_j,cy_j,"
                    "cz_j,depth_j");
    int rows = 0;
    while (std::getline(csv, line))
        ++rows;
    CHECK(rows == 4);
}

TEST_CASE("save --out F.obj gives the same patches and counts through --mesh", "[cli][3d][obj]") {
    for (std::string scene :
         {std::string("parallel3d l=2 w=1 d=0.5"), std::string("perpendicular3d"),
          std::string("cornell"), "--mesh " + kData + "/two_plates.obj"}) {
        INFO(scene);
        std::string obj = Scratch("saved.obj");
        REQUIRE(Cli("save " + scene + " --out " + obj).exitCode == 0);
        json original = json::parse(Cli("save " + scene).out);
        json back = json::parse(Cli("save --mesh " + obj).out);
        REQUIRE(back["patches"].size() == original["patches"].size());
        for (size_t k = 0; k < original["patches"].size(); ++k) {
            // The same corners in the same order: the same shape and front normal.
            const json &p = original["patches"][k], &q = back["patches"][k];
            CHECK(q["vertices"] == p["vertices"]);
            CHECK(q["reflectance"] == p["reflectance"]);
            CHECK(q["emission"] == p["emission"]);
        }
        std::string refine = " --eps 0.2 --max-depth 5 --json";
        json a = json::parse(Cli("run " + scene + refine).out);
        json b = json::parse(Cli("run --mesh " + obj + refine).out);
        for (const char *key : {"nodes", "leaves", "links", "oracle_calls", "max_depth",
                                "forced_links", "culled_pairs", "scene_sha256"})
            CHECK(a[key] == b[key]);
        CHECK(b["scene"] == "mesh");
    }
}

TEST_CASE("save --out F.obj keeps quads, shares corners and writes the MTL", "[cli][3d][obj]") {
    std::string obj = Scratch("plates.obj");
    REQUIRE(Cli("save parallel3d --out " + obj).exitCode == 0);
    CHECK(ReadFile(obj) == "# hrbench scene 'parallel3d', 2 patches: faces counter-clockwise seen "
                           "from the front\nmtllib plates.mtl\n"
                           "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 1 1\nv 1 1 1\nv 1 0 1\n"
                           "v 0 0 1\nusemtl m0\nf 1 2 3 4\nf 5 6 7 8\n");
    CHECK(ReadFile(Scratch("plates.mtl")) ==
          "# Materials of plates.obj: reflectance = mean(Kd), emission = mean(Ke)\n"
          "newmtl m0\nKd 0.5 0.5 0.5\nKe 0 0 0\n");
    // The Cornell box: the light's emission, the walls' and blocks' colours.
    std::string box = Scratch("box.obj");
    REQUIRE(Cli("save cornell --out " + box).exitCode == 0);
    std::string mtl = ReadFile(Scratch("box.mtl"));
    CHECK(mtl.find("Kd 0.78 0.78 0.78\nKe 11 11 11\n") != std::string::npos);
    CHECK(mtl.find("Kd 0.63 0.065 0.05\nKe 0 0 0\n") != std::string::npos);
    // 2D scenes have no OBJ form; OFF would lose the emission.
    CheckError("save parallel --out " + Scratch("flat.obj"), 2,
               "an OBJ file holds 3D faces, and this scene is 2D (segments); write it as .json");
    CheckError("save parallel3d --out " + Scratch("plates.off"), 2,
               "save writes .json or .obj files, not OFF");
}

TEST_CASE("The Cornell box runs with visibility from the command line", "[cli][3d]") {
    CliResult r = Cli("run cornell --eps 0.05 --oracle hanrahan --min-area 1e-2 --visibility "
                      "fraction --count-only --json");
    REQUIRE(r.exitCode == 0);
    json j = json::parse(r.out);
    CHECK(j["patches"] == 17);
    CHECK(j["links"].get<int>() > 0);
    CHECK(j["occluded_pairs"].get<int>() > 0);
}

TEST_CASE("The form-factor estimate reaches the record, the table, sweeps and check-links",
          "[cli][estimate]") {
    auto record = [](const std::string &args) {
        CliResult r = Cli(args);
        INFO("hrbench " << args << "\n" << r.err);
        REQUIRE(r.exitCode == 0);
        return json::parse(r.out);
    };
    // The default is clamped-cosine, recorded for hanrahan and bf, null for garmann.
    const std::string plates = "run parallel l=64 d=1 --oracle hanrahan --count-only --json";
    json byDefault = record(plates + " --eps 0.1");
    CHECK(byDefault["ff_estimate"] == "clamped-cosine");
    json clamped = record(plates + " --eps 0.1 --ff-estimate clamped-cosine");
    CHECK(clamped["nodes"] == byDefault["nodes"]);
    CHECK(clamped["links"] == byDefault["links"]);
    // centre-cosine stops at N = 4, L = 2 on these plates for every eps above its cliff
    // (docs/hanrahan-oracle.md); the others refine on.
    json centre = record(plates + " --eps 0.1 --ff-estimate centre-cosine");
    CHECK(centre["ff_estimate"] == "centre-cosine");
    CHECK(centre["nodes"] == 4);
    CHECK(centre["links"] == 2);
    CHECK(clamped["nodes"].get<int>() > 4);
    CHECK(record(plates + " --eps 0.1 --ff-estimate solid-angle")["ff_estimate"] == "solid-angle");
    CHECK(record("run parallel --eps 0.25 --json")["ff_estimate"].is_null());
    CHECK(record("run cornell --oracle bf --eps 0.05 --min-area 0.01 --ff-estimate solid-angle "
                 "--json")["ff_estimate"] == "solid-angle");
    CHECK(record("solve room lamp=1 --eps 0.1 --min-area 0.01 --oracle hanrahan --ff-estimate "
                 "centre-cosine --json")["ff_estimate"] == "centre-cosine");
    CHECK_THAT(Cli("run parallel --eps 0.1 --oracle hanrahan --ff-estimate solid-angle").out,
               Catch::Contains("oracle    hanrahan (solid-angle)  eps 0.1"));
    CHECK_THAT(Cli("run parallel --eps 0.25").out, Catch::Contains("oracle    garmann  eps 0.25"));
    CHECK_THAT(Cli("solve room lamp=1 --eps 0.1 --min-area 0.01 --oracle hanrahan").out,
               Catch::Contains("oracle    hanrahan (clamped-cosine)  eps 0.1"));

    SECTION("a sweep counts each value as its own run does") {
        const std::string scene = "run parallel l=16 d=1 --oracle hanrahan --ff-estimate "
                                  "solid-angle --count-only --json";
        CliResult sweep = Cli(scene + " --sweep eps=0.1,0.02");
        REQUIRE(sweep.exitCode == 0);
        std::istringstream lines(sweep.out);
        std::string line;
        for (const char *eps : {"0.1", "0.02"}) {
            REQUIRE(std::getline(lines, line));
            json swept = json::parse(line), alone = record(scene + " --eps " + eps);
            INFO("eps " << eps);
            CHECK(swept["ff_estimate"] == "solid-angle");
            for (const char *counter : {"nodes", "links", "oracle_calls", "links_per_depth"})
                CHECK(swept[counter] == alone[counter]);
        }
    }
    SECTION("check-links rebuilds the oracle with the estimate it is given") {
        // On parallel l=8 d=1 at eps 0.05 the estimates link differently (4428 links with
        // solid-angle, 2164 with clamped-cosine), so the dump of one fails the other.
        std::string dump = Scratch("estimate.dump");
        const std::string scene = "parallel l=8 d=1 --oracle hanrahan --eps 0.05";
        REQUIRE(Cli("links " + scene + " --ff-estimate solid-angle --format probe --out " + dump)
                    .exitCode == 0);
        CHECK(Cli("check-links " + scene + " --ff-estimate solid-angle --links " + dump).exitCode ==
              0);
        CliResult other = Cli("check-links " + scene + " --links " + dump);
        CHECK(other.exitCode == 4);
        CHECK_THAT(other.err, Catch::StartsWith("hrbench: error: " + dump));
    }
}

// ---------------------------------------------------------------------------------------
// capabilities

TEST_CASE("capabilities --json lists the engine's families, methods and options",
          "[cli][capabilities]") {
    CliResult r = Cli("capabilities --json");
    REQUIRE(r.exitCode == 0);
    CHECK(r.err.empty());
    json caps = json::parse(r.out);
    CHECK(caps["schema_version"] == 1);
    CHECK(caps["engine"] == "hrbench");
    CHECK(caps["version"] == hrbench::EngineVersion());
    CHECK(caps["run_schema_version"] == hrbench::kRunSchemaVersion);
    CHECK(caps["context"]["git_commit"].is_string());
    std::vector<std::string> families, expected;
    for (const json &f : caps["families"])
        families.push_back(f["name"]);
    for (const hrbench::Family &f : hrbench::Families())
        expected.push_back(f.name);
    CHECK(families == expected);
    std::vector<std::string> methods;
    for (const json &m : caps["methods"])
        methods.push_back(m["name"]);
    CHECK(methods == std::vector<std::string>{"enumerate", "translation"});
    std::string help = Cli("--help").out;
    for (const json &o : caps["options"]) {
        INFO(o["flag"]);
        CHECK_THAT(help, Catch::Contains(o["flag"].get<std::string>()));
        CHECK(o["commands"].size() > 0);
    }
}

TEST_CASE("capabilities --json lists the options that exclude each other, and run refuses each "
          "pair in either order",
          "[cli][capabilities]") {
    json caps = json::parse(Cli("capabilities --json").out);
    std::set<std::pair<std::string, std::string>> pairs;
    for (const json &o : caps["options"]) {
        REQUIRE(o["excludes"].is_array());
        for (const json &x : o["excludes"])
            pairs.insert({o["name"].get<std::string>(), x.get<std::string>()});
    }
    // What the analysis's planner reads to keep these options out of a shared --sweep run.
    CHECK(pairs == std::set<std::pair<std::string, std::string>>{{"all", "json"},
                                                                 {"clusters", "sweep"},
                                                                 {"link_form_factors", "sweep"},
                                                                 {"sweep", "method"},
                                                                 {"sweep", "threads"}});
    std::map<std::string, std::string> words = {{"clusters", "--clusters"},
                                                {"link_form_factors", "--link-form-factors"},
                                                {"sweep", "--sweep eps=0.5,0.2"},
                                                {"method", "--method enumerate"},
                                                {"threads", "--threads 1"},
                                                {"all", "--all"},
                                                {"json", "--json"}};
    for (const auto &[a, b] : pairs)
        for (const std::string &order : {words[a] + " " + words[b], words[b] + " " + words[a]}) {
            CliResult r = Cli((a == "all" ? "check-links parallel l=1 d=1 --eps 0.5 --links x.dump "
                                          : "run parallel l=1 d=1 --count-only ") +
                              order);
            INFO(order);
            CHECK(r.exitCode == 2);
            CHECK_THAT(r.err, Catch::Contains("which") && Catch::Contains("drop one of them"));
            CHECK(std::count(r.err.begin(), r.err.end(), '\n') == 1);
        }
    CHECK(Cli("run parallel l=1 d=1 --count-only --sweep eps=0.5,0.2").exitCode == 0);
}

TEST_CASE("capabilities --json lists exactly the registry's oracles, and each of them runs",
          "[cli][capabilities]") {
    CliResult r = Cli("capabilities --json");
    REQUIRE(r.exitCode == 0);
    json caps = json::parse(r.out);
    std::vector<std::string> listed, registry;
    for (const json &o : caps["oracles"])
        listed.push_back(o["name"]);
    for (const hrbench::OracleInfo &info : hrbench::OracleInfos())
        registry.push_back(info.name);
    CHECK(listed == registry);
    REQUIRE(!listed.empty());
    // Scenes with an emitter, which bf needs: the parallel plates with P emitting, and
    // the Cornell box.
    hrbench::Scene lit = hrbench::MakeScene("parallel", {});
    lit.Get<hrbench::Segment>()[0].material.emission = 1;
    std::string litPath = Scratch("lit_parallel.json");
    hrbench::SaveScene(lit, litPath);
    for (const json &o : caps["oracles"]) {
        std::string name = o["name"];
        INFO("oracle " << name);
        CHECK(o["dimensions"] == json({2, 3}));
        for (const std::string &scene :
             {"--scene-file " + litPath, std::string("cornell --min-area 0.01")}) {
            INFO(scene);
            CliResult run = Cli("run " + scene + " --eps 0.3 --oracle " + name + " --json");
            CHECK(run.exitCode == 0);
            CHECK(run.err.empty());
            json record = json::parse(run.out);
            CHECK(record["oracle"] == name);
            CHECK(record["links"].get<int>() > 0);
        }
    }
    // A name it does not list is refused, with the names it does.
    std::string unlisted = "magic";
    REQUIRE(std::find(listed.begin(), listed.end(), unlisted) == listed.end());
    CheckError("run parallel --eps 0.3 --oracle " + unlisted + " --json", 2,
               "unknown oracle 'magic' (choose one of: garmann, hanrahan, bf)");
}

TEST_CASE("capabilities --json lists the form-factor estimates and the oracles that read them",
          "[cli][capabilities][estimate]") {
    json caps = json::parse(Cli("capabilities --json").out);
    std::vector<std::string> names;
    int defaults = 0;
    for (const json &e : caps["ff_estimates"]) {
        names.push_back(e["name"]);
        INFO(e["name"]);
        const hrbench::FfEstimateInfo &info =
            hrbench::FfEstimateInfoOf(hrbench::ParseFfEstimate(e["name"]));
        CHECK(e["formula_2d"] == info.formula2d);
        CHECK(e["formula_3d"] == info.formula3d);
        CHECK(e["source"] == info.source);
        CHECK(e["oracles"] == json({"hanrahan", "bf"}));
        CHECK(e["default"] == (info.estimate == hrbench::kDefaultFfEstimate));
        defaults += e["default"].get<bool>();
    }
    CHECK(names == std::vector<std::string>{"clamped-cosine", "centre-cosine", "solid-angle"});
    CHECK(defaults == 1);
    CHECK(caps["ff_estimates"][0]["default"] == true);
    CHECK(caps["ff_estimates"][0]["formula_3d"] ==
          "f max(|cos_i|, 2f) max(|cos_j|, 2f), f = A_j / (pi r^2 + A_j)");
    for (const json &o : caps["oracles"])
        CHECK(o["parameters"] ==
              (o["name"] == "garmann" ? json({"eps"}) : json({"eps", "ff_estimate"})));
    for (const json &o : caps["options"])
        if (o["name"] == "ff_estimate") {
            CHECK(o["flag"] == "--ff-estimate");
            CHECK(o["choices"] == json(names));
            CHECK(o["commands"] == json({"run", "links", "check-links", "solve"}));
        }
    std::string scenes = Cli("scenes").out, help = Cli("--help").out;
    for (const std::string &name : names) {
        CHECK_THAT(scenes, Catch::Contains("  " + name + " "));
        CHECK_THAT(help, Catch::Contains(name));
    }
}

TEST_CASE("capabilities --json lists exactly the counters of a run record, in order",
          "[cli][capabilities]") {
    json caps = json::parse(Cli("capabilities --json").out);
    std::vector<std::string> listed;
    for (const json &c : caps["counters"]) {
        listed.push_back(c["name"]);
        CHECK((c["kind"] == "scalar" || c["kind"] == "histogram"));
    }
    std::vector<std::string> table;
    for (const hrbench::CounterInfo &c : hrbench::CounterTable())
        table.push_back(c.name);
    CHECK(listed == table);
    // The run record holds every listed counter and nothing else that is not context.
    json record = json::parse(Cli("run parallel --eps 0.3 --json").out);
    std::set<std::string> recordCounters;
    for (const auto &[key, value] : record.items())
        if (!kRunContextKeys.count(key))
            recordCounters.insert(key);
    CHECK(recordCounters == std::set<std::string>(listed.begin(), listed.end()));
    for (const json &c : caps["counters"]) {
        INFO(c["name"]);
        CHECK(record[c["name"].get<std::string>()].is_array() == (c["kind"] == "histogram"));
    }
}

// ---------------------------------------------------------------------------------------
// Errors and exit codes

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
    CheckError("run --scene-file " HRBENCH_TEST_DATA "/truncated.json --eps 1", 2,
               "malformed JSON");
    CheckError("run --scene-file " HRBENCH_TEST_DATA "/degenerate.json --eps 1", 2, "degenerate");
    CheckError("run parallel --scene-file x.json --eps 1", 2, "either");
    CheckError("links parallel --eps 1", 2, "needs --out");
    CheckError("links parallel --eps 1 --out x.csv --json", 2, "--json does not apply to links");
    CheckError("save parallel --eps 1", 2, "--eps does not apply to save");
    CheckError("scenes parallel", 2, "takes no scene");
    CheckError("capabilities", 2, "add --json");
    CheckError("capabilities parallel --json", 2, "takes no scene");
    CheckError("run parallel --eps 1 --oracle magic", 2,
               "unknown oracle 'magic' (choose one of: garmann, hanrahan, bf)");
    // --ff-estimate: only for the oracles that read it, only its names (check-links judges
    // it against the dump's oracle unless --oracle is given: check_links_test.cpp).
    for (const char *command : {"run parallel --eps 0.1", "links parallel --eps 0.1 --out x.csv",
                                "check-links parallel --eps 0.1 --oracle garmann --links x.dump",
                                "solve room lamp=1 --eps 0.1 --min-area 0.01"})
        CheckError(std::string(command) + " --ff-estimate solid-angle", 2,
                   "--ff-estimate applies to the oracles hanrahan and bf only, not to garmann");
    CheckError("run parallel --eps 0.1 --oracle garmann --ff-estimate centre-cosine", 2,
               "--ff-estimate applies to the oracles hanrahan and bf only, not to garmann");
    CheckError("run parallel --eps 0.1 --oracle hanrahan --ff-estimate magic", 2,
               "unknown ff_estimate 'magic' (choose one of: clamped-cosine, centre-cosine, "
               "solid-angle)");
    CheckError("save parallel --ff-estimate solid-angle", 2,
               "--ff-estimate does not apply to save");
    CheckError("run parallel --eps 0.1 --oracle hanrahan --ff-estimate centre-cosine --method "
               "translation --count-only",
               2, "--method translation supports --oracle garmann only");
}

TEST_CASE("Bad 3D input gives one line on stderr and exit code 2", "[cli][errors][3d]") {
    std::string nonPlanar = Scratch("nonplanar.obj"), truncated = Scratch("short.off");
    std::ofstream(nonPlanar) << "v 0 0 0\nv 1 0 0\nv 1 1 0.5\nv 0 1 0\nf 1 2 3 4\n";
    std::ofstream(truncated) << "OFF\n4 2 0\n0 0 0\n1 0 0\n0 1 0\n";
    CheckError("run --mesh " + nonPlanar + " --eps 0.1", 2, "not planar");
    CheckError("run --mesh " + truncated + " --eps 0.1", 2, "line 2: truncated");
    CheckError("run --mesh /no/such.obj --eps 0.1", 2, "cannot read");
    CheckError("run --mesh " + kData + "/two_plates.obj parallel --eps 0.1", 2, "either");
    CheckError("run --mesh " + kData + "/two_plates.obj l=2 --eps 0.1", 2, "apply to a family");
    CheckError("run parallel3d --eps 0.1 --visibility some", 2, "unknown visibility");
    CheckError("run parallel3d --eps 0.1 --subdivision octree", 2, "unknown subdivision");
    CheckError("run parallel --eps 0.1 --subdivision quadtree", 2, "3D scenes only");
    CheckError("run parallel3d --eps 0.1 --visibility refine", 2, "--min-area");
    CheckError("run parallel3d --eps 0.1 --rays-per-side 0", 2, "--rays-per-side");
    CheckError("run perpendicular3d gap=0 --eps 0.1", 2, "touch");
    CheckError("run cornell --eps 0.1", 2, "touch");
    CheckError("run occluded3d h=2 --eps 0.1", 2, "between the plates");
}

TEST_CASE("Hostile command lines and outputs give one line and exit code 2", "[cli][errors]") {
    CheckError("run parallel --eps 0.3 --eps 0.2", 2, "option --eps is given twice");
    CheckError("run parallel --eps 0.3 --json --json", 2, "option --json is given twice");
    CheckError("run parallel d=1e-320 --eps 0.3", 2, "parameter d: '1e-320' underflows double");
    CheckError("run parallel l=1e400 --eps 0.3", 2, "parameter l: '1e400' overflows double");
    CheckError("run parallel l=1e155 --eps 0.3", 2, "too long for double precision");
    CheckError("run --scene-file /tmp --eps 0.3", 2, "it is a directory");
    CheckError("run --scene-file /dev/zero --eps 0.3 --max-input 1", 2,
               "larger than the input limit of 1 MiB");
    CheckError("run parallel --eps 0.3 --max-input 0", 2, "--max-input must be between");
    CheckError("run parallel --eps 0.3 --max-memory 99999999999999", 2,
               "--max-memory must be between");
    CheckError("save parallel --out /dev/full", 2, "cannot write scene file '/dev/full'");
    CheckError("save parallel --out /no/such/folder/s.json", 2, "cannot write scene file");
    CheckError("links parallel --eps 0.3 --out /dev/full", 2, "cannot write links file");
    CheckError("links parallel --eps 0.3 --out /tmp", 2, "it is a folder");
}

TEST_CASE("An output is written whole or refused, and never over an input", "[cli][errors]") {
    std::string dump = Scratch("own.dump"), scene = Scratch("own.json");
    REQUIRE(Cli("links parallel l=4 d=1 --eps 0.5 --format probe --out " + dump).exitCode == 0);
    REQUIRE(Cli("save parallel --out " + scene).exitCode == 0);
    std::string dumpText = ReadFile(dump), sceneText = ReadFile(scene);
    SECTION("an output that is the input is refused before anything is written") {
        CheckError("dump-paths parallel l=4 d=1 --links " + dump + " --out " + dump, 2,
                   "is the file --links '" + dump + "' reads");
        CheckError("save --scene-file " + scene + " --out " + scene, 2, "--scene-file");
        std::filesystem::remove(Scratch("own-link.json"));
        std::filesystem::create_symlink(scene, Scratch("own-link.json"));
        CheckError("save --scene-file " + Scratch("own-link.json") + " --out " + scene, 2,
                   "reads; write the output to another file");
        CHECK(ReadFile(dump) == dumpText);
        CHECK(ReadFile(scene) == sceneText);
    }
    SECTION("a symbolic link's target is replaced, the link kept") {
        std::string target = Scratch("target.json"), link = Scratch("link.json");
        std::filesystem::remove(link);
        std::ofstream(target) << "previous";
        std::filesystem::create_symlink(target, link);
        REQUIRE(Cli("save parallel --out " + link).exitCode == 0);
        CHECK(std::filesystem::is_symlink(link));
        CHECK(ReadFile(target) == sceneText);
    }
    SECTION("an OBJ through a symbolic link gets its MTL beside its real target") {
        std::filesystem::create_directories(Scratch("real"));
        std::string target = Scratch("real/target.obj"), link = Scratch("named.obj");
        std::filesystem::remove(link);
        std::filesystem::remove(Scratch("named.mtl"));
        std::filesystem::create_symlink(target, link);
        REQUIRE(Cli("save parallel3d --out " + link).exitCode == 0);
        CHECK(std::filesystem::is_symlink(link));
        CHECK_THAT(ReadFile(target), Catch::Contains("\nmtllib target.mtl\n"));
        CHECK_THAT(ReadFile(Scratch("real/target.mtl")),
                   Catch::StartsWith("# Materials of target.obj:"));
        CHECK(!std::filesystem::exists(Scratch("named.mtl")));
        // Read back through the link, the materials are found.
        CliResult r = Cli("run --mesh " + link + " --eps 0.5 --json");
        CHECK(r.exitCode == 0);
        CHECK(r.err.empty());
    }
    SECTION("an mtllib name OBJ cannot carry is refused, before the MTL is written") {
        // '#' would start a comment, a line break end the statement.
        std::string hash = Scratch("a#b.obj"), mtl = Scratch("a#b.mtl");
        CheckError("save parallel3d --out '" + hash + "'", 2,
                   "an mtllib name is one word without '#' or control characters");
        CHECK(!std::filesystem::exists(mtl));
        CheckError("save parallel3d --out \"$(printf '" + Scratch("a") + "\\nb.obj')\"", 2,
                   "cannot name material library 'a\\x0ab.mtl'");
        CHECK(!std::filesystem::exists(Scratch("a\nb.mtl")));
    }
}

TEST_CASE("Every input is checked as run checks it, and quoted on one short line",
          "[cli][errors]") {
    std::string dump = Scratch("quoted.dump"), scene = Scratch("typed.json");
    REQUIRE(Cli("links parallel l=4 d=1 --eps 0.5 --format probe --out " + dump).exitCode == 0);
    CheckError("dump-paths parallel --subdivision quadtree --links " + dump + " --out " +
                   Scratch("quadtree.dump"),
               2, "--subdivision quadtree applies to 3D scenes only");
    REQUIRE(Cli("save parallel --out " + scene).exitCode == 0);
    std::string text = ReadFile(scene);
    size_t digest = text.find("\"scene_sha256\"");
    REQUIRE(digest != std::string::npos);
    size_t end = text.find_first_of(",}", digest);
    std::ofstream(scene) << text.substr(0, digest) << "\"scene_sha256\": 12" << text.substr(end);
    CheckError("run --scene-file " + scene + " --eps 1", 2, "\"scene_sha256\" must be a string");
    // A NUL byte is shown escaped; a 1 MB token as its first 60 bytes and its length.
    std::ofstream(dump) << "hrbench-link-dump 1\n0 1\n0/1" << std::string(1, '\0') << "x 1\n";
    CheckError("check-links parallel l=4 d=1 --eps 0.5 --links " + dump, 2, "'0/1\\x00x'");
    std::ofstream(dump) << "hrbench-link-dump 1\n0 1\n" << std::string(1 << 20, '7') << " 1\n";
    CliResult r = Cli("check-links parallel l=4 d=1 --eps 0.5 --links " + dump);
    CHECK(r.exitCode == 2);
    CHECK(r.err.size() < 400);
    CHECK_THAT(r.err, Catch::Contains("... (104857"));
}

TEST_CASE("Limits reached during refinement give exit code 3", "[cli][errors]") {
    CheckError("run parallel l=1024 --eps 0.01 --max-memory 1", 3, "memory budget");
    // The records of the refined root pairs count: 1.1 million pairs of 24 bytes.
    CheckError("run random n=3000 size=100 --eps 0.5 --count-only --max-memory 5", 3,
               "refined root pairs and ");
    // The translation method's states, refused by the estimate before the run starts.
    CheckError(
        "run parallel l=1024 --eps 1e-8 --count-only --method translation --max-memory 1", 3,
        "pair states, 4e+08 on a level at most (4/eps)), more than its memory budget of 1 MiB");
    // A --min-area that small draws the warning of a scene and --min-area in other units.
    CliResult deep = Cli("run perpendicular gap=0 --eps 0.5 --min-area 1e-300");
    CHECK(deep.exitCode == 3);
    CHECK(deep.out.empty());
    CHECK_THAT(deep.err, Catch::StartsWith("hrbench: warning: --min-area 1e-300 is below 1e-08 "
                                           "of the largest patch's length, 1:") &&
                             Catch::Contains("\nhrbench: error: ") &&
                             Catch::Contains("safety depth"));
    CHECK(std::count(deep.err.begin(), deep.err.end(), '\n') == 2);
}

// Not under AddressSanitizer: its shadow memory needs terabytes of address space, which
// the address-space limit this test sets refuses before any allocation of ours.
#ifndef __SANITIZE_ADDRESS__
TEST_CASE("Memory running out before the budget advises --count-only only where it applies",
          "[cli][errors]") {
    // A budget of 100 GB under an address-space limit of 400 MB: the system refuses first.
    auto outOfMemory = [](const std::string &args) {
        INFO("hrbench " << args);
        CliResult r = Cli(args + " --max-memory 100000 >/dev/null", "ulimit -v 400000; ");
        CHECK(r.exitCode == 3);
        return r.err;
    };
    CHECK(outOfMemory("run parallel l=100000 --eps 0.0001") ==
          "hrbench: error: out of memory; use --count-only or a larger eps\n");
    // Counting keeps the elements and the refined root pairs' records only; a soup of
    // 20,000 triangles has 2e8 root pairs and outgrows the address space in seconds.
    CHECK(outOfMemory("run random n=20000 size=100 --eps 0.5 --count-only") ==
          "hrbench: error: out of memory; use a larger eps\n");
    // A tenth of the links of the runs above: estimated within the budget, the solve's
    // arrays still outgrow the address space.
    CHECK(outOfMemory("solve parallel l=100000 --eps 0.001 --emission 1") ==
          "hrbench: error: out of memory; use a larger eps\n");
}
#endif

// ---------------------------------------------------------------------------------------
// dump-paths: elements named by their corners

namespace {

std::string Coordinates(const std::vector<double> &xyz) {
    std::string text;
    for (double x : xyz)
        text += (text.empty() ? "" : ",") + hrbench::FormatDouble(x);
    return text;
}

// The corner token of element _path_ ("3" or "3/0110") of _scene_: its corners from the
// second on, backwards, each coordinate moved by 1e-7 of its root's diameter, after
// its root index when _withRoot_.
std::string CornerToken(const hrbench::Scene &scene, hrbench::Subdivision mode,
                        const std::string &path, bool withRoot) {
    size_t slash = path.find('/');
    size_t root = std::stoul(path.substr(0, slash));
    std::string digits = slash == std::string::npos ? "" : path.substr(slash + 1);
    std::vector<std::vector<double>> corners;
    double diameter = 0;
    if (scene.Dimension() == 2) {
        hrbench::Segment s = scene.Get<hrbench::Segment>()[root].shape;
        diameter = (s.b - s.a).norm();
        std::array<hrbench::Segment, 4> children;
        for (char d : digits)
            s.Subdivide(mode, children), s = children[size_t(d - '0')];
        corners = {{s.a.x(), s.a.y()}, {s.b.x(), s.b.y()}};
    } else {
        hrbench::Polygon p = scene.Get<hrbench::Polygon>()[root].shape;
        diameter = p.Diameter();
        std::array<hrbench::Polygon, 4> children;
        for (char d : digits)
            p.Subdivide(mode, children), p = children[size_t(d - '0')];
        for (int k = 0; k < p.n; ++k)
            corners.push_back({p.v[k].x(), p.v[k].y(), p.v[k].z()});
    }
    std::string token = withRoot ? std::to_string(root) + "@" : "@";
    int n = int(corners.size());
    for (int k = 0; k < n; ++k) {
        std::vector<double> c = corners[size_t((1 - k + n) % n)];
        for (size_t i = 0; i < c.size(); ++i)
            c[i] += ((k + int(i)) % 2 ? 1e-7 : -1e-7) * diameter;
        token += (k ? ";" : "") + Coordinates(c);
    }
    return token;
}

}  // namespace

TEST_CASE("dump-paths turns corner tokens back into hrbench's paths exactly", "[cli][dump-paths]") {
    struct Case {
        std::string scene, options;
        hrbench::Subdivision mode;
    };
    for (const Case &c :
         {Case{"parallel l=4 d=1", "", hrbench::Subdivision::Binary},
          Case{"parallel3d l=2 d=1 ox=0.3", "", hrbench::Subdivision::Binary},
          Case{"parallel3d l=2 d=1 ox=0.3", " --subdivision quadtree",
               hrbench::Subdivision::Quadtree},
          Case{"perpendicular3d", " --subdivision quadtree", hrbench::Subdivision::Quadtree}}) {
        INFO(c.scene << c.options);
        std::istringstream words(c.scene);
        std::string family, word;
        words >> family;
        hrbench::ParamMap params;
        while (words >> word)
            params[word.substr(0, word.find('='))] = std::stod(word.substr(word.find('=') + 1));
        hrbench::Scene scene = hrbench::MakeScene(family, params);
        std::string original = Scratch("paths.dump"), corners = Scratch("corners.dump"),
                    back = Scratch("back.dump");
        REQUIRE(
            Cli("links " + c.scene + " --eps 0.5" + c.options + " --format probe --out " + original)
                .exitCode == 0);
        // Every link line with corner tokens (the first with its root given, the second
        // found by the corners alone), and two lines of other kinds carrying tokens.
        std::istringstream text(ReadFile(original));
        std::string expected, converted, line;
        int links = 0;
        while (std::getline(text, line)) {
            std::istringstream tokens(line);
            std::string a, b, rest;
            if (!line.empty() && isdigit(line[0]) && tokens >> a >> b && !(tokens >> rest)) {
                converted += CornerToken(scene, c.mode, a, true) + "\t" +
                             CornerToken(scene, c.mode, b, false) + "\n";
                expected += a + "\t" + b + "\n";
                if (++links == 1) {
                    converted += "# a comment @ is copied as it is\n";
                    expected += "# a comment @ is copied as it is\n";
                    converted += "unlink " + CornerToken(scene, c.mode, a, false) + " " + b +
                                 " x=" + CornerToken(scene, c.mode, b, true) + "\n";
                    expected += "unlink " + a + " " + b + " x=" + b + "\n";
                }
            } else {
                converted += line + "\n";
                expected += line + "\n";
            }
        }
        REQUIRE(links > 4);
        std::ofstream(corners) << converted;
        CliResult r =
            Cli("dump-paths " + c.scene + c.options + " --links " + corners + " --out " + back);
        INFO(r.err);
        REQUIRE(r.exitCode == 0);
        CHECK(ReadFile(back) == expected);
    }
}

TEST_CASE("dump-paths names the line of a token that matches no element", "[cli][dump-paths]") {
    std::string dump = Scratch("bad_corners.dump"), out = Scratch("bad_out.dump");
    auto check = [&](const std::string &token, const std::string &what) {
        std::ofstream(dump) << "hrbench-link-dump 1\n0 1\n" << token << " 1\n";
        CheckError("dump-paths parallel3d --links " + dump + " --out " + out, 2,
                   dump + ":3: " + what);
    };
    // [0, 0.5] x [0, 0.25] on plate 0 is no element of the binary tree (the quarter
    // [0, 0.5]^2 is halved across v0v1 on a tie), nor a rectangle between the plates,
    // nor a third of the plate.
    check("@0,0,0;0.5,0,0;0.5,0.25,0;0,0.25,0",
          "element '@0,0,0;0.5,0,0;0.5,0.25,0;0,0.25,0' matches no element of root patch 0 under "
          "the subdivision within the tolerance "
          "1e-05 of its diameter");
    check("@0,0,0.5;1,0,0.5;1,1,0.5;0,1,0.5",
          "element '@0,0,0.5;1,0,0.5;1,1,0.5;0,1,0.5' lies in no root patch within the tolerance "
          "1e-05 of its diameter");
    check("0@0,0,0;0.3,0,0;0.3,1,0;0,1,0",
          "element '0@0,0,0;0.3,0,0;0.3,1,0;0,1,0' matches no element of root patch 0 under the "
          "subdivision within the tolerance "
          "1e-05 of its diameter");
    check(
        "7@0,0,0;1,0,0;1,1,0",
        "element '7@0,0,0;1,0,0;1,1,0': '7' before '@' is not a root patch of the scene (0 to 1)");
    check("@0,0;1,0;1,1",
          "bad element '@0,0;1,0;1,1': a corner needs 3 coordinates separated by ',', got '0,0'");
    check("@0,0,0;1,0,0",
          "bad element '@0,0,0;1,0,0': 3 or 4 corners separated by ';' in a 3D scene, got 2");
    CheckError("dump-paths parallel3d --links " + dump + " --out " + out + " --tolerance 0.5", 2,
               "--tolerance of dump-paths must be at least 0 and below 0.01, not 0.5");
    CheckError("dump-paths parallel3d --links " + dump, 2, "dump-paths needs --links IN");
}

TEST_CASE("a run estimated beyond its memory or --max-links stops at once with exit code 3",
          "[cli][errors]") {
    // Each within seconds: the estimate comes from small pilot refinements.
    auto timed = [](const std::string &args) {
        auto start = std::chrono::steady_clock::now();
        CliResult r = Cli(args);
        double seconds =
            std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        CHECK(seconds < 20);
        return r;
    };
    SECTION("a store run beyond the memory budget") {
        CliResult r = timed("run parallel l=64 d=1 --eps 1e-9");
        CHECK(r.exitCode == 3);
        CHECK_THAT(r.err, Catch::Contains("this run would take about") &&
                              Catch::Contains("links") &&
                              Catch::Contains("--max-memory MIB raises it"));
        CHECK(std::count(r.err.begin(), r.err.end(), '\n') == 1);
    }
    SECTION("a count-only run beyond --max-links") {
        CliResult r = timed("run parallel l=64 d=1 --eps 1e-9 --count-only");
        CHECK(r.exitCode == 3);
        CHECK_THAT(r.err, Catch::Contains("this run would take about"));
        // A cap of its own, below the links of a run that the default lets through.
        CliResult capped = timed("run parallel l=64 d=1 --eps 0.01 --count-only --max-links 1e5");
        CHECK(capped.exitCode == 3);
        CHECK_THAT(capped.err, Catch::Contains("more than --max-links 1e+05") &&
                                   Catch::Contains("--max-links N raises the cap, 0 lifts it"));
        CHECK(Cli("run parallel l=64 d=1 --eps 0.01 --count-only --max-links 0").exitCode == 0);
        CHECK(Cli("run parallel l=64 d=1 --eps 0.01 --count-only --max-links -1").exitCode == 2);
    }
    SECTION("the translation method by its pair states") {
        CliResult r = timed("run parallel l=64 d=1 --eps 1e-9 --count-only --method translation");
        CHECK(r.exitCode == 3);
        CHECK_THAT(r.err, Catch::Contains("pair states") && Catch::Contains("--max-memory"));
    }
    SECTION("an estimate near the counts: within 10% for a run scaled over 2 decades") {
        // 262142 elements and 339577246 links when run (docs/limits.md#estimates).
        CliResult r = Cli("run parallel l=64 d=1 --eps 1e-3 --count-only --max-links 1e8");
        REQUIRE(r.exitCode == 3);
        double elements = std::stod(r.err.substr(r.err.find("about ") + 6));
        double links = std::stod(r.err.substr(r.err.find("elements, ") + 10));
        CHECK_THAT(elements, Catch::WithinRel(262142.0, 0.1));
        CHECK_THAT(links, Catch::WithinRel(339577246.0, 0.1));
    }
}
