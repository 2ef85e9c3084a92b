// The OFF and OBJ readers and writers behind mesh_io.h.
#pragma once

#include <functional>
#include <optional>
#include <string>
#include <string_view>

#include "faces.h"
#include "hrbench/mesh_io.h"

namespace hrbench::meshio {

using LibraryReader = std::function<std::optional<std::string>(const std::string &mtlName)>;

// The folder of _path_ with its trailing slash, or "" for a bare file name.
std::string Directory(const std::string &path);

// The patches of the OFF or COFF _text_ of the file _source_ (ParseMesh).
MeshPatches ReadOff(std::string_view text, const std::string &source, const MeshOptions &options);

// The patches of the OBJ _text_ of the file _source_, its materials read with
// _readLibrary_ (ParseMesh).
MeshPatches ReadObj(std::string_view text, const std::string &source,
                    const LibraryReader &readLibrary, const MeshOptions &options);

// Writes _scene_ as OFF at _path_: the geometry only (SaveMesh).
void SaveOff(const Scene &scene, const std::string &path);

// Writes _scene_ as OBJ at _path_ and its materials as the MTL library beside it
// (docs/scene-format.md#obj-and-mtl): corners shared where equal, faces in scene order
// with their corners in order, one material per distinct surface.
void SaveObj(const Scene &scene, const std::string &path);

}  // namespace hrbench::meshio
