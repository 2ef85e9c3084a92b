#include "scene.h"

#include <cmath>

#include "util/error.h"

namespace hrbench {

static bool IsFinite(const Vec2 &p) { return std::isfinite(p.x()) && std::isfinite(p.y()); }

static void ValidateMaterial(const Material &m, const std::string &name) {
    if (!(m.reflectance >= 0 && m.reflectance < 1))
        throw InputError(name + " has reflectance outside [0, 1)");
    if (!(m.emission >= 0) || !std::isfinite(m.emission))
        throw InputError(name + " has emission that is negative or not finite");
}

// The 3D part of ValidateScene: every face a valid patch (see PolygonProblem).
static void ValidateFaces(const Scene &scene) {
    if (!scene.segments.empty())
        throw InputError("a 3D scene cannot have 2D patches");
    if (scene.faces.empty())
        throw InputError("scene has no patches");
    for (size_t k = 0; k < scene.faces.size(); ++k) {
        std::string name = "patch " + std::to_string(k);
        std::string problem = PolygonProblem(scene.faces[k].polygon);
        if (!problem.empty())
            throw InputError(name + " " + problem);
        ValidateMaterial(scene.faces[k].material, name);
    }
}

void ValidateScene(const Scene &scene) {
    if (scene.dimension == 3)
        return ValidateFaces(scene);
    if (scene.dimension != 2)
        throw InputError("scene has dimension " + std::to_string(scene.dimension) +
                         "; only 2 and 3 are supported");
    if (!scene.faces.empty())
        throw InputError("a 2D scene cannot have 3D patches");
    if (scene.segments.empty())
        throw InputError("scene has no patches");
    for (size_t k = 0; k < scene.segments.size(); ++k) {
        const Segment &s = scene.segments[k];
        std::string name = "patch " + std::to_string(k);
        if (!IsFinite(s.a) || !IsFinite(s.b))
            throw InputError(name + " has a coordinate that is not finite");
        if (s.a == s.b || !(s.Length() > 0) || !std::isfinite(s.Length()))
            throw InputError(name + " is degenerate (its endpoints coincide)");
        ValidateMaterial(s.material, name);
    }
}

}  // namespace hrbench
