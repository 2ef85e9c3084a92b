// Root-pair classification with exact predicates (CGAL), before any refinement.
#pragma once

#include <cstdint>
#include <string>

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

// Whether a patch of the scene may block the light between two others (docs/solve.md,
// "Occlusion"): false when the scene has at most two patches, or when every patch has
// the corners of all the others on one closed side of its line (2D) or of the plane of
// each of its occluder triangles (3D: a quad as v0 v1 v2 and v0 v2 v3, as Occluders
// cuts it). A segment between points of two other patches then meets the patch only
// where it lies in that line or plane, which no sample segment of a linked pair does.
// True otherwise (the patch may still miss every such segment). Exact predicates; one
// orientation test per patch and corner of another at most.
bool CanOcclude(const Scene &scene);

// A hint (one line, "" for none) when faces holding more than half of the area of a mesh
// scene (Scene::family "mesh") each have every other face behind or in their plane, a
// corner strictly behind: every root pair of such a face is culled, and it exchanges no
// light. A room whose faces point outward (written clockwise seen from inside) gives
// that; the hint says so, with the share and the count.
std::string FacingAwayHint(const Scene &scene);

// Whether refinement runs ProjectKernel on root pair (_p_, _q_) of relation _relation_:
// not when culled. Throws InputError for touching patches when _options_ set no
// recursion limit, since their refinement would not terminate.
bool RefinesRootPair(PairRelation relation, uint32_t p, uint32_t q, const RefineOptions &options);

}  // namespace hrbench
