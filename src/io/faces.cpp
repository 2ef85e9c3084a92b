// Faces as patches, and the triangulation of those that cannot be one (exact, with CGAL).
#include "faces.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <numeric>

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_2_algorithms.h>

namespace hrbench::meshio {

namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;

// Corner indices of a triangle of a split face, counter-clockwise like the face.
using CornerTriangle = std::array<size_t, 3>;

// Largest number of corners of a face that is split by ear clipping (a non-convex one):
// the clipping takes up to n^3 steps.
constexpr size_t kMaxClippedCorners = 512;

// Why _quad_ (of a face that Polygon::Problem refuses) is not planar or not convex, with
// corners numbered from 1; "" when it is neither, but degenerate, not finite or too
// large. Same measures and tolerances as Polygon::Problem.
std::string QuadShapeProblem(const Polygon &quad) {
    double diameter = quad.Diameter();
    Vec3 areaVector = quad.AreaVector();
    double twiceArea = areaVector.norm();
    if (!std::isfinite(diameter) || !std::isfinite(twiceArea) ||
        !(twiceArea > 2e-12 * diameter * diameter))
        return "";
    Vec3 normal = areaVector / twiceArea;
    // The diagonals are perpendicular to the normal, so all four corners lie equally far
    // from the plane through their mean, on alternate sides.
    Vec3 centroid = 0.25 * (quad.v[0] + quad.v[1] + quad.v[2] + quad.v[3]);
    double distance = std::abs((quad.v[0] - centroid).dot(normal));
    for (int k = 1; k < 4; ++k)
        distance = std::max(distance, std::abs((quad.v[k] - centroid).dot(normal)));
    if (distance > kMeshPlanarityTolerance * diameter)
        return "is not planar: its corners lie " + ThreeDigits(distance) +
               " off their mean plane, " + ThreeDigits(distance / diameter) +
               " of the face's diameter " + ThreeDigits(diameter) + " (tolerance " +
               ThreeDigits(kMeshPlanarityTolerance) + " of the diameter)";
    for (int k = 0; k < 4; ++k) {
        const Vec3 &a = quad.v[k], &b = quad.v[(k + 1) % 4], &c = quad.v[(k + 2) % 4];
        if (!((b - a).cross(c - b).dot(normal) > 1e-12 * diameter * diameter))
            return "is not a convex quad: corner " + std::to_string((k + 1) % 4 + 1) +
                   " turns the wrong way or goes straight on";
    }
    return "";
}

// The corners of a face seen along its normal: each corner's two coordinates other than
// the one where the face's area vector is largest (ties: x before y before z), exactly
// as read, in the order that keeps the face counter-clockwise.
class ProjectedFace {
  public:
    using Point2 = Kernel::Point_2;

    ProjectedFace(const std::vector<Vec3> &corners, int dropped) {
        int u = (dropped + 1) % 3, w = (dropped + 2) % 3;
        for (const Vec3 &c : corners)
            points_.emplace_back(c[u], c[w]);
    }

    // Whether the projected polygon is simple (no two edges cross or touch, no corner
    // repeats), decided exactly; if so, it fixes the orientation.
    bool IsSimple() {
        const Kernel traits{};  // a named one: GCC warns that a temporary is uninitialized
        if (!CGAL::is_simple_2(points_.begin(), points_.end(), traits))
            return false;
        clockwise_ = CGAL::orientation_2(points_.begin(), points_.end(), traits) == CGAL::CLOCKWISE;
        return true;
    }

    // +1 when a, b, c turn left (counter-clockwise seen from the front), -1 when right,
    // 0 when collinear; exact.
    int Turn(size_t a, size_t b, size_t c) const {
        int turn = int(CGAL::orientation(points_[a], points_[b], points_[c]));
        return clockwise_ ? -turn : turn;
    }

    bool StrictlyConvex() const {
        size_t n = points_.size();
        for (size_t k = 0; k < n; ++k)
            if (Turn((k + n - 1) % n, k, (k + 1) % n) <= 0)
                return false;
        return true;
    }

    // Whether _b_ with its neighbours _a_ and _c_ among the _remaining_ corners is an ear:
    // it turns left, and no other remaining corner lies in or on the triangle a b c.
    bool IsEar(size_t a, size_t b, size_t c, const std::vector<size_t> &remaining) const {
        if (Turn(a, b, c) <= 0)
            return false;
        for (size_t x : remaining)
            if (x != a && x != b && x != c && Turn(a, b, x) >= 0 && Turn(b, c, x) >= 0 &&
                Turn(c, a, x) >= 0)
                return false;
        return true;
    }

