// The counters of several --min-area values from one enumeration (`hrbench run
// --min-areas A1,A2,...`), the way a recursion-limit sweep is counted.
//
// The recursion limit only ever turns a split into a forced link, and along a chain of
// pairs the preferred size A never grows (the larger element is the one split). So the
// refinement at a larger threshold is a prefix of the refinement at a smaller one: a
// pair is reached at threshold m iff its parent pair's preferred size is at least m,
// where it is decided exactly as at the smallest threshold (the oracle does not read
// m); a rejected pair is split at m iff its own preferred size is at least m, and
// linked by force otherwise. An element is split at m iff it is split at the smallest
// threshold and its size is at least m (every pair above the one that splits it has a
// preferred size at least as large). One enumeration at the smallest threshold, which
// carries with every pair the number of thresholds that reach it, therefore yields
// every counter of every threshold, identical to separate runs: each decision is the
// same comparison of A^2 with the same bound (SquaredSizeBound) as in the kernel.
#pragma once

#include <vector>

#include "hrbench/record.h"
#include "hrbench/refine_options.h"
#include "hrbench/scene.h"

namespace hrbench {

// The run record of _scene_ at each value of _minAreas_ (in the order given, each > 0,
// no two equal), from one enumeration: what Count(scene, options with minArea = m,
// "enumerate") reports for each m, with _seconds_ an equal share of the enumeration's
// time (so that the records' seconds add up to it).
// Count-only, one thread, no visibility (InputError otherwise, naming the option);
// options.minArea is ignored. Throws what Refine() throws at the smallest value (the
// safety depth, the memory budget, precision), even where a larger value alone would
// succeed.
std::vector<RunRecord> CountMinAreaSweep(const Scene &scene, const RefineOptions &options,
                                         const std::vector<double> &minAreas);

}  // namespace hrbench
