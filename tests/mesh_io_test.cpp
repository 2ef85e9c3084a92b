// Mesh input and output through CGAL's OFF and OBJ readers: round trips, materials,
// and every kind of bad file.
#include <catch2/catch.hpp>

#include <cstdio>
#include <filesystem>
#include <fstream>

#include <unistd.h>

#include "generators.h"
#include "hrbench.h"
#include "mesh_io.h"

using namespace hrbench;

namespace {

const std::string kData = HRBENCH_TEST_DATA;

// A scratch file in a temporary folder of this test process, removed when the test ends.
struct ScratchFile {
    std::string path;
    explicit ScratchFile(const std::string &name, const std::string &text = "")
        : path((std::filesystem::temp_directory_path() /
                ("hrbench_mesh_io_test_" + std::to_string(getpid()) + "_" + name))
                   .string()) {
        std::ofstream(path, std::ios::binary) << text;
    }
    ~ScratchFile() { std::remove(path.c_str()); }
};

// Expects LoadMesh on _text_ (a file named _name_) to fail with one line containing _fragment_.
void CheckBadMesh(const std::string &name, const std::string &text, const std::string &fragment) {
    ScratchFile file(name, text);
    INFO(name << ":\n" << text);
    try {
        LoadMesh(file.path);
        FAIL("no error");
    } catch (const InputError &e) {
        CHECK_THAT(e.what(), Catch::Contains(fragment));
        CHECK_THAT(e.what(), Catch::Contains(file.path));
        CHECK(std::string(e.what()).find('\n') == std::string::npos);
    }
}

const char *kSquareObj = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n";

}  // namespace

TEST_CASE("Meshes round-trip through CGAL's OFF and OBJ writers and readers", "[mesh]") {
    Scene scene = MakeScene("random3d", {{"n", 12}, {"seed", 3}});
    scene.Get<Polygon>().push_back(MakeScene("cornell", {}).Get<Polygon>()[0]);  // a quad too
    const Patches<Polygon> &faces = scene.Get<Polygon>();
    for (const char *ext : {"off", "obj"}) {
        INFO(ext);
        ScratchFile file(std::string("roundtrip.") + ext);
        SaveMesh(scene, file.path);
        Scene back = LoadMesh(file.path);
        CHECK(back.Dimension() == 3);
        CHECK(back.family == "mesh");
        const Patches<Polygon> &read = back.Get<Polygon>();
        REQUIRE(read.size() == faces.size());
        for (size_t k = 0; k < faces.size(); ++k) {
            REQUIRE(read[k].shape.n == faces[k].shape.n);
            for (int v = 0; v < faces[k].shape.n; ++v)
                CHECK(read[k].shape.v[v] == faces[k].shape.v[v]);  // 17 digits
            CHECK(read[k].material.reflectance == kMeshDefaultReflectance);
            CHECK(read[k].material.emission == kMeshDefaultEmission);
        }
    }
}

TEST_CASE("OBJ materials come from usemtl and the mtllib's Kd and Ke", "[mesh]") {
    Patches<Polygon> s = LoadMesh(kData + "/two_plates.obj").Get<Polygon>();
    REQUIRE(s.size() == 2);
    CHECK_THAT(s[0].material.reflectance, Catch::Matchers::WithinRel(0.5, 1e-15));
    CHECK(s[0].material.emission == 0);
    CHECK_THAT(s[1].material.reflectance, Catch::Matchers::WithinRel(0.8, 1e-15));
    CHECK_THAT(s[1].material.emission, Catch::Matchers::WithinRel(4.0, 1e-15));
    // The geometry of parallel3d l=1 d=1.
    Patches<Polygon> p = MakeScene("parallel3d", {}).Get<Polygon>();
    for (int k = 0; k < 2; ++k)
        for (int v = 0; v < 4; ++v)
            CHECK(s[k].shape.v[v] == p[k].shape.v[v]);
}

