// Hanrahan, Salzman & Aupperle's BF refinement: the form-factor estimate weighted by the
// radiosity it would carry (docs/conventions.md).
#pragma once

#include <memory>
#include <stdexcept>
#include <string>
#include <variant>
#include <vector>

#include "hrbench/forest.h"
#include "hrbench/oracles/hanrahan.h"
#include "hrbench/oracles/oracle.h"
#include "hrbench/radiosity_estimate.h"
#include "hrbench/refine_options.h"
#include "hrbench/util/error.h"

namespace hrbench {

// Acceptable iff V B_j F(i<-j) <= eps and V B_i F(j<-i) <= eps, evaluated as
// (V * B) * F, with F the hanrahan estimates (FormFactorEstimates, the run's choice of
// RefineOptions::ffEstimate, DecideOnEstimates) and B from a
// RadiosityEstimate: the run's (RefineOptions::estimate), or else the roots' emission,
// HSA91's first pass, in which a pair of non-emitting roots is accepted at once.
template <typename Shape>
class BFOracle {
  public:
    static constexpr OracleInfo kInfo = {
        "bf", kFlatland | kSpace, "eps ff_estimate",
        "B_j F(i<-j), B_i F(j<-i) <= eps: hanrahan's F weighted by radiosity B, the roots' "
        "emission or a previous solution (Hanrahan, Salzman & Aupperle's BF refinement)"};
    using ElementType = Element<Shape::kDimension>;
    using Vec = typename Shape::Vec;

    // Reads B from _estimate_ (not owned; it must outlive the oracle), or from the roots'
    // emission when it is null. Throws InputError when B is 0 everywhere: every pair
    // would be accepted at the roots.
    BFOracle(double eps, const Patches<Shape> &roots,
             const RadiosityEstimate<Shape> *estimate = nullptr,
             FfEstimate ffEstimate = kDefaultFfEstimate)
        : eps_(eps), ffEstimate_(ffEstimate), estimate_(estimate) {
        if (!estimate_) {
            owned_ = std::make_shared<const RadiosityEstimate<Shape>>(
                RadiosityEstimate<Shape>::FromEmission(roots));
            estimate_ = owned_.get();
        }
        if (estimate_->NumRoots() != roots.size())
            throw std::invalid_argument("the radiosity estimate has " +
                                        std::to_string(estimate_->NumRoots()) +
                                        " root patches, the scene " + std::to_string(roots.size()));
        if (!(estimate_->Max() > 0))
            throw InputError("the bf oracle needs an emitter: no patch of the scene emits, so "
                             "every pair would be accepted at the roots (give a patch an "
                             "emission, as the cornell family's light has)");
        for (const Patch<Shape> &p : roots)
            normals_.push_back(p.shape.Normal());
    }

    // The run's radiosity estimate, of this shape (RefineOptions::estimate), or the
    // emission; the run's form-factor estimate.
    BFOracle(const RefineOptions &options, const Patches<Shape> &roots)
        : BFOracle(options.eps, roots, EstimateOf(options), options.ffEstimate) {}

    [[gnu::always_inline]] bool Acceptable(const ElementType &i, const ElementType &j) const {
        return AcceptableVisible(i, j, 1.0);
    }

    [[gnu::always_inline]] bool AcceptableVisible(const ElementType &i, const ElementType &j,
                                                  double visible) const {
        const RadiosityEstimate<Shape> &b = *estimate_;
        return DecideOnEstimates<Shape>(
            ffEstimate_, i, j, normals_[i.root], normals_[j.root], [&](const Eigen::Array2d &f) {
                return visible * b(j) * f[0] <= eps_ && visible * b(i) * f[1] <= eps_;
            });
    }

  private:
    // The estimate of _options_ when it is of this shape, null for none; an estimate of
    // the other shape is a caller's mistake.
    static const RadiosityEstimate<Shape> *EstimateOf(const RefineOptions &options) {
        if (auto estimate = std::get_if<const RadiosityEstimate<Shape> *>(&options.estimate))
            return *estimate;
        if (!std::holds_alternative<std::monostate>(options.estimate))
            throw std::invalid_argument(std::string("the radiosity estimate is not of ") +
                                        Shape::kName + "s, the scene's shape");
        return nullptr;
    }

    double eps_;
    FfEstimate ffEstimate_;
    const RadiosityEstimate<Shape> *estimate_;
    // The emission estimate when the run gives none; shared, so that a copy of the
    // oracle reads the same one.
    std::shared_ptr<const RadiosityEstimate<Shape>> owned_;
    std::vector<Vec> normals_;
};

}  // namespace hrbench
