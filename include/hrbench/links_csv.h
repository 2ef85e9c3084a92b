// The links of a refinement as CSV, one row per stored link (docs/conventions.md).
#pragma once

#include <ostream>

#include "hrbench/refine.h"

namespace hrbench {

// Writes every stored link as a CSV row: for each of its two elements the root, the
// element id and the depth, with the element's interval [t0, t1] in arc length along
// its root (segments) or its area and centroid (polygons).
void WriteLinksCsv(const AnyRefinement &refinement, std::ostream &out);

}  // namespace hrbench
