#include "scene.h"

#include <cmath>

#include "util/error.h"

namespace hrbench {

static bool IsFinite(const Vec2 &p) { return std::isfinite(p.x()) && std::isfinite(p.y()); }

void ValidateScene(const Scene &scene) {
    if (scene.dimension != 2)
        throw InputError("scene has dimension " + std::to_string(scene.dimension) +
                         "; only 2 is supported");
    if (scene.segments.empty())
        throw InputError("scene has no patches");
    for (size_t k = 0; k < scene.segments.size(); ++k) {
        const Segment &s = scene.segments[k];
        std::string name = "patch " + std::to_string(k);
        if (!IsFinite(s.a) || !IsFinite(s.b))
            throw InputError(name + " has a coordinate that is not finite");
        if (s.a == s.b || !(s.Length() > 0) || !std::isfinite(s.Length()))
            throw InputError(name + " is degenerate (its endpoints coincide)");
        const Material &m = s.material;
        if (!(m.reflectance >= 0 && m.reflectance < 1))
            throw InputError(name + " has reflectance outside [0, 1)");
        if (!(m.emission >= 0) || !std::isfinite(m.emission))
            throw InputError(name + " has emission that is negative or not finite");
    }
}

}  // namespace hrbench
