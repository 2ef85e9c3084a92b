// Garmann & Mueller's oracle: element size over distance (docs/conventions.md).
#pragma once

#include <algorithm>
#include <cmath>
#include <limits>

#include "hrbench/forest.h"
#include "hrbench/oracles/oracle.h"

namespace hrbench {

// e = max(A_i, A_j) / r in 2D and / r^2 in 3D, with r the distance between the
// centroids; acceptable iff max(A_i, A_j) <= eps r (2D) or <= eps r^2 (3D), evaluated
// in that form, with A = sqrt(A^2) of the elements, so that ties fall the same way in
// every implementation.
template <typename Shape>
class GarmannOracle {
  public:
    static constexpr OracleInfo kInfo = {
        "garmann", kFlatland | kSpace, "eps",
        "max(A_i,A_j)/r <= eps in 2D, max(A_i,A_j)/r^2 <= eps in 3D (Garmann & Mueller)"};
    using ElementType = Element<Shape::kDimension>;

    GarmannOracle(double eps, const Patches<Shape> &) : eps_(eps) {
        // The decision on squares needs eps^2, widened either side by the margin, and
        // (3D) its reciprocals, as normal doubles; for an eps too large or too small
        // for that, every pair takes the exact form (accept never below 0, reject never
        // above +inf; in 3D s * inf is never < r^4, s * 0 never > r^4).
        constexpr double kMin = std::numeric_limits<double>::min() * 0x1p+8;
        constexpr double kMax = std::numeric_limits<double>::max() * 0x1p-8;
        double eps2 = eps * eps;
        bool normal = eps2 >= kMin && eps2 <= kMax;
        double below = eps2 * (1 - 1e-12), above = eps2 * (1 + 1e-12);
        acceptBelow_ = normal ? below : 0;
        rejectAbove_ = normal ? above : std::numeric_limits<double>::infinity();
        acceptScale_ = normal ? 1 / below : std::numeric_limits<double>::infinity();
        rejectScale_ = normal ? 1 / above : 0;
    }

    [[gnu::always_inline]] bool Acceptable(const ElementType &i, const ElementType &j) const {
        // s = max(A_i, A_j)^2: A = sqrt(A^2) is monotone, so this is the square of the
        // larger A. Decide on squares, which needs no square root, unless the pair is
        // within rounding of the threshold; then evaluate the exact form with
        // max(A_i, A_j) = sqrt(s) so that ties fall as defined. 1e-12 exceeds the
        // relative error of either side.
        double s = std::max(i.sizeSquared, j.sizeSquared);
        double r2 = (i.center - j.center).squaredNorm();
        if constexpr (Shape::kDimension == 3) {
            // A <= eps r^2 against s <= eps^2 r^4, written as s / eps^2 against r^4: an
            // overflow of either side to +inf then falls on the right side (a large
            // r^4 accepts, a large s / eps^2 rejects or falls through), and an
            // underflow keeps both on one grid of subnormals.
            double r4 = r2 * r2;
            if (s * acceptScale_ < r4)
                return true;
            if (s * rejectScale_ > r4)
                return false;
            return std::sqrt(s) <= eps_ * r2;
        } else {
            if (s < acceptBelow_ * r2)
                return true;
            if (s > rejectAbove_ * r2)
                return false;
            return std::sqrt(s) <= eps_ * std::sqrt(r2);
        }
    }

    [[gnu::always_inline]] bool AcceptableVisible(const ElementType &i, const ElementType &j,
                                                  double visible) const {
        double m = visible * std::sqrt(std::max(i.sizeSquared, j.sizeSquared));
        double r2 = (i.center - j.center).squaredNorm();
        if constexpr (Shape::kDimension == 3)
            return m <= eps_ * r2;
        else
            return m <= eps_ * std::sqrt(r2);
    }

  private:
    double eps_;
    double acceptBelow_, rejectAbove_;  // eps^2 widened by the margin, either side (2D)
    double acceptScale_, rejectScale_;  // their reciprocals (3D)
};

}  // namespace hrbench
