// Root-pair classification with exact predicates (CGAL), before any refinement.
#pragma once

#include <cstdint>

#include "hrbench/refine_options.h"
#include "hrbench/scene.h"

namespace hrbench {

enum class PairRelation {
    Interacting,  // some light can pass between the fronts of the two patches
    Culled,       // collinear, or one lies wholly behind or in the other's line
    Touching,     // they interact and share a point: refinement needs a recursion limit
};

// Classifies the root pair of patches _p_ and _q_ as docs/conventions.md defines culling.
PairRelation ClassifyPair(const Segment &p, const Segment &q);

// The same for two 3D patches: culled when either lies wholly behind or in the plane
// of the other (the plane of its corners v0, v1, v2), touching when they share a point.
PairRelation ClassifyPair(const Polygon &p, const Polygon &q);

// Whether refinement runs ProjectKernel on root pair (_p_, _q_) of relation _relation_:
// not when culled. Throws InputError for touching patches when _options_ set no
// recursion limit, since their refinement would not terminate.
bool RefinesRootPair(PairRelation relation, uint32_t p, uint32_t q, const RefineOptions &options);

}  // namespace hrbench