TEST_CASE("OFF face colours set the reflectance, capped below 1", "[mesh]") {
    Patches<Polygon> s = LoadMesh(kData + "/tetra_colours.off").Get<Polygon>();
    REQUIRE(s.size() == 4);
    CHECK_THAT(s[0].material.reflectance, Catch::Matchers::WithinRel(1.0 / 3, 1e-12));
    CHECK(s[3].material.reflectance == kMeshMaxReflectance);
    CHECK(s[3].shape.Normal().isApprox(Vec3(1, 1, 1).normalized()));
}

TEST_CASE("A mesh without materials gets the documented defaults", "[mesh]") {
    ScratchFile file("plain.obj", std::string(kSquareObj) + "usemtl nowhere\nf 1 2 3 4\n");
    Patches<Polygon> s = LoadMesh(file.path).Get<Polygon>();
    REQUIRE(s.size() == 1);
    CHECK(s[0].material.reflectance == 0.5);
    CHECK(s[0].material.emission == 0);
}

TEST_CASE("Bad mesh files are rejected with one line naming the file", "[mesh]") {
    SECTION("missing file") {
        CHECK_THROWS_WITH(LoadMesh("no/such/file.obj"), Catch::Contains("cannot read"));
    }
    SECTION("unknown extension") {
        CHECK_THROWS_WITH(LoadMesh("scene.stl"), Catch::Contains(".off or .obj"));
    }
    SECTION("empty files") {
        CheckBadMesh("empty.obj", "", "empty");
        CheckBadMesh("empty.off", "", "empty");
        CheckBadMesh("nofaces.obj", kSquareObj, "no faces");
        CheckBadMesh("nofaces.off", "OFF\n3 0 0\n0 0 0\n1 0 0\n0 1 0\n", "no faces");
    }
    SECTION("truncated files") {
        CheckBadMesh("truncated.off", "OFF\n4 2 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 1 2\n",
                     "truncated");
        CheckBadMesh("truncated_vertices.off", "OFF\n4 1 0\n0 0 0\n1 0 0\n", "truncated");
        CheckBadMesh("truncated.obj", std::string(kSquareObj) + "f 1 2", "2 corners");
    }
    SECTION("not a mesh") {
        CheckBadMesh("garbage.obj", "hello world\n", "not an OBJ");
        CheckBadMesh("garbage.off", "solid ascii\n", "OFF");
    }
    SECTION("bad indices") {
        CheckBadMesh("index.obj", std::string(kSquareObj) + "f 1 2 5\n", "vertex 5 of 4");
        CheckBadMesh("index0.obj", std::string(kSquareObj) + "f 0 1 2\n", "");
        CheckBadMesh("index.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 3\n", "OFF");
    }
    SECTION("coordinates that are not finite") {
        CheckBadMesh("nan.obj", "v nan 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", "OBJ");
        CheckBadMesh("inf.obj", "v 1e999 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", "");
        CheckBadMesh("nan.off", "OFF\n3 1 0\nnan 0 0\n1 0 0\n0 1 0\n3 0 1 2\n", "");
    }
    SECTION("bad faces") {
        CheckBadMesh("nonplanar.obj", "v 0 0 0\nv 1 0 0\nv 1 1 0.3\nv 0 1 0\nf 1 2 3 4\n",
                     "not planar");
        CheckBadMesh("nonconvex.obj", "v 0 0 0\nv 1 0 0\nv 0.2 0.2 0\nv 0 1 0\nf 1 2 3 4\n",
                     "not a convex quad");
        CheckBadMesh("degenerate.off", "OFF\n3 1 0\n0 0 0\n1 1 1\n2 2 2\n3 0 1 2\n", "degenerate");
        CheckBadMesh("pentagon.obj",
                     "v 0 0 0\nv 1 0 0\nv 1.5 1 0\nv 0.5 2 0\nv -0.5 1 0\nf 1 2 3 4 5\n",
                     "5 corners");
    }
}
