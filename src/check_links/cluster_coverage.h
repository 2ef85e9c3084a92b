// check-links --clusters: a dump's cluster links against the scene's cluster hierarchy
// (internal to check-links; docs/probe.md, "Cluster links"). Each link is checked alone
// (its clusters exist, its ends are disjoint), then the hierarchy is walked as the
// traversal walks it: a node pair a cluster link covers is judged by the cluster form of
// the oracle, a root pair that none covers goes to the checker's root-pair checks, and
// any other pair is opened on the side where a link of the other end lies, else as the
// traversal opens it.
#pragma once

#include <algorithm>
#include <map>
#include <optional>
#include <string>
#include <tuple>
#include <unordered_map>
#include <vector>

#include "../cluster/cluster_oracles.h"
#include "hrbench/check_links.h"
#include "hrbench/clusters.h"
#include "util/format.h"
#include "violations.h"

namespace hrbench {

template <typename Shape, typename Oracle>
class ClusterCoverage {
  public:
    ClusterCoverage(const Patches<Shape> &patches, const RefineOptions &options,
                    const LinkConventions &conv, const LinkDump &dump, Violations &violations)
        : patches_(patches), options_(options), conv_(conv), dump_(dump), v_(violations),
          tree_(patches) {
        position_.resize(patches_.size());
        for (uint32_t k = 0; k < tree_.Patches().size(); ++k)
            position_[tree_.Patches()[k]] = k;
        opened_.assign(tree_.NumClusters(), false);
        used_.assign(dump_.clusterLinks.size(), false);
        IndexClusterLinks();
    }

    // Walks the hierarchy, calling rootPair(p, q), p < q, for every root pair that no
    // cluster link covers, in the traversal's order; then reports the cluster links the
    // walk never reached.
    template <typename RootPair>
    void Run(RootPair rootPair) {
        ClusterForm<Oracle> form(options_, patches_, tree_);
        NodeViews<Shape> views(patches_, tree_);
        if (tree_.NumClusters() > 0)
            Self(0, form, views, rootPair);
        for (uint32_t k = 0; k < dump_.clusterLinks.size(); ++k)
            if (valid_[k] && !used_[k])
                UnusedClusterLink(k);
    }

    bool HasLinks() const { return !linkOf_.empty(); }
    uint64_t NumClusters() const { return tree_.NumClusters(); }
    uint64_t Calls() const { return clusterCalls_; }  // cluster-oracle calls of the walk
    uint64_t Opened() const { return uint64_t(std::count(opened_.begin(), opened_.end(), true)); }

    // A valid cluster link other than _self_ that covers the node pair x, y: one between
    // an ancestor of x (or x) and an ancestor of y (or y).
    std::optional<uint32_t> CoveringLink(uint32_t x, uint32_t y,
                                         std::optional<uint32_t> self) const {
        std::vector<uint32_t> ys = Ancestors(y);
        for (uint32_t a : Ancestors(x))
            for (uint32_t b : ys) {
                auto found = linkOf_.find(Key(a, b));
                if (found != linkOf_.end())
                    for (uint32_t k : found->second)
                        if (k != self)
                            return k;
            }
        return std::nullopt;
    }

    // A node's patches: positions [begin, end) in the hierarchy's order of patches.
    std::pair<uint32_t, uint32_t> NodeRange(uint32_t node) const {
        if (IsCluster(node))
            return {tree_[ClusterIndex(node)].begin, tree_[ClusterIndex(node)].end};
        return {position_[node], position_[node] + 1};
    }
    // The node and its ancestors, the root cluster last.
    std::vector<uint32_t> Ancestors(uint32_t node) const {
        std::vector<uint32_t> chain = {node};
        if (tree_.NumClusters() == 0)
            return chain;
        if (!IsCluster(node))
            chain.push_back(node = ClusterNode(tree_.ParentOfPatch(node)));
        while (ClusterIndex(node) != 0)
            chain.push_back(node = ClusterNode(tree_[ClusterIndex(node)].parent));
        return chain;
    }
    std::string ClusterLinkName(uint32_t k) const {
        const DumpClusterLink &l = dump_.clusterLinks[k];
        return LinkDump::NodeName(l.a) + " " + LinkDump::NodeName(l.b);
    }