  private:
    std::vector<Point2> points_;
    bool clockwise_ = false;
};

// Splits the face with _corners_ (named _face_ in messages) into triangles:
//  - a quad convex seen along its normal: along its shorter diagonal (ties: v1v3 only
//    when strictly shorter than v0v2), as a fan from the diagonal's first corner;
//  - a polygon of 5 or more corners that is strictly convex seen along its normal: a fan
//    from its first corner, (v0, vk, vk+1) for k = 1 .. n-2;
//  - any other simple polygon: ear clipping, walking the corners from the first; an ear
//    is cut off as (previous, current, next), and the walk goes back to the previous
//    corner, otherwise on to the next; the last three corners, in their order, make the
//    last triangle.
// Fails at the current line of _lines_ when the face is degenerate or not simple.
std::vector<CornerTriangle> Triangulate(const Lines &lines, const std::string &face,
                                        const std::vector<Vec3> &corners) {
    size_t n = corners.size();
    // Twice the area vector, relative to the first corner so that it does not depend on
    // where the face lies.
    Vec3 areaVector = Vec3::Zero();
    Vec3 low = corners[0], high = corners[0];
    for (size_t k = 0; k < n; ++k) {
        areaVector += (corners[k] - corners[0]).cross(corners[(k + 1) % n] - corners[0]);
        low = low.cwiseMin(corners[k]);
        high = high.cwiseMax(corners[k]);
    }
    double size = (high - low).norm();  // the bounding box's diagonal: O(n), unlike the diameter
    if (!areaVector.allFinite() || !std::isfinite(size))
        lines.Fail(face + " is too large for double precision (its size or area overflows)");
    if (!(areaVector.norm() > 2e-12 * size * size))
        lines.Fail(face + " is degenerate (its area is zero), so it cannot be triangulated");
    int dropped = 0;
    for (int axis = 1; axis < 3; ++axis)
        if (std::abs(areaVector[axis]) > std::abs(areaVector[dropped]))
            dropped = axis;
    ProjectedFace projected(corners, dropped);
    if (!projected.IsSimple())
        lines.Fail(face + " is not a simple polygon seen along its normal (two edges cross or "
                          "touch, or a corner repeats), so it cannot be triangulated");

    std::vector<CornerTriangle> triangles;
    if (projected.StrictlyConvex()) {
        if (n == 4) {
            bool v1v3 =
                (corners[3] - corners[1]).squaredNorm() < (corners[2] - corners[0]).squaredNorm();
            return v1v3 ? std::vector<CornerTriangle>{{1, 2, 3}, {1, 3, 0}}
                        : std::vector<CornerTriangle>{{0, 1, 2}, {0, 2, 3}};
        }
        for (size_t k = 1; k + 1 < n; ++k)
            triangles.push_back({0, k, k + 1});
        return triangles;
    }
    if (n > kMaxClippedCorners)
        lines.Fail(face + " is a non-convex polygon of " + std::to_string(n) +
                   " corners; at most " + std::to_string(kMaxClippedCorners) +
                   " can be triangulated");
    std::vector<size_t> ring(n);
    std::iota(ring.begin(), ring.end(), size_t(0));
    size_t at = 0, misses = 0;
    while (ring.size() > 3) {
        size_t r = ring.size();
        size_t a = ring[(at + r - 1) % r], b = ring[at], c = ring[(at + 1) % r];
        if (projected.IsEar(a, b, c, ring)) {
            triangles.push_back({a, b, c});
            ring.erase(ring.begin() + std::ptrdiff_t(at));
            at = (at + r - 2) % (r - 1);  // back to the previous corner
            misses = 0;
        } else {
            at = (at + 1) % r;
            // A simple polygon always has an ear: a full round without one cannot happen.
            if (++misses > r)
                lines.Fail(face + " cannot be triangulated (no ear found)");
        }
    }
    triangles.push_back({ring[0], ring[1], ring[2]});
    return triangles;
}

}  // namespace

// Fails at the current line of _lines_ unless _face_ may have _n_ corners: at least 3,
// and at most 4 unless faces are triangulated.
void CheckCornerCount(const Lines &lines, const std::string &face, uint64_t n, bool triangulate) {
    if (n < 3)
        lines.Fail(face + " has " + std::to_string(n) + " corners (a face needs at least 3)");
    if (n > 4 && !triangulate)
        lines.Fail(face + " has " + std::to_string(n) +
                   " corners (triangles and quads are read as they are; --triangulate splits "
                   "polygons into triangles)");
}

// Appends face number _number_ (from 1; _face_ is "face N") with _corners_ (as
// CheckCornerCount allows) to
// _patches_ with _material_: as it is when it can be a patch (Polygon::Problem), split
// into triangles when _triangulate_ and it is a polygon of 5 or more corners or a quad
// that is not planar or not convex; otherwise fails at the current line of _lines_
// saying why.
void AddFace(const Lines &lines, size_t number, const std::string &face,
             const std::vector<Vec3> &corners, const Material &material, bool triangulate,
             MeshPatches &patches) {
    size_t n = corners.size();
    if (n <= 4) {
        Polygon polygon = n == 3 ? Polygon::Triangle(corners[0], corners[1], corners[2])
                                 : Polygon::Quad(corners[0], corners[1], corners[2], corners[3]);
        std::string problem = polygon.Problem();
        if (problem.empty())
            return patches.Add(polygon, material, lines.Number(), number);
        std::string shape = n == 4 ? QuadShapeProblem(polygon) : "";
        if (shape.empty())
            lines.Fail(face + " " + problem);
        if (!triangulate)
            lines.Fail(face + " " + shape + "; --triangulate splits it into triangles");
    }
    std::vector<CornerTriangle> triangles = Triangulate(lines, face, corners);
    for (size_t k = 0; k < triangles.size(); ++k) {
        const CornerTriangle &t = triangles[k];
        Polygon triangle = Polygon::Triangle(corners[t[0]], corners[t[1]], corners[t[2]]);
        std::string problem = triangle.Problem();
        if (!problem.empty())
            lines.Fail(face + ", triangle " + std::to_string(k + 1) + " of " +
                       std::to_string(triangles.size()) + " of its triangulation, " + problem);
        patches.Add(triangle, material, lines.Number(), number);
    }
}

}  // namespace hrbench::meshio
