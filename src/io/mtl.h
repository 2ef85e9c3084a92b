// MTL material libraries of OBJ files: `newmtl`, `Kd` and `Ke` (docs/3d.md, "Mesh input").
#pragma once

#include <map>
#include <string>
#include <string_view>

#include "hrbench/scene.h"

namespace hrbench::meshio {

// The value an MTL `Kd` or `Ke` stands for: the mean of r g b; three equal values (or
// one) give that value exactly, so that SaveMesh's grey values read back unchanged (their
// mean in floating point may differ in the last bit).
double MtlMean(const Rgb &rgb);

// _rho_ in [0, kMeshMaxReflectance], the reflectances the radiosity system admits.
double CappedReflectance(double rho);

// A material of an OBJ's libraries, with where it was defined, for duplicates.
struct DefinedMaterial {
    Material material;
    std::string library;  // "material library 'PATH'"
    size_t line;
};
using Materials = std::map<std::string, DefinedMaterial, std::less<>>;

// Reads the MTL _text_ of _library_ ("material library 'PATH'") into _materials_.
void ReadMaterials(std::string_view text, const std::string &library, Materials &materials);

}  // namespace hrbench::meshio
