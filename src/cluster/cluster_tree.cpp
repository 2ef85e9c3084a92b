#include <algorithm>
#include <limits>
#include <numeric>

#include "hrbench/clusters.h"
#include "hrbench/geometry/polygon.h"
#include "hrbench/geometry/segment.h"

namespace hrbench {

namespace {

// Calls _f_ with each corner of _s_.
template <typename F>
void ForEachCorner(const Segment &s, F &&f) {
    f(s.a), f(s.b);
}
template <typename F>
void ForEachCorner(const Polygon &s, F &&f) {
    for (int k = 0; k < s.n; ++k)
        f(s.v[size_t(k)]);
}

// The axis-aligned box of points, grown one point at a time.
template <int D>
struct Box {
    Vector<D> lo = Vector<D>::Constant(std::numeric_limits<double>::infinity());
    Vector<D> hi = Vector<D>::Constant(-std::numeric_limits<double>::infinity());
    void Add(const Vector<D> &p) { lo = lo.cwiseMin(p), hi = hi.cwiseMax(p); }
};

// The ball of docs/conventions.md#clusters around the corners of _shapes_[k] for the
// indices k of [first, last): centre of their box, radius the largest distance to one.
template <typename Shape, typename It>
Ball<Shape::kDimension> CornerBall(const Patches<Shape> &patches, It first, It last) {
    constexpr int D = Shape::kDimension;
    Box<D> box;
    for (It k = first; k != last; ++k)
        ForEachCorner(patches[*k].shape, [&](const Vector<D> &v) { box.Add(v); });
    Ball<D> ball{0.5 * (box.lo + box.hi), 0};
    for (It k = first; k != last; ++k)
        ForEachCorner(patches[*k].shape, [&](const Vector<D> &v) {
            ball.radius = std::max(ball.radius, (v - ball.center).norm());
        });
    return ball;
}

}  // namespace

template <typename Shape>
Ball<Shape::kDimension> PatchBall(const Patches<Shape> &patches, uint32_t p) {
    return CornerBall(patches, &p, &p + 1);
}

template <typename Shape>
ClusterTree<Shape>::ClusterTree(const hrbench::Patches<Shape> &patches)
    : order_(patches.size()), patchParent_(patches.size()) {
    constexpr int D = kDimension;
    const uint32_t k = uint32_t(patches.size());
    std::iota(order_.begin(), order_.end(), 0u);
    if (k < 2)
        return;
    clusters_.reserve(k - 1);
    std::vector<Vector<D>> centroid(k);
    for (uint32_t p = 0; p < k; ++p)
        centroid[p] = patches[p].shape.Centroid();
    // Splits the range [begin, end) of order_ (two patches at least) into the subtree
    // of a new cluster under _parent_, numbered in preorder; returns the cluster.
    auto build = [&](auto &&self, uint32_t begin, uint32_t end, uint32_t parent) -> uint32_t {
        const uint32_t c = uint32_t(clusters_.size());
        clusters_.push_back({Vector<D>::Zero(), 0, 0, {0, 0}, 0, 0, 0});  // set below
        Box<D> box;
        for (uint32_t k = begin; k < end; ++k)
            box.Add(centroid[order_[k]]);
        Vector<D> extent = box.hi - box.lo;
        int axis = 0;
        for (int a = 1; a < D; ++a)
            if (extent[a] > extent[axis])
                axis = a;
        // The first half in the order below, a strict total one, goes left: partitioning
        // at the median picks the same patches as sorting the range would, and each half
        // is partitioned again below, down to single patches, so that order_ comes out
        // as sorting at every level leaves it, in linear rather than n log n time a level.
        const uint32_t mid = begin + (end - begin) / 2;
        std::nth_element(order_.begin() + begin, order_.begin() + mid, order_.begin() + end,
                         [&](uint32_t x, uint32_t y) {
                             double cx = centroid[x][axis], cy = centroid[y][axis];
                             return cx < cy || (cx == cy && x < y);
                         });
        uint32_t children[2];
        const uint32_t ranges[2][2] = {{begin, mid}, {mid, end}};
        for (int s = 0; s < 2; ++s) {
            auto [from, to] = ranges[s];
            if (to - from == 1) {
                children[s] = order_[from];
                patchParent_[order_[from]] = c;
            } else {
                children[s] = ClusterNode(self(self, from, to, c));
            }
        }
        ClusterType &cluster = clusters_[c];
        Ball<D> ball = CornerBall(patches, order_.begin() + begin, order_.begin() + end);
        cluster.center = ball.center;
        cluster.radius = ball.radius;
        cluster.measure = 0;
        for (int s = 0; s < 2; ++s) {
            uint32_t child = children[s];
            cluster.measure += IsCluster(child) ? clusters_[ClusterIndex(child)].measure
                                                : patches[child].shape.Measure();
        }
        cluster.children[0] = children[0], cluster.children[1] = children[1];
        cluster.parent = parent;
        cluster.begin = begin, cluster.end = end;
        return c;
    };
    build(build, 0, k, 0);
}

template class ClusterTree<Segment>;
template class ClusterTree<Polygon>;
template Ball<2> PatchBall(const Patches<Segment> &, uint32_t);
template Ball<3> PatchBall(const Patches<Polygon> &, uint32_t);

}  // namespace hrbench
