// The concrete oracles. Each is a small value type with an inline Acceptable(),
// so the kernel instantiated for it compiles the oracle into the recursion.
#pragma once

#include <algorithm>
#include <cmath>
#include <vector>

#include "element_tree.h"

namespace hrbench {

// Garmann & Mueller (flatland): e = max(A_i, A_j) / r_ij, acceptable iff max(A_i, A_j) <= eps * r.
class GarmannOracle {
  public:
    explicit GarmannOracle(double eps)
        : eps_(eps), acceptBelow_(eps * eps * (1 - 1e-12)), rejectAbove_(eps * eps * (1 + 1e-12)) {}

    bool Acceptable(const Element<2> &i, const Element<2> &j) const {
        double m = std::max(i.size, j.size);
        double r2 = (i.center - j.center).squaredNorm();
        // Decide on squares, which needs no square root, unless the pair is within
        // rounding of the threshold; then evaluate the exact form so that ties fall
        // as in DESIGN section 2. 1e-12 exceeds the relative error of either side.
        double m2 = m * m;
        if (m2 < acceptBelow_ * r2)
            return true;
        if (m2 > rejectAbove_ * r2)
            return false;
        return m <= eps_ * std::sqrt(r2);
    }

  private:
    double eps_;
    double acceptBelow_, rejectAbove_;  // eps^2 widened by the margin, either side
};

// Hanrahan, Salzman & Aupperle (flatland): the point-to-centred-segment form factor
// F(i<-j) = A_j cos+_i cos+_j / sqrt(4 r^2 + A_j^2), cosines at the centroids.
class HanrahanOracle {
  public:
    HanrahanOracle(double eps, std::vector<Vec2> rootNormals)
        : eps_(eps), normals_(std::move(rootNormals)) {}

    bool Acceptable(const Element<2> &i, const Element<2> &j) const {
        Vec2 d = j.center - i.center;
        double r2 = d.squaredNorm();
        double r = std::sqrt(r2);
        double cosI = std::max(0.0, normals_[i.root].dot(d) / r);
        double cosJ = std::max(0.0, -normals_[j.root].dot(d) / r);
        double fIJ = j.size * cosI * cosJ / std::sqrt(4 * r2 + j.size * j.size);
        double fJI = i.size * cosI * cosJ / std::sqrt(4 * r2 + i.size * i.size);
        return fIJ <= eps_ && fJI <= eps_;
    }

  private:
    double eps_;
    std::vector<Vec2> normals_;
};

}  // namespace hrbench
