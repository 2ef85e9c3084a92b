// Polygon meshes as 3D scenes: OFF and OBJ files through CGAL's readers and writers
// (docs/3d.md, "Mesh input").
#pragma once

#include <string>

#include "scene.h"

namespace hrbench {

// Default surface of a face whose file says nothing about it.
constexpr double kMeshDefaultReflectance = 0.5;
constexpr double kMeshDefaultEmission = 0.0;
// Largest reflectance taken from a file's colours: the radiosity system needs rho < 1.
constexpr double kMeshMaxReflectance = 0.99;

// Reads the OFF or OBJ file at _path_ (chosen by its extension, .off or .obj) as a 3D
// scene with one patch per face, in file order. Faces must be triangles or planar
// convex quads, counter-clockwise seen from the front. Materials:
//  - OFF: a face colour (r g b after the indices; CGAL reads them from COFF files)
//    gives reflectance mean(r,g,b) / 255;
//  - OBJ: `usemtl NAME` selects the material NAME of the `mtllib` file(s): reflectance
//    mean(Kd), emission mean(Ke);
// reflectance capped at kMeshMaxReflectance; defaults otherwise (0.5 and 0, also when
// the material library is missing). Throws InputError with one line naming the file
// for an unreadable, truncated or empty file, a bad index or face, or bad coordinates.
Scene LoadMesh(const std::string &path);

// Writes the geometry of the 3D _scene_ to _path_ as OFF or OBJ (by extension), with
// 17 significant digits so that it reads back exactly. Materials are not written.
void SaveMesh(const Scene &scene, const std::string &path);

}  // namespace hrbench
