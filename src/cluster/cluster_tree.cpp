// ClusterTree's construction by the rule of include/hrbench/clusters.h: top-down median
// split on the longest axis of the patch centroids' box (ties by patch index), floor(n/2)
// patches to the left, clusters numbered in preorder; the ball is centred on the box of
// the patches' corners and reaches the farthest corner.
#include "hrbench/clusters.h"

#include <algorithm>
#include <array>
#include <functional>

namespace hrbench {

namespace {

// Every corner of a patch's shape.
template <int D>
void CornersOf(const Segment &s, std::vector<Vector<D>> &out) {
    out.push_back(s.a), out.push_back(s.b);
}
template <int D>
void CornersOf(const Polygon &p, std::vector<Vector<D>> &out) {
    for (int k = 0; k < p.n; ++k)
        out.push_back(p.v[size_t(k)]);
}

}  // namespace

template <typename Shape>
ClusterTree<Shape>::ClusterTree(const hrbench::Patches<Shape> &patches) {
    constexpr int D = kDimension;
    using Vec = Vector<D>;
    uint32_t k = uint32_t(patches.size());
    order_.resize(k);
    for (uint32_t p = 0; p < k; ++p)
        order_[p] = p;
    patchParent_.assign(k, 0);
    if (k < 2)
        return;
    std::vector<Vec> centroid(k);
    for (uint32_t p = 0; p < k; ++p)
        centroid[p] = patches[p].shape.Centroid();
    clusters_.reserve(k - 1);
    std::vector<Vec> corners;
    // Builds the cluster over order_[begin, end) (at least two patches) and returns its
    // index; its subtrees follow it (preorder).
    std::function<uint32_t(uint32_t, uint32_t, uint32_t)> build = [&](uint32_t begin,
                                                                      uint32_t end,
                                                                      uint32_t parent) {
        uint32_t index = uint32_t(clusters_.size());
        clusters_.push_back({Vec::Zero(), 0, 0, 0, {0, 0}, 0, 0, 0});
        Vec low = centroid[order_[begin]], high = low;
        for (uint32_t i = begin; i < end; ++i)
            low = low.cwiseMin(centroid[order_[i]]), high = high.cwiseMax(centroid[order_[i]]);
        int axis = 0;
        for (int d = 1; d < D; ++d)
            if (high[d] - low[d] > high[axis] - low[axis])
                axis = d;
        std::sort(order_.begin() + begin, order_.begin() + end, [&](uint32_t a, uint32_t b) {
            double x = centroid[a][axis], y = centroid[b][axis];
            return x < y || (x == y && a < b);
        });
        corners.clear();
        double measure = 0, maxMeasure = 0;
        for (uint32_t i = begin; i < end; ++i) {
            CornersOf<D>(patches[order_[i]].shape, corners);
            double a = patches[order_[i]].shape.Measure();
            measure += a, maxMeasure = std::max(maxMeasure, a);
        }
        Vec cLow = corners[0], cHigh = corners[0];
        for (const Vec &c : corners)
            cLow = cLow.cwiseMin(c), cHigh = cHigh.cwiseMax(c);
        Vec center = 0.5 * (cLow + cHigh);
        double radius = 0;
        for (const Vec &c : corners)
            radius = std::max(radius, (c - center).norm());
        uint32_t mid = begin + (end - begin) / 2;
        std::array<uint32_t, 2> children;
        std::array<std::pair<uint32_t, uint32_t>, 2> halves = {{{begin, mid}, {mid, end}}};
        for (int c = 0; c < 2; ++c) {
            auto [b, e] = halves[size_t(c)];
            if (e - b == 1) {
                children[size_t(c)] = order_[b];
                patchParent_[order_[b]] = index;
            } else {
                children[size_t(c)] = ClusterNode(build(b, e, index));
            }
        }
        ClusterType &cluster = clusters_[index];
        cluster.center = center;
        cluster.radius = radius;
        cluster.measure = measure;
        cluster.maxMeasure = maxMeasure;
        cluster.children[0] = children[0], cluster.children[1] = children[1];
        cluster.parent = parent;
        cluster.begin = begin, cluster.end = end;
        return index;
    };
    build(0, k, 0);
}

template class ClusterTree<Segment>;
template class ClusterTree<Polygon>;

}  // namespace hrbench
