// What a shape is: the geometry of one element, whatever the dimension. The engine's
// forest, kernel, oracles and visibility are written once against this contract, and
// the two shapes (segment.h, polygon.h) are its variants.
//
// A Shape is a small value type with
//   static constexpr int kDimension;        2 (flatland) or 3
//   static constexpr const char *kName;     "segment", "polygon"
//   using Vec = Vector<kDimension>;
//   double SquaredMeasure() const;          A^2, by the formula of docs/conventions.md
//                                           (what the kernel compares)
//   double Measure() const;                 the element size A = sqrt(A^2): length or area
//   Vec Centroid() const;                   where the oracle measures distances
//   Vec Normal() const;                     unit normal on the front side
//   int Subdivide(Subdivision, std::array<Shape, 4> &out) const;   children, first first
//   void SamplePoints(int k, std::vector<Vec> &out) const;          visibility samples
//   std::string Problem() const;            why it cannot be a patch, or ""
//   static bool Resolves(double measure, const std::array<double, 4> &children, int n);
//                                           false when double precision no longer
//                                           resolves the children of an element
#pragma once

#include <Eigen/Core>

namespace hrbench {

template <int D>
using Vector = Eigen::Matrix<double, D, 1>;
using Vec2 = Vector<2>;
using Vec3 = Vector<3>;

}  // namespace hrbench
