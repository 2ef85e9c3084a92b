#include "hrbench/translation_count.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

#include "hrbench/oracles/garmann.h"
#include "hrbench/util/error.h"
#include "hrbench/util/format.h"

namespace hrbench {

namespace {

// The two plates: P from (0,0) to (l,0), Q from (xa,d) to (xb,d) = (xa-l,d).
struct Plates {
    double l;   // length of both plates
    double xa;  // x of Q's start (offset + l)
    double xb;  // x of Q's end (offset)
    double d;   // distance between the plates, > 0
};

// Exponent of the lowest set bit of a finite _x_ != 0: x = odd * 2^LowBit(x).
int LowBit(double x) {
    int e;
    double m = std::frexp(std::abs(x), &e);           // |x| = m 2^e, m in [0.5, 1)
    uint64_t mantissa = uint64_t(std::ldexp(m, 53));  // exact: at most 53 bits
    return e - 53 + __builtin_ctzll(mantissa);
}

// True when every boundary and midpoint of both trees down to element depth _depth_,
// and every difference of two such midpoints, is exact in double precision. Then the
// engine's midpoints (halved again and again) are the exact ones, and two pairs with
// the same exact offset give the oracle the same doubles.
bool ExactToDepth(const Plates &plates, int depth) {
    // Find the grid 2^e all these points lie on (midpoints at depth D are boundaries at
    // depth D+1), and require the largest magnitude, doubled for sums and differences,
    // to need at most 53 bits on it.
    int e = LowBit(plates.l) - (depth + 1);
    if (plates.xa != 0)
        e = std::min(e, LowBit(plates.xa));
    if (plates.xb != 0)
        e = std::min(e, LowBit(plates.xb));
    double bound = 2 * std::max({std::abs(plates.xa), std::abs(plates.xb), plates.l});
    return std::isfinite(bound) && std::ilogb(bound) <= 52 + e;
}

[[noreturn]] void NotExact(const Plates &plates, int depth) {
    throw InputError("--method translation: the element midpoints of l=" + FormatDouble(plates.l) +
                     ", offset=" + FormatDouble(plates.xb) + " are not exact in double precision" +
                     (depth > 0 ? " at depth " + std::to_string(depth) : std::string()) +
                     "; use lengths and offsets with few significant bits (e.g. 64, 1000, "
                     "0.75), or --method enumerate");
}

Plates PlatesOf(const Scene &scene) {
    const char *scope = "--method translation needs the parallel scene with l2 = l: P from (0,0) "
                        "to (l,0) and Q from (offset+l,d) to (offset,d), d > 0";
    if (!std::holds_alternative<Patches<Segment>>(scene.patches) || scene.NumPatches() != 2)
        throw InputError(scope);
    const Segment &p = scene.Get<Segment>()[0].shape, &q = scene.Get<Segment>()[1].shape;
    Plates plates{p.b.x(), q.a.x(), q.b.x(), q.a.y()};
    bool shape = p.a.x() == 0 && p.a.y() == 0 && p.b.y() == 0 && plates.l > 0 &&
                 q.b.y() == plates.d && plates.d > 0 && std::isfinite(2 * plates.d) &&
                 plates.xa > plates.xb;
    if (!shape)
        throw InputError(scope);
    if (!ExactToDepth(plates, 0))
        NotExact(plates, 0);
    // Exact, by the check above.
    if (plates.xa - plates.xb != plates.l)
        throw InputError(std::string(scope) + " (here l2 = " + FormatDouble(plates.xa - plates.xb) +
                         " differs from l = " + FormatDouble(plates.l) + ")");
    return plates;
}

// All pairs of one level at one offset. _c_ is the offset of the midpoints,
// x_i - x_j = -offset + c * l / 2^(depth_i + 1); (p, q) is one of the pairs, by
// its element positions, to evaluate the oracle on.
struct PairState {
    int64_t c;
    uint64_t pairs;  // how many visited pairs are in this state
    int64_t p, q;
};

// Elements of one tree at one level whose visited pairs have the states lo, lo+step,
// ..., hi (step 2 or 4, set by the level and the tree).
struct ElementState {
    int64_t lo, hi;
    uint64_t elements;  // how many elements are in this state

