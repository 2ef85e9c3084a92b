// The coefficients of one element pair, shared by the hierarchy's links
// (ComputeCoefficients, link_coefficients.cpp) and the dense reference's pairs
// (reference_solve.cpp), so that both weigh a pair the same way.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>

#include "hrbench/forest.h"
#include "hrbench/refine_options.h"
#include "hrbench/solve.h"
#include "solve/form_factor.h"
#include "visibility/visibility.h"

namespace hrbench {

// The scene's occluders when visibility counts, else none.
template <typename Shape>
std::unique_ptr<Occluders> OccludersFor(const Patches<Shape> &patches, const RefineOptions &o) {
    return o.visibility == VisibilityMode::None ? nullptr : std::make_unique<Occluders>(patches);
}

// The coefficients of element pairs, one instance per worker: the visible fraction as
// refinement estimates it (1 with --visibility none), with the scratch space of its
// sampling, and the form factors of the elements' shapes (Forest::AllShapes()).
template <typename Shape>
class PairCoefficients {
  public:
    PairCoefficients(const std::vector<Shape> &shapes, const Occluders *occluders,
                     const RefineOptions &options)
        : shapes_(&shapes) {
        if (occluders)
            sampled_.emplace(*occluders, options.raysPerSide, options.visibility);
    }

    // The visible fraction of elements _i_ and _j_.
    double Visible(const Forest<Shape> &forest, uint32_t i, uint32_t j) {
        return sampled_ ? sampled_->Fraction(forest, i, j, tally_) : 1.0;
    }

    // Elements _i_ and _j_'s coefficients given their _visible_ fraction: F_ij times it,
    // and F_ji by reciprocity A_i F_ij / A_j.
    LinkCoefficients operator()(const Forest<Shape> &forest, uint32_t i, uint32_t j,
                                double visible) const {
        return Weighted(forest, i, j, FormFactor((*shapes_)[i], (*shapes_)[j]), visible);
    }

    // The same from the form factor _ij_ = FormFactor(i, j); visible = 1 gives the exact
    // (unoccluded) form factors both ways.
    static LinkCoefficients Weighted(const Forest<Shape> &forest, uint32_t i, uint32_t j, double ij,
                                     double visible) {
        ij *= visible;
        return {ij, forest[i].Size() * ij / forest[j].Size()};
    }

    double FormFactorOf(uint32_t i, uint32_t j) const {
        return FormFactor((*shapes_)[i], (*shapes_)[j]);
    }

  private:
    const std::vector<Shape> *shapes_;
    std::optional<SampledVisibility<Shape>> sampled_;
    VisibilityTally tally_;
};

}  // namespace hrbench
