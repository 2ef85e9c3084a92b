// The 3D shape: a planar convex triangle or quad (see shape.h for the contract), its
// measures, subdivision and sample points (docs/conventions.md, docs/3d.md).
#pragma once

#include <array>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "hrbench/geometry/shape.h"
#include "hrbench/geometry/subdivision.h"

namespace hrbench {

// A triangle (3 corners) or a convex quad (4 corners), counter-clockwise seen from
// its front, so that the front normal is (v1 - v0) x (v2 - v0) normalised.
struct Polygon {
    static constexpr int kDimension = 3;
    static constexpr const char *kName = "polygon";
    using Vec = Vec3;

    std::array<Vec3, 4> v;  // corners; v[3] is unused for a triangle
    int n = 0;              // number of corners, 3 or 4

    static Polygon Triangle(const Vec3 &a, const Vec3 &b, const Vec3 &c) {
        return {{a, b, c, c}, 3};
    }
    static Polygon Quad(const Vec3 &a, const Vec3 &b, const Vec3 &c, const Vec3 &d) {
        return {{a, b, c, d}, 4};
    }

    // The squared area A^2 = (Vx*Vx + Vy*Vy + Vz*Vz) / 4 of the area vector V below,
    // evaluated in that order without FMA (docs/conventions.md#preferred-subdivision):
    // the engine compares elements by it.
    double SquaredArea() const;
    double SquaredMeasure() const { return SquaredArea(); }
    // Area: the element size A = sqrt(A^2) (half the norm of V, except where A^2 is
    // below the smallest normal double).
    double Area() const;
    double Measure() const { return Area(); }
    // Area centroid; for a parallelogram (v0 + v2 == v1 + v3 in doubles) 0.5 (v0 + v2).
    Vec3 Centroid() const;
    // Unit normal on the front side, from the corners v0, v1, v2 (v0, v2, v3 would give
    // the same for a planar quad).
    Vec3 Normal() const;
    // Twice the area vector V (its direction is the normal): (v1 - v0) x (v2 - v0) for a
    // triangle, the cross product of the diagonals (v2 - v0) x (v3 - v1) for a quad, with
    // (p x q) = (py*qz - pz*qy, pz*qx - px*qz, px*qy - py*qx), spelled out component by
    // component.
    Vec3 AreaVector() const;
    // Largest distance between two corners.
    double Diameter() const;

    // Point at parameters (_s_, _t_) in [0,1]^2: bilinear in the corners for a quad
    // (v0 at (0,0), v1 at (1,0), v2 at (1,1), v3 at (0,1)); v0 + s (v1 - v0) + t (v2 - v0)
    // for a triangle (valid for s + t <= 1).
    Vec3 At(double s, double t) const;

    // "" when the polygon can be a patch, otherwise what is wrong with it: a coordinate
    // that is not finite, a degenerate triangle or quad (area below 1e-12 of its diameter
    // squared), a quad whose corners lie off their mean plane by more than 1e-6 of its
    // diameter, or a quad that is not strictly convex.
    std::string Problem() const;

    // The children under _mode_, first child first (docs/3d.md):
    //  - binary quad: halves through the midpoints of the longer pair of opposite edges
    //    (sum of the two lengths; ties cut v0v1 and v2v3); the first child keeps v0.
    //  - binary triangle: halves from the midpoint m of the longest edge (ties: the first
    //    of v0v1, v1v2, v2v0) to the opposite corner; the first child keeps the
    //    lower-numbered end of that edge, and each child keeps its parent's corner order
    //    with m in place of the corner it lost.
    //  - quadtree quad: four quads meeting at the mean of the corners, in corner order
    //    (the child at v0 first); quadtree triangle: the three corner triangles in corner
    //    order, then the middle one.
    // Returns the number of children written to _out_ (2 or 4).
    int Subdivide(Subdivision mode, std::array<Polygon, 4> &out) const;

    // _k_ x _k_ deterministic, equal-weight sample points: for a quad, the centres of a
    // k x k grid of cells in the bilinear parameters (s, t); for a triangle, the
    // centroids of the k^2 congruent triangles of its regular subdivision, row by row.
    void SamplePoints(int k, std::vector<Vec3> &out) const;

    // The children's areas must be positive and add up to the parent's to 1e-6: corners
    // too coarse for an element no longer resolve it.
    static bool Resolves(double measure, const std::array<double, 4> &children, int n);
};

}  // namespace hrbench
