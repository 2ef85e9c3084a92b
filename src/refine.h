// ProjectKernel over every root pair of a scene (DESIGN section 2).
#pragma once

#include <cstdint>
#include <vector>

#include "counters.h"
#include "element_tree.h"
#include "link_buffer.h"
#include "oracle.h"
#include "polygon.h"
#include "polygon_forest.h"
#include "scene.h"
#include "visibility.h"

namespace hrbench {

// Depth beyond which no element is halved without a user limit: deeper elements
// lose their midpoints to double rounding, and a pair that gets there would not
// terminate on its own (touching patches). Reaching it is an error.
constexpr int kSafetyDepth = 48;

struct RefineOptions {
    OracleKind oracle = OracleKind::Garmann;
    double eps = 0;          // oracle threshold, > 0
    double minArea = 0;      // link a pair whose preferred element is smaller; 0 = off
    int maxDepth = -1;       // link a pair whose preferred element has this depth; -1 = off
    bool storeLinks = false; // keep every link (store mode) or only count (count-only)
    size_t memoryBudget = 0; // bytes for elements and links; 0 = what the machine has free
    int threads = 1;         // worker threads; counts never depend on it
    Subdivision subdivision = Subdivision::Binary;  // 3D: two halves or four quarters
    VisibilityMode visibility = VisibilityMode::None;  // how occlusion counts (docs/3d.md)
    int raysPerSide = 3;     // k: sample points per element side for visibility, 1..16

    bool HasRecursionLimit() const { return minArea > 0 || maxDepth >= 0; }
};

// Throws InputError naming the option when _options_ are out of range.
void ValidateOptions(const RefineOptions &options);

// Per root pair tallies, for the invariant oracle_calls = 2 * links - 1.
struct PairTally {
    uint32_t p, q;         // root indices, p < q
    uint64_t links;        // links made between the trees of p and q
    uint64_t oracleCalls;  // oracle calls spent on the pair
};

// Element ids are canonical: roots first, then the union of all trees in preorder,
// children allocated when their parent is first reached. So ids, like counts, do
// not depend on the number of threads. Links are ordered by the refinement's task
// order, which does not depend on it either.
struct Refinement {
    SegmentForest forest;
    Counters counters;
    LinkBuffer links;              // empty in count-only mode
    std::vector<PairTally> pairs;  // refined (non-culled) root pairs in order
    double seconds = 0;            // wall time of the refinement
    PolygonForest forest3d = PolygonForest();  // the trees of a 3D scene; empty in 2D
};

// Refines every root pair of _scene_ (its trees go to _forest_ in 2D, _forest3d_ in 3D).
// Throws InputError for invalid options or touching patches without a recursion limit,
// LimitError when the safety depth or the memory budget is reached.
Refinement Refine(const Scene &scene, const RefineOptions &options);

// Free memory reported by the operating system (MemAvailable), in bytes.
size_t AvailableMemoryBytes();

}  // namespace hrbench
