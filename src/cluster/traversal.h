// The traversal of the cluster hierarchy that replaces the loop over every root pair
// under --clusters (docs/conventions.md#clusters): Self(root), each cluster's own
// pair of children, and Pair(X, Y), which links a node pair that the run's
// --cluster-bound and its cluster oracle accept, hands a pair of root patches to the
// refinement, and otherwise opens a cluster (OpensFirst). Internal to refine/refine.cpp.
// Nothing is kept per root pair.
#pragma once

#include <cstdint>
#include <vector>

#include "cluster_oracles.h"
#include "hrbench/clusters.h"
#include "hrbench/record.h"

namespace hrbench {

// _Form_: a ClusterForm; _RootPair_: called with (p, q), p < q, for each root pair
// reached, in traversal order. Links go to _links_ when it is not null.
template <typename Shape, typename Form, typename RootPair>
class ClusterTraversal {
  public:
    ClusterTraversal(const ClusterTree<Shape> &tree, const NodeViews<Shape> &views,
                     const Form &form, ClusterBound bound, RootPair &rootPair,
                     std::vector<ClusterLink> *links)
        : tree_(tree), views_(views), form_(form), bound_(bound), rootPair_(rootPair),
          links_(links), opened_(tree.NumClusters(), false) {}

    // Traverses the whole hierarchy, adding to the cluster counters of _c_.
    void Run(Counters &c) {
        counters_ = &c;
        c.clusterNodes = tree_.NumClusters();
        if (tree_.NumClusters() > 0)
            Self(0);
    }

  private:
    void Self(uint32_t cluster) {
        const uint32_t *children = tree_[cluster].children;
        for (int s = 0; s < 2; ++s)
            if (IsCluster(children[s]))
                Self(ClusterIndex(children[s]));
        Pair(children[0], children[1]);
    }

    void Pair(uint32_t x, uint32_t y) {
        if (!IsCluster(x) && !IsCluster(y))
            return x < y ? rootPair_(x, y) : rootPair_(y, x);
        ++counters_->clusterOracleCalls;
        const auto &vx = views_[x], &vy = views_[y];
        if (ClusterAccepts(form_, bound_, vx, vy)) {
            ++counters_->clusterLinks;
            if (links_)
                links_->push_back({x, y});
            return;
        }
        bool openX = OpensFirst(bound_, vx, vy);
        uint32_t open = openX ? x : y;
        if (!opened_[ClusterIndex(open)]) {
            opened_[ClusterIndex(open)] = true;
            ++counters_->openedClusters;
        }
        const uint32_t *children = tree_[ClusterIndex(open)].children;
        for (int s = 0; s < 2; ++s)
            openX ? Pair(children[s], y) : Pair(x, children[s]);
    }

    const ClusterTree<Shape> &tree_;
    const NodeViews<Shape> &views_;
    const Form &form_;
    ClusterBound bound_;
    RootPair &rootPair_;
    std::vector<ClusterLink> *links_;
    std::vector<bool> opened_;  // per cluster: opened by a refused pair
    Counters *counters_ = nullptr;
};

}  // namespace hrbench
