// What the translation method's flatland (translation_count.cpp) and space
// (translation_count3d.cpp) halves share: exactness, checked counters, the rejected run
// of a monotone oracle, and the trees' summary.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "count/translation_count.h"
#include "hrbench/record.h"
#include "hrbench/refine_options.h"
#include "hrbench/scene.h"
#include "hrbench/util/error.h"

namespace hrbench::translation {

// Exponent of the lowest set bit of a finite _x_ != 0: x = odd * 2^LowBit(x).
inline int LowBit(double x) {
    int e;
    double m = std::frexp(std::abs(x), &e);           // |x| = m 2^e, m in [0.5, 1)
    uint64_t mantissa = uint64_t(std::ldexp(m, 53));  // exact: at most 53 bits
    return e - 53 + __builtin_ctzll(mantissa);
}

// True when every multiple of 2^_gridExponent_ of magnitude at most _bound_ is a
// double: _bound_ needs at most 53 significant bits on that grid.
inline bool FitsGrid(double bound, int gridExponent) {
    return std::isfinite(bound) && std::ilogb(bound) <= 52 + gridExponent;
}

[[noreturn]] inline void Overflow() {
    throw LimitError("--method translation: a counter exceeds 2^64; use a larger eps");
}

inline uint64_t CheckedAdd(uint64_t a, uint64_t b) {
    uint64_t sum;
    if (__builtin_add_overflow(a, b, &sum))
        Overflow();
    return sum;
}

inline uint64_t CheckedMul(uint64_t a, uint64_t b) {
    uint64_t product;
    if (__builtin_mul_overflow(a, b, &product))
        Overflow();
    return product;
}

inline uint64_t Checked(unsigned __int128 sum) {
    if (sum > UINT64_MAX)
        Overflow();
    return uint64_t(sum);
}

// The rejected states of a row of states, indices [lo, end) (empty when lo = end).
// _rejected_ is monotone in |x_i - x_j| (the oracle compares a fixed size with a
// rounded, hence monotone, function of the distance), and x_i - x_j grows with the
// index: the rejected states are one run around the sign change, whose two ends a
// binary search finds. _below_ says whether x_i - x_j of an index is negative.
template <typename Rejected, typename Below>
std::pair<size_t, size_t> RejectedRun(size_t size, const Rejected &rejected, const Below &below) {
    // The end of the prefix of [lo, end) on which _holds_ is true.
    auto prefixEnd = [](size_t lo, size_t end, const auto &holds) {
        while (lo < end) {
            size_t mid = lo + (end - lo) / 2;
            if (holds(mid))
                lo = mid + 1;
            else
                end = mid;
        }
        return lo;
    };
    size_t zero = prefixEnd(0, size, below);
    size_t lo = prefixEnd(0, zero, [&](size_t i) { return !rejected(i); });
    return {lo, prefixEnd(zero, size, rejected)};
}

// Throws what Refine() throws when the preferred element of a rejected pair of
// patches 0 and 1 has reached the safety depth.
inline void CheckSafetyDepth(int preferredDepth) {
    if (preferredDepth >= kSafetyDepth)
        ThrowSafetyDepth(0, 1);
}

// Fills the tree counters from the elements halved per depth in P and Q (each halving
// adds _arity_ children), and drops the trailing zeros of the link histogram.
inline void SummariseTrees(std::vector<uint64_t> splitP, std::vector<uint64_t> splitQ, int arity,
                           Counters &counters) {
    size_t depths = std::max(splitP.size(), splitQ.size()) + 1;
    splitP.resize(depths, 0), splitQ.resize(depths, 0);
    counters.nodesPerDepth.assign(depths, 0);
    counters.nodesPerDepth[0] = 2;
    uint64_t halvedTotal = 0;
    for (size_t k = 0; k + 1 < depths; ++k) {
        uint64_t halved = CheckedAdd(splitP[k], splitQ[k]);
        counters.nodesPerDepth[k + 1] = CheckedMul(uint64_t(arity), halved);
        halvedTotal = CheckedAdd(halvedTotal, halved);
    }
    while (counters.nodesPerDepth.size() > 1 && counters.nodesPerDepth.back() == 0)
        counters.nodesPerDepth.pop_back();
    for (uint64_t n : counters.nodesPerDepth)
        counters.nodes = CheckedAdd(counters.nodes, n);
    counters.leaves = counters.nodes - halvedTotal;
    counters.maxDepth = counters.nodesPerDepth.size() - 1;
    DropTrailingZeros(counters.linksPerDepth);
}

// The two halves of the method, for the `parallel` and the `parallel3d` plates; the
// public functions of translation_count.h dispatch on the scene's dimension.
void CheckFlatlandScope(const Scene &scene, const RefineOptions &options);
TranslationCount CountFlatland(const Scene &scene, const RefineOptions &options);
void CheckSpaceScope(const Scene &scene, const RefineOptions &options);
TranslationCount CountSpace(const Scene &scene, const RefineOptions &options);

}  // namespace hrbench::translation