  private:
    static std::pair<uint32_t, uint32_t> Key(uint32_t x, uint32_t y) {
        return {std::min(x, y), std::max(x, y)};
    }

    // Checks each cluster link alone (its clusters exist, its ends are disjoint) and
    // indexes the valid ones: by node pair, and per node its partners sorted by range.
    void IndexClusterLinks() {
        valid_.assign(dump_.clusterLinks.size(), false);
        const uint32_t clusters = uint32_t(tree_.NumClusters());
        for (uint32_t k = 0; k < dump_.clusterLinks.size(); ++k) {
            const DumpClusterLink &l = dump_.clusterLinks[k];
            bool known = true;
            for (uint32_t node : {l.a, l.b})
                if (IsCluster(node) && ClusterIndex(node) >= clusters && known) {
                    known = false;
                    v_.Add("bad-cluster", l.line, false, 0, 0, [&] {
                        return ClusterLinkName(k) + ": the scene's hierarchy has no cluster " +
                               LinkDump::NodeName(node) + " (" + std::to_string(clusters) +
                               " cluster" + (clusters == 1 ? "" : "s") +
                               (clusters ? ", C0 to C" + std::to_string(clusters - 1) : "") + ")";
                    });
                }
            if (!known)
                continue;
            auto ra = NodeRange(l.a), rb = NodeRange(l.b);
            auto inside = [](std::pair<uint32_t, uint32_t> in, std::pair<uint32_t, uint32_t> out) {
                return out.first <= in.first && in.second <= out.second;
            };
            if (inside(ra, rb) || inside(rb, ra)) {
                v_.Add("link-within-cluster", l.line, false, 0, 0, [&] {
                    std::string a = LinkDump::NodeName(l.a), b = LinkDump::NodeName(l.b);
                    if (l.a == l.b)
                        return ClusterLinkName(k) + " (one cluster with itself)";
                    bool aIn = inside(ra, rb);
                    return ClusterLinkName(k) + " (" +
                           (IsCluster(aIn ? l.a : l.b) ? "cluster " : "patch ") + (aIn ? a : b) +
                           " lies in cluster " + (aIn ? b : a) + ")";
                });
                continue;
            }
            valid_[k] = true;
            linkOf_[Key(l.a, l.b)].push_back(k);
            partners_[l.a].push_back({rb.first, rb.second, k});
            partners_[l.b].push_back({ra.first, ra.second, k});
        }
        for (auto &entry : partners_)
            std::sort(
                entry.second.begin(), entry.second.end(), [](const Partner &a, const Partner &b) {
                    return std::tie(a.begin, a.end, a.link) < std::tie(b.begin, b.end, b.link);
                });
    }

    // A cluster link of _node_ whose other end lies strictly inside the range _in_, by
    // binary search over the node's partners (ranges of a tree: nested or disjoint).
    std::optional<uint32_t> PartnerInside(uint32_t node, std::pair<uint32_t, uint32_t> in) const {
        auto found = partners_.find(node);
        if (found == partners_.end())
            return std::nullopt;
        const std::vector<Partner> &list = found->second;
        auto it =
            std::lower_bound(list.begin(), list.end(), in.first,
                             [](const Partner &p, uint32_t begin) { return p.begin < begin; });
        // Those starting where _in_ starts come smallest first: descendants, then the
        // node of _in_ itself and its ancestors; any starting later inside it is inside.
        for (; it != list.end() && it->begin < in.second; ++it)
            if (it->end <= in.second && !(it->begin == in.first && it->end == in.second))
                return it->link;
        return std::nullopt;
    }

