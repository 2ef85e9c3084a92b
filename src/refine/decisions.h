// The rules of the refinement (docs/conventions.md), written once for the kernels that
// apply them: ProjectKernel (kernel.h) and the sweep's (count/sweep_count.cpp). Each is inlined
// into the hot path, where a call would cost more than the rule.
#pragma once

#include <cstdint>

#include "hrbench/forest.h"
#include "hrbench/refine_options.h"
#include "visibility/visibility.h"

namespace hrbench {

// Whether a rejected pair (i, j) splits i rather than j: the larger element by A^2,
// compared exactly; ties split the first.
template <typename E>
[[gnu::always_inline]] inline bool SplitsFirst(const E &ei, const E &ej) {
    return ei.sizeSquared >= ej.sizeSquared;
}

// Whether the oracle accepts elements _ei_, _ej_ whose visible fraction is _visible_
// (in (0, 1]; 1 without visibility): a fully visible pair by the plain test; a partly
// visible one by the test weighted by _visible_ (--visibility fraction) or never
// (refine: it goes to the recursion limit).
template <typename Oracle, typename Visibility, typename E>
[[gnu::always_inline]] inline bool AcceptsVisible(const Oracle &oracle,
                                                  const Visibility &visibility, const E &ei,
                                                  const E &ej, double visible) {
    if constexpr (Visibility::kEnabled) {
        if (visible < 1)
            return visibility.Mode() == VisibilityMode::Fraction &&
                   oracle.AcceptableVisible(ei, ej, visible);
    }
    return oracle.Acceptable(ei, ej);
}

// The recursion limits that keep an element whole, fixed for a run: A < --min-area,
// decided on A^2 without rounding, and the depth limit (--max-depth, or kSafetyDepth,
// whose reach is an error).
class RecursionLimits {
  public:
    explicit RecursionLimits(const RefineOptions &options)
        : depthLimit_(options.maxDepth >= 0 ? options.maxDepth : kSafetyDepth),
          userDepthLimit_(options.maxDepth >= 0) {}

    // Whether --min-area keeps an element of squared size _sizeSquared_ whole, where
    // _bound_ is SquaredSizeBound(--min-area).
    [[gnu::always_inline]] static bool BelowMinArea(double sizeSquared, double bound) {
        return sizeSquared < bound;
    }

    // Whether the depth limit keeps an element at _depth_ whole, splitting it being
    // needed by a rejected pair of the trees of roots _p_ and _q_; throws the safety
    // depth's error where no user limit is set.
    [[gnu::always_inline]] bool DepthStops(int depth, uint32_t p, uint32_t q) const {
        if (depth < depthLimit_)
            return false;
        if (!userDepthLimit_)
            ThrowSafetyDepth(p, q);
        return true;
    }

  private:
    int depthLimit_;
    bool userDepthLimit_;
};

}  // namespace hrbench
