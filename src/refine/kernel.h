// ProjectKernel: the refinement recursion of docs/conventions.md, compiled once per
// forest, arity, oracle, storage mode and visibility policy (chosen by Refine()).
// Internal to the engine (refine.cpp and its tests), not installed.
#pragma once

#include <algorithm>
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "decisions.h"
#include "hrbench/forest.h"
#include "hrbench/link_buffer.h"
#include "hrbench/refine_options.h"
#include "hrbench/util/error.h"
#include "visibility/visibility.h"

namespace hrbench {

// Pairs whose depths add up to this are handed to the worker threads as tasks.
// A constant, not a function of the thread count, so that the task list (and with
// it the order of links) is the same for every thread count.
constexpr int kTaskDepth = 10;

// A pending ProjectKernel call.
struct Call {
    uint32_t i, j;
    int32_t depthI, depthJ;
};

// A subtree of the refinement left to a worker, with the root pair it belongs to.
struct Task {
    Call call;
    uint32_t pair;
};

// What one kernel instance counted.
struct Tally {
    uint64_t oracleCalls = 0, forcedLinks = 0;
    VisibilityTally visibility;
    std::array<uint64_t, 2 * kSafetyDepth + 1> linksPerDepth{};

    // The links, summed from their depths (the kernel counts each link once).
    uint64_t Links() const {
        uint64_t links = 0;
        for (uint64_t n : linksPerDepth)
            links += n;
        return links;
    }

    void Add(const Tally &other) {
        oracleCalls += other.oracleCalls, forcedLinks += other.forcedLinks;
        visibility.Add(other.visibility);
        for (size_t d = 0; d < linksPerDepth.size(); ++d)
            linksPerDepth[d] += other.linksPerDepth[d];
    }
};

// The recursion of docs/conventions.md for one forest, one arity, one oracle type and
// one storage mode, so that subdivision, the oracle and the link sink are inlined. It
// runs depth-first, first child first. With _kFrontier_ it stops at kTaskDepth and
// records the pairs there as tasks instead. _Visibility_ is NoVisibility (occlusion
// ignored, compiled out) or SampledVisibility (docs/3d.md).
template <typename Forest, int kArity, typename Oracle, bool kStoreLinks, bool kFrontier,
          typename Visibility = NoVisibility>
class ProjectKernel {
  public:
    ProjectKernel(Forest &forest, const Oracle &oracle, const RefineOptions &options,
                  size_t maxLinks, const Visibility &visibility = Visibility())
        : forest_(forest), oracle_(oracle), visibility_(visibility),
          minAreaBound_(SquaredSizeBound(options.minArea)), limits_(options), maxLinks_(maxLinks) {}

    // Refines _start_ completely (below the frontier), appending links to _links_, with
    // visibility (store mode) each link's visible fraction to _visible_, and frontier
    // pairs to _tasks_.
    void Project(Call start, uint32_t pair, LinkBuffer &links, std::vector<double> &visible,
                 std::vector<Task> *tasks) {
        if (links_ != &links)  // a buffer this kernel has not backed yet (tasks share one)
            links_ = &links, backedEnd_ = links.end();
        visible_ = &visible;
        next_ = links.end();
        tasks_ = tasks;
        pair_ = pair;
        if constexpr (kLookahead) {
            ++tally.oracleCalls;
            if (oracle_.Acceptable(forest_[start.i], forest_[start.j]))
                AddLink(start.i, start.j, start.depthI + start.depthJ);
            else
                Split(start.i, start.j, start.depthI, start.depthJ);
        } else {
            Recurse(start.i, start.j, start.depthI, start.depthJ);
        }
        if constexpr (kStoreLinks)
            links.Resize(size_t(next_ - links.begin()));
    }

    Tally tally;

  private:
    // Below the frontier and without visibility the kernel runs Split(), which decides
    // the oracle calls of a rejected pair's children before it descends: about half of
    // all calls are accepted, and these then cost no function call of their own
    // (about 10 % less CPU time on the headline configuration, docs/benchmarks.md).
    static constexpr bool kLookahead = !kFrontier && !Visibility::kEnabled;

    // The rest of ProjectKernel(i, j) for a pair the oracle rejected: the recursion
    // limit, then the children of the preferred element. Their oracle calls are made
    // here, all before the first child's subtree (the oracle reads only what never
    // changes), and their links and subtrees follow in order, first child first, so
    // that links, counts and errors come out exactly as from Recurse().
    void Split(uint32_t i, uint32_t j, int depthI, int depthJ) {
        bool acceptable[kArity];
        if (SplitsFirst(forest_[i], forest_[j])) {
            uint32_t child = ChildrenOrLink(i, depthI, i, j, depthI + depthJ);
            if (child == kNoChildren)
                return;
            tally.oracleCalls += kArity;
            for (int c = 0; c < kArity; ++c)
                acceptable[c] = oracle_.Acceptable(forest_[child + c], forest_[j]);
            for (int c = 0; c < kArity; ++c) {
                if (acceptable[c])
                    AddLink(child + c, j, depthI + 1 + depthJ);
                else
                    Split(child + c, j, depthI + 1, depthJ);
            }
        } else {
            uint32_t child = ChildrenOrLink(j, depthJ, i, j, depthI + depthJ);
            if (child == kNoChildren)
                return;
            tally.oracleCalls += kArity;
            for (int c = 0; c < kArity; ++c)
                acceptable[c] = oracle_.Acceptable(forest_[i], forest_[child + c]);
            for (int c = 0; c < kArity; ++c) {
                if (acceptable[c])
                    AddLink(i, child + c, depthI + depthJ + 1);
                else
                    Split(i, child + c, depthI, depthJ + 1);
            }
        }
    }

