#include "culling.h"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>

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

}  // namespace hrbench
