#include "hrbench/refine_options.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>

#include "hrbench/link_buffer.h"
#include "hrbench/oracles/registry.h"
#include "hrbench/scene.h"
#include "hrbench/util/error.h"
#include "util/named.h"

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

const std::vector<ClusterBoundInfo> &ClusterBounds() {
    static const std::vector<ClusterBoundInfo> bounds = {
        {"cluster", "a link may join two clusters, bounded from both ends' balls",
         ClusterBound::Cluster},
        {"patch", "one end of a link above the patches is a patch, bounded from its own ball",
         ClusterBound::Patch},
    };
    return bounds;
}

ClusterBound ParseClusterBound(const std::string &name) {
    return FindNamed(ClusterBounds(), name, "cluster bound").bound;
}

std::string ClusterBoundName(ClusterBound bound) {
    return NameOf(ClusterBounds(), &ClusterBoundInfo::bound, bound);
}

void ThrowSafetyDepth(uint64_t p, uint64_t q) {
    throw LimitError("refinement of patches " + std::to_string(p) + " and " + std::to_string(q) +
                     " reached the safety depth " + std::to_string(kSafetyDepth) +
                     " without an acceptable link; set a recursion limit with --min-area or "
                     "--max-depth");
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
    CheckSubdivision(o.subdivision, dimension);
}

std::string MinAreaWarning(const Scene &scene, const RefineOptions &options) {
    if (!(options.minArea > 0))
        return "";
    double largest = std::visit(
        [](const auto &patches) {
            double measure = 0;
            for (const auto &patch : patches)
                measure = std::max(measure, patch.shape.Measure());
            return measure;
        },
        scene.patches);
    std::string size = scene.Dimension() == 2 ? "length" : "area";
    std::string units = " (are the scene and --min-area in the same units? --scale rescales a "
                        "mesh)";
    auto shown = [](double value) {
        char text[32];
        std::snprintf(text, sizeof text, "%.3g", value);
        return std::string(text);
    };
    if (options.minArea > largest)
        return "--min-area " + shown(options.minArea) + " exceeds the largest patch's " + size +
               ", " + shown(largest) + ": no element will be split" + units;
    if (options.minArea < kMinAreaWarnFraction * largest)
        return "--min-area " + shown(options.minArea) + " is below " + shown(kMinAreaWarnFraction) +
               " of the largest patch's " + size + ", " + shown(largest) +
               ": elements may be halved " +
               std::to_string(int(std::ceil(std::log2(largest) - std::log2(options.minArea)))) +
               " times before it applies" + units;
    return "";
}

size_t EffectiveBudget(const RefineOptions &options) {
    return options.memoryBudget > 0 ? options.memoryBudget : AvailableMemoryBytes() / 10 * 9;
}

size_t StoredLinkBytes(const RefineOptions &options) {
    return sizeof(Link) + (options.visibility != VisibilityMode::None ? sizeof(double) : 0);
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
