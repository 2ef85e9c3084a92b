// Root-pair classification with exact predicates (CGAL), before any refinement.
#pragma once

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

}  // namespace hrbench
