// Faces of a mesh file as patches: as they are, or split into triangles (docs/3d.md,
// "Mesh input").
#pragma once

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "hrbench/mesh_io.h"
#include "hrbench/scene.h"
#include "text_reader.h"

namespace hrbench::meshio {

// Surface of a face whose file says nothing about it.
const Material kDefaultMaterial{kMeshDefaultReflectance, kMeshDefaultEmission};

// The patches read from a mesh file, with the line and the number (from 1) of the face
// each comes from, for messages.
struct MeshPatches {
    Patches<Polygon> patches;
    std::vector<std::pair<size_t, size_t>> origins;  // line, face
    std::vector<std::string> warnings;               // Scene::warnings

    void Reserve(size_t faces) {
        patches.reserve(faces);
        origins.reserve(faces);
    }

    void Add(const Polygon &shape, const Material &material, size_t line, size_t face) {
        patches.push_back({shape, material});
        origins.emplace_back(line, face);
    }
};

// Fails at the current line of _lines_ unless _face_ may have _n_ corners: at least 3,
// and at most 4 unless faces are triangulated.
void CheckCornerCount(const Lines &lines, const std::string &face, uint64_t n, bool triangulate);

// Appends face number _number_ (from 1; _face_ is "face N") with _corners_ (as
// CheckCornerCount allows) to _patches_ with _material_: as it is when it can be a patch
// (Polygon::Problem), split into triangles when _triangulate_ and it is a polygon of 5 or
// more corners or a quad that is not planar or not convex; otherwise fails at the current
// line of _lines_ saying why.
void AddFace(const Lines &lines, size_t number, const std::string &face,
             const std::vector<Vec3> &corners, const Material &material, bool triangulate,
             MeshPatches &patches);

}  // namespace hrbench::meshio
