// The checks of one dump against the tiling, the oracle and the recursion limits
// (internal to check-links).
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <map>
#include <optional>
#include <tuple>
#include <unordered_map>

#include "cluster_coverage.h"
#include "hrbench/check_links.h"
#include "hrbench/forest.h"
#include "hrbench/oracles/registry.h"
#include "hrbench/refine.h"
#include "util/format.h"
#include "violations.h"
#include "visibility/culling.h"

namespace hrbench {

// A decision's tri-state judgement by a documented oracle: under accept=lt a pair between
// the oracle at eps and at the next double below may go either way.
enum class Judgement { Refuse, Accept, Either };

// The checks of one dump for one shape and one oracle. Every element pair is a region
// of its root pair's parameter domain: element x stands for the part of its root that
// its descendants cover, so pairs of tree elements tile exactly when their paths do,
// and the tiling is checked on paths alone, with no arithmetic.
template <typename Shape, typename Oracle>
class Checker {
  public:
    Checker(const Patches<Shape> &patches, const Oracle &oracle, const Oracle *oracleBelow,
            const RefineOptions &options, const LinkConventions &conv, const LinkDump &dump,
            Violations &violations)
        : patches_(patches), oracle_(oracle), oracleBelow_(oracleBelow), options_(options),
          conv_(conv), dump_(dump), v_(violations), forest_(patches, SIZE_MAX, options.subdivision),
          arity_(forest_.Arity()), minAreaBound_(MinAreaBound(options.minArea, conv.minAreaLe)),
          depthLimit_(options.maxDepth >= 0 ? options.maxDepth : kSafetyDepth),
          decided_(!dump.decisions.empty()) {}

    LinkCheck Run() {
        LinkCheck check;
        IndexDecisions();
        CheckPatches();
        SortByPair();
        // The refined root pairs (each direction of them) in scene order, classified as
        // Refine() does (touching patches without a recursion limit refused first, as it
        // refuses them), each checked as it comes: no list of pairs is kept, so that this
        // check's memory stays within the dump's size however large the scene.
        // With --clusters the walk of the hierarchy reaches the root pairs that no
        // cluster link covers, in the traversal's order.
        const uint32_t n = uint32_t(patches_.size());
        if (options_.clusters)
            ClusterWalk(check);
        else
            for (uint32_t p = 0; p < n; ++p)
                for (uint32_t q = p + 1; q < n; ++q)
                    RootPair(p, q, check);
        // Elements split by decisions the final links no longer follow (an earlier
        // pass's) were created all the same.
        for (const DumpDecision &d : dump_.decisions)
            if (d.action == DumpAction::Split)
                CreateChildren(d.splitI ? d.i : d.j);
        // With one pass every decision lies on the recursion; only where it went through
        // everywhere does an unreached one say more than the violations already found.
        if (decided_ && dump_.passes == 1 && v_.Total() == 0)
            for (size_t k = 0; k < dump_.decisions.size(); ++k)
                if (!reached_[k]) {
                    const DumpDecision &d = dump_.decisions[k];
                    v_.Add("stray-decision", d.line, true, d.i.root, d.j.root, [&] {
                        return "decide " + dump_.Name(d.i) + " " + dump_.Name(d.j) +
                               " is on a pair that ProjectKernel, following the recorded "
                               "decisions, never reaches (one pass)";
                    });
                }
        Counters &c = check.fromLinks;
        c.links = links_, c.forcedLinks = forced_;
        c.oracleCalls = calls_;
        check.forcedKnown = decided_ || !conv_.ownOracle;
        if (decided_) {
            c.oracleCalls = 0;
            for (const DumpDecision &d : dump_.decisions) {
                bool call = d.action != DumpAction::Cull;
                check.totalOracleCalls += call;
                c.oracleCalls += call && d.pass == dump_.passes;
            }
        } else {
            check.totalOracleCalls = calls_;
            check.oracleCallsKnown = dump_.passes == 1;
        }
        check.passes = dump_.passes;
        c.nodes = forest_.Size();
        c.leaves = forest_.NumLeaves();
        c.nodesPerDepth = forest_.NodesPerDepth();
        c.maxDepth = c.nodesPerDepth.size() - 1;
        c.rootPairs = check.rootPairs, c.culledPairs = check.culledPairs;
        if (clusters_) {
            check.clusters = true;
            c.oracleCalls += clusters_->Calls();
            check.totalOracleCalls += clusters_->Calls();
            c.clusterNodes = clusters_->NumClusters();
            c.clusterOracleCalls = clusters_->Calls();
            c.openedClusters = clusters_->Opened();
        }
        return check;
    }

