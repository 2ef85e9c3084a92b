// The coefficients of one element pair, shared by the hierarchy's links
// (ComputeCoefficients, link_coefficients.cpp) and the dense reference's pairs
// (reference_solve.cpp), so that both weigh a pair the same way.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>

#include "hrbench/forest.h"
#include "hrbench/form_factor.h"
#include "hrbench/refine_options.h"
#include "hrbench/solve.h"
#include "hrbench/visibility.h"

namespace hrbench {

// The scene's occluders when visibility counts, else none.
template <typename Shape>
std::unique_ptr<Occluders> OccludersFor(const Patches<Shape> &patches, const RefineOptions &o) {
    return o.visibility == VisibilityMode::None ? nullptr : std::make_unique<Occluders>(patches);
}

// The visible fraction of an element pair, as refinement estimates it (1 with
// --visibility none); one per worker, for the scratch space of the sampling.
template <typename Shape>
class PairFraction {
  public:
    PairFraction(const Occluders *occluders, const RefineOptions &options) {
        if (occluders)
            sampled_.emplace(*occluders, options.raysPerSide, options.visibility);
    }
    double operator()(const Forest<Shape> &forest, uint32_t i, uint32_t j) {
        return sampled_ ? sampled_->Fraction(forest, i, j, tally_) : 1.0;
    }

  private:
    std::optional<SampledVisibility<Shape>> sampled_;
    VisibilityTally tally_;
};

// Elements _i_ and _j_'s coefficients given their _visible_ fraction: F_ij times it, and
// F_ji by reciprocity A_i F_ij / A_j.
template <typename Shape>
LinkCoefficients PairCoefficients(const Forest<Shape> &forest, uint32_t i, uint32_t j,
                                  double visible) {
    double ij = FormFactor(forest.ShapeOf(i), forest.ShapeOf(j)) * visible;
    return {ij, forest[i].Size() * ij / forest[j].Size()};
}

}  // namespace hrbench
