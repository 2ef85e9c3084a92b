// The flatland shape: an oriented segment (see shape.h for the contract).
#pragma once

#include <array>
#include <cmath>
#include <string>
#include <vector>

#include "hrbench/geometry/shape.h"
#include "hrbench/geometry/subdivision.h"

namespace hrbench {

// An oriented segment from _a_ to _b_; its front side is on the left (the direction
// rotated by +90 degrees).
struct Segment {
    static constexpr int kDimension = 2;
    static constexpr const char *kName = "segment";
    using Vec = Vec2;

    Vec2 a, b;

    // The squared length A^2 = dx*dx + dy*dy with (dx, dy) = b - a, evaluated in that
    // order without FMA (docs/conventions.md#preferred-subdivision): the engine compares
    // elements by it. Spelled out rather than left to an Eigen reduction.
    double SquaredLength() const {
        double dx = b.x() - a.x(), dy = b.y() - a.y();
        return dx * dx + dy * dy;
    }
    double SquaredMeasure() const { return SquaredLength(); }
    // The length A = sqrt(A^2), bit for bit Eigen's (b - a).norm().
    double Length() const { return std::sqrt(SquaredLength()); }
    double Measure() const { return Length(); }
    Vec2 Midpoint() const { return 0.5 * (a + b); }
    Vec2 Centroid() const { return Midpoint(); }
    // Unit normal on the front (left) side.
    Vec2 Normal() const {
        Vec2 dir = (b - a).normalized();
        return Vec2(-dir.y(), dir.x());
    }

    // The two halves at the midpoint, the first starting at _a_. Segments have no
    // quadtree rule; the refinement options refuse it before any split. Inline, as
    // Resolves(): a forest splits every element it grows through them.
    int Subdivide(Subdivision, std::array<Segment, 4> &out) const {
        Vec2 m = Midpoint();
        out[0] = {a, m};
        out[1] = {m, b};
        return 2;
    }

    // _k_ points at the centres of the _k_ equal parts, from _a_ to _b_.
    void SamplePoints(int k, std::vector<Vec2> &out) const;

    // "" when the segment can be a patch; otherwise what is wrong with it.
    std::string Problem() const;

    // Both halves must measure half the parent to 1e-6: midpoints of an element too small
    // for its coordinates no longer halve it.
    static bool Resolves(double measure, const std::array<double, 4> &children, int n) {
        double half = 0.5 * measure;
        for (int c = 0; c < n; ++c)
            if (!(std::abs(children[c] - half) <= 1e-6 * half))
                return false;
        return true;
    }
};

}  // namespace hrbench
