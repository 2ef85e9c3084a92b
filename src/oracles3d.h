// The oracles of DESIGN section 2 in 3D, and in either dimension with a visibility
// weight: `--visibility fraction` accepts a pair when its error times the visible
// fraction V of the pair is within eps. With V = 1 they decide exactly as the plain
// forms do (multiplying by 1 is exact), so the 2D ones agree with oracles.h.
#pragma once

#include <algorithm>
#include <cmath>
#include <vector>

#include "element_tree.h"

namespace hrbench {

constexpr double kOraclePi = 3.14159265358979323846;

// Garmann & Mueller: e = max(A_i, A_j) / r (2D) or / r^2 (3D), acceptable iff
// V max(A_i, A_j) <= eps r (2D) or V max(A_i, A_j) <= eps r^2 (3D), evaluated in that form.
template <int D>
class GarmannOracleND {
  public:
    explicit GarmannOracleND(double eps) : eps_(eps) {}

    bool Acceptable(const Element<D> &i, const Element<D> &j) const {
        return AcceptableVisible(i, j, 1.0);
    }

    bool AcceptableVisible(const Element<D> &i, const Element<D> &j, double visible) const {
        double m = visible * std::max(i.size, j.size);
        double r2 = (i.center - j.center).squaredNorm();
        if constexpr (D == 3)
            return m <= eps_ * r2;
        else
            return m <= eps_ * std::sqrt(r2);
    }

  private:
    double eps_;
};

// Hanrahan, Salzman & Aupperle: the form-factor estimate with cosines at the centroids,
// clamped at 0: 3D F(i<-j) = A_j cos+_i cos+_j / (pi r^2 + A_j), 2D F(i<-j) =
// A_j cos+_i cos+_j / sqrt(4 r^2 + A_j^2). Acceptable iff V F(i<-j) <= eps and V F(j<-i) <= eps.
template <int D>
class HanrahanOracleND {
  public:
    using Vec = Eigen::Matrix<double, D, 1>;

    // _rootNormals_: the unit front normal of every root patch, in scene order.
    HanrahanOracleND(double eps, std::vector<Vec> rootNormals)
        : eps_(eps), normals_(std::move(rootNormals)) {}

    bool Acceptable(const Element<D> &i, const Element<D> &j) const {
        return AcceptableVisible(i, j, 1.0);
    }

    bool AcceptableVisible(const Element<D> &i, const Element<D> &j, double visible) const {
        Vec d = j.center - i.center;
        double r2 = d.squaredNorm();
        double r = std::sqrt(r2);
        double cosI = std::max(0.0, normals_[i.root].dot(d) / r);
        double cosJ = std::max(0.0, -normals_[j.root].dot(d) / r);
        double fIJ, fJI;
        if constexpr (D == 3) {
            fIJ = j.size * cosI * cosJ / (kOraclePi * r2 + j.size);
            fJI = i.size * cosI * cosJ / (kOraclePi * r2 + i.size);
        } else {
            fIJ = j.size * cosI * cosJ / std::sqrt(4 * r2 + j.size * j.size);
            fJI = i.size * cosI * cosJ / std::sqrt(4 * r2 + i.size * i.size);
        }
        return visible * fIJ <= eps_ && visible * fJI <= eps_;
    }

  private:
    double eps_;
    std::vector<Vec> normals_;
};

using Garmann3DOracle = GarmannOracleND<3>;
using Hanrahan3DOracle = HanrahanOracleND<3>;

}  // namespace hrbench
