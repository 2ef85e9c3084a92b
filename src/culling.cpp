#include "hrbench/culling.h"

#include <string>

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>

#include "hrbench/util/error.h"

namespace hrbench {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;

static Kernel::Point_2 ToPoint(const Vec2 &v) { return {v.x(), v.y()}; }

// True when no point of _other_ lies strictly in front of (left of) _patch_.
static bool WhollyBehindOrIn(const Segment &patch, const Segment &other) {
    auto a = ToPoint(patch.a), b = ToPoint(patch.b);
    return CGAL::orientation(a, b, ToPoint(other.a)) != CGAL::LEFT_TURN &&
           CGAL::orientation(a, b, ToPoint(other.b)) != CGAL::LEFT_TURN;
}

PairRelation ClassifyPair(const Segment &p, const Segment &q) {
    if (WhollyBehindOrIn(p, q) || WhollyBehindOrIn(q, p))
        return PairRelation::Culled;
    Kernel::Segment_2 sp(ToPoint(p.a), ToPoint(p.b)), sq(ToPoint(q.a), ToPoint(q.b));
    return CGAL::do_intersect(sp, sq) ? PairRelation::Touching : PairRelation::Interacting;
}

static Kernel::Point_3 ToPoint(const Vec3 &v) { return {v.x(), v.y(), v.z()}; }

// True when no corner of _other_ lies strictly in front of the plane of _patch_:
// orientation(v0, v1, v2, c) is POSITIVE exactly when c is on the side of the front
// normal (v1 - v0) x (v2 - v0).
static bool WhollyBehindOrIn(const Polygon &patch, const Polygon &other) {
    auto a = ToPoint(patch.v[0]), b = ToPoint(patch.v[1]), c = ToPoint(patch.v[2]);
    for (int k = 0; k < other.n; ++k)
        if (CGAL::orientation(a, b, c, ToPoint(other.v[k])) == CGAL::POSITIVE)
            return false;
    return true;
}

// A polygon as one or two triangles (a quad split along v0 v2).
static int Triangles(const Polygon &p, Kernel::Triangle_3 out[2]) {
    out[0] = {ToPoint(p.v[0]), ToPoint(p.v[1]), ToPoint(p.v[2])};
    if (p.n == 3)
        return 1;
    out[1] = {ToPoint(p.v[0]), ToPoint(p.v[2]), ToPoint(p.v[3])};
    return 2;
}

PairRelation ClassifyPair(const Polygon &p, const Polygon &q) {
    if (WhollyBehindOrIn(p, q) || WhollyBehindOrIn(q, p))
        return PairRelation::Culled;
    Kernel::Triangle_3 tp[2], tq[2];
    int np = Triangles(p, tp), nq = Triangles(q, tq);
    for (int a = 0; a < np; ++a)
        for (int b = 0; b < nq; ++b)
            if (CGAL::do_intersect(tp[a], tq[b]))
                return PairRelation::Touching;
    return PairRelation::Interacting;
}

bool RefinesRootPair(PairRelation relation, uint32_t p, uint32_t q, const RefineOptions &options) {
    if (relation == PairRelation::Touching && !options.HasRecursionLimit())
        throw InputError("patches " + std::to_string(p) + " and " + std::to_string(q) +
                         " touch, so refinement cannot terminate; set a recursion limit with "
                         "--min-area or --max-depth");
    return relation != PairRelation::Culled;
}

}  // namespace hrbench
