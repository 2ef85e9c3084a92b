#include "element_tree.h"

#include <cmath>

#include "util/error.h"

namespace hrbench {

SegmentForest::SegmentForest(const Scene &scene, size_t maxElements)
    : numRoots_(scene.segments.size()), maxElements_(maxElements) {
    if (numRoots_ >= (size_t(1) << 31))
        throw InputError("scene has too many patches");
    for (const Segment &s : scene.segments) {
        hot_.push_back({s.Midpoint(), s.Length(), kNoChildren, uint32_t(hot_.size())});
        start_.push_back(s.a);
        end_.push_back(s.b);
        depth_.push_back(0);
        parent_.push_back(uint32_t(parent_.size()));
        position_.push_back(0);
        rootLength_.push_back(s.Length());
    }
}

uint32_t SegmentForest::Subdivide(uint32_t i) {
    // Refuse to grow past the budget or past 32-bit indices.
    if (hot_.size() + 2 > maxElements_ || hot_.size() + 2 > UINT32_MAX)
        throw LimitError("element trees would exceed the memory budget (" +
                         std::to_string(hot_.size()) + " elements); raise --max-memory or eps");

    // Halve element _i_ at its midpoint; the first child starts at the element's start.
    Vec2 a = start_[i], b = end_[i], m = hot_[i].center;
    double size0 = (m - a).norm(), size1 = (b - m).norm();
    double half = 0.5 * hot_[i].size;
    // Coordinates too coarse for the element: midpoints would no longer halve it.
    if (!(std::abs(size0 - half) <= 1e-6 * half && std::abs(size1 - half) <= 1e-6 * half))
        throw LimitError("element " + std::to_string(i) + " of patch " +
                         std::to_string(hot_[i].root) +
                         " is too small for double precision at depth " +
                         std::to_string(depth_[i]) + "; use --min-area or --max-depth");
    uint32_t first = uint32_t(hot_.size());
    uint32_t root = hot_[i].root;
    int depth = depth_[i] + 1;
    uint64_t position = position_[i] * 2;
    hot_.push_back({0.5 * (a + m), size0, kNoChildren, root});
    hot_.push_back({0.5 * (m + b), size1, kNoChildren, root});
    start_.push_back(a), end_.push_back(m);
    start_.push_back(m), end_.push_back(b);
    depth_.push_back(uint8_t(depth)), depth_.push_back(uint8_t(depth));
    parent_.push_back(i), parent_.push_back(i);
    position_.push_back(position), position_.push_back(position + 1);
    hot_[i].firstChild = first;
    return first;
}

double SegmentForest::T0(uint32_t i) const {
    return rootLength_[hot_[i].root] * std::ldexp(double(position_[i]), -depth_[i]);
}

double SegmentForest::T1(uint32_t i) const {
    return rootLength_[hot_[i].root] * std::ldexp(double(position_[i] + 1), -depth_[i]);
}

std::vector<uint64_t> DepthHistogram(const std::vector<uint8_t> &depths) {
    std::vector<uint64_t> histogram;
    for (uint8_t d : depths) {
        if (d >= histogram.size())
            histogram.resize(d + 1, 0);
        ++histogram[d];
    }
    return histogram;
}

std::vector<uint64_t> SegmentForest::NodesPerDepth() const { return DepthHistogram(depth_); }

uint64_t SegmentForest::NumLeaves() const { return CountLeaves(hot_); }

}  // namespace hrbench