    // One ProjectKernel call, for the frontier pass and with visibility (Split() runs
    // the rest). Plain recursion with scalar arguments: measured with fewer
    // instructions per call than an explicit stack, a packed argument struct, or a
    // separate function for rejected pairs that still made one call per pair.
    void Recurse(uint32_t i, uint32_t j, int depthI, int depthJ) {
        if constexpr (kFrontier) {
            if (depthI + depthJ >= kTaskDepth)
                return tasks_->push_back({{i, j, depthI, depthJ}, pair_});
        }
        ++tally.oracleCalls;
        const auto &ei = forest_[i], &ej = forest_[j];
        if constexpr (Visibility::kEnabled) {
            // Estimate the visible fraction: drop occluded pairs, weight or refine partial ones.
            double visible = visibility_.Fraction(forest_, i, j, tally.visibility);
            fraction_ = visible;
            if (visible == 0) {
                ++tally.visibility.occludedPairs;
                return;
            }
            if (AcceptsVisible(oracle_, visibility_, ei, ej, visible))
                return AddLink(i, j, depthI + depthJ);
        } else {
            if (oracle_.Acceptable(ei, ej))
                return AddLink(i, j, depthI + depthJ);
        }

        // Recurse into the children of the preferred element, first child first, unless
        // the recursion limits stop it.
        if (SplitsFirst(ei, ej)) {
            uint32_t child = ChildrenOrLink(i, depthI, i, j, depthI + depthJ);
            if (child == kNoChildren)
                return;
            for (int c = 0; c < kArity; ++c)
                Recurse(child + c, j, depthI + 1, depthJ);
        } else {
            uint32_t child = ChildrenOrLink(j, depthJ, i, j, depthI + depthJ);
            if (child == kNoChildren)
                return;
            for (int c = 0; c < kArity; ++c)
                Recurse(i, child + c, depthI, depthJ + 1);
        }
    }

    // The first child of element _e_ (at depth _depthE_), which the rejected pair (i, j)
    // splits; or, where the recursion limits keep _e_ whole, kNoChildren, the pair then
    // a forced link. The limits are properties of the element alone, fixed for a run, and an
    // element is only ever split after passing them, so an element split before needs
    // no check: the children it already has are all that the hot path reads.
    uint32_t ChildrenOrLink(uint32_t e, int depthE, uint32_t i, uint32_t j, int depth) {
        uint32_t first = forest_[e].firstChild;
        if (first != kNoChildren) [[likely]]
            return first;
        // The depth first: its error stands whatever --min-area says.
        if (limits_.DepthStops(depthE, forest_[i].root, forest_[j].root) ||
            RecursionLimits::BelowMinArea(forest_[e].sizeSquared, minAreaBound_)) {
            ++tally.forcedLinks;
            AddLink(i, j, depth);
            return kNoChildren;
        }
        return forest_.Children(e);  // may move the arena: index again
    }

    void AddLink(uint32_t i, uint32_t j, int depth) {
        ++tally.linksPerDepth[depth];
        if constexpr (kStoreLinks) {
            if (next_ == backedEnd_)
                GrowLinks();
            *next_++ = {i, j};
            if constexpr (Visibility::kEnabled)
                visible_->push_back(fraction_);
        }
    }

    // Makes room for the next links: doubles the buffer when it is full (within the
    // budget), and backs the next kPopulate links with memory in one system call,
    // where a fault per page cost store mode about a tenth of its time
    // (docs/benchmarks.md). The first kPopulate links fault page by page, so that a
    // small run touches no more than it writes. Out of line: it runs once per
    // kPopulate links.
    [[gnu::noinline]] void GrowLinks() {
        links_->Resize(size_t(next_ - links_->begin()));
        if (links_->size() == links_->capacity()) {
            size_t capacity = std::max<size_t>(2 * links_->capacity(), 1 << 16);
            if (capacity > maxLinks_)
                throw LimitError("stored links would exceed the memory budget (" +
                                 std::to_string(links_->size()) +
                                 " links); use --count-only, a larger eps or --max-memory");
            links_->Reserve(capacity);
            if constexpr (Visibility::kEnabled)
                visible_->reserve(capacity);
        }
        size_t backed = std::min(links_->capacity(), links_->size() + kPopulate);
        if (links_->size() >= kPopulate)
            links_->Populate(links_->size(), backed);
        next_ = links_->end(), backedEnd_ = links_->begin() + backed;
    }
    static constexpr size_t kPopulate = size_t(1) << 16;  // 512 KiB: still in cache when written

    Forest &forest_;
    const Oracle oracle_;
    Visibility visibility_;
    const double minAreaBound_;  // sqrt(A^2) < --min-area iff A^2 < minAreaBound_
    const RecursionLimits limits_;
    const size_t maxLinks_;
    // Appending writes at next_, and syncs the buffer's size at the end of Project()
    // and in GrowLinks(): the kernel then keeps no buffer fields in step per link.
    LinkBuffer *links_ = nullptr;
    Link *next_ = nullptr;       // where the next link goes
    Link *backedEnd_ = nullptr;  // links_ is backed with memory up to here
    // With visibility: each stored link's visible fraction, in link order, and the
    // fraction of the pair that Recurse() is at, which a link made there takes (the
    // solve weighs the link by it rather than sampling the same rays again).
    std::vector<double> *visible_ = nullptr;
    double fraction_ = 1;
    std::vector<Task> *tasks_ = nullptr;
    uint32_t pair_ = 0;
};

}  // namespace hrbench
