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

// Whether the scene is closed: every ray leaving the front of a patch meets the front of
// another (docs/solve.md, "Clusters"), so that each patch's form factors to the others sum
// to 1. True when (1) every edge of a patch, corners compared exactly, is run the other way
// by exactly one edge of another patch and by none the same way (2D: every end of a
// segment is the start of exactly one other), so that the patches bound regions; (2) of
// the parts that the shared edges join, each either faces inward (the measure of its
// front side, -1/6 sum (v0 . (v1 x v2)) over its triangles in 3D, the shoelace area in
// 2D, is positive: its front is the region it bounds) or has its bounding box inside the
// bounding box of a part that faces inward; and (3) some part faces inward. (2) takes a
// part of outward fronts inside an inward part's box to be inside that part, which holds
// for a box, a room or a sphere around objects, not for every concave enclosure.
bool IsClosed(const Scene &scene);

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
