// The counters of several values of eps or of --min-area from one enumeration
// (`hrbench run --sweep eps=E1,E2,...` or `--sweep min_area=A1,A2,...`), the way a
// sweep of the analysis is counted.
//
// A pair is reached at a value iff every pair above it was rejected and split there.
// Both parameters only ever turn splits into links as they grow: the oracle is
// monotone in eps (it compares a quantity of the pair with eps times another, and
// rounding is monotone), so a pair accepted at one eps is accepted at every larger
// one; and a larger --min-area turns a split into a forced link. So the refinement at
// a larger value is a prefix of the refinement at a smaller one, and one enumeration
// at the smallest value, which carries with every pair the number of values that
// reach it, counts them all:
//  - a reached pair costs an oracle call (and its visibility query) at each of them;
//  - it is accepted at the values from the first that accepts it on (eps: found by
//    bisection with the engine's own oracle at each value; --min-area: the oracle does
//    not read it), and linked there;
//  - below that it is rejected: split at the values where the recursion limit lets
//    it (its preferred size A_p against each --min-area, compared as A_p^2 with the
//    kernel's bound), linked by force at the others;
//  - its children are reached at the values where it is split, and an element is
//    split at a value iff some pair splits it there.
// Every decision is the kernel's own comparison on the same doubles, so the counters
// equal separate runs exactly (tests/sweep_count_test.cpp checks them counter by
// counter).
#pragma once

#include <string>
#include <vector>

#include "hrbench/record.h"
#include "hrbench/refine_options.h"
#include "hrbench/scene.h"

namespace hrbench {

// Which option a sweep varies, and its values (each valid for that option, no two
// equal, at most kMaxSweepValues).
struct SweepValues {
    std::string param;  // "eps" or "min_area"
    std::vector<double> values;
};

constexpr size_t kMaxSweepValues = 255;

// The run record of _scene_ at each value of _sweep_ (in the order given), from one
// enumeration: what Count(scene, options with the parameter set to the value,
// "enumerate") reports for each, with _seconds_ an equal share of the enumeration's
// time (so that the records' seconds add up to it); the option the sweep varies is
// ignored in _options_, and each record carries its value (RunRecord::sweptEps or
// sweptMinArea), which its JSON reports. Count-only and one thread (InputError otherwise, naming
// the option). Throws what Refine() throws at the smallest value (the safety depth, the memory
// budget, precision), even where a larger value alone would succeed.
std::vector<RunRecord> CountSweep(const Scene &scene, const RefineOptions &options,
                                  const SweepValues &sweep);

}  // namespace hrbench
