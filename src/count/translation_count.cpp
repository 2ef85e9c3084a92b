#include "count/translation_count.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "hrbench/oracles/garmann.h"
#include "hrbench/util/error.h"
#include "translation_internal.h"
#include "util/format.h"
#include "util/stopwatch.h"

namespace hrbench::translation {

namespace {

// The two plates: P from (0,0) to (l,0), Q from (xa,d) to (xb,d) = (xa-l,d).
struct Plates {
    double l;   // length of both plates
    double xa;  // x of Q's start (offset + l)
    double xb;  // x of Q's end (offset)
    double d;   // distance between the plates, > 0
};

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
    return FitsGrid(bound, e);
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

// One state of a level: the pairs in it, and the elements counted there. An element's
// visited pairs have a contiguous run of states, one pair per state, so the elements
// whose run contains a state number exactly its _pairs_; an element is therefore
// counted once, at the start of its run, and the run's end is never needed.
struct State {
    uint64_t pairs;         // visited pairs in the state
    uint64_t columnStarts;  // P elements whose run of states starts here
    uint64_t rowStarts;     // Q elements whose run of states starts here
};

// The states of one level, in a flat array: index i holds the offset c = first + 2 i
// (the offsets of a level all have one parity).
struct Level {
    int64_t first = 0;
    std::vector<State> states;
    uint64_t pairs = 0;  // the sum over the states: the level's oracle calls
};

// What the rejected run [lo, end) of a level holds.
struct RunSums {
    uint64_t pairs = 0, columns = 0, rows = 0;  // pairs, and elements that meet the run
    uint64_t starts = 0;                        // distinct element states: nonzero starts
};

// Keeps the rejected run [lo, end) of the level, moved to the front, and the elements
// that meet it: an element whose run misses it is dropped, and every other run now
// starts at its first rejected state. The runs that contain state lo (lo + 1 for
// the other residue, when a tree's runs step by two states) number exactly its pairs.
RunSums KeepRejected(Level &level, size_t lo, size_t end, size_t columnRunStep) {
    std::vector<State> &s = level.states;
    for (size_t i = lo; i < lo + columnRunStep && i < end; ++i)
        s[i].columnStarts = s[i].pairs;
    s[lo].rowStarts = s[lo].pairs;
    unsigned __int128 pairs = 0, columns = 0, rows = 0;
    uint64_t starts = 0;
    for (size_t i = lo; i < end; ++i) {
        const State state = s[i];
        pairs += state.pairs;
        columns += state.columnStarts;
        rows += state.rowStarts;
        starts += (state.columnStarts != 0) + (state.rowStarts != 0);
        s[i - lo] = state;
    }
    level.first += 2 * int64_t(lo);
    s.resize(end - lo);
    return {Checked(pairs), Checked(columns), Checked(rows), starts};
}

// Halving P: a rejected state c has the children 2c - 1 and 2c + 1 (first child
// first), distinct for distinct c; each P run has two children runs, each Q run one run
// of twice the states, starting at 2 lo - 1. In place, from the back.
void HalveP(Level &level) {
    std::vector<State> &s = level.states;
    size_t n = s.size();
    s.resize(2 * n);
    for (size_t k = n; k-- > 0;) {
        const State state = s[k];
        s[2 * k] = state;
        s[2 * k + 1] = {state.pairs, state.columnStarts, 0};
    }
    level.first = 2 * level.first - 1;
}

// Halving Q: a rejected state c has the children c - 1 and c + 1, shared with the
// neighbouring states; each Q run has two children runs, shifted by -1 and +1, each P
// run one run grown by a state at both ends. In place, from the back.
void HalveQ(Level &level) {
    std::vector<State> &s = level.states;
    size_t n = s.size();
    s.push_back({0, 0, 0});
    for (size_t j = n + 1; j-- > 0;) {
        State right = j < n ? s[j] : State{0, 0, 0}, left = j > 0 ? s[j - 1] : State{0, 0, 0};
        s[j] = {left.pairs + right.pairs, right.columnStarts, left.rowStarts + right.rowStarts};
    }
    level.first -= 1;
}

}  // namespace

void CheckFlatlandScope(const Scene &scene, const RefineOptions &options) {
    if (options.subdivision != Subdivision::Binary)
        throw InputError("--method translation needs binary subdivision; drop --subdivision");
    PlatesOf(scene);
}

TranslationCount CountFlatland(const Scene &scene, const RefineOptions &options) {
    const Plates plates = PlatesOf(scene);
    const GarmannOracle<Segment> oracle(options.eps, scene.Get<Segment>());

    TranslationCount result;
    Counters &counters = result.record.counters;
    std::vector<uint64_t> splitP, splitQ;  // elements halved, per depth, in P and in Q

    // Start from the root pair: offset c = 0, one column (P element) and one row (Q element).
    Level level;
    level.states = {{1, 1, 1}};
    level.pairs = 1;
    const size_t budget = EffectiveBudget(options);
    for (int n = 0; !level.states.empty(); ++n) {
        // At level n = depth_i + depth_j, P is halved on even levels (equal squared
        // sizes: ties go to the first argument), Q on odd ones (Q's squared size is four
        // times P's: exact while it is a normal double, which Resolves() in the forest
        // and ExactToDepth() keep).
        const int depthI = (n + 1) / 2, depthJ = n / 2;
        const bool splitsP = n % 2 == 0;
        if (!ExactToDepth(plates, depthI))
            NotExact(plates, depthI);
        // Squared sizes as the engine computes them, dx*dx + dy*dy with the exact
        // (dx, dy) = (+-l / 2^depth, 0): dx*dx, as adding 0*0 changes nothing.
        const double sizeI = std::ldexp(plates.l, -depthI), sizeJ = std::ldexp(plates.l, -depthJ);
        Element<2> ei{Vec2(0, 0), sizeI * sizeI, kNoChildren, 0};
        Element<2> ej{Vec2(plates.xb, plates.d), sizeJ * sizeJ, kNoChildren, 1};

        // The midpoints of a pair in state c are x_i - x_j = c u - offset apart, with
        // u = l / 2^(depth_i + 1); ExactToDepth() makes c u and the difference exact, so
        // these centres give the oracle the doubles of every pair in the state.
        const double u = std::ldexp(plates.l, -(depthI + 1));
        auto offsetOf = [&](size_t i) { return double(level.first + 2 * int64_t(i)) * u; };
        auto rejected = [&](size_t i) {
            ++result.oracleEvaluations;
            ei.center.x() = offsetOf(i);
            return !oracle.Acceptable(ei, ej);
        };
        auto below = [&](size_t i) { return offsetOf(i) < plates.xb; };
        auto [lo, end] = RejectedRun(level.states.size(), rejected, below);

        counters.oracleCalls = CheckedAdd(counters.oracleCalls, level.pairs);
        result.pairStates += level.states.size();
        if (lo == end) {
            counters.linksPerDepth.push_back(level.pairs);
            counters.links = CheckedAdd(counters.links, level.pairs);
            break;
        }
        // The preferred element has depth _depthJ_ on both kinds of level.
        CheckSafetyDepth(depthJ);
        // Refuse a level whose states could outgrow the memory budget (the array grows
        // in place, by doubling).
        size_t nextSize = splitsP ? 2 * (end - lo) : end - lo + 1;
        if (2 * sizeof(State) * std::max(nextSize, level.states.size()) > budget)
            throw LimitError("--method translation would exceed the memory budget (" +
                             std::to_string(nextSize) + " pair states at level " +
                             std::to_string(n + 1) + "); raise --max-memory or eps");

        // Keep the elements that meet a rejected state, and halve P's (even levels) or
        // Q's (odd). On odd levels a P run steps by two states (4 in c): a Q element is
        // then twice as long as a P element, so neighbouring ones are 4 apart in c.
        RunSums run = KeepRejected(level, lo, end, splitsP ? 1 : 2);
        uint64_t linked = level.pairs - run.pairs;
        counters.linksPerDepth.push_back(linked);
        counters.links = CheckedAdd(counters.links, linked);
        (splitsP ? splitP : splitQ).push_back(splitsP ? run.columns : run.rows);
        result.elementStates += run.starts;
        if (splitsP)
            HalveP(level);
        else
            HalveQ(level);
        level.pairs = Checked((unsigned __int128)run.pairs * 2);  // each pair has two children
    }

    SummariseTrees(std::move(splitP), std::move(splitQ), 2, counters);
    return result;
}

}  // namespace hrbench::translation

namespace hrbench {

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
    if (options.clusters)
        throw InputError("--method translation counts every root pair; drop --clusters");
    if (scene.Dimension() == 2)
        translation::CheckFlatlandScope(scene, options);
    else
        translation::CheckSpaceScope(scene, options);
}

TranslationCount CountByTranslation(const Scene &scene, const RefineOptions &options) {
    ValidateOptions(options, scene.Dimension());
    ValidateScene(scene);
    CheckTranslationScope(scene, options);
    Stopwatch watch;
    TranslationCount result = scene.Dimension() == 2 ? translation::CountFlatland(scene, options)
                                                     : translation::CountSpace(scene, options);
    result.record.method = "translation";
    result.record.counters.rootPairs = 1;
    CountInitialLinking(result.record.counters);
    result.record.seconds = watch.WallSeconds();
    result.record.cpuSeconds = watch.CpuSeconds();
    return result;
}

}  // namespace hrbench
