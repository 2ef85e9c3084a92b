// Shared by the libFuzzer harnesses (docs/fuzzing.md): what counts as the expected
// outcome of bad input, what counts as a finding, and a quick refinement of every scene
// that parses, checked against the invariants of docs/conventions.md.
#pragma once

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <string>
#include <type_traits>
#include <typeinfo>
#include <variant>
#include <vector>

#include "../tests/refinement_helpers.h"
#include "hrbench/hrbench.h"
#include "util/format.h"

namespace hrbench_fuzz {

// What the harness is doing beyond parsing, reported with a finding: the options of the
// quick refinement as hrbench flags, so that the finding can be rerun with the CLI.
inline std::string &Doing() {
    static std::string doing;
    return doing;
}

// Reports a finding on stderr and aborts, which libFuzzer records as a crash.
[[noreturn]] inline void Finding(const std::string &what) {
    std::fprintf(stderr, "FINDING: %s\n", what.c_str());
    if (!Doing().empty())
        std::fprintf(stderr, "FINDING while %s\n", Doing().c_str());
    std::fflush(stderr);
    std::abort();
}

#define FUZZ_CHECK(condition, what)                                                                \
    do {                                                                                           \
        if (!(condition))                                                                          \
            ::hrbench_fuzz::Finding(std::string(what) + " (" #condition ", " __FILE__ ":" +        \
                                    std::to_string(__LINE__) + ")");                               \
    } while (0)

// Runs _body_: hrbench::Error (InputError, LimitError) is the expected outcome of bad
// input; any other exception is a finding.
template <typename Body>
void Guarded(Body &&body) {
    try {
        body();
    } catch (const hrbench::Error &) {
        // Rejected with a documented exit code: fine.
    } catch (const std::exception &e) {
        Finding(std::string("unexpected exception ") + typeid(e).name() + ": " + e.what());
    } catch (...) {
        Finding("unexpected exception of unknown type");
    }
}

// FNV-1a of the input: picks the refinement options, so that an input always runs
// with the same options and a reproducer reproduces.
inline uint64_t Hash(const uint8_t *data, size_t size) {
    uint64_t h = 1469598103934665603ull;
    for (size_t k = 0; k < size; ++k)
        h = (h ^ data[k]) * 1099511628211ull;
    return h;
}

// Scenes with more patches are parsed and validated but not refined (time per input).
constexpr size_t kMaxPatchesRefined = 6;
// The recursion limit of the quick refinement, binary subdivision: 2^5 leaves per root,
// at most 4^5 links per root pair. Quadtree subdivision and visibility go less deep.
constexpr int kMaxDepth = 5;
// Memory budget of the quick refinement; reaching it is a LimitError.
constexpr size_t kMemoryBudget = size_t(64) << 20;

// Whether _calls_ oracle calls on _pairs_ root pairs are what a refinement that ended in
// _terminals_ calls that did not split (links and fully occluded pairs) must have spent:
// every other call splits one element into _arity_ children, each met by one call.
inline bool CallsFollowFromTerminals(uint64_t calls, uint64_t terminals, uint64_t pairs,
                                     int arity) {
    return (uint64_t(arity) - 1) * calls + pairs == uint64_t(arity) * terminals;
}

// The invariants of a stored quick refinement of _scene_ under _options_.
template <typename Shape>
void CheckStoredRefinement(const hrbench::Scene &scene, const hrbench::RefineOptions &options,
                           const hrbench::Refinement<Shape> &r) {
    using namespace hrbench;
    const Counters &c = r.record.counters;
    FUZZ_CHECK(c.maxDepth <= uint64_t(options.maxDepth), "an element is deeper than --max-depth");
    FUZZ_CHECK(c.rootPairs == scene.NumPatches() * (scene.NumPatches() - 1) / 2,
               "root pairs are not all unordered pairs");
    FUZZ_CHECK(r.pairs.size() + c.culledPairs == c.rootPairs,
               "refined and culled pairs do not add up to the root pairs");
    FUZZ_CHECK(CallsFollowFromTerminals(c.oracleCalls, c.links + c.occludedPairs, r.pairs.size(),
                                        r.forest.Arity()),
               "oracle calls do not follow from links and occluded pairs");
    if (options.visibility != VisibilityMode::None)
        return;
    FUZZ_CHECK(c.occludedPairs == 0 && c.rays == 0, "visibility counted with --visibility none");
    // Per root pair, calls follow from links and links tile P x Q; the products of the
    // root measures must be representable for the tiling to be checked. To 1e-5, not
    // the 1e-9 of the property tests: the engine splits an element as long as its
    // children measure what they should to 1e-6 (Shape::Resolves), so slivers far from
    // the origin tile their pair only to about that much per level.
    for (const PairTally &pair : r.pairs) {
        double product =
            scene.Get<Shape>()[pair.p].shape.Measure() * scene.Get<Shape>()[pair.q].shape.Measure();
        if (!std::isnormal(product) || product > 1e300)
            return;
    }
    std::string violations = hrbench_test::TilingViolations(scene, r, 1e-5);
    FUZZ_CHECK(violations.empty(), "invariants violated: " + violations);
}

// Options for the quick refinement, picked by _seed_: the oracle, eps, subdivision and
// visibility vary, and the recursion limit with the last two; the memory budget does not.
inline hrbench::RefineOptions QuickOptions(int dimension, uint64_t seed) {
    using namespace hrbench;
    static const double kGarmannEps[] = {1, 0.5, 0.2, 0.05};
    static const double kHanrahanEps[] = {0.1, 0.05, 0.02, 0.005};  // form factors are smaller
    std::vector<OracleInfo> oracles = OracleInfos();
    RefineOptions o;
    o.oracle = oracles[seed % oracles.size()].name;
    o.eps = (o.oracle == "garmann" ? kGarmannEps : kHanrahanEps)[(seed >> 8) % 4];
    o.maxDepth = kMaxDepth;
    o.memoryBudget = kMemoryBudget;
    o.storeLinks = true;
    o.threads = 1;
    if (dimension == 3 && (seed >> 16) % 4 == 0) {
        o.subdivision = Subdivision::Quadtree;
        o.maxDepth = kMaxDepth / 2;  // no more leaves than binary subdivision
    }
    if ((seed >> 24) % 8 == 0) {
        o.visibility = VisibilityMode::Fraction;  // rays are costly: fewer elements
        o.raysPerSide = 1 + int((seed >> 32) % 2);
        o.maxDepth = o.subdivision == Subdivision::Quadtree ? 1 : 3;
    }
    return o;
}

// What every harness does with a scene that parsed: it must be valid; a small one is
// refined in store and count-only mode, and the invariants are checked.
inline void CheckScene(const hrbench::Scene &scene, uint64_t seed) {
    using namespace hrbench;
    try {
        ValidateScene(scene);
    } catch (const InputError &e) {
        Finding(std::string("a parsed scene is invalid: ") + e.what());
    }
    if (scene.NumPatches() > kMaxPatchesRefined)
        return;
    RefineOptions options = QuickOptions(scene.Dimension(), seed);
    struct DoingScope {
        explicit DoingScope(const RefineOptions &o) {
            Doing() = "refining with --oracle " + o.oracle + " --eps " + FormatDouble(o.eps) +
                      " --max-depth " + std::to_string(o.maxDepth) + " --subdivision " +
                      SubdivisionName(o.subdivision) + " --visibility " +
                      VisibilityName(o.visibility) + " --rays-per-side " +
                      std::to_string(o.raysPerSide) + " --max-memory " +
                      std::to_string(o.memoryBudget >> 20) + " (store, then --count-only)";
        }
        ~DoingScope() { Doing().clear(); }
    } doing(options);
    Guarded([&] {
        std::visit(
            [&](const auto &patches) {
                using Shape = std::decay_t<decltype(patches.front().shape)>;
                Refinement<Shape> stored = Refine<Shape>(scene, options);
                CheckStoredRefinement(scene, options, stored);
                RefineOptions countOnly = options;
                countOnly.storeLinks = false;
                Refinement<Shape> counted = Refine<Shape>(scene, countOnly);
                std::string differences = hrbench_test::CounterDifferences(stored.record.counters,
                                                                           counted.record.counters);
                FUZZ_CHECK(differences.empty(),
                           "count-only counters differ from store mode: " + differences);
                FUZZ_CHECK(counted.links.size() == 0, "count-only mode stored links");
            },
            scene.patches);
    });
}

}  // namespace hrbench_fuzz
