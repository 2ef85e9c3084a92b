#include "hrbench/geometry/polygon.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "hrbench/util/error.h"

namespace hrbench {

namespace {

// p x q, component by component in the order of docs/conventions.md (the same
// expressions as Eigen's cross(), written out so that no library decides them).
Vec3 Cross(const Vec3 &p, const Vec3 &q) {
    return Vec3(p.y() * q.z() - p.z() * q.y(), p.z() * q.x() - p.x() * q.z(),
                p.x() * q.y() - p.y() * q.x());
}

}  // namespace

Vec3 Polygon::AreaVector() const {
    if (n == 3)
        return Cross(v[1] - v[0], v[2] - v[0]);
    // The cross product of the diagonals: exact twice the area vector of a planar quad.
    return Cross(v[2] - v[0], v[3] - v[1]);
}

double Polygon::SquaredArea() const {
    Vec3 twice = AreaVector();
    double x = twice.x(), y = twice.y(), z = twice.z();
    return (x * x + y * y + z * z) / 4;
}

double Polygon::Area() const { return std::sqrt(SquaredArea()); }

Vec3 Polygon::Centroid() const {
    if (n == 3)
        return (v[0] + v[1] + v[2]) / 3;
    // A parallelogram's centroid is the midpoint of its diagonals: exact where the
    // corners are (dyadic), so that congruent elements of a grid have centroids exactly
    // as far apart as their corners, which --method translation relies on.
    if (v[0] + v[2] == v[1] + v[3])
        return 0.5 * (v[0] + v[2]);
    // Weight the centroids of the triangles (v0, v1, v2) and (v0, v2, v3) by their areas.
    double a0 = (v[1] - v[0]).cross(v[2] - v[0]).norm();
    double a1 = (v[2] - v[0]).cross(v[3] - v[0]).norm();
    Vec3 c0 = (v[0] + v[1] + v[2]) / 3, c1 = (v[0] + v[2] + v[3]) / 3;
    return (a0 * c0 + a1 * c1) / (a0 + a1);
}

Vec3 Polygon::Normal() const { return (v[1] - v[0]).cross(v[2] - v[0]).normalized(); }

double Polygon::Diameter() const {
    double d2 = 0;
    for (int a = 0; a < n; ++a)
        for (int b = a + 1; b < n; ++b)
            d2 = std::max(d2, (v[a] - v[b]).squaredNorm());
    return std::sqrt(d2);
}

Vec3 Polygon::At(double s, double t) const {
    if (n == 3)
        return v[0] + s * (v[1] - v[0]) + t * (v[2] - v[0]);
    return (1 - s) * (1 - t) * v[0] + s * (1 - t) * v[1] + s * t * v[2] + (1 - s) * t * v[3];
}

std::string Polygon::Problem() const {
    const Polygon &p = *this;
    if (p.n != 3 && p.n != 4)
        return "has " + std::to_string(p.n) + " corners (only triangles and quads are supported)";
    for (int k = 0; k < p.n; ++k)
        if (!p.v[k].allFinite())
            return "has a coordinate that is not finite";
    double diameter = p.Diameter();
    Vec3 areaVector = p.AreaVector();
    double twiceArea = areaVector.norm();
    if (!std::isfinite(diameter) || !std::isfinite(twiceArea))
        return "is too large for double precision (its size or area overflows)";
    // Below the smallest normal double, squared sizes and areas lose precision.
    if (diameter > 0 && !(diameter * diameter >= std::numeric_limits<double>::min()))
        return "is too small for double precision (its squared size underflows)";
    if (diameter == 0 && (p.v[1] != p.v[0] || p.v[2] != p.v[0]))
        return "is too small for double precision (its squared size underflows)";
    if (!(diameter > 0) || !std::isfinite(twiceArea) ||
        !(twiceArea > 2e-12 * diameter * diameter))  // relative: area below 1e-12 diameter^2
        return p.n == 3 ? "is degenerate (triangle with zero area)"
                        : "is degenerate or self-intersecting (quad with zero area)";
    if (p.n == 3)
        return "";
    Vec3 normal = areaVector / twiceArea;
    for (int k = 0; k < 4; ++k) {
        // Every corner turns the same way as the area vector: strictly convex.
        Vec3 turn = (p.v[(k + 1) % 4] - p.v[k]).cross(p.v[(k + 2) % 4] - p.v[(k + 1) % 4]);
        if (!(turn.dot(normal) > 1e-12 * diameter * diameter))
            return "is not a convex quad (corner " + std::to_string((k + 1) % 4) +
                   " turns the wrong way or is straight)";
    }
    Vec3 centroid = 0.25 * (p.v[0] + p.v[1] + p.v[2] + p.v[3]);
    for (int k = 0; k < 4; ++k)
        if (!(std::abs((p.v[k] - centroid).dot(normal)) <= 1e-6 * diameter))  // planarity tolerance
            return "is not planar (corner " + std::to_string(k) + " lies " +
                   std::to_string(std::abs((p.v[k] - centroid).dot(normal))) +
                   " off the mean plane)";
    return "";
}

int Polygon::Subdivide(Subdivision mode, std::array<Polygon, 4> &out) const {
    const Polygon &p = *this;
    auto mid = [](const Vec3 &a, const Vec3 &b) -> Vec3 { return 0.5 * (a + b); };
    if (mode == Subdivision::Binary) {
        if (p.n == 4) {
            // Cut across the longer pair of opposite edges; ties halve v0v1 and v2v3.
            double pairA = (v[1] - v[0]).norm() + (v[3] - v[2]).norm();
            double pairB = (v[2] - v[1]).norm() + (v[0] - v[3]).norm();
            if (pairA >= pairB) {
                Vec3 m01 = mid(v[0], v[1]), m23 = mid(v[2], v[3]);
                out[0] = Polygon::Quad(v[0], m01, m23, v[3]);
                out[1] = Polygon::Quad(m01, v[1], v[2], m23);
            } else {
                Vec3 m12 = mid(v[1], v[2]), m30 = mid(v[3], v[0]);
                out[0] = Polygon::Quad(v[0], v[1], m12, m30);
                out[1] = Polygon::Quad(m30, m12, v[2], v[3]);
            }
            return 2;
        }
        // Halve the longest edge (a, a+1); ties go to the first edge in corner order.
        int a = 0;
        double longest = (v[1] - v[0]).squaredNorm();
        for (int e = 1; e < 3; ++e) {
            double len = (v[(e + 1) % 3] - v[e]).squaredNorm();
            if (len > longest)
                longest = len, a = e;
        }
        int b = (a + 1) % 3;
        Vec3 m = mid(v[a], v[b]);
        Polygon keepA = p, keepB = p;
        keepA.v[b] = m;                  // keeps corner a
        keepB.v[a] = m;                  // keeps corner b
        out[0] = a < b ? keepA : keepB;  // the child keeping the lower-numbered corner first
        out[1] = a < b ? keepB : keepA;
        return 2;
    }

    // Quadtree: four children through the edge midpoints.
    if (p.n == 4) {
        Vec3 m01 = mid(v[0], v[1]), m12 = mid(v[1], v[2]), m23 = mid(v[2], v[3]),
             m30 = mid(v[3], v[0]);
        Vec3 c = 0.25 * (v[0] + v[1] + v[2] + v[3]);
        out[0] = Polygon::Quad(v[0], m01, c, m30);
        out[1] = Polygon::Quad(m01, v[1], m12, c);
        out[2] = Polygon::Quad(c, m12, v[2], m23);
        out[3] = Polygon::Quad(m30, c, m23, v[3]);
        return 4;
    }
    Vec3 m01 = mid(v[0], v[1]), m12 = mid(v[1], v[2]), m20 = mid(v[2], v[0]);
    out[0] = Polygon::Triangle(v[0], m01, m20);
    out[1] = Polygon::Triangle(m01, v[1], m12);
    out[2] = Polygon::Triangle(m20, m12, v[2]);
    out[3] = Polygon::Triangle(m12, m20, m01);  // the middle one, same orientation
    return 4;
}

void Polygon::SamplePoints(int k, std::vector<Vec3> &out) const {
    const Polygon &p = *this;
    double step = 1.0 / k;
    if (p.n == 4) {
        for (int b = 0; b < k; ++b)
            for (int a = 0; a < k; ++a)
                out.push_back(p.At((a + 0.5) * step, (b + 0.5) * step));
        return;
    }
    // Row _b_ along v0 -> v2 holds k - b upward and k - b - 1 downward small triangles.
    for (int b = 0; b < k; ++b) {
        for (int a = 0; a + b < k; ++a) {
            out.push_back(p.At((a + 1.0 / 3) * step, (b + 1.0 / 3) * step));
            if (a + b + 1 < k)
                out.push_back(p.At((a + 2.0 / 3) * step, (b + 2.0 / 3) * step));
        }
    }
}

bool Polygon::Resolves(double measure, const std::array<double, 4> &children, int n) {
    double sum = 0;
    for (int c = 0; c < n; ++c) {
        if (!(children[c] > 0))
            return false;
        sum += children[c];
    }
    return std::abs(sum - measure) <= 1e-6 * measure;
}

}  // namespace hrbench
