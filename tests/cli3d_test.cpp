// End-to-end tests of the 3D and visibility options of the hrbench command: JSON fields,
// meshes, links CSV and the exit code of every kind of bad input.
#include <catch2/catch.hpp>

#include "cli_helpers.h"

#include <nlohmann/json.hpp>

using nlohmann::json;

using namespace hrbench_test;

namespace {

const std::string kData = HRBENCH_TEST_DATA;

}  // namespace

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
    json q = json::parse(
        Cli("run occluded3d --eps 0.1 --subdivision quadtree --visibility fraction "
            "--rays-per-side 2 --json")
            .out);
    CHECK(q["subdivision"] == "quadtree");
    CHECK(q["visibility"] == "fraction");
    CHECK(q["rays_per_side"] == 2);
    CHECK(q["rays"] == 16 * q["visibility_queries"].get<int>());
    CHECK(q["occluded_pairs"].get<int>() > 0);
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

TEST_CASE("A mesh runs like the family it copies, and is named in the record", "[cli][mesh]") {
    json a = json::parse(Cli("run --mesh " + kData + "/two_plates.obj --eps 0.05 --json").out);
    json b = json::parse(Cli("run parallel3d --eps 0.05 --json").out);
    CHECK(a["scene"] == "mesh");
    CHECK(a["mesh_file"] == kData + "/two_plates.obj");
    for (const char *key : {"nodes", "leaves", "links", "oracle_calls"})
        CHECK(a[key] == b[key]);
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

TEST_CASE("Bad 3D input gives one line on stderr and exit code 2", "[cli][errors][3d]") {
    std::string nonPlanar = Scratch("nonplanar.obj"), truncated = Scratch("truncated.off");
    std::ofstream(nonPlanar) << "v 0 0 0\nv 1 0 0\nv 1 1 0.5\nv 0 1 0\nf 1 2 3 4\n";
    std::ofstream(truncated) << "OFF\n4 2 0\n0 0 0\n1 0 0\n0 1 0\n";
    CheckError("run --mesh " + nonPlanar + " --eps 0.1", 2, "not planar");
    CheckError("run --mesh " + truncated + " --eps 0.1", 2, "truncated");
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

TEST_CASE("The Cornell box runs with visibility from the command line", "[cli][3d]") {
    CliResult r = Cli("run cornell --eps 0.05 --oracle hanrahan --min-area 1e-2 --visibility "
                      "fraction --count-only --json");
    REQUIRE(r.exitCode == 0);
    json j = json::parse(r.out);
    CHECK(j["patches"] == 17);
    CHECK(j["links"].get<int>() > 0);
    CHECK(j["occluded_pairs"].get<int>() > 0);
}
