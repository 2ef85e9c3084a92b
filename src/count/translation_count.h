// Exact counters of the parallel-plate family far beyond enumeration, from the
// translation invariance of ProjectKernel (the `--method translation` of `hrbench run`).
//
// For two facing plates of equal length (`parallel`, l2 = l) every element pair
// that the recursion reaches at level n = depth_i + depth_j has the same two sizes
// (l / 2^ceil(n/2), l / 2^floor(n/2)), and its oracle outcome and its whole subtree
// depend only on the vector between the two midpoints. The method therefore counts
// pairs by *state* (n, c), with c the exact integer offset of the midpoints in units
// of l / 2^(ceil(n/2)+1), level by level, carrying for each state the number of
// pairs in it in a flat array. The oracle is monotone in the distance, so the rejected
// states of a level are one run, whose ends a binary search finds. The elements are
// counted the same way: the pairs visited in one element's column (or row) form a
// contiguous run of states, one pair per state, so the elements whose run contains a
// state are as many as its pairs, and each element is counted once, at the state its
// run starts. A level costs a few additions per state (about 4 / eps states), not an
// oracle call per state and not the number of links.
//
// The oracle is evaluated with the engine's own code on the midpoint difference of
// the state, and the method only accepts plates whose midpoints, down to the deepest
// level reached, are exact in double precision (dyadic lengths and offset), so that
// every pair in a state gives the oracle the same doubles and the counts equal direct
// enumeration, ties included.
//
// In 3D (`parallel3d`, the rectangles one above the other: no offset) the states are
// the offsets (cx, cy) of the centroids in a dense grid, one rejected run per row, and
// every element of the plate halved at a level is halved (the pair above or below it
// is its nearest and is visited), so the trees need no states; quadtree subdivision
// halves both sides at once (translation_count3d.cpp).
#pragma once

#include <cstdint>

#include "hrbench/record.h"
#include "hrbench/refine_options.h"
#include "hrbench/scene.h"

namespace hrbench {

// What the translation method computed, and how much work it took.
struct TranslationCount {
    RunRecord record;                // method "translation": the counters Refine() reports
                                     // in count-only mode, and the time
    uint64_t pairStates = 0;         // distinct (level, offset) states carried
    uint64_t elementStates = 0;      // distinct (level, tree, run start) element states
                                     // (3D: one per level, whose plate halves entirely)
    uint64_t oracleEvaluations = 0;  // oracle calls made, a few per level
};

// Throws InputError, with a message naming what is wrong, unless _scene_ and _options_
// are in the method's scope: two facing parallel plates of equal length, P from (0,0)
// to (l,0) and Q from (offset+l,d) to (offset,d) with d > 0 (the `parallel` family with
// l2 = l), or two facing l x w rectangles, P = [0,l] x [0,w] at z=0 and Q the same at
// z=d > 0 (`parallel3d` with ox = oy = 0); oracle garmann; count-only; no recursion
// limit (no --min-area, --max-depth); no visibility mode; binary subdivision (3D:
// binary or quadtree); and sides and offset with exact midpoints and centroids in
// double precision (checked again, level by level, during the count).
void CheckTranslationScope(const Scene &scene, const RefineOptions &options);

// Counts exactly what Refine(scene, options) counts in count-only mode, without
// enumerating the pairs. Throws InputError outside the method's scope (see
// CheckTranslationScope), LimitError where Refine() would reach the safety depth or
// a counter would exceed 64 bits.
TranslationCount CountByTranslation(const Scene &scene, const RefineOptions &options);

}  // namespace hrbench
