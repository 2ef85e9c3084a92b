// Polygon meshes as 3D scenes: OFF and OBJ files read by our own strict readers, written
// by CGAL's writers (docs/3d.md, "Mesh input").
#pragma once

#include <cstddef>
#include <functional>
#include <optional>
#include <string>

#include "hrbench/scene.h"
#include "hrbench/util/input_file.h"

namespace hrbench {

// Default surface of a face whose file says nothing about it.
constexpr double kMeshDefaultReflectance = 0.5;
constexpr double kMeshDefaultEmission = 0.0;
// Largest reflectance taken from a file's colours: the radiosity system needs rho < 1.
constexpr double kMeshMaxReflectance = 0.99;

// The two mesh formats, chosen by a file's extension (.off or .obj).
enum class MeshFormat { Off, Obj };

// Largest distance of a quad's corner from the quad's mean plane, as a fraction of its
// diameter, for the quad to be a patch (Polygon::Problem).
constexpr double kMeshPlanarityTolerance = 1e-6;

// How a mesh file becomes patches (docs/3d.md, "Mesh input").
struct MeshOptions {
    // Split every face that cannot be a patch as it is (a quad that is not planar or not
    // convex, a polygon of 5 or more corners) into triangles by the documented rule;
    // otherwise such a face is an error.
    bool triangulate = false;
    // Multiplies every coordinate (a finite number > 0): 0.001 reads millimetres as metres.
    double scale = 1;
};

// Reads the OFF or OBJ file at _path_ (chosen by its extension, .off or .obj) as a 3D
// scene: the file and its OBJ material libraries (relative to the OBJ's folder, a missing
// one meaning defaults and a warning) are read with ReadInputFile within _maxInputBytes_
// each, then parsed by ParseMesh. Throws InputError with one line.
Scene LoadMesh(const std::string &path, size_t maxInputBytes = kDefaultMaxInputBytes,
               const MeshOptions &options = {});

// Parses the text of a mesh file as a 3D scene with one patch per face, in file order
// (with _options_.triangulate, a split face gives its triangles in their order).
// Faces must be triangles or planar convex quads, counter-clockwise seen from the front;
// with _options_.triangulate, any polygon that is simple seen along its normal.
// Materials:
//  - OFF: a face colour (r g b [a] after the indices: integers 0..255, or numbers in
//    [0, 1]) gives reflectance mean(r,g,b);
//  - OBJ: `usemtl NAME` selects the material NAME of the `mtllib` libraries read so far:
//    reflectance mean(Kd), emission mean(Ke);
// reflectance capped at kMeshMaxReflectance; defaults otherwise (0.5 and 0, also for an
// unknown material name). _source_ names the file in messages and in Scene::file.
// _readMaterialLibrary_ returns the text of the library an OBJ's `mtllib` names, or
// std::nullopt when it does not exist; an empty function reads no library. A library
// that does not exist, and a `usemtl` name that the libraries read so far do not define
// (where none was missing), are read as the defaults and each adds one line to
// Scene::warnings, naming the file and line. Throws InputError with one line,
// "mesh file 'SOURCE', line N: what is wrong", lines and faces counted from 1 (docs/3d.md
// lists what is refused). A scale or triangulation other than the defaults is recorded in
// Scene::params ("scale", "triangulate" = 1).
Scene ParseMesh(const std::string &text, MeshFormat format, const std::string &source,
                const std::function<std::optional<std::string>(const std::string &mtlName)>
                    &readMaterialLibrary,
                const MeshOptions &options = {});

// Writes the 3D _scene_ to _path_ as OFF or OBJ (by extension) so that LoadMesh reads
// back the same patches, corners in order, exactly. OBJ: with its materials in the MTL
// library MaterialLibraryPath(_path_) (`Kd`: reflectance, `Ke`: emission, as ParseMesh
// reads them; docs/scene-format.md#obj-and-mtl); a reflectance above kMeshMaxReflectance
// is an InputError. OFF: the geometry only.
void SaveMesh(const Scene &scene, const std::string &path);

// The MTL library written beside the OBJ file _objPath_: its name with the extension .mtl.
std::string MaterialLibraryPath(const std::string &objPath);

}  // namespace hrbench
