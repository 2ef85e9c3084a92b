#include "mesh_io.h"

#include <algorithm>
#include <array>
#include <cctype>
#include <fstream>
#include <iostream>
#include <map>
#include <sstream>
#include <vector>

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/IO/OBJ.h>
#include <CGAL/IO/OFF.h>

#include "util/error.h"

namespace hrbench {

namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point3 = Kernel::Point_3;
using PolygonIndices = std::vector<std::size_t>;

enum class MeshFormat { Off, Obj };

MeshFormat FormatOf(const std::string &path) {
    size_t dot = path.find_last_of('.');
    std::string ext = dot == std::string::npos ? "" : path.substr(dot + 1);
    std::transform(ext.begin(), ext.end(), ext.begin(),
                   [](unsigned char c) { return char(std::tolower(c)); });
    if (ext == "off")
        return MeshFormat::Off;
    if (ext == "obj")
        return MeshFormat::Obj;
    throw InputError("mesh file '" + path + "' must end in .off or .obj");
}

// Silences std::cerr while CGAL's readers run: they print their own diagnostics,
// and an error must be one line of ours.
class QuietCerr {
  public:
    QuietCerr() : saved_(std::cerr.rdbuf(sink_.rdbuf())) {}
    ~QuietCerr() { std::cerr.rdbuf(saved_); }

  private:
    std::ostringstream sink_;
    std::streambuf *saved_;
};

double Mean(const std::array<double, 3> &rgb) { return (rgb[0] + rgb[1] + rgb[2]) / 3; }

double CappedReflectance(double rho) { return std::min(std::max(rho, 0.0), kMeshMaxReflectance); }

std::string Directory(const std::string &path) {
    size_t slash = path.find_last_of('/');
    return slash == std::string::npos ? "" : path.substr(0, slash + 1);
}

// Reads `newmtl`, `Kd` and `Ke` of an MTL file into _materials_; a missing file adds nothing.
void ReadMaterialLibrary(const std::string &path, std::map<std::string, Material> &materials) {
    std::ifstream in(path);
    std::string line, current;
    while (std::getline(in, line)) {
        std::istringstream words(line);
        std::string key;
        if (!(words >> key))
            continue;
        if (key == "newmtl") {
            words >> current;
            materials[current] = {kMeshDefaultReflectance, kMeshDefaultEmission};
        } else if ((key == "Kd" || key == "Ke") && !current.empty()) {
            std::array<double, 3> rgb{};
            if (!(words >> rgb[0]))
                continue;
            if (!(words >> rgb[1] >> rgb[2]))
                rgb[1] = rgb[2] = rgb[0];  // one value stands for all three channels
            if (key == "Kd")
                materials[current].reflectance = CappedReflectance(Mean(rgb));
            else
                materials[current].emission = Mean(rgb);
        }
    }
}

// The material of every `f` line of an OBJ file, in order: the one its last `usemtl`
// names, looked up in the `mtllib` files next to it.
std::vector<Material> ObjFaceMaterials(const std::string &path) {
    std::ifstream in(path);
    std::map<std::string, Material> library;
    std::vector<Material> faces;
    Material current{kMeshDefaultReflectance, kMeshDefaultEmission};
    std::string line;
    while (std::getline(in, line)) {
        std::istringstream words(line);
        std::string key;
        if (!(words >> key))
            continue;
        if (key == "mtllib") {
            for (std::string file; words >> file;)
                ReadMaterialLibrary(Directory(path) + file, library);
        } else if (key == "usemtl") {
            std::string name;
            words >> name;
            auto it = library.find(name);
            current = it != library.end() ? it->second
                                          : Material{kMeshDefaultReflectance, kMeshDefaultEmission};
        } else if (key == "f") {
            faces.push_back(current);
        }
    }
    return faces;
}

}  // namespace

