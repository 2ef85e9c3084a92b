#include "hrbench/geometry/subdivision.h"

#include "hrbench/util/error.h"

namespace hrbench {

std::string SubdivisionName(Subdivision mode) {
    return mode == Subdivision::Binary ? "binary" : "quadtree";
}

Subdivision ParseSubdivision(const std::string &name) {
    if (name == "binary")
        return Subdivision::Binary;
    if (name == "quadtree")
        return Subdivision::Quadtree;
    throw InputError("unknown subdivision '" + name + "' (choose binary or quadtree)");
}

void CheckSubdivision(Subdivision mode, int dimension) {
    if (dimension == 2 && mode != Subdivision::Binary)
        throw InputError("--subdivision quadtree applies to 3D scenes only (segments are halved)");
}

}  // namespace hrbench
