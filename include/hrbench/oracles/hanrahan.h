// Hanrahan, Salzman & Aupperle's oracle: form-factor estimates (docs/conventions.md).
#pragma once

#include <algorithm>
#include <cmath>
#include <vector>

#include "hrbench/forest.h"
#include "hrbench/oracles/ff_estimate.h"
#include "hrbench/oracles/oracle.h"
#include "hrbench/refine_options.h"

namespace hrbench {

// The form-factor estimates _E_ of an element pair, both directions
// (docs/conventions.md#oracles; oracles/ff_estimate.h names each and gives its source).
// With r = |c_j - c_i|, cos_i = n_i . (c_j - c_i) / r, cos_j = -n_j . (c_j - c_i) / r
// (c the centres, n_i, n_j the unit front normals of the elements' roots) and
// f(i<-j) = A_j / (pi r^2 + A_j) in 3D, A_j / sqrt(4 r^2 + A_j^2) in 2D (the factor from
// a point to a disc, or a segment, of area A_j centred in front of it):
//   centre-cosine   F(i<-j) = A_j max(0, cos_i) max(0, cos_j) / (pi r^2 + A_j), resp.
//                   / sqrt(4 r^2 + A_j^2): f times both cosines clamped at 0;
//   solid-angle     F(i<-j) = f(i<-j);
//   clamped-cosine  F(i<-j) = f * max(|cos_i|, 2f) * max(|cos_j|, 2f), f = f(i<-j),
//                   the receiver's cosine first.
// Returns (F(i<-j), F(j<-i)). Shared by hanrahan and bf, so that both evaluate one
// formula, rounded alike.
template <typename Shape, FfEstimate E>
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
    Pair q = Pair(ni.dot(d), -nj.dot(d)) / r;  // (cos_i, cos_j)
    // The sizes A = sqrt(A^2) of the hot records (Element::Size()).
    Pair a = Pair(j.sizeSquared, i.sizeSquared).sqrt();
    Pair denominator;
    if constexpr (Shape::kDimension == 3)
        denominator = kPi * r2 + a;
    else
        denominator = (4 * r2 + a * a).sqrt();
    if constexpr (E == FfEstimate::CentreCosine) {
        return a * std::max(0.0, q[0]) * std::max(0.0, q[1]) / denominator;
    } else {
        Pair f = a / denominator;
        if constexpr (E == FfEstimate::SolidAngle)
            return f;
        Pair floor = 2 * f;
        Pair c = q.abs();
        // Lane 0 receives at i (its cosine first), lane 1 at j.
        return f * c.max(floor) * Pair(c[1], c[0]).max(floor);
    }
}

// decide(FormFactorEstimates<Shape, E>(i, j, ni, nj)) for E = _estimate_, the value of
// the run. Each path estimates and decides in one piece, so that the branch, which goes
// the same way on every call of a run, is all that the choice adds to an oracle call.
template <typename Shape, typename Decide>
[[gnu::always_inline]] inline bool
DecideOnEstimates(FfEstimate estimate, const Element<Shape::kDimension> &i,
                  const Element<Shape::kDimension> &j, const typename Shape::Vec &ni,
                  const typename Shape::Vec &nj, Decide &&decide) {
    switch (estimate) {
    case FfEstimate::CentreCosine:
        return decide(FormFactorEstimates<Shape, FfEstimate::CentreCosine>(i, j, ni, nj));
    case FfEstimate::SolidAngle:
        return decide(FormFactorEstimates<Shape, FfEstimate::SolidAngle>(i, j, ni, nj));
    case FfEstimate::ClampedCosine:
        break;
    }
    return decide(FormFactorEstimates<Shape, FfEstimate::ClampedCosine>(i, j, ni, nj));
}

// The estimates of _estimate_, chosen at run time (for tests and tools).
template <typename Shape>
Eigen::Array2d FormFactorEstimates(const Element<Shape::kDimension> &i,
                                   const Element<Shape::kDimension> &j,
                                   const typename Shape::Vec &ni, const typename Shape::Vec &nj,
                                   FfEstimate estimate) {
    Eigen::Array2d f;
    DecideOnEstimates<Shape>(estimate, i, j, ni, nj, [&](const Eigen::Array2d &e) {
        f = e;
        return true;
    });
    return f;
}

// Acceptable iff V F(i<-j) <= eps and V F(j<-i) <= eps (V = 1 without visibility), F the
// estimates of FormFactorEstimates() of the run's choice (RefineOptions::ffEstimate).
template <typename Shape>
class HanrahanOracle {
  public:
    static constexpr OracleInfo kInfo = {
        "hanrahan", kFlatland | kSpace, "eps ff_estimate",
        "form-factor estimates F(i<-j), F(j<-i) <= eps (Hanrahan, Salzman & Aupperle; "
        "--ff-estimate)"};
    using ElementType = Element<Shape::kDimension>;
    using Vec = typename Shape::Vec;

    // Keeps the unit front normal of every root patch, in scene order.
    HanrahanOracle(double eps, const Patches<Shape> &roots,
                   FfEstimate estimate = kDefaultFfEstimate)
        : eps_(eps), estimate_(estimate) {
        for (const Patch<Shape> &p : roots)
            normals_.push_back(p.shape.Normal());
    }

    // The run's threshold and estimate.
    HanrahanOracle(const RefineOptions &options, const Patches<Shape> &roots)
        : HanrahanOracle(options.eps, roots, options.ffEstimate) {}

    [[gnu::always_inline]] bool Acceptable(const ElementType &i, const ElementType &j) const {
        return AcceptableVisible(i, j, 1.0);
    }

    [[gnu::always_inline]] bool AcceptableVisible(const ElementType &i, const ElementType &j,
                                                  double visible) const {
        return DecideOnEstimates<Shape>(estimate_, i, j, normals_[i.root], normals_[j.root],
                                        [&](const Eigen::Array2d &f) {
                                            return visible * f[0] <= eps_ && visible * f[1] <= eps_;
                                        });
    }

  private:
    double eps_;
    FfEstimate estimate_;
    std::vector<Vec> normals_;
};

}  // namespace hrbench
