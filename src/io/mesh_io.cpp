// The public interface of mesh_io.h: the format by extension, the file and its
// libraries read, the patches validated; the formats themselves in off.cpp and obj.cpp.
#include "hrbench/mesh_io.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <utility>

#include "formats.h"
#include "hrbench/util/error.h"
#include "hrbench/util/input_file.h"

namespace hrbench {

using meshio::LibraryReader;

namespace {

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

}  // namespace

namespace meshio {

std::string Directory(const std::string &path) {
    size_t slash = path.find_last_of('/');
    return slash == std::string::npos ? "" : path.substr(0, slash + 1);
}

}  // namespace meshio

Scene ParseMesh(const std::string &text, MeshFormat format, const std::string &source,
                const LibraryReader &readMaterialLibrary, const MeshOptions &options) {
    if (!(options.scale > 0) || !std::isfinite(options.scale))
        throw InputError("the scale of mesh file '" + source +
                         "' must be a finite number greater than 0");
    meshio::MeshPatches read = format == MeshFormat::Off
                                   ? meshio::ReadOff(text, source, options)
                                   : meshio::ReadObj(text, source, readMaterialLibrary, options);
    Scene scene;
    scene.family = "mesh";
    scene.file = source;
    if (options.scale != 1)
        scene.params["scale"] = options.scale;
    if (options.triangulate)
        scene.params["triangulate"] = 1;
    scene.patches = std::move(read.patches);  // a copy would double the memory of a large mesh
    scene.warnings = std::move(read.warnings);
    // The readers check each face where they read it; this keeps the scene contract
    // should ValidateScene come to check more, naming the face's line.
    try {
        ValidateScene(scene);
    } catch (const InputError &) {
        const Patches<Polygon> &patches = scene.Get<Polygon>();
        for (size_t k = 0; k < patches.size(); ++k) {
            Scene one;
            one.patches = Patches<Polygon>{patches[k]};
            try {
                ValidateScene(one);
            } catch (const InputError &e) {
                std::string what = e.what(), prefix = "patch 0 ";
                if (what.rfind(prefix, 0) == 0)
                    what.erase(0, prefix.size());
                auto [line, face] = read.origins[k];
                throw InputError("mesh file '" + source + "', line " + std::to_string(line) +
                                 ": face " + std::to_string(face) + " " + what);
            }
        }
        throw;
    }
    return scene;
}

Scene LoadMesh(const std::string &path, size_t maxInputBytes, const MeshOptions &options) {
    MeshFormat format = FormatOf(path);
    std::string text = ReadInputFile(path, "mesh file", maxInputBytes);
    // Libraries are relative to the OBJ's real folder: a symbolic link to an OBJ reads
    // those beside its target, where `save --out LINK` writes them.
    std::error_code realError;
    std::string real = std::filesystem::canonical(path, realError).string();
    const std::string folder = meshio::Directory(realError ? path : real);
    auto readLibrary = [&](const std::string &name) -> std::optional<std::string> {
        std::string libraryPath = folder + name;
        std::error_code error;
        if (std::filesystem::status(libraryPath, error).type() ==
            std::filesystem::file_type::not_found)
            return std::nullopt;  // its faces get the defaults, with a warning (docs/3d.md)
        return ReadInputFile(libraryPath, "material library", maxInputBytes);
    };
    return ParseMesh(text, format, path, readLibrary, options);
}

std::string MaterialLibraryPath(const std::string &objPath) {
    return objPath.substr(0, objPath.find_last_of('.')) + ".mtl";
}

void SaveMesh(const Scene &scene, const std::string &path) {
    MeshFormat format = FormatOf(path);
    if (scene.Dimension() != 3)
        throw InputError("only 3D scenes can be written as meshes");
    if (format == MeshFormat::Obj)
        return meshio::SaveObj(scene, path);
    meshio::SaveOff(scene, path);
}

}  // namespace hrbench
