// A scene: the ordered list of root patches that refinement starts from, in one
// dimension: segments (flatland) or polygons (3D).
#pragma once

#include <array>
#include <map>
#include <optional>
#include <string>
#include <type_traits>
#include <variant>
#include <vector>

#include "hrbench/geometry/polygon.h"
#include "hrbench/geometry/segment.h"

namespace hrbench {

// A colour: red, green, blue, each in [0, 1].
using Rgb = std::array<double, 3>;

// Surface properties of a root patch, inherited by all of its elements.
struct Material {
    double reflectance = 0.5;  // rho, in [0, 1)
    double emission = 0.0;     // emitted radiosity E, >= 0
    // The surface's diffuse RGB where the scene gives one (an MTL Kd, an OFF face colour,
    // a scene file's "colour", the cornell family's). For display only: the solve is
    // monochrome and uses _reflectance_.
    std::optional<Rgb> colour{};

    // The colour to show the surface in: _colour_, else grey of the reflectance.
    Rgb DisplayColour() const {
        return colour.value_or(Rgb{reflectance, reflectance, reflectance});
    }
};

// A root patch: its shape and its surface.
template <typename Shape>
struct Patch {
    Shape shape;
    Material material;
};

template <typename Shape>
using Patches = std::vector<Patch<Shape>>;

// The patches of a scene, of one shape for the whole scene.
using AnyPatches = std::variant<Patches<Segment>, Patches<Polygon>>;

// Scene parameters, by name (lengths in scene units, angles in degrees).
using ParamMap = std::map<std::string, double>;

// Scene with its provenance (family and parameters, or the file it was read from) so
// that results explain themselves.
struct Scene {
    std::string family;  // generator family, "file" for a scene file, "mesh" for a mesh
    ParamMap params;     // parameters after defaults
    std::string file;    // the scene or mesh file read, if any
    AnyPatches patches;  // root patches in scene order
    // What the file's reader let pass but found doubtful, one line each naming the file
    // and line (a missing material library, an undefined material): the CLI prints them.
    std::vector<std::string> warnings{};

    // 2 for segments, 3 for polygons.
    int Dimension() const {
        return std::visit(
            [](const auto &p) { return std::decay_t<decltype(p.front().shape)>::kDimension; },
            patches);
    }
    size_t NumPatches() const {
        return std::visit([](const auto &p) { return p.size(); }, patches);
    }
    // The patches, when they are of shape _Shape_ (std::bad_variant_access otherwise).
    template <typename Shape>
    const Patches<Shape> &Get() const {
        return std::get<Patches<Shape>>(patches);
    }
    template <typename Shape>
    Patches<Shape> &Get() {
        return std::get<Patches<Shape>>(patches);
    }
};

// Checks what refinement relies on: at least one patch, every shape valid (see each
// shape's Problem()), materials in range (reflectance only with _reflectance_: no
// oracle reads it, and check-links takes any). Throws InputError naming the patch.
void ValidateScene(const Scene &scene, bool reflectance = true);

// The canonical text of the scene's geometry (docs/scene-format.md#scene-digest): one line
// per root patch in scene order, its corners' coordinates (2D: a then b; 3D: every vertex
// in order) written with "%.17g" (negative zero as 0), separated by one space. Materials
// are left out: the counts depend on the geometry only.
std::string SceneGeometryText(const Scene &scene);

// The SHA-256 of SceneGeometryText as 64 lower-case hexadecimal digits: the run record's
// `scene_sha256`, by which the analysis checks that two engines refine the same patches.
std::string SceneSha256(const Scene &scene);

}  // namespace hrbench
