// ClusterTransfer: the coefficients of the cluster links, and the pull, gather and push
// of one sweep over the cluster tree (docs/solve.md, Clusters).
#include "cluster_transfer.h"

#include <algorithm>
#include <cmath>

namespace hrbench {

namespace {

// The mean of max(0, cos) over isotropic directions: 1/4 over the sphere, 1/pi over the
// circle. An isotropic cluster end receives and emits as if its patches faced every way
// alike.
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
                                        const std::vector<ClusterLink> &links,
                                        ClusterTransferKind kind)
    : tree_(tree), numPatches_(patches.size()), links_(links) {
    size_t slots = numPatches_ + tree.NumClusters();
    measure_.resize(slots), value_.resize(slots), gathered_.resize(slots);
    // Centres: a patch's centroid; a cluster's the area-weighted mean of its patches'.
    // Axis sums: P+_a = sum A_p max(0, n_p,a) and P-_a = sum A_p max(0, -n_p,a).
    // Clusters are numbered in preorder, so a pass in reverse sees every child first.
    std::vector<Vec> center(slots), positive(slots), negative(slots);
    for (size_t p = 0; p < numPatches_; ++p) {
        measure_[p] = patches[p].shape.Measure();
        center[p] = patches[p].shape.Centroid();
        Vec n = patches[p].shape.Normal();
        positive[p] = measure_[p] * n.cwiseMax(0.0);
        negative[p] = measure_[p] * (-n).cwiseMax(0.0);
    }
    for (size_t c = tree.NumClusters(); c-- > 0;) {
        size_t slot = numPatches_ + c;
        double measure = 0;
        Vec moment = Vec::Zero();
        positive[slot] = negative[slot] = Vec::Zero();
        for (uint32_t child : tree[uint32_t(c)].children) {
            uint32_t s = Slot(child);
            measure += measure_[s];
            moment += measure_[s] * center[s];
            positive[slot] += positive[s], negative[slot] += negative[s];
        }
        measure_[slot] = measure;
        center[slot] = moment / measure;
    }
    // A node's projected measure toward the unit vector _u_: a root patch's exact
    // A max(0, n . u); a cluster's from its axis sums, or A times the isotropic cosine.
    auto projected = [&](uint32_t node, const Vec &u) {
        uint32_t s = Slot(node);
        if (!IsCluster(node))
            return measure_[s] * std::max(0.0, patches[node].shape.Normal().dot(u));
        if (kind == ClusterTransferKind::Isotropic)
            return measure_[s] * kIsotropicCosine<kDimension>;
        double sum = 0;
        for (int a = 0; a < kDimension; ++a)
            sum += u[a] > 0 ? positive[s][a] * u[a] : negative[s][a] * -u[a];
        return sum;
    };
    // The flux from Y to X per unit B_Y, f_X(u) f_Y(-u) / (c_D r^(D-1)), u from X toward
    // Y, is the same both ways: each end's irradiance divides it by its own measure.
    coefficients_.reserve(links.size());
    for (const ClusterLink &l : links) {
        Vec d = center[Slot(l.b)] - center[Slot(l.a)];
        double r = d.norm();
        if (!(r > 0)) {  // ends sharing a centre: no direction to exchange light along
            coefficients_.push_back({0, 0});
            continue;
        }
        Vec u = d / r;
        double flux = projected(l.a, u) * projected(l.b, -u) / KernelDenominator<kDimension>(r);
        coefficients_.push_back({flux / measure_[Slot(l.a)], flux / measure_[Slot(l.b)]});
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
           (patches + clusters) * (3 * sizeof(double) + 3 * sizeof(Vec));
}

template class ClusterTransfer<Segment>;
template class ClusterTransfer<Polygon>;

}  // namespace hrbench
