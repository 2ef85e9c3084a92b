// Garmann & Mueller's oracle: element size over distance (docs/conventions.md).
#pragma once

#include <algorithm>
#include <cmath>

#include "forest.h"
#include "oracles/oracle.h"

namespace hrbench {

// e = max(A_i, A_j) / r in 2D and / r^2 in 3D, with r the distance between the
// centroids; acceptable iff max(A_i, A_j) <= eps r (2D) or <= eps r^2 (3D), evaluated
// in that form so that ties fall the same way in every implementation.
template <typename Shape>
class GarmannOracle {
  public:
    static constexpr OracleInfo kInfo = {
        "garmann", kFlatland | kSpace, "eps",
        "max(A_i,A_j)/r <= eps in 2D, max(A_i,A_j)/r^2 <= eps in 3D (Garmann & Mueller)"};
    using ElementType = Element<Shape::kDimension>;

    GarmannOracle(double eps, const Patches<Shape> &)
        : eps_(eps), acceptBelow_(eps * eps * (1 - 1e-12)), rejectAbove_(eps * eps * (1 + 1e-12)) {}

    [[gnu::always_inline]] bool Acceptable(const ElementType &i, const ElementType &j) const {
        double m = std::max(i.size, j.size);
        double r2 = (i.center - j.center).squaredNorm();
        if constexpr (Shape::kDimension == 3) {
            return m <= eps_ * r2;
        } else {
            // Decide on squares, which needs no square root, unless the pair is within
            // rounding of the threshold; then evaluate the exact form so that ties fall
            // as defined. 1e-12 exceeds the relative error of either side.
            double m2 = m * m;
            if (m2 < acceptBelow_ * r2)
                return true;
            if (m2 > rejectAbove_ * r2)
                return false;
            return m <= eps_ * std::sqrt(r2);
        }
    }

    [[gnu::always_inline]] bool AcceptableVisible(const ElementType &i, const ElementType &j,
                                                  double visible) const {
        double m = visible * std::max(i.size, j.size);
        double r2 = (i.center - j.center).squaredNorm();
        if constexpr (Shape::kDimension == 3)
            return m <= eps_ * r2;
        else
            return m <= eps_ * std::sqrt(r2);
    }

  private:
    double eps_;
    double acceptBelow_, rejectAbove_;  // eps^2 widened by the margin, either side (2D)
};

}  // namespace hrbench
