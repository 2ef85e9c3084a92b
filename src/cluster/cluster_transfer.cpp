// ClusterTransfer: the coefficients of the cluster links, and the pull, gather and push
// of one sweep over the cluster tree (docs/solve.md, Clusters).
#include "cluster/cluster_transfer.h"

#include <algorithm>
#include <cmath>

namespace hrbench {

namespace {

// The mean of max(0, cos) over isotropic directions: 1/4 over the sphere, 1/pi over the
// circle. A cluster end receives and emits as if its patches faced every way alike.
template <int D>
constexpr double kIsotropicCosine = D == 3 ? 0.25 : 1 / M_PI;

// The point-to-point kernel's denominator: cos cos / (pi r^2) in 3D, cos cos / (2 r) in 2D.
template <int D>
double KernelDenominator(double r) {
    return D == 3 ? M_PI * r * r : 2 * r;
}

}  // namespace

template <typename Shape>
ClusterTransfer<Shape>::ClusterTransfer(const Patches<Shape> &patches,
                                        const ClusterTree<Shape> &tree,
                                        const std::vector<ClusterLink> &links)
    : tree_(tree), numPatches_(patches.size()), links_(links) {
    size_t slots = numPatches_ + tree.NumClusters();
    measure_.resize(slots), value_.resize(slots), gathered_.resize(slots);
    // Centres: a patch's centroid; a cluster's the area-weighted mean of its patches'.
    // Clusters are numbered in preorder, so a pass in reverse sees every child first.
    std::vector<Vec> center(slots);
    for (size_t p = 0; p < numPatches_; ++p) {
        measure_[p] = patches[p].shape.Measure();
        center[p] = patches[p].shape.Centroid();
    }
    for (size_t c = tree.NumClusters(); c-- > 0;) {
        double measure = 0;
        Vec moment = Vec::Zero();
        for (uint32_t child : tree[uint32_t(c)].children) {
            measure += measure_[Slot(child)];
            moment += measure_[Slot(child)] * center[Slot(child)];
        }
        measure_[numPatches_ + c] = measure;
        center[numPatches_ + c] = moment / measure;
    }
    // H(X <- Y) = B_Y A_Y g_X g_Y / (c_D r^(D-1)): g is max(0, n . direction to the other
    // end) for a patch, kIsotropicCosine for a cluster.
    auto cosine = [&](uint32_t node, const Vec &toOther) {
        return IsCluster(node) ? kIsotropicCosine<kDimension>
                               : std::max(0.0, patches[node].shape.Normal().dot(toOther));
    };
    coefficients_.reserve(links.size());
    for (const ClusterLink &l : links) {
        Vec d = center[Slot(l.b)] - center[Slot(l.a)];
        double r = d.norm();
        if (!(r > 0)) {  // ends sharing a centre: no direction to exchange light along
            coefficients_.push_back({0, 0});
            continue;
        }
        Vec dir = d / r;
        double kernel = cosine(l.a, dir) * cosine(l.b, -dir) / KernelDenominator<kDimension>(r);
        coefficients_.push_back({kernel * measure_[Slot(l.b)], kernel * measure_[Slot(l.a)]});
    }
}

template <typename Shape>
void ClusterTransfer<Shape>::Gather(const std::vector<double> &radiosity,
                                    std::vector<double> &irradiance) {
    size_t k = numPatches_, clusters = tree_.NumClusters();
    // Pull: a cluster's radiosity is the area-weighted mean of its patches'.
    std::copy(radiosity.begin(), radiosity.begin() + long(k), value_.begin());
    for (size_t c = clusters; c-- > 0;) {
        double power = 0;
        for (uint32_t child : tree_[uint32_t(c)].children)
            power += measure_[Slot(child)] * value_[Slot(child)];
        value_[k + c] = power / measure_[k + c];
    }
    // Gather, link by link in their order.
    std::fill(gathered_.begin(), gathered_.end(), 0.0);
    for (size_t i = 0; i < links_.size(); ++i) {
        uint32_t a = Slot(links_[i].a), b = Slot(links_[i].b);
        gathered_[a] += coefficients_[i].ab * value_[b];
        gathered_[b] += coefficients_[i].ba * value_[a];
    }
    // Push: every patch of a cluster receives what the cluster and its ancestors gathered
    // (a parent's index is below its children's).
    for (size_t c = 0; c < clusters; ++c)
        if (uint32_t parent = tree_[uint32_t(c)].parent; parent != c)
            gathered_[k + c] += gathered_[k + parent];
    irradiance.resize(k);
    for (size_t p = 0; p < k; ++p)
        irradiance[p] =
            gathered_[p] + (clusters > 0 ? gathered_[k + tree_.ParentOfPatch(uint32_t(p))] : 0);
}

template <typename Shape>
std::vector<double> ClusterTransfer<Shape>::UnitIrradiance() {
    std::vector<double> irradiance;
    Gather(std::vector<double>(numPatches_, 1.0), irradiance);
    return irradiance;
}

template <typename Shape>
size_t ClusterTransfer<Shape>::Bytes(size_t clusters, size_t patches, size_t links) {
    return links * (sizeof(ClusterLink) + sizeof(Coefficients)) +
           (patches + clusters) * (3 * sizeof(double) + sizeof(Vec));
}

template class ClusterTransfer<Segment>;
template class ClusterTransfer<Polygon>;

}  // namespace hrbench
