#include "polygon_forest.h"

#include <algorithm>
#include <cmath>

#include "util/error.h"

namespace hrbench {

PolygonForest::PolygonForest(const Scene &scene, size_t maxElements, Subdivision mode)
    : numRoots_(scene.faces.size()), maxElements_(maxElements), mode_(mode) {
    if (numRoots_ >= (size_t(1) << 31))
        throw InputError("scene has too many patches");
    for (const Face &f : scene.faces) {
        hot_.push_back({f.polygon.Centroid(), f.polygon.Area(), kNoChildren, uint32_t(hot_.size())});
        shape_.push_back(f.polygon);
        depth_.push_back(0);
        parent_.push_back(uint32_t(parent_.size()));
    }
}

uint32_t PolygonForest::Subdivide(uint32_t i) {
    // Refuse to grow past the budget or past 32-bit indices.
    int arity = Arity();
    if (hot_.size() + arity > maxElements_ || hot_.size() + arity > UINT32_MAX)
        throw LimitError("element trees would exceed the memory budget (" +
                         std::to_string(hot_.size()) + " elements); raise --max-memory or eps");

    // Split element _i_; the children's areas must still add up to the parent's.
    std::array<Polygon, 4> children;
    hrbench::Subdivide(shape_[i], mode_, children);
    double parentArea = hot_[i].size, sum = 0;
    std::array<double, 4> areas{};
    for (int c = 0; c < arity; ++c)
        sum += areas[c] = children[c].Area();
    // Coordinates too coarse for the element: its corners no longer resolve it.
    if (!(std::abs(sum - parentArea) <= 1e-6 * parentArea) ||
        !(*std::min_element(areas.begin(), areas.begin() + arity) > 0))
        throw LimitError("element " + std::to_string(i) + " of patch " +
                         std::to_string(hot_[i].root) +
                         " is too small for double precision at depth " +
                         std::to_string(depth_[i]) + "; use --min-area or --max-depth");

    // Append the children, first child first.
    uint32_t first = uint32_t(hot_.size());
    uint32_t root = hot_[i].root;
    uint8_t depth = uint8_t(depth_[i] + 1);
    for (int c = 0; c < arity; ++c) {
        hot_.push_back({children[c].Centroid(), areas[c], kNoChildren, root});
        shape_.push_back(children[c]);
        depth_.push_back(depth);
        parent_.push_back(i);
    }
    hot_[i].firstChild = first;
    return first;
}

std::vector<uint64_t> PolygonForest::NodesPerDepth() const { return DepthHistogram(depth_); }

uint64_t PolygonForest::NumLeaves() const { return CountLeaves(hot_); }

}  // namespace hrbench
