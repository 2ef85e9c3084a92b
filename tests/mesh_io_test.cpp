// Mesh input and output: our strict OFF, OBJ and MTL readers, CGAL's writers; round
// trips, materials, and every kind of bad or hostile file with its one-line message.
#include <catch2/catch.hpp>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <optional>
#include <sstream>
#include <vector>

#include <unistd.h>

#include "generators.h"
#include "hrbench/hrbench.h"
#include "hrbench/mesh_io.h"

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
        std::string message = e.what();
        size_t at = message.find(file.path);
        REQUIRE(at != std::string::npos);
        // What follows the path, which may hold the fragment itself ("truncated.off").
        CHECK_THAT(message.substr(at + file.path.size()), Catch::Contains(fragment));
        CHECK(message.find('\n') == std::string::npos);
    }
}

const char *kSquareObj = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n";

// Lines 1 to 5 of an OFF file with one triangle: its face line is line 6.
const std::string kTriangleOff = "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n";
// Lines 1 to 3 of an OBJ file with one triangle: its face line is line 4.
const std::string kTriangleObj = "v 0 0 0\nv 1 0 0\nv 0 1 0\n";

// ParseMesh on _text_ as _format_ from 't.off' or 't.obj', with the material libraries
// _libraries_ by name (a name not there reads as a missing library).
Scene Parse(const std::string &text, MeshFormat format,
            const std::map<std::string, std::string> &libraries = {}) {
    auto read = [&](const std::string &name) -> std::optional<std::string> {
        auto it = libraries.find(name);
        return it == libraries.end() ? std::nullopt : std::optional(it->second);
    };
    return ParseMesh(text, format, format == MeshFormat::Off ? "t.off" : "t.obj", read);
}

// The one-line error of Parse, or "no error".
std::string ParseError(const std::string &text, MeshFormat format,
                       const std::map<std::string, std::string> &libraries = {}) {
    try {
        Parse(text, format, libraries);
    } catch (const InputError &e) {
        return e.what();
    }
    return "no error";
}

std::string OffError(const std::string &text) { return ParseError(text, MeshFormat::Off); }
std::string ObjError(const std::string &text) { return ParseError(text, MeshFormat::Obj); }

// The one-line error of LoadMesh, or "no error".
std::string LoadError(const std::string &path, size_t maxInputBytes = kDefaultMaxInputBytes) {
    try {
        LoadMesh(path, maxInputBytes);
    } catch (const InputError &e) {
        return e.what();
    }
    return "no error";
}

// Expects _a_ and _b_ to hold the same faces: corners and materials, exactly.
void CheckSameFaces(const Scene &a, const Scene &b) {
    const Patches<Polygon> &p = a.Get<Polygon>(), &q = b.Get<Polygon>();
    REQUIRE(p.size() == q.size());
    for (size_t k = 0; k < p.size(); ++k) {
        REQUIRE(p[k].shape.n == q[k].shape.n);
        for (int v = 0; v < 4; ++v)
            CHECK(p[k].shape.v[v] == q[k].shape.v[v]);
        CHECK(p[k].material.reflectance == q[k].material.reflectance);
        CHECK(p[k].material.emission == q[k].material.emission);
    }
}

// A folder in the temporary folder of this test process, removed with its files.
struct ScratchFolder {
    std::string path;
    explicit ScratchFolder(const std::string &name)
        : path((std::filesystem::temp_directory_path() /
                ("hrbench_mesh_io_test_" + std::to_string(getpid()) + "_" + name))
                   .string()) {
        std::filesystem::create_directories(path);
    }
    ~ScratchFolder() {
        std::error_code ignored;
        std::filesystem::remove_all(path, ignored);
    }
};

}  // namespace

TEST_CASE("Meshes round-trip through our OFF and OBJ writers and our readers", "[mesh]") {
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
            // OBJ: the materials too (the MTL beside it); OFF: the defaults.
            bool obj = std::string(ext) == "obj";
            CHECK(read[k].material.reflectance ==
                  (obj ? faces[k].material.reflectance : kMeshDefaultReflectance));
            CHECK(read[k].material.emission ==
                  (obj ? faces[k].material.emission : kMeshDefaultEmission));
        }
    }
}

TEST_CASE("OBJ + MTL keeps every reflectance and emission exactly, colours where they agree",
          "[mesh]") {
    Scene scene = MakeScene("parallel3d", {});
    // Values whose mean of three equal copies is not the value in floating point: grey
    // Kd and Ke must still read back exactly.
    std::vector<double> inexact;
    for (double r = 0.1; inexact.size() < 2; r = std::nextafter(r, 1.0))
        if ((r + r + r) / 3 != r)
            inexact.push_back(r);
    Patches<Polygon> &plates = scene.Get<Polygon>();
    plates[0].material = {inexact[0], inexact[1] * 7};
    plates[1].material = {0.3, 0, Rgb{0.1, 0.2, 0.6}};  // mean(colour) == 0.3 exactly
    plates.push_back(plates[0]);
    plates.back().material = {0.4, 0, Rgb{0.1, 0.2, 0.6}};  // a colour whose mean is not rho
    plates.back().shape = MakeScene("parallel3d", {{"d", 2}}).Get<Polygon>()[1].shape;
    REQUIRE((0.1 + 0.2 + 0.6) / 3 == 0.3);
    ScratchFolder folder("materials");
    std::string path = folder.path + "/scene.obj";
    SaveMesh(scene, path);
    Scene back = LoadMesh(path);
    CHECK(back.warnings.empty());
    const Patches<Polygon> &read = back.Get<Polygon>();
    REQUIRE(read.size() == 3);
    for (size_t k = 0; k < 3; ++k) {
        CHECK(read[k].material.reflectance == plates[k].material.reflectance);
        CHECK(read[k].material.emission == plates[k].material.emission);
    }
    CHECK(read[1].material.colour == plates[1].material.colour);
    CHECK(read[2].material.colour == Rgb{0.4, 0.4, 0.4});  // grey: Kd gives rho first
    std::ifstream mtl(MaterialLibraryPath(path));
    std::stringstream text;
    text << mtl.rdbuf();
    CHECK(text.str().find("newmtl m1\nKd 0.1 0.2 0.6\nKe 0 0 0\n") != std::string::npos);
    CHECK(text.str().find("newmtl m2\nKd 0.4 0.4 0.4\nKe 0 0 0\n") != std::string::npos);
    // A reflectance the reader would cap at kMeshMaxReflectance is refused.
    plates[0].material.reflectance = 0.995;
    CHECK_THROWS_WITH(SaveMesh(scene, path),
                      "patch 0 has reflectance 0.995, above 0.99, the most an MTL Kd gives when "
                      "read back (docs/3d.md)");
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
    Scene scene = LoadMesh(file.path);
    Patches<Polygon> s = scene.Get<Polygon>();
    REQUIRE(s.size() == 1);
    CHECK(s[0].material.reflectance == 0.5);
    CHECK(s[0].material.emission == 0);
    // A name no library defines is the defaults, with a warning on its line.
    CHECK(scene.warnings ==
          std::vector<std::string>{"mesh file '" + file.path +
                                   "', line 5: material 'nowhere' is not defined by the material "
                                   "libraries read so far: its faces get the default "
                                   "reflectance 0.5 and emission 0"});
    // No usemtl, or an OFF file: the defaults without a word.
    CHECK(LoadMesh(kData + "/tetra_colours.off").warnings.empty());
    CHECK(Parse(kTriangleObj + "f 1 2 3\n", MeshFormat::Obj).warnings.empty());
}

