#include "hrbench/scene.h"

#include <cmath>

#include "hrbench/util/error.h"

namespace hrbench {

static void ValidateMaterial(const Material &m, const std::string &name, bool reflectance) {
    if (reflectance && !(m.reflectance >= 0 && m.reflectance < 1))
        throw InputError(name + " has reflectance outside [0, 1)");
    if (!(m.emission >= 0) || !std::isfinite(m.emission))
        throw InputError(name + " has emission that is negative or not finite");
    if (m.colour)
        for (double c : *m.colour)
            if (!(c >= 0 && c <= 1))
                throw InputError(name + " has a colour component outside [0, 1]");
}

void ValidateScene(const Scene &scene, bool reflectance) {
    std::visit(
        [&](const auto &patches) {
            if (patches.empty())
                throw InputError("scene has no patches");
            for (size_t k = 0; k < patches.size(); ++k) {
                std::string name = "patch " + std::to_string(k);
                std::string problem = patches[k].shape.Problem();
                if (!problem.empty())
                    throw InputError(name + " " + problem);
                ValidateMaterial(patches[k].material, name, reflectance);
            }
        },
        scene.patches);
}

}  // namespace hrbench
