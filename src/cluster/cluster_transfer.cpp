// ClusterTransfer: the coefficients of the cluster links, and the pull, gather and push
// of one sweep over the cluster tree (docs/solve.md, Clusters).
#include "cluster_transfer.h"

#include <algorithm>
#include <cmath>

#include "direction_table.h"
#include "util/parallel_for.h"

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

// How many patches on from its place a sample looks for one facing the other end.
constexpr uint32_t kTries = 8;

}  // namespace

template <typename Shape>
void ClusterTransfer<Shape>::SamplePatches(const std::vector<Vec> &normal, uint32_t node,
                                           const Vec &u, int samples,
                                           std::vector<uint32_t> &out) const {
    out.clear();
    if (!IsCluster(node)) {
        out.push_back(node);
        return;
    }
    const auto &cluster = tree_[ClusterIndex(node)];
    uint32_t n = cluster.end - cluster.begin;
    uint32_t count = std::min(uint32_t(samples), n);
    for (uint32_t s = 0; s < count; ++s) {
        uint32_t place = uint32_t((uint64_t(2 * s + 1) * n) / (2 * uint64_t(count)));
        uint32_t chosen = tree_.Patches()[cluster.begin + place];
        for (uint32_t t = 0; t < std::min(kTries, n); ++t) {
            uint32_t p = tree_.Patches()[cluster.begin + (place + t) % n];
            if (normal[p].dot(u) > 0) {
                chosen = p;
                break;
            }
        }
        out.push_back(chosen);
    }
}

template <typename Shape>
ClusterTransfer<Shape>::ClusterTransfer(const Patches<Shape> &patches,
                                        const ClusterTree<Shape> &tree,
                                        const std::vector<ClusterLink> &links,
                                        ClusterTransferKind kind, const Occluders *occluders,
                                        int samples, int threads)
    : tree_(tree), numPatches_(patches.size()), links_(links) {
    size_t slots = numPatches_ + tree.NumClusters(), clusters = tree.NumClusters();
    measure_.resize(slots), value_.resize(slots), gathered_.resize(slots);
    // Per node: its centre (a patch's centroid; a cluster's the area-weighted mean of its
    // patches'), and whether its patches share one normal (then the node's projected
    // measure is exact from it). Per cluster of mixed normals: the projected measure
    // sum A_p max(0, n_p . v) at every direction v of the table. Clusters are numbered in
    // preorder, so a pass in reverse sees every child first.
    using Table = DirectionTable<kDimension>;
    std::vector<Vec> center(slots), normal(slots);
    std::vector<char> uniform(slots, 1);
    std::vector<float> table(kind == ClusterTransferKind::Projected ? clusters * Table::kSize : 0);
    std::vector<Vec> directions;
    for (size_t m = 0; !table.empty() && m < Table::kSize; ++m)
        directions.push_back(Table::Direction(m));
    for (size_t p = 0; p < numPatches_; ++p) {
        measure_[p] = patches[p].shape.Measure();
        center[p] = patches[p].shape.Centroid();
        normal[p] = patches[p].shape.Normal();
    }
    for (size_t c = clusters; c-- > 0;) {
        size_t slot = numPatches_ + c;
        double measure = 0;
        Vec moment = Vec::Zero();
        const auto &children = tree[uint32_t(c)].children;
        for (uint32_t child : children) {
            uint32_t s = Slot(child);
            measure += measure_[s];
            moment += measure_[s] * center[s];
            if (table.empty())
                continue;
            float *row = &table[c * Table::kSize];
            if (IsCluster(child)) {
                const float *from = &table[ClusterIndex(child) * Table::kSize];
                for (size_t m = 0; m < Table::kSize; ++m)
                    row[m] += from[m];
            } else {
                for (size_t m = 0; m < Table::kSize; ++m)
                    row[m] += float(measure_[s] * std::max(0.0, normal[s].dot(directions[m])));
            }
        }
        measure_[slot] = measure;
        center[slot] = moment / measure;
        uint32_t a = Slot(children[0]), b = Slot(children[1]);
        uniform[slot] = uniform[a] && uniform[b] && normal[a] == normal[b];
        normal[slot] = normal[a];
    }
    // A node's projected measure toward the unit vector _u_: exact for a root patch or a
    // cluster of one normal, A max(0, n . u); else A times the isotropic cosine, or
    // interpolated in the cluster's table.
    auto projected = [&](uint32_t node, const Vec &u) {
        uint32_t s = Slot(node);
        if (!IsCluster(node) || (kind == ClusterTransferKind::Projected && uniform[s]))
            return measure_[s] * std::max(0.0, normal[s].dot(u));
        if (kind == ClusterTransferKind::Isotropic)
            return measure_[s] * kIsotropicCosine<kDimension>;
        const float *row = &table[ClusterIndex(node) * Table::kSize];
        auto lookup = Table::Lookup(u);
        double sum = 0;
        for (size_t w = 0; w < lookup.index.size(); ++w)
            sum += lookup.weight[w] * double(row[lookup.index[w]]);
        return sum;
    };
    // The flux from Y to X per unit B_Y, f_X(u) f_Y(-u) / (c_D r^(D-1)), u from X toward
    // Y, is the same both ways: each end's irradiance divides it by its own measure.
    // Link by link, in parallel: each writes its own coefficients and ray counts.
    coefficients_.resize(links.size());
    std::vector<uint32_t> linkRays(occluders ? links.size() : 0);
    struct Scratch {
        std::vector<uint32_t> from, to;
    };
    ParallelFor(
        links.size(), 1024, threads, [] { return Scratch(); },
        [&](Scratch &scratch, size_t k) {
            const ClusterLink &l = links[k];
            Vec d = center[Slot(l.b)] - center[Slot(l.a)];
            double r = d.norm();
            if (!(r > 0)) {  // ends sharing a centre: no direction to exchange light along
                coefficients_[k] = {0, 0};
                return;
            }
            Vec u = d / r;
            double flux = projected(l.a, u) * projected(l.b, -u) / KernelDenominator<kDimension>(r);
            if (occluders && flux > 0) {
                SamplePatches(normal, l.a, u, samples, scratch.from);
                SamplePatches(normal, l.b, -u, samples, scratch.to);
                // Only segments whose ends face each other carry light: the others
                // (two coplanar cells of a wall, say) are not cast.
                uint32_t visible = 0, rays = 0;
                for (uint32_t p : scratch.from)
                    for (uint32_t q : scratch.to) {
                        const Vec &a = center[p], &b = center[q];
                        if (!(normal[p].dot(b - a) > 0 && normal[q].dot(a - b) > 0))
                            continue;
                        ++rays;
                        visible += !occluders->Blocked(a, b, p, q);
                    }
                linkRays[k] = rays;
                if (rays > 0)
                    flux *= double(visible) / double(rays);
            }
            coefficients_[k] = {flux / measure_[Slot(l.a)], flux / measure_[Slot(l.b)]};
        });
    for (size_t k = 0; k < linkRays.size(); ++k) {
        rays_ += linkRays[k];
        occludedLinks_ += linkRays[k] > 0 && coefficients_[k].ab == 0;
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
           (patches + clusters) * (3 * sizeof(double) + 2 * sizeof(Vec) + 1) +
           clusters * DirectionTable<kDimension>::kSize * sizeof(float);
}

template class ClusterTransfer<Segment>;
template class ClusterTransfer<Polygon>;

}  // namespace hrbench