    bool operator<(const ElementState &o) const { return lo != o.lo ? lo < o.lo : hi < o.hi; }
};

uint64_t CheckedAdd(uint64_t a, uint64_t b) {
    uint64_t sum;
    if (__builtin_add_overflow(a, b, &sum))
        throw LimitError("--method translation: a counter exceeds 2^64; use a larger eps");
    return sum;
}

// Sorts _states_ and merges equal intervals, adding their element counts.
void Merge(std::vector<ElementState> &states) {
    std::sort(states.begin(), states.end());
    size_t out = 0;
    for (size_t k = 0; k < states.size(); ++k) {
        if (out > 0 && states[out - 1].lo == states[k].lo && states[out - 1].hi == states[k].hi)
            states[out - 1].elements = CheckedAdd(states[out - 1].elements, states[k].elements);
        else
            states[out++] = states[k];
    }
    states.resize(out);
}

// Restricts the progression lo, lo+step, ..., hi to [rlo, rhi]; false if nothing is left.
bool Clip(int64_t &lo, int64_t &hi, int64_t step, int64_t rlo, int64_t rhi) {
    if (lo < rlo)
        lo += (rlo - lo + step - 1) / step * step;
    if (hi > rhi)
        hi -= (hi - rhi + step - 1) / step * step;
    return lo <= hi;
}

}  // namespace

void CheckTranslationScope(const Scene &scene, const RefineOptions &options) {
    if (options.oracle != GarmannOracle<Segment>::kInfo.name)
        throw InputError("--method translation supports --oracle garmann only");
    if (options.storeLinks)
        throw InputError("--method translation only counts; add --count-only");
    if (options.HasRecursionLimit())
        throw InputError("--method translation needs refinement without a recursion limit; "
                         "drop --min-area and --max-depth");
    if (options.visibility != VisibilityMode::None)
        throw InputError("--method translation counts without occlusion; drop --visibility");
    if (options.subdivision != Subdivision::Binary)
        throw InputError("--method translation needs binary subdivision; drop --subdivision");
    PlatesOf(scene);
}

TranslationCount CountByTranslation(const Scene &scene, const RefineOptions &options) {
    ValidateOptions(options, scene.Dimension());
    ValidateScene(scene);
    CheckTranslationScope(scene, options);
    const Plates plates = PlatesOf(scene);
    const GarmannOracle<Segment> oracle(options.eps, scene.Get<Segment>());
    auto start = std::chrono::steady_clock::now();

    TranslationCount result;
    result.record.method = "translation";
    Counters &counters = result.record.counters;
    counters.rootPairs = 1;
    std::vector<uint64_t> splitP, splitQ;  // elements halved, per depth, in P and in Q

    // Start from the root pair: offset c = 0, one column (P element) and one row (Q element).
    std::vector<PairState> pairs{{0, 1, 0, 0}}, nextPairs;
    std::vector<ElementState> columns{{0, 0, 1}}, rows{{0, 0, 1}}, nextColumns, nextRows;
    const size_t budget = EffectiveBudget(options);
    for (int level = 0; !pairs.empty(); ++level) {
        // Refuse a level whose states could outgrow the memory budget: each state has at
        // most two children, and the current and the next level are held together.
        size_t bound = 3 * (pairs.size() * sizeof(PairState) +
                            (columns.size() + rows.size()) * sizeof(ElementState));
        if (bound > budget)
            throw LimitError("--method translation would exceed the memory budget (" +
                             std::to_string(pairs.size()) + " pair states at level " +
                             std::to_string(level) + "); raise --max-memory or eps");

        // At level n = depth_i + depth_j, P is halved on even levels (equal squared
        // sizes: ties go to the first argument), Q on odd ones (Q's squared size is four
        // times P's: exact while it is a normal double, which Resolves() in the forest
        // and ExactToDepth() keep).
        const int depthI = (level + 1) / 2, depthJ = level / 2;
        const bool splitsP = level % 2 == 0;
        if (!ExactToDepth(plates, depthI))
            NotExact(plates, depthI);
        // Squared sizes as the engine computes them, dx*dx + dy*dy with the exact
        // (dx, dy) = (+-l / 2^depth, 0): dx*dx, as adding 0*0 changes nothing.
        const double sizeI = std::ldexp(plates.l, -depthI), sizeJ = std::ldexp(plates.l, -depthJ);
        Element<2> ei{Vec2(0, 0), sizeI * sizeI, kNoChildren, 0};
        Element<2> ej{Vec2(0, plates.d), sizeJ * sizeJ, kNoChildren, 1};

        // Evaluate the oracle once per state, on the midpoints the engine computes for
        // the representative pair, and count every pair of the state.
        uint64_t levelLinks = 0;
        size_t firstRejected = SIZE_MAX, lastRejected = 0, numRejected = 0;
        nextPairs.clear();
        for (size_t k = 0; k < pairs.size(); ++k) {
            const PairState &s = pairs[k];
            ei.center.x() = plates.l * std::ldexp(double(2 * s.p + 1), -(depthI + 1));
            ej.center.x() = plates.xa - plates.l * std::ldexp(double(2 * s.q + 1), -(depthJ + 1));
            counters.oracleCalls = CheckedAdd(counters.oracleCalls, s.pairs);
            if (oracle.Acceptable(ei, ej)) {
                levelLinks = CheckedAdd(levelLinks, s.pairs);
                continue;
            }
            // The preferred element has depth _depthJ_ on both kinds of level.
            if (depthJ >= kSafetyDepth)
                throw LimitError("refinement of patches 0 and 1 reached the safety depth " +
                                 std::to_string(kSafetyDepth) +
                                 " without an acceptable link; set a recursion limit with "
                                 "--min-area or --max-depth");
            firstRejected = std::min(firstRejected, k);
            lastRejected = k;
            ++numRejected;

            // Step to the children: halving P maps c to 2c -+ 1, halving Q to c -+ 1
            // (first child first). The states stay sorted; merge the equal neighbours.
            PairState first = s, second = s;
            if (splitsP) {
                first.c = 2 * s.c - 1, first.p = 2 * s.p;
                second.c = 2 * s.c + 1, second.p = 2 * s.p + 1;
            } else {
                first.c = s.c - 1, first.q = 2 * s.q;
                second.c = s.c + 1, second.q = 2 * s.q + 1;
            }
            for (const PairState &child : {first, second}) {
                if (!nextPairs.empty() && nextPairs.back().c == child.c)
                    nextPairs.back().pairs = CheckedAdd(nextPairs.back().pairs, child.pairs);
                else
                    nextPairs.push_back(child);
            }
        }
        counters.links = CheckedAdd(counters.links, levelLinks);
        counters.linksPerDepth.push_back(levelLinks);
        result.pairStates += pairs.size();

        // The oracle is monotone in the distance, so the rejected states are one run
        // [rlo, rhi]; the element intervals below rely on it.
        if (numRejected > 0 && lastRejected - firstRejected + 1 != numRejected)
            throw std::logic_error("translation count: rejected offsets are not contiguous at "
                                   "level " +
                                   std::to_string(level));
        // An empty run [1, 0] when every state is accepted.
        int64_t rlo = numRejected ? pairs[firstRejected].c : 1;
        int64_t rhi = numRejected ? pairs[lastRejected].c : 0;

        // Move the elements on: an element whose interval meets [rlo, rhi] is halved (P
        // on even levels, Q on odd) or keeps the children's states of its pairs.
        const int64_t columnStep = splitsP ? 2 : 4, rowStep = 2;
        uint64_t halved = 0;
        nextColumns.clear();
        for (ElementState e : columns) {
            if (!Clip(e.lo, e.hi, columnStep, rlo, rhi))
                continue;
            if (splitsP) {
                halved = CheckedAdd(halved, e.elements);
                nextColumns.push_back({2 * e.lo - 1, 2 * e.hi - 1, e.elements});
                nextColumns.push_back({2 * e.lo + 1, 2 * e.hi + 1, e.elements});
            } else {
                nextColumns.push_back({e.lo - 1, e.hi + 1, e.elements});
            }
        }
        nextRows.clear();
        for (ElementState e : rows) {
            if (!Clip(e.lo, e.hi, rowStep, rlo, rhi))
                continue;
            if (splitsP) {
                nextRows.push_back({2 * e.lo - 1, 2 * e.hi + 1, e.elements});
            } else {
                halved = CheckedAdd(halved, e.elements);
                nextRows.push_back({e.lo - 1, e.hi - 1, e.elements});
                nextRows.push_back({e.lo + 1, e.hi + 1, e.elements});
            }
        }
        (splitsP ? splitP : splitQ).push_back(halved);
        result.elementStates += columns.size() + rows.size();
        Merge(nextColumns);
        Merge(nextRows);
        std::swap(pairs, nextPairs);
        std::swap(columns, nextColumns);
        std::swap(rows, nextRows);
    }

    // Summarise the trees: one root each, two children per halved element.
    size_t depths = std::max(splitP.size(), splitQ.size()) + 1;
    splitP.resize(depths, 0), splitQ.resize(depths, 0);
    counters.nodesPerDepth.assign(depths, 0);
    counters.nodesPerDepth[0] = 2;
    uint64_t halvedTotal = 0;
    for (size_t k = 0; k + 1 < depths; ++k) {
        counters.nodesPerDepth[k + 1] = 2 * (splitP[k] + splitQ[k]);
        halvedTotal += splitP[k] + splitQ[k];
    }
    while (counters.nodesPerDepth.size() > 1 && counters.nodesPerDepth.back() == 0)
        counters.nodesPerDepth.pop_back();
    for (uint64_t n : counters.nodesPerDepth)
        counters.nodes = CheckedAdd(counters.nodes, n);
    counters.leaves = counters.nodes - halvedTotal;
    counters.maxDepth = counters.nodesPerDepth.size() - 1;
    while (!counters.linksPerDepth.empty() && counters.linksPerDepth.back() == 0)
        counters.linksPerDepth.pop_back();
    result.record.seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return result;
}

}  // namespace hrbench
