// Root-pair classification with exact predicates (CGAL), before any refinement.
#pragma once

#include "scene.h"

namespace hrbench {

enum class PairRelation {
    Interacting,  // some light can pass between the fronts of the two patches
    Culled,       // collinear, or one lies wholly behind or in the other's line
    Touching,     // they interact and share a point: refinement needs a recursion limit
};

// Classifies the root pair (_p_, _q_) as DESIGN section 2 defines culling.
PairRelation ClassifyPair(const Segment &p, const Segment &q);

}  // namespace hrbench