Scene LoadMesh(const std::string &path) {
    MeshFormat format = FormatOf(path);
    std::ifstream in(path, std::ios::binary);
    if (!in)
        throw InputError("cannot read mesh file '" + path + "'");

    // Read the polygon soup with CGAL, and the face colours of an OFF file.
    std::vector<Point3> points;
    std::vector<PolygonIndices> polygons;
    std::vector<CGAL::IO::Color> colors;
    bool ok;
    {
        QuietCerr quiet;
        if (format == MeshFormat::Off)
            ok = CGAL::IO::read_OFF(
                in, points, polygons,
                CGAL::parameters::face_color_output_iterator(std::back_inserter(colors))
                    .verbose(false));
        else
            ok = CGAL::IO::read_OBJ(in, points, polygons, CGAL::parameters::verbose(false));
    }
    std::string name = format == MeshFormat::Off ? "OFF" : "OBJ";
    if (!ok && polygons.empty())
        throw InputError("mesh file '" + path + "' is empty, has no faces or is not an " + name +
                         " file");
    if (!ok)
        throw InputError("mesh file '" + path + "' is truncated or malformed (CGAL's " + name +
                         " reader failed)");
    if (polygons.empty())
        throw InputError("mesh file '" + path + "' has no faces");

    // Check every face before building the scene.
    std::vector<Material> materials(polygons.size(),
                                    Material{kMeshDefaultReflectance, kMeshDefaultEmission});
    if (format == MeshFormat::Obj) {
        std::vector<Material> fromFile = ObjFaceMaterials(path);
        if (fromFile.size() == polygons.size())
            materials = fromFile;
    } else if (colors.size() == polygons.size()) {
        for (size_t f = 0; f < polygons.size(); ++f) {
            const CGAL::IO::Color &c = colors[f];
            materials[f].reflectance = CappedReflectance(
                (double(c.red()) + double(c.green()) + double(c.blue())) / (3 * 255.0));
        }
    }
    Scene scene;
    scene.family = "mesh";
    scene.file = path;
    Patches<Polygon> &faces = scene.patches.emplace<Patches<Polygon>>();
    for (size_t f = 0; f < polygons.size(); ++f) {
        const PolygonIndices &indices = polygons[f];
        std::string where = "mesh file '" + path + "': face " + std::to_string(f);
        if (indices.size() != 3 && indices.size() != 4)
            throw InputError(where + " has " + std::to_string(indices.size()) +
                             " corners (only triangles and quads are supported)");
        Polygon polygon;
        polygon.n = int(indices.size());
        for (size_t k = 0; k < indices.size(); ++k) {
            if (indices[k] >= points.size())
                throw InputError(where + " refers to vertex " + std::to_string(indices[k] + 1) +
                                 " of " + std::to_string(points.size()));
            const Point3 &p = points[indices[k]];
            polygon.v[k] = Vec3(p.x(), p.y(), p.z());
        }
        if (polygon.n == 3)
            polygon.v[3] = polygon.v[2];
        faces.push_back({polygon, materials[f]});
    }
    try {
        ValidateScene(scene);
    } catch (const InputError &e) {
        throw InputError("mesh file '" + path + "': " + e.what());
    }
    return scene;
}

void SaveMesh(const Scene &scene, const std::string &path) {
    MeshFormat format = FormatOf(path);
    if (scene.Dimension() != 3)
        throw InputError("only 3D scenes can be written as meshes");
    std::vector<Point3> points;
    std::vector<PolygonIndices> polygons;
    for (const Patch<Polygon> &f : scene.Get<Polygon>()) {
        PolygonIndices indices;
        for (int k = 0; k < f.shape.n; ++k) {
            indices.push_back(points.size());
            points.emplace_back(f.shape.v[k].x(), f.shape.v[k].y(), f.shape.v[k].z());
        }
        polygons.push_back(indices);
    }
    std::ofstream out(path, std::ios::binary);
    auto np = CGAL::parameters::stream_precision(17);
    bool ok = out && (format == MeshFormat::Off ? CGAL::IO::write_OFF(out, points, polygons, np)
                                                : CGAL::IO::write_OBJ(out, points, polygons, np));
    if (!ok || !out.flush())
        throw InputError("cannot write mesh file '" + path + "'");
}

}  // namespace hrbench