  private:
    // The least square that --min-area does not force: A_p < A (lt) or A_p <= A (le)
    // exactly when A_p^2 is below it.
    static double MinAreaBound(double minArea, bool le) {
        double bound = SquaredSizeBound(minArea);
        if (le && minArea > 0)
            while (std::sqrt(bound) <= minArea)
                bound = std::nextafter(bound, HUGE_VAL);
        return bound;
    }

    const DumpElement &Side(uint32_t link, bool first) const {
        const DumpLink &l = dump_.links[link];
        return first ? l.i : l.j;
    }
    std::string LinkName(uint32_t link) const {
        const DumpLink &l = dump_.links[link];
        return dump_.Name(l.i) + " " + dump_.Name(l.j);
    }
    size_t Line(uint32_t link) const { return dump_.links[link].line; }

    // Two links overlap: name the later line, and the earlier one.
    void Overlap(uint32_t a, uint32_t b, uint32_t p, uint32_t q) {
        if (Line(a) < Line(b))
            std::swap(a, b);
        v_.Add("overlapping-link", Line(a), true, p, q, [&] {
            return LinkName(a) + " overlaps " + LinkName(b) + " of line " + std::to_string(Line(b));
        });
    }

    // Creates the children of the element _e_ of the dump, and its ancestors' (within the
    // safety depth), as a kernel splitting it does.
    void CreateChildren(const DumpElement &e) {
        if (e.depth >= kSafetyDepth)
            return;
        uint32_t id = e.root;
        for (int level = 0; level < e.depth; ++level)
            id = forest_.Children(id) + dump_.Digit(e, level);
        forest_.Children(id);
    }

    // Decisions by pair: the last one of each pair counts; with one pass none repeats.
    void IndexDecisions() {
        reached_.assign(dump_.decisions.size(), false);
        for (uint32_t k = 0; k < dump_.decisions.size(); ++k) {
            const DumpDecision &d = dump_.decisions[k];
            auto [it, fresh] = decisionOf_.emplace(dump_.Name(d.i) + " " + dump_.Name(d.j), k);
            if (!fresh) {
                if (dump_.passes == 1) {
                    size_t earlier = dump_.decisions[it->second].line;
                    v_.Add("stray-decision", d.line, true, d.i.root, d.j.root, [&] {
                        return "decide " + dump_.Name(d.i) + " " + dump_.Name(d.j) +
                               " repeats the decision of line " + std::to_string(earlier) +
                               " in one pass";
                    });
                    reached_[it->second] = true;  // reported once, as the repeat
                }
                it->second = k;
            }
        }
    }

    // Dump order: no link within one patch, none between a culled pair.
    void CheckPatches() {
        for (uint32_t k = 0; k < dump_.links.size(); ++k) {
            const DumpLink &l = dump_.links[k];
            if (l.i.root == l.j.root)
                v_.Add("link-within-patch", l.line, false, 0, 0, [&] {
                    return LinkName(k) + " (both elements of patch " + std::to_string(l.i.root) +
                           ")";
                });
            else if (conv_.cull != LinkConventions::Cull::None && Culled(l.i.root, l.j.root))
                v_.Add("culled-pair-linked", l.line, true, l.i.root, l.j.root, [&] {
                    return LinkName(k) + " (patches " + std::to_string(l.i.root) + " and " +
                           std::to_string(l.j.root) +
                           " cannot exchange light; hrbench never refines them)";
                });
        }
    }

    // Whether the root pair of a dump link is culled, cached by pair: the dump's pairs
    // only, so that the cache stays within the dump's size.
    bool Culled(uint32_t p, uint32_t q) {
        auto key = std::minmax(p, q);
        auto it = culled_.find(key);
        if (it == culled_.end())
            it = culled_
                     .emplace(key, ClassifyPair(patches_[key.first].shape,
                                                patches_[key.second].shape) == PairRelation::Culled)
                     .first;
        return it->second;
    }

    // cull=elements: the element pair faces away, centre against front normal
    // (docs/probe.md), each dot product summed in coordinate order.
    bool ElementCulled(uint32_t ex, uint32_t ey) const {
        if (conv_.cull != LinkConventions::Cull::Elements)
            return false;
        const auto &a = forest_[ex], &b = forest_[ey];
        auto facing = [&](const auto &from, const auto &to, uint32_t root) {
            const auto n = patches_[root].shape.Normal();
            double dot = 0;
            for (int k = 0; k < int(n.size()); ++k)
                dot += n[k] * (to.center[k] - from.center[k]);
            return dot > 0;
        };
        return !facing(a, b, a.root) || !facing(b, a, b.root);
    }

