// Refinement: ProjectKernel over every root pair of a scene (docs/conventions.md),
// for either shape, with its forest, links and run record.
#pragma once

#include <atomic>
#include <cstdint>
#include <variant>
#include <vector>

#include "hrbench/clusters.h"
#include "hrbench/forest.h"
#include "hrbench/link_buffer.h"
#include "hrbench/record.h"
#include "hrbench/refine_options.h"
#include "hrbench/scene.h"

namespace hrbench {

// Where a refinement is, for a display on another thread (RefineOptions::progress):
// written at most once per root pair in the first pass (which refines every pair down
// to the task depth, src/refine/kernel.h) and once per task after it, never inside the
// recursion.
struct RefineProgress {
    std::atomic<uint64_t> rootPairs{0};  // of the scene, set when the run starts; 0: unknown
    std::atomic<uint64_t> pair{0};       // the root pair being refined, from 1; 0: none yet
    std::atomic<int> pass{0};            // 1: the first pass, 2: the tasks (or the only
                                         // pass, of a count-only run on one thread)

    // Starts pass _number_ (single-threaded).
    void StartPass(int number) {
        pair.store(0, std::memory_order_relaxed);
        pass.store(number, std::memory_order_relaxed);
    }
    // Moves on to root pair _ordinal_, unless a later one has been reached (threads).
    void At(uint64_t ordinal) {
        uint64_t seen = pair.load(std::memory_order_relaxed);
        while (seen < ordinal &&
               !pair.compare_exchange_weak(seen, ordinal, std::memory_order_relaxed)) {
        }
    }
};

// Per root pair tallies, for the invariant oracle_calls = 2 * links - 1.
struct PairTally {
    uint32_t p, q;         // root indices, p < q
    uint64_t links;        // links made between the trees of p and q
    uint64_t oracleCalls;  // oracle calls spent on the pair
};

// Element ids are canonical: roots first, in scene order, then each sibling group in
// the order the refinement first splits its parent, running in task order (the
// sequential pass down to the task depth, then the tasks in order, src/refine/kernel.h),
// as one thread makes them. Several workers' trees are merged into the same ids when links
// are stored, so ids, like counts, do not depend on the number of threads. Links are in
// that task order too. In count-only mode on several threads, where no link refers to
// an id, the forest holds only the roots: the workers' trees are counted as one rather
// than merged (the counters are the same).
template <typename Shape>
struct Refinement {
    Forest<Shape> forest;
    LinkBuffer links;  // empty in count-only mode
    // Refined (non-culled) root pairs in order; with --clusters in count-only mode none,
    // so that nothing is kept per pair (on several threads the pairs that reach the task
    // depth, src/refine/kernel.h, are kept while their tasks run).
    std::vector<PairTally> pairs;
    RunRecord record;                       // method "enumerate", the counters and the time
    ClusterTree<Shape> clusters;            // empty without --clusters
    std::vector<ClusterLink> clusterLinks;  // store mode only, in traversal order
    // Store mode with visibility (--visibility other than none): each link's visible
    // fraction as the refinement sampled it, in link order; else empty.
    std::vector<double> visible;
};

using AnyRefinement = std::variant<Refinement<Segment>, Refinement<Polygon>>;

// Refines every root pair of _scene_, whichever its shape. Throws InputError for an
// invalid scene or options, or touching patches without a recursion limit; LimitError
// when the safety depth or the memory budget is reached. The refinement's forest reads
// its roots' shapes from the scene's patches: the scene must outlive the refinement
// (a temporary is refused).
AnyRefinement Refine(const Scene &scene, const RefineOptions &options);
AnyRefinement Refine(const Scene &&, const RefineOptions &) = delete;

// The same for a scene known to hold _Shape_ patches (InputError otherwise).
template <typename Shape>
Refinement<Shape> Refine(const Scene &scene, const RefineOptions &options);
template <typename Shape>
Refinement<Shape> Refine(const Scene &&, const RefineOptions &) = delete;

extern template Refinement<Segment> Refine(const Scene &, const RefineOptions &);
extern template Refinement<Polygon> Refine(const Scene &, const RefineOptions &);

}  // namespace hrbench
