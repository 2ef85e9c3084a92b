// The cluster form of each oracle: the test of a pair of nodes of the cluster hierarchy
// (clusters or root patches) that accepts only where the element oracle would accept
// every element pair under it (docs/conventions.md#clusters). The element oracles'
// hot path is untouched: these run once per node pair of the cluster traversal.
#pragma once

#include <algorithm>
#include <cmath>
#include <vector>

#include "hrbench/clusters.h"
#include "hrbench/oracles/bf.h"
#include "hrbench/oracles/garmann.h"
#include "hrbench/oracles/hanrahan.h"
#include "hrbench/radiosity_estimate.h"
#include "hrbench/refine_options.h"

namespace hrbench {

// What a cluster oracle reads of a node: its ball, its measure A (a patch's own, a
// cluster's sum), and the node itself for what an oracle keeps per node.
template <int D>
struct ClusterNodeView {
    Vector<D> center;
    double radius;
    double measure;
    uint32_t node;  // as in ClusterLink
};

// The views of every node of a hierarchy, made when asked for: a root patch's from its
// ball and measure, kept here, a cluster's from the tree's own record, which holds the
// same (a copy of every cluster's took 48 bytes a cluster more, 96 MB for 2M patches).
template <typename Shape>
class NodeViews {
  public:
    static constexpr int D = Shape::kDimension;
    using View = ClusterNodeView<D>;

    NodeViews(const Patches<Shape> &patches, const ClusterTree<Shape> &tree) : tree_(tree) {
        balls_.reserve(patches.size()), measures_.reserve(patches.size());
        for (uint32_t p = 0; p < patches.size(); ++p) {
            balls_.push_back(PatchBall(patches, p));
            measures_.push_back(patches[p].shape.Measure());
        }
    }

    View operator[](uint32_t node) const {
        if (IsCluster(node)) {
            const Cluster<D> &c = tree_[ClusterIndex(node)];
            return {c.center, c.radius, c.measure, node};
        }
        return {balls_[node].center, balls_[node].radius, measures_[node], node};
    }

    size_t Bytes() const {
        return balls_.size() * sizeof(Ball<D>) + measures_.size() * sizeof(double);
    }

  private:
    const ClusterTree<Shape> &tree_;
    std::vector<Ball<D>> balls_;    // per root patch
    std::vector<double> measures_;  // per root patch
};

// The gap g = |c_X - c_Y| - R_X - R_Y between the balls of two nodes: every element of
// X is this far at least from every element of Y (their centroids lie in the balls).
template <int D>
double Gap(const ClusterNodeView<D> &x, const ClusterNodeView<D> &y) {
    return (x.center - y.center).norm() - x.radius - y.radius;
}

// F_c(X<-Y) = f max(1, 2f)^2, f = A_Y / (pi g^2 + A_Y) in 3D, A_Y / sqrt(4 g^2 + A_Y^2)
// in 2D: at least each form-factor estimate of an element pair under (X, Y), since f
// grows with A and falls with r >= g, and the cosines are at most 1.
template <int D>
double ClusterFormFactor(double sourceMeasure, double gap) {
    constexpr double kPi = 3.14159265358979323846;
    double a = sourceMeasure;
    double f = D == 3 ? a / (kPi * gap * gap + a) : a / std::sqrt(4 * gap * gap + a * a);
    double clamp = std::max(1.0, 2 * f);
    return f * clamp * clamp;
}

// The decision on node pair (x, y) under _bound_ (`--cluster-bound`): ClusterBound::Patch
// never links two clusters (refused by the rule alone, without a bound), and any pair it
// may link is accepted as the cluster form _form_ accepts it.
template <typename Form, int D>
bool ClusterAccepts(const Form &form, ClusterBound bound, const ClusterNodeView<D> &x,
                    const ClusterNodeView<D> &y) {
    if (bound == ClusterBound::Patch && IsCluster(x.node) && IsCluster(y.node))
        return false;
    return form.Acceptable(x, y);
}

// Whether a refused node pair (x, y), a cluster at one end at least, opens x (else y):
// the only cluster, or of two clusters under ClusterBound::Cluster the one of the larger
// measure, so that both ends shrink together, and under ClusterBound::Patch the one of
// the smaller, so that each patch meets the largest clusters that it may link to (as a
// point meets a tree's nodes from the top down). Ties open x.
template <int D>
bool OpensFirst(ClusterBound bound, const ClusterNodeView<D> &x, const ClusterNodeView<D> &y) {
    if (!IsCluster(x.node) || !IsCluster(y.node))
        return IsCluster(x.node);
    return bound == ClusterBound::Cluster ? x.measure >= y.measure : x.measure <= y.measure;
}

// The cluster form of _Oracle_ (one of the registry's, for _Shape_); an oracle without
// one has kExists false, and --clusters refuses it.
template <typename Oracle>
struct ClusterForm {
    static constexpr bool kExists = false;
};

// garmann: accept iff max(A_X, A_Y) <= eps g^(D-1), g > 0.
template <typename Shape>
struct ClusterForm<GarmannOracle<Shape>> {
    static constexpr bool kExists = true;
    using View = ClusterNodeView<Shape::kDimension>;

