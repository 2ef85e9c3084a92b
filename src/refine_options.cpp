#include "hrbench/refine_options.h"

#include <cmath>
#include <fstream>

#include "hrbench/oracles/registry.h"
#include "hrbench/util/error.h"

namespace hrbench {

std::string VisibilityName(VisibilityMode mode) {
    switch (mode) {
    case VisibilityMode::None:
        return "none";
    case VisibilityMode::Fraction:
        return "fraction";
    case VisibilityMode::Refine:
        return "refine";
    }
    return "unknown";
}

VisibilityMode ParseVisibility(const std::string &name) {
    if (name == "none")
        return VisibilityMode::None;
    if (name == "fraction")
        return VisibilityMode::Fraction;
    if (name == "refine")
        return VisibilityMode::Refine;
    throw InputError("unknown visibility mode '" + name + "' (choose none, fraction or refine)");
}

void ValidateOptions(const RefineOptions &o, int dimension) {
    const OracleInfo &oracle = FindOracle(o.oracle);
    if (!oracle.Supports(dimension))
        throw InputError("oracle " + o.oracle + " does not support " + std::to_string(dimension) +
                         "D scenes");
    if (!(o.eps > 0) || !std::isfinite(o.eps))
        throw InputError("--eps must be a finite number greater than 0");
    if (!(o.minArea >= 0) || !std::isfinite(o.minArea))
        throw InputError("--min-area must be a finite number >= 0");
    if (o.maxDepth < -1 || o.maxDepth > kSafetyDepth)
        throw InputError("--max-depth must be between 0 and " + std::to_string(kSafetyDepth));
    if (o.threads < 1 || o.threads > 256)
        throw InputError("--threads must be between 1 and 256");
    if (o.raysPerSide < 1 || o.raysPerSide > 16)
        throw InputError("--rays-per-side must be between 1 and 16");
    if (o.visibility == VisibilityMode::Refine && !o.HasRecursionLimit())
        throw InputError("--visibility refine splits partially visible pairs down to the "
                         "recursion limit; set one with --min-area or --max-depth");
    if (dimension == 2 && o.subdivision != Subdivision::Binary)
        throw InputError("--subdivision quadtree applies to 3D scenes only (segments are halved)");
}

size_t EffectiveBudget(const RefineOptions &options) {
    return options.memoryBudget > 0 ? options.memoryBudget : AvailableMemoryBytes() / 10 * 9;
}

size_t AvailableMemoryBytes() {
    std::ifstream meminfo("/proc/meminfo");
    std::string key;
    size_t kib = 0;
    while (meminfo >> key >> kib) {
        if (key == "MemAvailable:")
            return kib * 1024;
        meminfo.ignore(256, '\n');
    }
    return size_t(4) << 30;  // 4 GiB when the system does not say
}

}  // namespace hrbench