    // The links in order of root pair (as written for directed links), each pair's in
    // dump order.
    void SortByPair() {
        order_.resize(dump_.links.size());
        for (uint32_t k = 0; k < order_.size(); ++k)
            order_[k] = k;
        std::stable_sort(order_.begin(), order_.end(), [&](uint32_t a, uint32_t b) {
            const DumpLink &la = dump_.links[a], &lb = dump_.links[b];
            return std::make_pair(la.i.root, la.j.root) < std::make_pair(lb.i.root, lb.j.root);
        });
    }

    std::pair<size_t, size_t> Range(uint32_t p, uint32_t q) const {
        auto key = [&](uint32_t k) {
            return std::make_pair(dump_.links[k].i.root, dump_.links[k].j.root);
        };
        auto lo = std::partition_point(order_.begin(), order_.end(),
                                       [&](uint32_t k) { return key(k) < std::make_pair(p, q); });
        auto hi = std::partition_point(lo, order_.end(),
                                       [&](uint32_t k) { return key(k) == std::make_pair(p, q); });
        return {size_t(lo - order_.begin()), size_t(hi - order_.begin())};
    }

    // One root pair p < q: classified as Refine() does, and checked where it is refined.
    void RootPair(uint32_t p, uint32_t q, LinkCheck &check) {
        ++check.rootPairs;
        PairRelation relation = ClassifyPair(patches_[p].shape, patches_[q].shape);
        bool refined =
            conv_.cull == LinkConventions::Cull::None
                ? relation != PairRelation::Touching || RefinesRootPair(relation, p, q, options_)
                : RefinesRootPair(relation, p, q, options_);
        if (!refined) {
            ++check.culledPairs;
            return;
        }
        CheckPair(p, q);
        if (conv_.directed)
            CheckPair(q, p);
    }

    // --clusters: the dump's cluster links and the root pairs they leave, checked along
    // the hierarchy (ClusterCoverage), then element links under a cluster link.
    void ClusterWalk([[maybe_unused]] LinkCheck &check) {
        if constexpr (ClusterForm<Oracle>::kExists) {
            clusters_.emplace(patches_, options_, conv_, dump_, v_);
            clusters_->Run([&](uint32_t p, uint32_t q) { RootPair(p, q, check); });
            ElementLinksUnderClusterLinks();
        }
    }

    // Element links of a root pair that a cluster link covers cover it twice.
    void ElementLinksUnderClusterLinks() {
        if (!clusters_->HasLinks())
            return;
        for (size_t lo = 0; lo < order_.size();) {
            const DumpLink &first = dump_.links[order_[lo]];
            uint32_t p = first.i.root, q = first.j.root;
            size_t hi = Range(p, q).second;
            std::optional<uint32_t> cover;
            if (p != q)
                cover = clusters_->CoveringLink(p, q, std::nullopt);
            for (size_t k = lo; cover && k < hi; ++k)
                v_.Add("overlapping-link", Line(order_[k]), true, p, q, [&] {
                    return LinkName(order_[k]) + " lies in the root pair " + std::to_string(p) +
                           " " + std::to_string(q) + ", which the cluster link " +
                           clusters_->ClusterLinkName(*cover) + " of line " +
                           std::to_string(dump_.clusterLinks[*cover].line) + " covers";
                });
            lo = hi;
        }
    }

    // One refined root pair (one direction with directed links): its tiling, then, if
    // it tiles, ProjectKernel guided by its links and decisions.
    void CheckPair(uint32_t p, uint32_t q) {
        auto [lo, hi] = Range(p, q);
        std::string x, y;
        uint64_t before = v_.Total();
        Tile(lo, hi, p, q, x, y);
        if (v_.Total() != before)
            return;
        std::sort(order_.begin() + lo, order_.begin() + hi);  // dump order again
        Guide(lo, hi, p, q, p, q, x, y);
    }

    // Reorders order_[lo, hi) stably by the path digit at _level_ of side _first_;
    // returns where each child's links begin (and the end).
    std::array<size_t, 5> Partition(size_t lo, size_t hi, bool first, int level) {
        scratch_.assign(order_.begin() + lo, order_.begin() + hi);
        std::array<size_t, 5> begin{};
        for (uint32_t k : scratch_)
            ++begin[dump_.Digit(Side(k, first), level) + 1];
        begin[0] = lo;
        for (int c = 1; c <= arity_; ++c)
            begin[c] += begin[c - 1];
        std::array<size_t, 5> next = begin;
        for (uint32_t k : scratch_)
            order_[next[dump_.Digit(Side(k, first), level)]++] = k;
        return begin;
    }