    ClusterForm(const RefineOptions &options, const Patches<Shape> &, const ClusterTree<Shape> &)
        : eps_(options.eps) {}

    bool Acceptable(const View &x, const View &y) const {
        double g = Gap(x, y);
        if (!(g > 0))
            return false;
        double bound = Shape::kDimension == 3 ? eps_ * g * g : eps_ * g;
        return std::max(x.measure, y.measure) <= bound;
    }

  private:
    double eps_;
};

// hanrahan (any --ff-estimate): accept iff F_c(X<-Y) <= eps and F_c(Y<-X) <= eps.
template <typename Shape>
struct ClusterForm<HanrahanOracle<Shape>> {
    static constexpr bool kExists = true;
    using View = ClusterNodeView<Shape::kDimension>;

    ClusterForm(const RefineOptions &options, const Patches<Shape> &, const ClusterTree<Shape> &)
        : eps_(options.eps) {}

    bool Acceptable(const View &x, const View &y) const {
        double g = Gap(x, y);
        if (!(g > 0))
            return false;
        constexpr int D = Shape::kDimension;
        return ClusterFormFactor<D>(y.measure, g) <= eps_ &&
               ClusterFormFactor<D>(x.measure, g) <= eps_;
    }

  private:
    double eps_;
};

// bf: accept iff Bmax_Y F_c(X<-Y) <= eps and Bmax_X F_c(Y<-X) <= eps, Bmax of a node the
// largest radiosity the run's estimate gives any element of its patches (the emission
// in the first pass): per root patch, then per cluster as the larger of its children's.
template <typename Shape>
struct ClusterForm<BFOracle<Shape>> {
    static constexpr bool kExists = true;
    using View = ClusterNodeView<Shape::kDimension>;

    ClusterForm(const RefineOptions &options, const Patches<Shape> &patches,
                const ClusterTree<Shape> &tree)
        : eps_(options.eps) {
        if (auto estimate = std::get_if<const RadiosityEstimate<Shape> *>(&options.estimate))
            patchMax_ = (*estimate)->RootMax();
        else
            patchMax_ = RadiosityEstimate<Shape>::FromEmission(patches).RootMax();
        // Children come after their parent in preorder: the last cluster first.
        clusterMax_.assign(tree.NumClusters(), 0);
        for (uint32_t c = uint32_t(tree.NumClusters()); c-- > 0;)
            for (uint32_t child : tree[c].children)
                clusterMax_[c] = std::max(clusterMax_[c], Max(child));
    }

    bool Acceptable(const View &x, const View &y) const {
        double g = Gap(x, y);
        if (!(g > 0))
            return false;
        constexpr int D = Shape::kDimension;
        return Max(y.node) * ClusterFormFactor<D>(y.measure, g) <= eps_ &&
               Max(x.node) * ClusterFormFactor<D>(x.measure, g) <= eps_;
    }

    // Bmax of _node_.
    double Max(uint32_t node) const {
        return IsCluster(node) ? clusterMax_[ClusterIndex(node)] : patchMax_[node];
    }

  private:
    double eps_;
    std::vector<double> patchMax_, clusterMax_;
};

}  // namespace hrbench
