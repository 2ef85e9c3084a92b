// Hanrahan, Salzman & Aupperle's oracle: form-factor estimates (docs/conventions.md).
#pragma once

#include <algorithm>
#include <cmath>
#include <vector>

#include "hrbench/forest.h"
#include "hrbench/oracles/oracle.h"

namespace hrbench {

// The form factor of a point to a centred element, cosines at the centroids clamped
// at 0: 3D F(i<-j) = A_j cos+_i cos+_j / (pi r^2 + A_j), 2D (the exact point-to-
// centred-segment factor) F(i<-j) = A_j cos+_i cos+_j / sqrt(4 r^2 + A_j^2), with
// _ni_, _nj_ the unit front normals of the elements' roots. Returns (F(i<-j), F(j<-i)).
// Shared by hanrahan and bf, so that both evaluate one formula, rounded alike.
template <typename Shape>
[[gnu::always_inline]] inline Eigen::Array2d
FormFactorEstimates(const Element<Shape::kDimension> &i, const Element<Shape::kDimension> &j,
                    const typename Shape::Vec &ni, const typename Shape::Vec &nj) {
    constexpr double kPi = 3.14159265358979323846;
    typename Shape::Vec d = j.center - i.center;
    double r2 = d.squaredNorm();
    double r = std::sqrt(r2);
    // The two directions side by side, (j <- i in lane 0 is F(i<-j) with A_j; lane 1
    // F(j<-i) with A_i), as two-lane arrays: element-wise IEEE operations in the
    // order written, so each lane rounds exactly as the scalar formula would, and
    // the square roots and divisions of both lanes take one instruction each.
    using Pair = Eigen::Array2d;
    Pair q = Pair(ni.dot(d), -nj.dot(d)) / r;
    double cosI = std::max(0.0, q[0]);
    double cosJ = std::max(0.0, q[1]);
    // The sizes A = sqrt(A^2) of the hot records (Element::Size()).
    Pair a = Pair(j.sizeSquared, i.sizeSquared).sqrt();
    if constexpr (Shape::kDimension == 3)
        return a * cosI * cosJ / (kPi * r2 + a);
    else
        return a * cosI * cosJ / (4 * r2 + a * a).sqrt();
}

// Acceptable iff V F(i<-j) <= eps and V F(j<-i) <= eps (V = 1 without visibility).
template <typename Shape>
class HanrahanOracle {
  public:
    static constexpr OracleInfo kInfo = {
        "hanrahan", kFlatland | kSpace, "eps",
        "form-factor estimates F(i<-j), F(j<-i) <= eps (Hanrahan, Salzman & Aupperle)"};
    using ElementType = Element<Shape::kDimension>;
    using Vec = typename Shape::Vec;

    // Keeps the unit front normal of every root patch, in scene order.
    HanrahanOracle(double eps, const Patches<Shape> &roots) : eps_(eps) {
        for (const Patch<Shape> &p : roots)
            normals_.push_back(p.shape.Normal());
    }

    [[gnu::always_inline]] bool Acceptable(const ElementType &i, const ElementType &j) const {
        return AcceptableVisible(i, j, 1.0);
    }

    [[gnu::always_inline]] bool AcceptableVisible(const ElementType &i, const ElementType &j,
                                                  double visible) const {
        Eigen::Array2d f = FormFactorEstimates<Shape>(i, j, normals_[i.root], normals_[j.root]);
        return visible * f[0] <= eps_ && visible * f[1] <= eps_;
    }

  private:
    double eps_;
    std::vector<Vec> normals_;
};

}  // namespace hrbench
