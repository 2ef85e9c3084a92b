#include "flatland.h"

#include <cmath>
#include <cstdint>
#include <limits>
#include <random>

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>

#include "family_helpers.h"
#include "hrbench/util/error.h"
#include "util/format.h"

namespace hrbench {

namespace {

Patch<Segment> Seg(double ax, double ay, double bx, double by) {
    return {{Vec2(ax, ay), Vec2(bx, by)}, {}};
}

// P from (0,0) to (l,0) facing +y; Q from (offset+l2, d) to (offset, d) facing -y.
Patches<Segment> Parallel(const ParamMap &p) {
    double l = p.at("l"), d = p.at("d"), offset = p.at("offset"), l2 = p.at("l2");
    return {Seg(0, 0, l, 0), Seg(offset + l2, d, offset, d)};
}

// Plates as in `parallel` (l2 = l, no offset) with a blocker of length _b_ at height _h_
// between them, centred over x = l/2 + offset: two back-to-back patches, the first
// facing P (down), the second facing Q (up).
Patches<Segment> Occluded(const ParamMap &p) {
    double l = p.at("l"), d = p.at("d"), b = p.at("b"), h = p.at("h"), offset = p.at("offset");
    if (!(h < d))
        throw InputError("scene occluded: the blocker height h=" + FormatDouble(h) +
                         " must lie between the plates (h < d=" + FormatDouble(d) + ")");
    double x0 = 0.5 * l + offset - 0.5 * b, x1 = 0.5 * l + offset + 0.5 * b;
    return {Seg(0, 0, l, 0), Seg(l, d, 0, d), Seg(x1, h, x0, h), Seg(x0, h, x1, h)};
}

// Two plates meeting at the origin with opening _angle_ degrees, each starting _gap_
// from the corner: P along +x facing into the wedge, Q along the other arm.
Patches<Segment> Angled(double l, double l2, double angleDegrees, double gap) {
    double angle = angleDegrees * kPi / 180;
    Vec2 arm(std::cos(angle), std::sin(angle));
    if (angleDegrees == 90)
        arm = Vec2(0, 1);  // exact, so that `perpendicular` has exact coordinates
    Patch<Segment> p = Seg(gap, 0, gap + l, 0);
    Patch<Segment> q{{(gap + l2) * arm, gap * arm}, {}};
    return {p, q};
}

// k plates of length l on y=0 facing up, and k facing down at y=d, spaced _spacing_ apart.
Patches<Segment> Array(const ParamMap &p) {
    int k = int(p.at("k"));
    double l = p.at("l"), d = p.at("d"), spacing = p.at("spacing");
    Patches<Segment> segments;
    for (int i = 0; i < k; ++i)
        segments.push_back(Seg(i * (l + spacing), 0, i * (l + spacing) + l, 0));
    for (int i = 0; i < k; ++i)
        segments.push_back(Seg(i * (l + spacing) + l, d, i * (l + spacing), d));
    return segments;
}

// Closed regular n-gon of circumradius r, counter-clockwise, so normals point inward.
Patches<Segment> Enclosure(const ParamMap &p) {
    int n = int(p.at("n"));
    double r = p.at("radius");
    std::vector<Vec2> corners;
    for (int k = 0; k < n; ++k)
        corners.emplace_back(r * std::cos(2 * kPi * k / n), r * std::sin(2 * kPi * k / n));
    Patches<Segment> segments;
    for (int k = 0; k < n; ++k)
        segments.push_back({{corners[k], corners[(k + 1) % n]}, {}});
    return segments;
}

// Rectangle room [0,w] x [0,h], counter-clockwise, normals inward; the ceiling (y = h)
// emits _lamp_, so that a solve has an open-ended answer (uniform emission has B = E/(1-rho)).
Patches<Segment> Room(const ParamMap &p) {
    double w = p.at("w"), h = p.at("h");
    Patch<Segment> ceiling = Seg(w, h, 0, h);
    ceiling.material.emission = p.at("lamp");
    return {Seg(0, 0, w, 0), Seg(w, 0, w, h), ceiling, Seg(0, h, 0, 0)};
}

// n non-crossing segments of fixed length with uniform centres in [0,size]^2 and
// uniform directions; a candidate that touches an earlier segment is drawn again. With
// _density_ (centres per unit area) the box side is sqrt(n / density) instead of _size_,
// so that the soup keeps its density as n grows.
Patches<Segment> Random(const ParamMap &p) {
    using K = CGAL::Exact_predicates_inexact_constructions_kernel;
    int n = int(p.at("n"));
    auto density = p.find("density");
    double size = density == p.end() ? p.at("size") : std::sqrt(n / density->second);
    double length = p.at("length");
    std::mt19937_64 rng(uint64_t(p.at("seed")));
    Patches<Segment> segments;
    std::vector<K::Segment_2> placed;
    PlacementGrid<2> grid(length, size + 2 * length);
    const int64_t maxDraws = MaxDraws(n);
    for (int64_t draw = 0; int(segments.size()) < n; ++draw) {
        if (draw == maxDraws)
            throw InputError("scene random: cannot place " + std::to_string(n) +
                             " non-crossing segments of length " + FormatDouble(length) +
                             " in a box of size " + FormatDouble(size) +
                             (density == p.end() ? "; enlarge size" : "; lower density"));
        Vec2 c(size * Uniform(rng), size * Uniform(rng));
        double angle = 2 * kPi * Uniform(rng);
        Vec2 half = 0.5 * length * Vec2(std::cos(angle), std::sin(angle));
        Segment s{c - half, c + half};
        K::Segment_2 candidate({s.a.x(), s.a.y()}, {s.b.x(), s.b.y()});
        std::array<double, 2> lo{std::min(s.a.x(), s.b.x()), std::min(s.a.y(), s.b.y())};
        std::array<double, 2> hi{std::max(s.a.x(), s.b.x()), std::max(s.a.y(), s.b.y())};
        if (grid.AnyNear(lo, hi,
                         [&](uint32_t k) { return CGAL::do_intersect(candidate, placed[k]); }))
            continue;
        grid.Insert(uint32_t(placed.size()), lo, hi);
        segments.push_back({s, {}});
        placed.push_back(candidate);
    }
    return segments;
}

}  // namespace

std::vector<Family> FlatlandFamilies() {
    return {
        {"parallel",
         "two facing parallel plates: P (0,0)->(l,0), Q (offset+l2,d)->(offset,d)",
         {Length("l", 64, "length of plate P"), Length("d", 1, "distance between the plates"),
          Offset("offset", "lateral offset of plate Q along x"),
          LengthLike("l2", "l", "length of plate Q (default: l)")},
         2,
         Parallel},
        {"occluded",
         "parallel plates P (0,0)->(l,0), Q (l,d)->(0,d) with a blocker of length b at height h "
         "between them, made of two back-to-back patches",
         {Length("l", 1, "length of the plates"), Length("d", 1, "distance between the plates"),
          Length("b", 0.5, "length of the blocker"),
          Length("h", 0.5, "height of the blocker above P (< d)"),
          Offset("offset", "offset of the blocker's centre from x = l/2")},
         2,
         Occluded},
        {"perpendicular",
         "two plates at a right angle, P on the x axis and Q on the y axis, both facing the "
         "quadrant between them",
         {Length("l", 1, "length of plate P"),
          LengthLike("l2", "l", "length of plate Q (default: l)"),
          Gap("gap", 0.1, "distance of both plates from the corner; 0 means touching")},
         2,
         [](const ParamMap &p) { return Angled(p.at("l"), p.at("l2"), 90, p.at("gap")); }},
        {"angled",
         "two plates meeting at the origin with an opening angle, facing into the wedge",
         {Length("l", 1, "length of plate P (on the x axis)"),
          LengthLike("l2", "l", "length of plate Q (default: l)"),
          {"angle", 60, "", 0, 180, true, true, false, "opening angle in degrees"},
          Gap("gap", 0.1, "distance of both plates from the corner; 0 means touching")},
         2,
         [](const ParamMap &p) {
             return Angled(p.at("l"), p.at("l2"), p.at("angle"), p.at("gap"));
         }},
        {"enclosure",
         "closed regular n-gon, counter-clockwise, normals inward (corners touch: needs a "
         "recursion limit)",
         {Count("n", 6, 3, 100000, "number of walls"), Length("radius", 1, "circumradius")},
         2,
         Enclosure},
        {"room",
         "closed rectangular room [0,w] x [0,h], normals inward (corners touch: needs a "
         "recursion limit)",
         {Length("w", 2, "width"), Length("h", 1, "height"),
          Gap("lamp", 0, "emitted radiosity of the ceiling y = h (the other walls emit nothing)")},
         2,
         Room},
        {"array",
         "k collinear plates facing k others at distance d: the geometry grows, each pair stays "
         "the same",
         {Count("k", 4, 1, 100000, "plates per row"), Length("l", 1, "length of each plate"),
          Length("d", 1, "distance between the rows"),
          Gap("spacing", 1, "gap between neighbouring plates in a row")},
         2,
         Array},
        {"random",
         "n non-crossing segments of one length, uniform centres and directions in a box",
         {Count("n", 10, 1, 100000, "number of segments"),
          Count("seed", 1, 0, 9.0e15, "random seed (same seed, same scene)"),
          Length("size", 10, "side of the square box of centres"),
          Length("length", 1, "length of every segment"),
          OptionalPositive("density", "size",
                           "segment centres per unit area: the box side is sqrt(n / density) "
                           "(instead of size)")},
         2,
         Random},
    };
}

}  // namespace hrbench
