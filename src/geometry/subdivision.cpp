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

}  // namespace hrbench