    template <typename Form, typename RootPair>
    void Self(uint32_t cluster, const Form &form, const NodeViews<Shape> &views,
              RootPair &rootPair) {
        const uint32_t *children = tree_[cluster].children;
        for (int s = 0; s < 2; ++s)
            if (IsCluster(children[s]))
                Self(ClusterIndex(children[s]), form, views, rootPair);
        NodePair(children[0], children[1], form, views, rootPair);
    }

    template <typename Form, typename RootPair>
    void NodePair(uint32_t x, uint32_t y, const Form &form, const NodeViews<Shape> &views,
                  RootPair &rootPair) {
        if (!IsCluster(x) && !IsCluster(y))
            return x < y ? rootPair(x, y) : rootPair(y, x);
        ++clusterCalls_;
        auto found = linkOf_.find(Key(x, y));
        if (found != linkOf_.end()) {
            // The first link of the pair covers it; a repeat stays unused, an overlap.
            uint32_t k = found->second.front();
            used_[k] = true;
            if (!conv_.ownOracle &&
                !ClusterAccepts(form, options_.clusterBound, views[x], views[y]))
                v_.Add("cluster-oracle", dump_.clusterLinks[k].line, false, 0, 0, [&] {
                    if (IsCluster(x) && IsCluster(y) &&
                        options_.clusterBound == ClusterBound::Patch)
                        return ClusterLinkName(k) +
                               " joins two clusters, which --cluster-bound patch never links";
                    return ClusterLinkName(k) + " is refused by the cluster form of the oracle " +
                           Oracle::kInfo.name + " (eps " + FormatDouble(options_.eps) + ")";
                });
            return;
        }
        std::optional<uint32_t> inY = PartnerInside(x, NodeRange(y));
        std::optional<uint32_t> inX = PartnerInside(y, NodeRange(x));
        if (inY && inX) {
            used_[*inY] = used_[*inX] = true;  // reported here, not again as unused
            return ClusterOverlap(*inY, *inX);
        }
        bool openX = inX || (!inY && OpensFirst(options_.clusterBound, views[x], views[y]));
        uint32_t open = openX ? x : y;
        opened_[ClusterIndex(open)] = true;
        const uint32_t *children = tree_[ClusterIndex(open)].children;
        for (int s = 0; s < 2; ++s)
            openX ? NodePair(children[s], y, form, views, rootPair)
                  : NodePair(x, children[s], form, views, rootPair);
    }

    // Two cluster links that cover a common root pair: name the later line, and the earlier.
    void ClusterOverlap(uint32_t a, uint32_t b) {
        size_t la = dump_.clusterLinks[a].line, lb = dump_.clusterLinks[b].line;
        if (la < lb)
            std::swap(a, b), std::swap(la, lb);
        v_.Add("overlapping-link", la, false, 0, 0, [&] {
            return ClusterLinkName(a) + " overlaps " + ClusterLinkName(b) + " of line " +
                   std::to_string(lb);
        });
    }

    // A cluster link the walk never reached lies inside a pair that another covers (or
    // below a pair where two overlap, already reported).
    void UnusedClusterLink(uint32_t k) {
        const DumpClusterLink &l = dump_.clusterLinks[k];
        std::optional<uint32_t> other = CoveringLink(l.a, l.b, k);
        if (!other)
            return;
        ClusterOverlap(k, *other);
    }

    const Patches<Shape> &patches_;
    const RefineOptions &options_;
    const LinkConventions &conv_;
    const LinkDump &dump_;
    Violations &v_;
    struct Partner {
        uint32_t begin, end;  // the other end's range
        uint32_t link;
    };
    ClusterTree<Shape> tree_;
    std::vector<uint32_t> position_;  // per patch: its place in tree_.Patches()
    std::map<std::pair<uint32_t, uint32_t>, std::vector<uint32_t>> linkOf_;
    std::unordered_map<uint32_t, std::vector<Partner>> partners_;
    std::vector<bool> valid_, used_, opened_;
    uint64_t clusterCalls_ = 0;
};

}  // namespace hrbench
