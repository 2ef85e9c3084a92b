// The light that crosses the cluster links of a refinement (`--clusters`), each cluster
// end facing the other by its projected area or as Sillion's isotropic cluster, gathered
// once per sweep by the hierarchical solve (solve/solve.cpp). docs/solve.md (Clusters) derives
// both transfers and states the order of the sweep.
#pragma once

#include <cstdint>
#include <vector>

#include "hrbench/clusters.h"
#include "hrbench/scene.h"
#include "hrbench/solve.h"
#include "visibility/visibility.h"

namespace hrbench {

template <typename Shape>
class ClusterTransfer {
  public:
    static constexpr int kDimension = Shape::kDimension;

    // The coefficients of every link of _links_ over _tree_, whose patches are _patches_,
    // a cluster end facing the other as _kind_ says. With _occluders_, each weighed by
    // its visible fraction: the share of unblocked segments between up to _samples_
    // patch centroids of either end (VisibleFraction), on _threads_ threads.
    ClusterTransfer(const Patches<Shape> &patches, const ClusterTree<Shape> &tree,
                    const std::vector<ClusterLink> &links, ClusterTransferKind kind,
                    const Occluders *occluders = nullptr, int samples = 1, int threads = 1);

    size_t NumLinks() const { return coefficients_.size(); }

    // Segments cast for the visible fractions, and links found fully occluded.
    uint64_t Rays() const { return rays_; }
    uint64_t OccludedLinks() const { return occludedLinks_; }

    // What every root patch gathers through the cluster links, per unit of its measure,
    // into _irradiance_ (by patch index), from _radiosity_, which holds each root patch's
    // radiosity at its element id (the root patch's index). O(clusters + patches + links).
    void Gather(const std::vector<double> &radiosity, std::vector<double> &irradiance);

    // Gather's result for the radiosity 1 everywhere: each root patch's sum of cluster
    // coefficients, which the consistency scale counts beside its links' (docs/solve.md).
    std::vector<double> UnitIrradiance();

    // Bytes of the arrays for _clusters_ clusters, _patches_ patches and _links_ links.
    static size_t Bytes(size_t clusters, size_t patches, size_t links);

  private:
    using Vec = Vector<kDimension>;
    struct Coefficients {
        double ab, ba;  // irradiance of a per unit radiosity of b, and of b per unit of a
    };

    // Radiosity and irradiance slots: root patches first, then the clusters.
    uint32_t Slot(uint32_t node) const {
        return IsCluster(node) ? uint32_t(numPatches_) + ClusterIndex(node) : node;
    }

    // The patches of node _node_ that stand for it as a light's end toward _u_: itself
    // for a root patch; for a cluster, up to _samples_ of its patches, spread over its
    // range, each the first from its place on (up to kTries on) whose normal (in
    // _normal_, by patch) faces _u_.
    void SamplePatches(const std::vector<Vec> &normal, uint32_t node, const Vec &u, int samples,
                       std::vector<uint32_t> &out) const;

    const ClusterTree<Shape> &tree_;
    size_t numPatches_;
    uint64_t rays_ = 0, occludedLinks_ = 0;
    std::vector<ClusterLink> links_;
    std::vector<Coefficients> coefficients_;
    std::vector<double> measure_;  // by slot: the patch's, the sum of the cluster's patches'
    std::vector<double> value_;    // by slot: radiosity, then irradiance (scratch)
    std::vector<double> gathered_;
};

extern template class ClusterTransfer<Segment>;
extern template class ClusterTransfer<Polygon>;

}  // namespace hrbench