    // Tiling: the links order_[lo, hi) (those inside the region x * y of root pair p, q)
    // must cover it without overlap. Where no link covers the region whole, one side of
    // it has every link finer than the region: split that side (x first). If neither
    // side has, a link whole in x and one whole in y cross, so they overlap. An empty
    // region is left to Guide where decisions or element culling may explain it.
    void Tile(size_t lo, size_t hi, uint32_t p, uint32_t q, std::string &x, std::string &y) {
        if (lo == hi) {
            if (!decided_ && conv_.cull != LinkConventions::Cull::Elements)
                v_.Add("missing-link", 0, true, p, q, [&] {
                    return "nothing covers the element pair " + ElementName(p, x) + " " +
                           ElementName(q, y) + " of patches " + std::to_string(p) + " and " +
                           std::to_string(q);
                });
            return;
        }
        const size_t dx = x.size(), dy = y.size();
        size_t wholeX = hi, wholeY = hi;
        for (size_t k = lo; k < hi; ++k) {
            bool coarseX = Side(order_[k], true).depth <= dx;
            bool coarseY = Side(order_[k], false).depth <= dy;
            if (coarseX && coarseY) {
                if (hi - lo > 1)
                    Overlap(order_[k], order_[k == lo ? lo + 1 : lo], p, q);
                return;
            }
            if (coarseX && wholeX == hi)
                wholeX = k;
            if (coarseY && wholeY == hi)
                wholeY = k;
        }
        if (wholeX != hi && wholeY != hi)
            return Overlap(order_[wholeX], order_[wholeY], p, q);
        bool splitX = wholeX == hi;
        std::string &side = splitX ? x : y;
        std::array<size_t, 5> begin = Partition(lo, hi, splitX, int(side.size()));
        for (int c = 0; c < arity_; ++c) {
            side.push_back(char('0' + c));
            Tile(begin[c], begin[c + 1], p, q, x, y);
            side.pop_back();
        }
    }

    Judgement Judge(const typename Forest<Shape>::ElementType &ei,
                    const typename Forest<Shape>::ElementType &ej) const {
        bool at = oracle_.Acceptable(ei, ej);
        if (!oracleBelow_)
            return at ? Judgement::Accept : Judgement::Refuse;
        bool below = oracleBelow_->Acceptable(ei, ej);
        return below ? Judgement::Accept : at ? Judgement::Either : Judgement::Refuse;
    }

    // ProjectKernel on the pair of elements ex (path x, root p) and ey (path y, root q),
    // guided by the links of the region (which tile it) and, where the dump has them, by
    // the recorded decisions.
    void Guide(size_t lo, size_t hi, uint32_t p, uint32_t q, uint32_t ex, uint32_t ey,
               std::string &x, std::string &y);

    // The calls on the children of the split element, first child first.
    void Descend(size_t lo, size_t hi, uint32_t p, uint32_t q, uint32_t ex, uint32_t ey,
                 std::string &x, std::string &y, bool splitX);

    const char *TieName() const {
        switch (conv_.tie) {
        case LinkConventions::Tie::First:
            return "first";
        case LinkConventions::Tie::Second:
            return "second";
        case LinkConventions::Tie::Receiver:
            return "receiver";
        default:
            return "source";
        }
    }

    const Patches<Shape> &patches_;
    const Oracle &oracle_;
    const Oracle *oracleBelow_;  // accept=lt: the oracle at the next double below eps
    const RefineOptions &options_;
    const LinkConventions &conv_;
    const LinkDump &dump_;
    Violations &v_;
    Forest<Shape> forest_;  // the elements ProjectKernel creates, in its order
    const int arity_;
    const double minAreaBound_;
    const int depthLimit_;
    const bool decided_;  // the dump records decisions
    std::map<std::pair<uint32_t, uint32_t>, bool> culled_;
    std::unordered_map<std::string, uint32_t> decisionOf_;  // pair -> its last decision
    std::vector<bool> reached_;
    std::vector<uint32_t> order_, scratch_;
    uint64_t calls_ = 0, links_ = 0, forced_ = 0;

    // --clusters: the hierarchy, and the cluster links by node pair and by node.
    std::optional<ClusterCoverage<Shape, Oracle>> clusters_;  // --clusters
};

}  // namespace hrbench

#include "guide.h"  // Checker::Guide and Descend, the replay of ProjectKernel
