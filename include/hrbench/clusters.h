// The cluster hierarchy over a scene's root patches (`--clusters`): a binary tree of
// bounding balls, built once by a deterministic rule, whose clusters take part in
// refinement as elements do (docs/conventions.md#clusters). Refinement then starts from
// the root cluster paired with itself instead of from every pair of root patches.
#pragma once

#include <cstdint>
#include <vector>

#include "hrbench/geometry/shape.h"
#include "hrbench/scene.h"

namespace hrbench {

// One end of a link made through the clusters: a root patch (its element id, which is
// its index in scene order) or a cluster (its index in the tree, with kClusterBit set).
// A patch is never subdivided against a cluster, so an element end is always a root.
constexpr uint32_t kClusterBit = 1u << 31;

constexpr bool IsCluster(uint32_t node) { return (node & kClusterBit) != 0; }
constexpr uint32_t ClusterIndex(uint32_t node) { return node & ~kClusterBit; }
constexpr uint32_t ClusterNode(uint32_t cluster) { return cluster | kClusterBit; }

// A link with a cluster at one end at least, {a, b} as ProjectKernel's links are: each
// stands for both directions.
struct ClusterLink {
    uint32_t a, b;  // nodes, as above
};

// A bounding ball (docs/conventions.md#clusters).
template <int D>
struct Ball {
    Vector<D> center;
    double radius;
};

// The ball of root patch _p_ as a node paired with a cluster: centre of the box of its
// corners, radius the largest distance from it to a corner.
template <typename Shape>
Ball<Shape::kDimension> PatchBall(const Patches<Shape> &patches, uint32_t p);

// A cluster: what the cluster oracles read, and where its patches are (64 bytes in 3D:
// the tree holds one per patch, less one).
template <int D>
struct Cluster {
    Vector<D> center;      // centre of the bounding ball
    double radius;         // radius of the bounding ball (every corner of its patches inside)
    double measure;        // A_C: the sum of its patches' lengths (2D) or areas (3D)
    uint32_t children[2];  // nodes (above): two clusters, two patches, or one of each
    uint32_t parent;       // cluster index of the parent; the root's is itself
    // Its patches are ClusterTree::Patches()[begin, end): every cluster covers a range.
    uint32_t begin, end;
};
static_assert(sizeof(Cluster<3>) == 64, "a cluster is 64 bytes in 3D");

// The hierarchy over the root patches of one scene. With k >= 2 patches it holds k - 1
// clusters, cluster 0 the root; with one patch, none.
template <typename Shape>
class ClusterTree {
  public:
    static constexpr int kDimension = Shape::kDimension;
    using ClusterType = Cluster<kDimension>;

    ClusterTree() = default;
    explicit ClusterTree(const Patches<Shape> &patches);

    size_t NumClusters() const { return clusters_.size(); }
    const ClusterType &operator[](uint32_t cluster) const { return clusters_[cluster]; }
    // The root patches in the tree's order (a permutation of 0..k-1).
    const std::vector<uint32_t> &Patches() const { return order_; }
    // The cluster whose child root patch _p_ is.
    uint32_t ParentOfPatch(uint32_t p) const { return patchParent_[p]; }

    size_t Bytes() const {
        return clusters_.size() * sizeof(ClusterType) +
               (order_.size() + patchParent_.size()) * sizeof(uint32_t);
    }

  private:
    std::vector<ClusterType> clusters_;
    std::vector<uint32_t> order_;
    std::vector<uint32_t> patchParent_;
};

extern template Ball<2> PatchBall(const Patches<Segment> &, uint32_t);
extern template Ball<3> PatchBall(const Patches<Polygon> &, uint32_t);
extern template class ClusterTree<Segment>;
extern template class ClusterTree<Polygon>;

}  // namespace hrbench
