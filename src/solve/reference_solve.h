// What Solve needs of the dense uniform reference (reference_solve.cpp).
#pragma once

#include <vector>

#include "hrbench/forest.h"
#include "hrbench/refine_options.h"
#include "hrbench/scene.h"
#include "hrbench/solve.h"

namespace hrbench {

// InputError when the reference of _depth_ is out of range or above
// kMaxReferenceElements elements, LimitError when its dense matrices exceed the budget:
// checked before refining, so that a bad --reference fails fast.
void CheckReferenceSize(const Scene &scene, int depth, const RefineOptions &refine);

// The dense reference of depth _depth_ and, from depth 1 on, its change from the mesh of
// depth - 1: whether it is converged well below the errors it measures.
template <typename Shape>
UniformSolution SolveReference(const Patches<Shape> &patches, int depth,
                               const RefineOptions &refine, const std::vector<Material> &materials);

// _result_'s leaves, of _forest_, averaged onto the reference's elements, and the errors.
template <typename Shape>
ReferenceComparison Compare(const Forest<Shape> &forest, const SolveResult &result,
                            const UniformSolution &reference);

}  // namespace hrbench