TEST_CASE("A missing material library or an undefined material is a warning naming the line",
          "[mesh]") {
    // The data files, as the command line reads them.
    Scene missing = LoadMesh(kData + "/missing_library.obj");
    CHECK(missing.warnings ==
          std::vector<std::string>{"mesh file '" + kData +
                                   "/missing_library.obj', line 2: material library '" + kData +
                                   "/no_such_library.mtl' does not exist: the faces of its "
                                   "materials get the default reflectance 0.5 and emission 0"});
    for (const Patch<Polygon> &p : missing.Get<Polygon>())
        CHECK((p.material.reflectance == 0.5 && p.material.emission == 0));
    Scene misspelt = LoadMesh(kData + "/undefined_material.obj");
    CHECK(misspelt.warnings ==
          std::vector<std::string>{"mesh file '" + kData +
                                   "/undefined_material.obj', line 14: material 'lmap' is not "
                                   "defined by the material libraries read so far: its faces "
                                   "get the default reflectance 0.5 and emission 0"});
    const Patches<Polygon> &faces = misspelt.Get<Polygon>();
    CHECK_THAT(faces[0].material.reflectance, Catch::Matchers::WithinRel(0.5, 1e-15));  // floor
    CHECK(faces[1].material.emission == 0);  // the lamp that was meant emits 4
    CHECK(LoadMesh(kData + "/two_plates.obj").warnings.empty());

    // Each name once; a name defined only by a later library is still undefined where used.
    const std::string square = std::string(kSquareObj) + "f 1 2 3 4\n";
    CHECK(Parse("mtllib a.mtl\nusemtl red\nusemtl blue\nusemtl red\n" + square, MeshFormat::Obj,
                {{"a.mtl", "newmtl green\n"}})
              .warnings.size() == 2);
    CHECK(Parse("usemtl red\nmtllib a.mtl\nusemtl red\n" + square, MeshFormat::Obj,
                {{"a.mtl", "newmtl red\n"}})
              .warnings == std::vector<std::string>{
                               "mesh file 't.obj', line 1: material 'red' is not defined by the "
                               "material libraries read so far: its faces get the default "
                               "reflectance 0.5 and emission 0"});
    // A missing library, named once however often: its line explains the names after it.
    CHECK(Parse("mtllib a.mtl\nmtllib a.mtl b.mtl\nusemtl red\n" + square, MeshFormat::Obj,
                {{"b.mtl", "newmtl green\n"}})
              .warnings ==
          std::vector<std::string>{"mesh file 't.obj', line 1: material library 'a.mtl' does not "
                                   "exist: the faces of its materials get the default reflectance "
                                   "0.5 and emission 0"});
    // Without a library reader, materials are not read and nothing is warned about.
    CHECK(ParseMesh("mtllib a.mtl\nusemtl red\n" + square, MeshFormat::Obj, "t.obj", {})
              .warnings.empty());
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
        CheckBadMesh("garbage.obj", "hello world\n", "unsupported statement 'hello'");
        CheckBadMesh("garbage.off", "solid ascii\n", "OFF");
    }
    SECTION("bad indices") {
        CheckBadMesh("index.obj", std::string(kSquareObj) + "f 1 2 5\n", "vertex 5 of 4");
        CheckBadMesh("index0.obj", std::string(kSquareObj) + "f 0 1 2\n", "'0' is not a corner");
        CheckBadMesh("index.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 3\n", "OFF");
    }
    SECTION("coordinates that are not finite") {
        CheckBadMesh("nan.obj", "v nan 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n",
                     "line 1: coordinate 'nan' is not finite");
        CheckBadMesh("inf.obj", "v 1e999 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n",
                     "line 1: coordinate '1e999' overflows double precision (largest 1.8e308)");
        CheckBadMesh("nan.off", "OFF\n3 1 0\nnan 0 0\n1 0 0\n0 1 0\n3 0 1 2\n",
                     "line 3: coordinate 'nan' is not finite");
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

TEST_CASE("The data files parse to the same scenes as CGAL's readers gave", "[mesh]") {
    // Recorded from the CGAL-based reader before ours replaced it.
    Scene tetra;
    Vec3 o(0, 0, 0), x(1, 0, 0), y(0, 1, 0), z(0, 0, 1);
    double third = 255 / (3 * 255.0);
    tetra.patches = Patches<Polygon>{{Polygon::Triangle(o, y, x), {third, 0}},
                                     {Polygon::Triangle(o, x, z), {third, 0}},
                                     {Polygon::Triangle(o, z, y), {third, 0}},
                                     {Polygon::Triangle(x, y, z), {kMeshMaxReflectance, 0}}};
    CheckSameFaces(LoadMesh(kData + "/tetra_colours.off"), tetra);

    Scene plates;
    plates.patches =
        Patches<Polygon>{{Polygon::Quad(o, x, Vec3(1, 1, 0), y), {0.5, 0}},
                         {Polygon::Quad(Vec3(0, 1, 1), Vec3(1, 1, 1), Vec3(1, 0, 1), z),
                          {0.8, 4}}};  // Kd 0.8 0.8 0.8: equal values give 0.8 exactly
    Scene read = LoadMesh(kData + "/two_plates.obj");
    CheckSameFaces(read, plates);
    CHECK(read.file == kData + "/two_plates.obj");
}

TEST_CASE("OFF comments, blank lines and CRLF line endings read like the plain file", "[mesh]") {
    Scene plain = Parse(kTriangleOff + "3 0 1 2\n", MeshFormat::Off);
    CheckSameFaces(Parse("# a triangle\n\nOFF # keyword\n# counts next\n3 1 0\n0 0 0 # origin\n"
                         "\n1 0 0\n  # indented comment\n0 1 0\n\t3 0 1 2\t# face\n# end\n",
                         MeshFormat::Off),
                   plain);
    CheckSameFaces(Parse("OFF\r\n3 1 0\r\n0 0 0\r\n1 0 0\r\n0 1 0\r\n3 0 1 2\r\n", MeshFormat::Off),
                   plain);
    CheckSameFaces(Parse("OFF 3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2", MeshFormat::Off), plain);
    CheckSameFaces(Parse("\xEF\xBB\xBF" + kTriangleOff + "3 0 1 2\n", MeshFormat::Off), plain);
}

TEST_CASE("OBJ comments, ignored statements and CRLF line endings read like the plain file",
          "[mesh]") {
    Scene plain = Parse(kTriangleObj + "f 1 2 3\n", MeshFormat::Obj);
    CheckSameFaces(Parse("# a triangle\no thing\ng group\ns off\nv 0 0 0 # origin\n\nv 1 0 0\n"
                         "vt 0 0\nvn 0 0 1\nvp 0.5\nv 0 1 0 1\n\tf 1 2 3\t# face\n",
                         MeshFormat::Obj),
                   plain);
    CheckSameFaces(Parse("v 0 0 0\r\nv 1 0 0\r\nv 0 1 0\r\nf 1 2 3\r\n", MeshFormat::Obj), plain);
    CheckSameFaces(Parse(kTriangleObj + "vt 0 0\nvt 1 0\nvt 0 1\nvn 0 0 1\nf 1/1/1 2/2/1 3/3/-1\n",
                         MeshFormat::Obj),
                   plain);
    CheckSameFaces(Parse(kTriangleObj + "vn 0 0 1\nf 1//1 2//1 3//1\n", MeshFormat::Obj), plain);
}

TEST_CASE("OBJ negative references count back from the last vertex read so far", "[mesh]") {
    Patches<Polygon> s =
        Parse("v 0 0 0\nv 1 0 0\nv 0 1 0\nf -3 -2 -1\nv 0 0 5\nv 1 0 5\nv 0 1 5\nf -3 -2 -1\n"
              "f 1 -2 -1\n",
              MeshFormat::Obj)
            .Get<Polygon>();
    REQUIRE(s.size() == 3);
    CHECK(s[0].shape.v[0] == Vec3(0, 0, 0));
    CHECK(s[1].shape.v[0] == Vec3(0, 0, 5));
    CHECK(s[1].shape.v[2] == Vec3(0, 1, 5));
    CHECK(s[2].shape.v[0] == Vec3(0, 0, 0));
    CHECK(s[2].shape.v[1] == Vec3(1, 0, 5));
    CHECK(ObjError(kTriangleObj + "f -1 -2 -4\n") ==
          "mesh file 't.obj', line 4: face 1 refers to vertex -4 of 3 defined so far");
}

TEST_CASE("OFF face colours: integers 0..255 or fractions in [0, 1], with an alpha", "[mesh]") {
    auto rho = [](const std::string &colour) {
        return Parse(kTriangleOff + "3 0 1 2 " + colour + "\n", MeshFormat::Off)
            .Get<Polygon>()[0]
            .material.reflectance;
    };
    CHECK(rho("255 0 0") == 255 / (3 * 255.0));
    CHECK(rho("255 0 0 128") == 255 / (3 * 255.0));
    CHECK(rho("0.2 0.4 0.6") == (0.2 + 0.4 + 0.6) / 3);
    CHECK(rho("1 0 0.5 1") == (1 + 0 + 0.5) / 3);
    CHECK(rho("1 1 1.0") == kMeshMaxReflectance);
    CHECK(rho("1 0 0") == 1 / (3 * 255.0));  // integers only: 0..255
    // The colour itself is kept for display, scaled to [0, 1] and not capped.
    auto colour = [](const std::string &colour) {
        return Parse(kTriangleOff + "3 0 1 2 " + colour + "\n", MeshFormat::Off)
            .Get<Polygon>()[0]
            .material.DisplayColour();
    };
    CHECK(colour("255 0 51 128") == Rgb{1, 0, 51 / 255.0});
    CHECK(colour("0.2 0.4 0.6") == Rgb{0.2, 0.4, 0.6});
    CHECK(colour("1 1 1.0") == Rgb{1, 1, 1});
    CHECK(colour("") == Rgb{kMeshDefaultReflectance, kMeshDefaultReflectance,
                            kMeshDefaultReflectance});  // none: grey of the reflectance
    CHECK(Parse("COFF\n3 1 0\n0 0 0 1 2 3\n1 0 0 0.5 0.5 0.5 1\n0 1 0\n3 0 1 2\n", MeshFormat::Off)
              .NumPatches() == 1);
}

TEST_CASE("Hostile OFF files are refused with one line naming the file and line", "[mesh]") {
    const std::string at = "mesh file 't.off', ";
    SECTION("header") {
        CHECK(OffError("") == at + "line 1: the file is empty");
        CHECK(OffError("# nothing\n\n") ==
              at + "line 3: no OFF header: the file holds only comments and blank lines");
        CHECK(OffError("solid ascii\n") ==
              at + "line 1: not an OFF file: it starts with 'solid' instead of OFF or COFF");
        CHECK(OffError("NOFF\n3 1 0\n") ==
              at + "line 1: 'NOFF' files are not supported (only OFF and COFF)");
        CHECK(OffError("STOFF\n3 1 0\n") ==
              at + "line 1: 'STOFF' files are not supported (only OFF and COFF)");
        CHECK(OffError("OFF BINARY\n\x03\x01") ==
              at + "line 1: binary OFF files are not supported");
        CHECK(OffError("OFF\n") == at + "line 2: truncated: the file ends before the counts of "
                                        "vertices, faces and edges");
        CHECK(OffError("OFF\n3 1\n") ==
              at + "line 2: the counts line needs 3 numbers (vertices faces edges), not 2");
        CHECK(OffError(kTriangleOff.substr(0, 4) + "3 0 0\n0 0 0\n1 0 0\n0 1 0\n") ==
              at + "line 2: the header announces no faces");
    }
    SECTION("counts") {
        CHECK(OffError("COFF\n4 4 1e400\n0 0 0 128 128 128\n") ==
              at + "line 2: edge count '1e400' overflows double precision (largest 1.8e308)");
        CHECK(OffError("OFF\n-3 1 0\n") == at + "line 2: vertex count '-3' is negative");
        CHECK(OffError("OFF\n3 1.5 0\n") == at + "line 2: face count '1.5' is not an integer");
        CHECK(OffError("OFF\n3 99999999999999999999 0\n") ==
              at + "line 2: face count '99999999999999999999' is too large");
        CHECK(OffError("OFF\n1000000000 1 0\n0 0 0\n") ==
              at + "line 2: truncated: announces 1000000000 vertices but has only 6 bytes left");
        CHECK(OffError("OFF\n3 1000000 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n") ==
              at + "line 2: truncated: announces 1000000 faces but has only 8 bytes left after the "
                   "vertices");
    }
    SECTION("vertices") {
        CHECK(OffError("OFF\n3 1 0\n1e400 0 0\n1 0 0\n0 1 0\n3 0 1 2\n") ==
              at + "line 3: coordinate '1e400' overflows double precision (largest 1.8e308)");
        CHECK(OffError("OFF\n3 1 0\n0 0 0\n1 0 x\n0 1 0\n3 0 1 2\n") ==
              at + "line 4: coordinate 'x' is not a number");
        CHECK(OffError("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 inf\n3 0 1 2\n") ==
              at + "line 5: coordinate 'inf' is not finite");
        CHECK(OffError("OFF\n3 1 0\n0 0 0\n1 0\n0 1 0\n3 0 1 2\n") ==
              at + "line 4: a vertex needs 3 coordinates, this line has 2 values (vertex colours "
                   "need the COFF keyword)");
        CHECK(OffError("OFF\n3 1 0\n0 0 0 255 0 0\n1 0 0\n0 1 0\n3 0 1 2\n") ==
              at + "line 3: a vertex needs 3 coordinates, this line has 6 values (vertex colours "
                   "need the COFF keyword)");
        CHECK(OffError("COFF\n3 1 0\n0 0 0 255 0\n1 0 0\n0 1 0\n3 0 1 2\n") ==
              at + "line 3: a COFF vertex needs 3 coordinates and optionally a colour of 3 or 4 "
                   "values, this line has 5 values");
        CHECK(OffError("OFF\n4 1 0\n0 0 0\n1 0 0\n# no more vertices\n\n\n\n\n") ==
              at + "line 10: truncated: the file ends after 2 of the 4 vertices");
    }
    SECTION("faces") {
        CHECK(OffError(kTriangleOff + "-3 0 1 2\n") ==
              at + "line 6: face 1: corner count '-3' is negative");
        CHECK(OffError(kTriangleOff + "3.0 0 1 2\n") ==
              at + "line 6: face 1: corner count '3.0' is not an integer");
        CHECK(OffError(kTriangleOff + "5 0 1 2 0 1\n") ==
              at + "line 6: face 1 has 5 corners (triangles and quads are read as they are; "
                   "--triangulate splits polygons into triangles)");
        CHECK(OffError(kTriangleOff + "2 0 1   \n") ==
              at + "line 6: face 1 has 2 corners (a face needs at least 3)");
        CHECK(OffError(kTriangleOff + "3 0  1\n") ==
              at + "line 6: face 1 announces 3 corners but lists only 2");
        CHECK(OffError(kTriangleOff + "3 0 1 3\n") ==
              at + "line 6: face 1 refers to vertex 3 of 3 (OFF vertices count from 0)");
        CHECK(OffError(kTriangleOff + "3 0 1 -1\n") ==
              at + "line 6: face 1: vertex index '-1' is negative");
        CHECK(OffError(kTriangleOff + "3 0 1 2 1 2\n") ==
              at + "line 6: face 1 has 2 values after its corners; expected none or a colour of "
                   "3 or 4");
        CHECK(OffError(kTriangleOff + "3 0 1 2 300 0 0\n") ==
              at + "line 6: face 1: colour component '300' is outside 0..255");
        CHECK(OffError(kTriangleOff + "3 0 1 2 0.5 1.5 0\n") ==
              at + "line 6: face 1: colour component '1.5' is outside [0, 1] (a colour written "
                   "with fractions is read in 0..1)");
        CHECK(OffError(kTriangleOff + "3 0 1 2 red green blue\n") ==
              at + "line 6: face 1: colour component 'red' is not a number");
        CHECK(OffError("OFF\n3 2 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n") ==
              at + "line 2: truncated: announces 2 faces but has only 8 bytes left after the "
                   "vertices");
        CHECK(OffError("OFF\n3 2 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n# and no more\n") ==
              at + "line 8: truncated: the file ends after 1 of the 2 faces");
        CHECK(OffError("OFF\n3 2 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n3 0 0 1\n") ==
              at + "line 7: face 2 is degenerate (triangle with zero area)");
        CHECK(OffError(kTriangleOff + "3 0 1 2\n3 0 1 2\n") ==
              at + "line 7: unexpected text after the last of the 1 faces");
    }
    SECTION("line endings and bytes") {
        CHECK(OffError("OFF\r3 1 0\r0 0 0\r1 0 0\r0 1 0\r3 0 1 2\r") ==
              at + "line 1: carriage return inside a line (line endings must be \\n or \\r\\n)");
        CHECK(OffError(kTriangleOff + "3 0 1 2\x01\x02\n") ==
              at + "line 6: face 1: vertex index '2\\x01\\x02' is not a number");
        CHECK(OffError(kTriangleOff + "3 0 1 " + std::string(100, '7') + "\n") ==
              at + "line 6: face 1: vertex index '" + std::string(40, '7') + "...' is too large");
    }
}

TEST_CASE("Hostile OBJ files are refused with one line naming the file and line", "[mesh]") {
    const std::string at = "mesh file 't.obj', ";
    SECTION("statements") {
        CHECK(ObjError("") == at + "line 1: the file is empty");
        CHECK(ObjError("# only a comment\n") == at + "line 2: the file has no faces");
        CHECK(ObjError(kTriangleObj) == at + "line 4: the file has no faces");
        CHECK(ObjError(kTriangleObj + "l 1 2\nf 1 2 3\n") ==
              at + "line 4: unsupported statement 'l' (hrbench reads v, f, usemtl and mtllib, "
                   "and ignores vt, vn, vp, o, g and s)");
        CHECK(ObjError(kTriangleObj + "curv 0 1 1 2\n") ==
              at + "line 4: unsupported statement 'curv' (hrbench reads v, f, usemtl and mtllib, "
                   "and ignores vt, vn, vp, o, g and s)");
        CHECK(ObjError(kTriangleObj + "usemtl\nf 1 2 3\n") ==
              at + "line 4: usemtl needs one material name (one word)");
        CHECK(ObjError("mtllib\n" + kTriangleObj + "f 1 2 3\n") ==
              at + "line 1: mtllib needs at least one file name");
    }
    SECTION("vertices") {
        CHECK(ObjError("v 0 0\n") ==
              at + "line 1: a vertex needs 3 coordinates and an optional weight, this line has 2 "
                   "values");
        CHECK(ObjError("v 0 0 0 1 1 1\n") ==
              at + "line 1: a vertex needs 3 coordinates and an optional weight, this line has 6 "
                   "values");
        CHECK(ObjError("v 0 0 -1e400\n") ==
              at + "line 1: coordinate '-1e400' overflows double precision (largest 1.8e308)");
        CHECK(ObjError("v 0 0 0 nan\n") == at + "line 1: weight 'nan' is not finite");
        CHECK(ObjError("v 0 0 1e-400\n") ==
              at + "line 1: coordinate '1e-400' underflows double precision (smallest normal "
                   "2.2e-308)");
        CHECK(ObjError("v 0 0 1e-320\n") ==
              at + "line 1: coordinate '1e-320' underflows double precision (smallest normal "
                   "2.2e-308)");
        CHECK(
            Parse("v 0 0 -0.0\nv 1 0 0\nv 0 1 2.3e-308\nf 1 2 3\n", MeshFormat::Obj).NumPatches() ==
            1);
    }
    SECTION("faces") {
        const std::string corner = " is not a corner: i, i/t, i/t/n or i//n with integers "
                                   "counting from 1 (or back from -1)";
        CHECK(ObjError(kTriangleObj + "f 1 2 3 x\n") == at + "line 4: face 1: 'x'" + corner);
        CHECK(ObjError(kTriangleObj + "f 0 1 2\n") == at + "line 4: face 1: '0'" + corner);
        CHECK(ObjError(kTriangleObj + "f 1 2 3.0\n") == at + "line 4: face 1: '3.0'" + corner);
        CHECK(ObjError(kTriangleObj + "f 1 2 3/\n") == at + "line 4: face 1: '3/'" + corner);
        CHECK(ObjError(kTriangleObj + "f 1 2 3/1/1/1\n") ==
              at + "line 4: face 1: '3/1/1/1'" + corner);
        CHECK(ObjError(kTriangleObj + "f 1 2 4\n") ==
              at + "line 4: face 1 refers to vertex 4 of 3 defined so far");
        CHECK(ObjError(kTriangleObj + "f 1 2 99999999999999999999999\n") ==
              at + "line 4: face 1 refers to vertex 99999999999999999999999 of 3 defined so far");
        CHECK(ObjError(kTriangleObj + "f 1/1 2/1 3/1\n") ==
              at + "line 4: face 1 refers to texture coordinate 1 of 0 defined so far");
        CHECK(ObjError(kTriangleObj + "vn 0 0 1\nf 1//1 2//1 3//2\n") ==
              at + "line 5: face 1 refers to normal 2 of 1 defined so far");
        CHECK(ObjError("f 1 2 3\n" + kTriangleObj) ==
              at + "line 1: face 1 refers to vertex 1 of 0 defined so far");
        CHECK(ObjError(kTriangleObj + "f 1 2\n") ==
              at + "line 4: face 1 has 2 corners (a face needs at least 3)");
        CHECK(ObjError(kTriangleObj + "f 1 2 3\nf 1 1 2\n") ==
              at + "line 5: face 2 is degenerate (triangle with zero area)");
    }
}

TEST_CASE("MTL libraries are read strictly, and a missing one gives the defaults", "[mesh]") {
    const std::string obj = "mtllib a.mtl\n" + kTriangleObj + "usemtl red\nf 1 2 3\n";
    auto rho = [&](const std::string &mtl) {
        return Parse(obj, MeshFormat::Obj, {{"a.mtl", mtl}}).Get<Polygon>()[0].material;
    };
    CHECK(rho("newmtl red\nKd 0.3\n").reflectance == (0.3 + 0.3 + 0.3) / 3);
    // Kd is kept as the display colour, each component clamped to [0, 1].
    CHECK(rho("newmtl red\nKd 0.3\n").colour == Rgb{0.3, 0.3, 0.3});
    CHECK(rho("newmtl red\nKd 0.1 0.2 0.3\n").colour == Rgb{0.1, 0.2, 0.3});
    CHECK(rho("newmtl red\nKd 2 -1 0.5\n").colour == Rgb{1, 0, 0.5});
    CHECK_FALSE(rho("newmtl red\nKe 1 1 1\n").colour);
    CHECK(rho("newmtl red\nKd 0.1 0.2 0.3\nKe 1 2 3\n").emission == 2);
    CHECK(rho("# standard statements\nnewmtl red\nKa 1 1 1\nKs 0 0 0\nNs 10\nNi 1.5\nd 1\n"
              "illum 2\nmap_Kd red.png\nbump b.png\nKd 2 2 2\n")
              .reflectance == kMeshMaxReflectance);
    CHECK(rho("newmtl blue\nKd 0.1 0.1 0.1\n").reflectance == kMeshDefaultReflectance);
    CHECK(Parse(obj, MeshFormat::Obj).Get<Polygon>()[0].material.reflectance ==
          kMeshDefaultReflectance);  // missing library
    CHECK(Parse(obj, MeshFormat::Obj, {}).NumPatches() == 1);

    auto error = [&](const std::string &mtl) {
        return ParseError(obj, MeshFormat::Obj, {{"a.mtl", mtl}});
    };
    const std::string at = "material library 'a.mtl', ";
    CHECK(error("newmtl red\nKd 1 1 1\nnewmtl red\n") ==
          at + "line 3: material 'red' is defined twice (first on line 1)");
    CHECK(ParseError("mtllib a.mtl b.mtl\n" + kTriangleObj + "f 1 2 3\n", MeshFormat::Obj,
                     {{"a.mtl", "newmtl red\n"}, {"b.mtl", "\nnewmtl red\n"}}) ==
          "material library 'b.mtl', line 2: material 'red' is defined twice (first in material "
          "library 'a.mtl', on line 1)");
    CHECK(ParseError("mtllib a.mtl\nmtllib a.mtl\n" + kTriangleObj + "f 1 2 3\n", MeshFormat::Obj,
                     {{"a.mtl", "newmtl red\n"}}) == "no error");  // read once
    CHECK(error("Kd 1 1 1\n") == at + "line 1: Kd before any newmtl");
    CHECK(error("newmtl red\nKd 1 1\n") ==
          at + "line 2: Kd needs r g b (or one value for all three), this line has 2 values");
    CHECK(error("newmtl red\nKd spectral red.rfl\n") ==
          at + "line 2: Kd needs r g b (or one value for all three), this line has 2 values");
    CHECK(error("newmtl red\nKe 1 1 1e999\n") ==
          at + "line 2: Ke value '1e999' overflows double precision (largest 1.8e308)");
    CHECK(error("newmtl red\r\nKe -1 0 0\r\n") ==
          at + "line 2: Ke gives a negative emission: the mean of its values is below 0");
    CHECK(error("newmtl red\nKe 1e308 1e308 1.5e308\n") ==
          at + "line 2: Ke values overflow: their mean is not finite");
    CHECK(error("newmtl red green\n") == at + "line 1: newmtl needs one material name (one word)");
    CHECK(error("newmtl red\nfoo 1\n") ==
          at + "line 2: unsupported statement 'foo' (hrbench reads newmtl, Kd and Ke, and "
               "ignores the other standard statements)");
}

TEST_CASE("Mesh files and libraries are read within the input limit, never a folder", "[mesh]") {
    ScratchFolder folder("folder.off");
    CHECK(LoadError(folder.path) ==
          "cannot read mesh file '" + folder.path + "': it is a directory");

    ScratchFile coff("coff.off", "COFF\n4 4 1e400\n0 0 0 128 128 128\n");
    CHECK(LoadError(coff.path) ==
          "mesh file '" + coff.path +
              "', line 2: edge count '1e400' overflows double precision (largest 1.8e308)");

    std::string bigText = kTriangleOff + "3 0 1 2\n" + std::string(1 << 20, '#');
    ScratchFile big("big.off", bigText);
    CHECK(LoadError(big.path, 1 << 20) ==
          "mesh file '" + big.path + "' has " + std::to_string(bigText.size()) +
              " bytes, more than the input limit of 1 MiB; raise it with --max-input MIB");
    CHECK(LoadMesh(big.path, 2 << 20).NumPatches() == 1);

    // Libraries: next to the OBJ, missing means defaults, a folder or one too big is refused.
    ScratchFolder dir("libraries");
    std::string objPath = dir.path + "/m.obj";
    std::ofstream(objPath) << "mtllib lib.mtl\n" << kTriangleObj << "usemtl red\nf 1 2 3\n";
    CHECK(LoadMesh(objPath).Get<Polygon>()[0].material.reflectance == kMeshDefaultReflectance);
    std::filesystem::create_directory(dir.path + "/lib.mtl");
    CHECK(LoadError(objPath) == "mesh file '" + objPath +
                                    "', line 1: cannot read material library '" + dir.path +
                                    "/lib.mtl': it is a directory");
    std::filesystem::remove(dir.path + "/lib.mtl");
    std::ofstream(dir.path + "/lib.mtl") << "newmtl red\nKd 0.2 0.2 0.2\n"
                                         << std::string(1 << 20, '#');
    CHECK(LoadMesh(objPath, 2 << 20).Get<Polygon>()[0].material.reflectance == 0.2);
    CHECK_THAT(LoadError(objPath, 1 << 20),
               Catch::StartsWith("mesh file '" + objPath + "', line 1: material library '" +
                                 dir.path + "/lib.mtl' has "));
}

// ---------------------------------------------------------------------------------------
// --triangulate and --scale (docs/3d.md, "Mesh input")

namespace {

const MeshOptions kTriangulate{true, 1};

// ParseMesh on _text_ as 't.obj' or 't.off' with _options_ and no material library.
Scene ParseWith(const std::string &text, MeshFormat format, const MeshOptions &options) {
    return ParseMesh(text, format, format == MeshFormat::Off ? "t.off" : "t.obj", {}, options);
}

// The one-line error of ParseWith, or "no error".
std::string ErrorWith(const std::string &text, MeshFormat format, const MeshOptions &options) {
    try {
        ParseWith(text, format, options);
    } catch (const InputError &e) {
        return e.what();
    }
    return "no error";
}

// Expects _patch_ to be the triangle a b c, corners in that order.
void CheckTriangle(const Patch<Polygon> &patch, const Vec3 &a, const Vec3 &b, const Vec3 &c) {
    REQUIRE(patch.shape.n == 3);
    CHECK(patch.shape.v[0] == a);
    CHECK(patch.shape.v[1] == b);
    CHECK(patch.shape.v[2] == c);
}

double TotalArea(const Patches<Polygon> &patches) {
    double sum = 0;
    for (const Patch<Polygon> &p : patches)
        sum += p.shape.Area();
    return sum;
}

}  // namespace

TEST_CASE("Option --triangulate splits a quad that is not planar along its shorter diagonal",
          "[mesh]") {
    // A B C D with C lifted by 0.1: BD (length sqrt 5) is shorter than AC (sqrt 5.01), so
    // the fan from B: (B, C, D) of area |(0,1,0.1) x (-2,1,0)| / 2 = sqrt(4.05) / 2, and
    // (B, D, A) of area 1. The face's colour (255 0 0: reflectance 1/3) goes to both.
    const Vec3 a(0, 0, 0), b(2, 0, 0), c(2, 1, 0.1), d(0, 1, 0);
    const std::string off = "OFF\n4 1 0\n0 0 0\n2 0 0\n2 1 0.1\n0 1 0\n4 0 1 2 3 255 0 0\n";
    Patches<Polygon> p = ParseWith(off, MeshFormat::Off, kTriangulate).Get<Polygon>();
    REQUIRE(p.size() == 2);
    CheckTriangle(p[0], b, c, d);
    CheckTriangle(p[1], b, d, a);
    CHECK(p[0].shape.Area() == Approx(std::sqrt(4.05) / 2).epsilon(1e-14));
    CHECK(p[1].shape.Area() == Approx(1).epsilon(1e-14));
    for (const Patch<Polygon> &t : p)
        CHECK(t.material.reflectance == Approx(1.0 / 3).epsilon(1e-14));

    // Diagonals of equal length (both sqrt 2): v0v2, the fan from A, (A B C) and (A C D).
    const Vec3 e(0, 0, 0), f(1, 0, 1), g(1, 1, 0), h(0, 1, 1);
    Patches<Polygon> tie =
        ParseWith("v 0 0 0\nv 1 0 1\nv 1 1 0\nv 0 1 1\nf 1 2 3 4\n", MeshFormat::Obj, kTriangulate)
            .Get<Polygon>();
    REQUIRE(tie.size() == 2);
    CheckTriangle(tie[0], e, f, g);
    CheckTriangle(tie[1], e, g, h);

    // Without --triangulate: the line, the face, the measure and the tolerance. The four
    // corners lie 0.1 / |(-0.1, -0.2, 4)| = 0.02496 off their mean plane; the diameter
    // is |AC| = sqrt(5.01) = 2.2383.
    CHECK(ObjError("# a twisted quad\nv 0 0 0\nv 2 0 0\nv 2 1 0.1\nv 0 1 0\nf 1 2 3 4\n") ==
          "mesh file 't.obj', line 6: face 1 is not planar: its corners lie 0.025 off their "
          "mean plane, 0.0112 of the face's diameter 2.24 (tolerance 1e-06 of the diameter); "
          "--triangulate splits it into triangles");
}

TEST_CASE("Option --triangulate keeps triangles and valid quads, and splits n-gons", "[mesh]") {
    // A planar convex quad and a triangle stay as they are.
    Scene plates = LoadMesh(kData + "/two_plates.obj");
    CheckSameFaces(LoadMesh(kData + "/two_plates.obj", kDefaultMaxInputBytes, kTriangulate),
                   plates);
    CHECK(ParseWith(kTriangleObj + "f 1 2 3\n", MeshFormat::Obj, kTriangulate).NumPatches() == 1);

    SECTION("a convex pentagon: a fan from its first corner") {
        // Triangles of areas 1, 4 and 2: the pentagon's 7 (shoelace: (0+2+8+4+0) / 2).
        std::string obj = kTriangleObj + "f 1 2 3\nv 0 0 5\nv 2 0 5\nv 3 1 5\nv 1 3 5\n"
                                         "v -1 1 5\nf -5 -4 -3 -2 -1\n";
        Patches<Polygon> p = ParseWith(obj, MeshFormat::Obj, kTriangulate).Get<Polygon>();
        REQUIRE(p.size() == 4);
        const Vec3 v0(0, 0, 5), v1(2, 0, 5), v2(3, 1, 5), v3(1, 3, 5), v4(-1, 1, 5);
        CheckTriangle(p[1], v0, v1, v2);
        CheckTriangle(p[2], v0, v2, v3);
        CheckTriangle(p[3], v0, v3, v4);
        CHECK(p[1].shape.Area() == 1);
        CHECK(p[2].shape.Area() == 4);
        CHECK(p[3].shape.Area() == 2);
        CHECK(ObjError(obj) == "mesh file 't.obj', line 10: face 2 has 5 corners (triangles and "
                               "quads are read as they are; --triangulate splits polygons into "
                               "triangles)");
    }
    SECTION("a non-convex hexagon: ear clipping") {
        // An L of area 3 with its reflex corner at v3 = (1, 1): the walk cuts v1, is sent
        // back to v0 (not an ear: v3 lies in v5 v0 v2), cuts v2, then v0; v3 v4 v5 remain.
        std::string off = "OFF\n6 1 0\n0 0 0\n2 0 0\n2 1 0\n1 1 0\n1 2 0\n0 2 0\n"
                          "6 0 1 2 3 4 5\n";
        Patches<Polygon> p = ParseWith(off, MeshFormat::Off, kTriangulate).Get<Polygon>();
        REQUIRE(p.size() == 4);
        const Vec3 v0(0, 0, 0), v1(2, 0, 0), v2(2, 1, 0), v3(1, 1, 0), v4(1, 2, 0), v5(0, 2, 0);
        CheckTriangle(p[0], v0, v1, v2);
        CheckTriangle(p[1], v0, v2, v3);
        CheckTriangle(p[2], v5, v0, v3);
        CheckTriangle(p[3], v3, v4, v5);
        CHECK(TotalArea(p) == 3);
    }
    SECTION("a quad with a straight corner: ear clipping") {
        Patches<Polygon> p = ParseWith("v 0 0 0\nv 1 0 0\nv 2 0 0\nv 1 1 0\nf 1 2 3 4\n",
                                       MeshFormat::Obj, kTriangulate)
                                 .Get<Polygon>();
        REQUIRE(p.size() == 2);
        CheckTriangle(p[0], Vec3(1, 1, 0), Vec3(0, 0, 0), Vec3(1, 0, 0));
        CheckTriangle(p[1], Vec3(1, 0, 0), Vec3(2, 0, 0), Vec3(1, 1, 0));
        CHECK(ObjError("v 0 0 0\nv 1 0 0\nv 2 0 0\nv 1 1 0\nf 1 2 3 4\n") ==
              "mesh file 't.obj', line 5: face 1 is not a convex quad: corner 2 turns the wrong "
              "way or goes straight on; --triangulate splits it into triangles");
    }
    SECTION("faces that cannot be triangulated") {
        // A pentagram: its edges cross.
        CHECK(ErrorWith("v 0 10 0\nv 6 -8 0\nv -10 3 0\nv 10 3 0\nv -6 -8 0\nf 1 2 3 4 5\n",
                        MeshFormat::Obj, kTriangulate) ==
              "mesh file 't.obj', line 6: face 1 is not a simple polygon seen along its normal "
              "(two edges cross or touch, or a corner repeats), so it cannot be triangulated");
        CHECK(ErrorWith("v 0 0 0\nv 1 0 0\nv 2 0 0\nv 3 0 0\nv 4 0 0\nf 1 2 3 4 5\n",
                        MeshFormat::Obj, kTriangulate) ==
              "mesh file 't.obj', line 6: face 1 is degenerate (its area is zero), so it cannot "
              "be triangulated");
        // Faces keep their number in the file after a face split into triangles.
        CHECK(ErrorWith("v 0 0 0\nv 2 0 0\nv 3 1 0\nv 1 3 0\nv -1 1 0\nf 1 2 3 4 5\n"
                        "f 1 1 2\n",
                        MeshFormat::Obj, kTriangulate) ==
              "mesh file 't.obj', line 7: face 2 is degenerate (triangle with zero area)");
        CHECK(ErrorWith("OFF\n5 2 0\n0 0 0\n2 0 0\n3 1 0\n1 3 0\n-1 1 0\n5 0 1 2 3 4\n"
                        "3 0 1 9\n",
                        MeshFormat::Off, kTriangulate) ==
              "mesh file 't.off', line 9: face 2 refers to vertex 9 of 5 (OFF vertices count "
              "from 0)");
        // A bow tie is refused as before: its area is zero.
        CHECK(ErrorWith("v 0 0 0\nv 1 1 0\nv 1 0 0\nv 0 1 0\nf 1 2 3 4\n", MeshFormat::Obj,
                        kTriangulate) == "mesh file 't.obj', line 5: face 1 is degenerate or "
                                         "self-intersecting (quad with zero area)");
    }
}

TEST_CASE("Option --scale multiplies every coordinate, within double precision", "[mesh]") {
    Scene scaled = ParseWith("v 1000 0 0\nv 0 1000 0\nv 0 0 0\nf 3 1 2\n", MeshFormat::Obj,
                             MeshOptions{false, 0.001});
    const Polygon &t = scaled.Get<Polygon>()[0].shape;
    CHECK(t.v[0] == Vec3(0, 0, 0));
    CHECK(t.v[1] == Vec3(1, 0, 0));  // 1000 * 0.001 rounds to 1 exactly
    CHECK(t.v[2] == Vec3(0, 1, 0));
    CHECK(scaled.params == ParamMap{{"scale", 0.001}});
    CHECK(ParseWith(kTriangleObj + "f 1 2 3\n", MeshFormat::Obj, kTriangulate).params ==
          ParamMap{{"triangulate", 1}});
    CHECK(Parse(kTriangleObj + "f 1 2 3\n", MeshFormat::Obj).params.empty());

    // Doubling is exact: every corner of the OFF file, times 2.
    Scene plain = LoadMesh(kData + "/tetra_colours.off");
    Scene doubled = LoadMesh(kData + "/tetra_colours.off", kDefaultMaxInputBytes, {false, 2});
    for (size_t k = 0; k < plain.NumPatches(); ++k)
        for (int v = 0; v < 3; ++v)
            CHECK(doubled.Get<Polygon>()[k].shape.v[v] == 2 * plain.Get<Polygon>()[k].shape.v[v]);

    CHECK(ErrorWith("OFF\n3 1 0\n1e300 0 0\n1 0 0\n0 1 0\n3 0 1 2\n", MeshFormat::Off,
                    {false, 1e10}) ==
          "mesh file 't.off', line 3: coordinate '1e300' times the scale 1e+10 overflows "
          "double precision (largest 1.8e308)");
    CHECK(ErrorWith("v 1 0 0\nv 0 1e-300 0\nv 0 0 0\nf 1 2 3\n", MeshFormat::Obj, {false, 1e-10}) ==
          "mesh file 't.obj', line 2: coordinate '1e-300' times the scale 1e-10 underflows "
          "double precision (smallest normal 2.2e-308)");
    for (double bad : {0.0, -1.0, std::numeric_limits<double>::infinity()})
        CHECK(ErrorWith(kTriangleObj + "f 1 2 3\n", MeshFormat::Obj, {false, bad}) ==
              "the scale of mesh file 't.obj' must be a finite number greater than 0");
}

TEST_CASE("The published Cornell box OBJ files load with --triangulate only", "[mesh]") {
    const std::string dir = kData + "/meshes/";
    SECTION("Morgan McGuire's CornellBox-Original.obj (CRLF lines, with its MTL)") {
        std::string path = dir + "CornellBox-Original.obj";
        // The red left wall: its corners lie 5 mm off one plane.
        CHECK(LoadError(path) == "mesh file '" + path +
                                     "', line 62: face 5 is not planar: its corners lie 0.005 "
                                     "off their mean plane, 0.00176 of the face's diameter 2.84 "
                                     "(tolerance 1e-06 of the diameter); --triangulate splits it "
                                     "into triangles");
        Patches<Polygon> p = LoadMesh(path, kDefaultMaxInputBytes, kTriangulate).Get<Polygon>();
        REQUIRE(p.size() == 19);  // 18 quads, the left wall in two triangles
        // Its diagonal v0v2 (squared length 8.0811) is shorter than v1v3 (8.0819).
        const Vec3 w0(-1.01, 0, 0.99), w1(-0.99, 0, -1.04), w2(-1.02, 1.99, -1.04),
            w3(-1.02, 1.99, 0.99);
        CheckTriangle(p[4], w0, w1, w2);
        CheckTriangle(p[5], w0, w2, w3);
        for (int k : {4, 5})
            CHECK(p[k].material.reflectance == Approx((0.63 + 0.065 + 0.05) / 3));
        CHECK(p[18].material.emission == Approx(11));  // the light: Ke 17 12 4
        for (int k : {0, 1, 2, 3, 6, 18})
            CHECK(p[k].shape.n == 4);
    }
    SECTION("cornell_box.obj of the measured data, in millimetres (its MTL not stored)") {
        std::string path = dir + "cornell_box.obj";
        CHECK(LoadError(path) == "mesh file '" + path +
                                     "', line 77: face 8 is not planar: its corners lie 0.8 off "
                                     "their mean plane, 0.00102 of the face's diameter 784 "
                                     "(tolerance 1e-06 of the diameter); --triangulate splits it "
                                     "into triangles");
        Scene scene = LoadMesh(path, kDefaultMaxInputBytes, {true, 0.001});
        Patches<Polygon> p = scene.Get<Polygon>();
        REQUIRE(p.size() == 19);  // 18 quads, the red wall in two triangles
        CHECK(p[7].shape.n == 3);
        CHECK(p[8].shape.n == 3);
        CHECK(p[0].shape.v[3] == Vec3(549.6 * 0.001, 0, 559.2 * 0.001));  // mm read as metres
        for (const Patch<Polygon> &patch : p)
            CHECK(patch.material.reflectance == kMeshDefaultReflectance);
        CHECK(scene.warnings == std::vector<std::string>{
                                    "mesh file '" + path + "', line 8: material library '" + dir +
                                    "cornell_box.mtl' does not exist: the faces of its "
                                    "materials get the default reflectance 0.5 and emission "
                                    "0"});
    }
}
