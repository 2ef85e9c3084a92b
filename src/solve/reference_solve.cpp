// The dense reference on a uniform mesh (every pair of elements of different root
// patches linked, solved by BiCGSTAB), its change from the mesh one level coarser, and the
// hierarchical solution's errors against it (docs/solve.md).
#include "reference_solve.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <memory>
#include <string>

#include <Eigen/IterativeLinearSolvers>
#include <Eigen/LU>

#include "hrbench/util/error.h"
#include "link_coefficients.h"
#include "solve_internal.h"
#include "util/parallel_for.h"
#include "visibility/culling.h"

namespace hrbench {

namespace {

// Elements of the uniform mesh of depth _depth_, or UINT64_MAX when there are too many.
uint64_t UniformElements(const Scene &scene, int depth, Subdivision subdivision) {
    uint64_t perRoot = 1;
    for (int d = 0; d < depth && perRoot <= kMaxReferenceElements; ++d)
        perRoot *= uint64_t(scene.Dimension() == 2 ? 2 : SubdivisionArity(subdivision));
    uint64_t total = perRoot * scene.NumPatches();
    return perRoot > kMaxReferenceElements || total > kMaxReferenceElements ? UINT64_MAX : total;
}

// Solves M B = E for M = I - diag(rho) F. The rows of F sum to at most 1 and rho < 1,
// so the eigenvalues of M lie within max rho of 1 and BiCGSTAB reaches a residual of
// kReferenceResidual of |E| in a few dozen products with M, O(n^2) each, where LU
// takes O(n^3) (at n = 2048, 5x less time for the whole reference). LU with partial
// pivoting, in place, where BiCGSTAB does not converge.
Eigen::VectorXd SolveDense(Eigen::MatrixXd &M, const Eigen::VectorXd &E) {
    constexpr double kReferenceResidual = 1e-14;
    Eigen::BiCGSTAB<Eigen::MatrixXd, Eigen::IdentityPreconditioner> bicgstab;
    bicgstab.setTolerance(kReferenceResidual);
    bicgstab.setMaxIterations(1000);
    bicgstab.compute(M);
    Eigen::VectorXd B = bicgstab.solve(E);
    if (bicgstab.info() == Eigen::Success)
        return B;
    Eigen::PartialPivLU<Eigen::Ref<Eigen::MatrixXd>> lu(M);
    return lu.solve(E);
}

// The dense solution of the uniform mesh of depth _depth_.
template <typename Shape>
UniformSolution SolveUniformOf(const Patches<Shape> &patches, int depth,
                               const RefineOptions &refine,
                               const std::vector<Material> &materials) {
    Stopwatch watch;
    Forest<Shape> forest(patches, SIZE_MAX, refine.subdivision);
    // Split level by level, children in order: the last level is in position order.
    std::vector<uint32_t> elements;
    for (uint32_t root = 0; root < patches.size(); ++root) {
        std::vector<uint32_t> level{root};
        for (int d = 0; d < depth; ++d) {
            std::vector<uint32_t> deeper;
            for (uint32_t e : level) {
                uint32_t first = forest.Children(e);
                for (int c = 0; c < forest.Arity(); ++c)
                    deeper.push_back(first + c);
            }
            level.swap(deeper);
        }
        elements.insert(elements.end(), level.begin(), level.end());
    }
    const size_t n = elements.size();
    std::vector<PairRelation> relation(patches.size() * patches.size());
    for (size_t p = 0; p < patches.size(); ++p)
        for (size_t q = p + 1; q < patches.size(); ++q)
            relation[p * patches.size() + q] = ClassifyPair(patches[p].shape, patches[q].shape);

    // Form factors of every pair of elements of different, not culled, root patches.
    Eigen::MatrixXd F = Eigen::MatrixXd::Zero(n, n);
    std::unique_ptr<Occluders> occluders = OccludersFor(patches, refine);
    std::vector<Shape> shapes = forest.AllShapes();
    ParallelFor(
        n, 4, refine.threads,
        [&] { return PairCoefficients<Shape>(shapes, occluders.get(), refine); },
        [&](PairCoefficients<Shape> &pair, size_t a) {
            uint32_t e = elements[a];
            for (size_t b = a + 1; b < n; ++b) {
                uint32_t f = elements[b];
                uint32_t p = forest[e].root, q = forest[f].root;
                if (p == q || relation[p * patches.size() + q] == PairRelation::Culled)
                    continue;
                double visible = pair.Visible(forest, e, f);
                if (visible == 0)
                    continue;
                LinkCoefficients c = pair(forest, e, f, visible);
                F(a, b) = c.ij;
                F(b, a) = c.ji;
            }
        });

    // (I - diag(rho) F) B = E.
    Eigen::VectorXd rho(n), E(n);
    for (size_t a = 0; a < n; ++a) {
        rho(a) = materials[forest[elements[a]].root].reflectance;
        E(a) = materials[forest[elements[a]].root].emission;
    }
    Eigen::MatrixXd M = -(rho.asDiagonal() * F);
    M.diagonal().array() += 1;
    Eigen::VectorXd B = SolveDense(M, E);
    Eigen::VectorXd H = F * B;

    UniformSolution solution;
    solution.depth = depth;
    for (size_t a = 0; a < n; ++a) {
        uint32_t e = elements[a];
        double area = forest[e].Size();
        solution.elements.push_back(Describe(forest, e, B(a), H(a)));
        solution.emittedPower += E(a) * area;
        solution.absorbedPower += (1 - rho(a)) * H(a) * area;
    }
    solution.time = Elapsed(watch);
    return solution;
}

// How far _fine_ moved from _coarse_, the uniform mesh one level coarser: the largest
// |area-weighted mean of fine over a coarse element - coarse B|, relative to fine's
// largest |B|. Both are in root, then position order, and the children of the element at
// position p are at positions arity p .. arity p + arity - 1: the fine elements of coarse
// element k are arity k .. arity k + arity - 1.
double ReferenceChange(const UniformSolution &fine, const UniformSolution &coarse) {
    const auto &f = fine.elements, &c = coarse.elements;
    size_t arity = f.size() / c.size();
    double largest = 0, change = 0;
    for (const ElementRadiosity &e : f)
        largest = std::max(largest, std::abs(e.radiosity));
    for (size_t k = 0; k < c.size(); ++k) {
        double power = 0, area = 0;
        for (size_t child = arity * k; child < arity * (k + 1); ++child)
            power += f[child].measure * f[child].radiosity, area += f[child].measure;
        change = std::max(change, std::abs(power / area - c[k].radiosity));
    }
    return largest > 0 ? change / largest : 0;
}

// The norms of e_k = |a_k - b_k| / largest over the reference's elements, weighted by
// their measures. Each e_k is taken before any sum or square, so that none under- or
// overflows: the max, the area-weighted mean and the area-weighted root mean square.
ErrorNorms Norms(const std::vector<double> &a, const std::vector<double> &b,
                 const std::vector<ElementRadiosity> &ref, double largest) {
    double maxError = 0, sumError = 0, sumSquaredError = 0, sumMeasure = 0;
    for (size_t k = 0; k < ref.size(); ++k) {
        double error = std::abs(a[k] - b[k]) / largest;
        maxError = std::max(maxError, error);
        sumError += ref[k].measure * error;
        sumSquaredError += ref[k].measure * error * error;
        sumMeasure += ref[k].measure;
    }
    // The weighted means cannot exceed the largest term, nor the mean the root mean
    // square (Cauchy-Schwarz); min() keeps that through the sums' rounding.
    double l2Error = std::min(std::sqrt(sumSquaredError / sumMeasure), maxError);
    return {maxError, std::min(sumError / sumMeasure, l2Error), l2Error};
}

}  // namespace

void CheckReferenceSize(const Scene &scene, int depth, const RefineOptions &refine) {
    if (depth < 0 || depth > kSafetyDepth)
        throw InputError("--reference must be between 0 and " + std::to_string(kSafetyDepth));
    if (UniformElements(scene, depth, refine.subdivision) == UINT64_MAX)
        throw InputError("--reference " + std::to_string(depth) + " gives more than " +
                         std::to_string(kMaxReferenceElements) +
                         " elements, the most the dense reference solves; lower it");
    uint64_t n = UniformElements(scene, depth, refine.subdivision);
    if (2 * n * n * sizeof(double) > EffectiveBudget(refine))
        throw LimitError("--reference " + std::to_string(depth) +
                         ": the dense matrices would exceed the memory budget; raise "
                         "--max-memory or lower the depth");
}

template <typename Shape>
UniformSolution SolveReference(const Patches<Shape> &patches, int depth,
                               const RefineOptions &refine,
                               const std::vector<Material> &materials) {
    UniformSolution reference = SolveUniformOf(patches, depth, refine, materials);
    if (depth >= 1) {
        UniformSolution coarse = SolveUniformOf(patches, depth - 1, refine, materials);
        reference.change = ReferenceChange(reference, coarse);
        AddTime(reference.time, coarse.time);
    }
    return reference;
}

template <typename Shape>
ReferenceComparison Compare(const Forest<Shape> &forest, const SolveResult &result,
                            const UniformSolution &reference) {
    const auto &ref = reference.elements;
    size_t perRoot = ref.size() / forest.NumRoots();
    // On each reference element: the hierarchy's leaves averaged onto it (power / area),
    // and the projection of the reference onto the leaves, averaged onto it likewise.
    // Both meshes are elements of the same trees, so a leaf either lies inside one
    // reference element or is a block of them: no leaf boundary crosses an element.
    std::vector<double> power(ref.size(), 0), area(ref.size(), 0), projected(ref.size());
    for (const ElementRadiosity &leaf : result.leaves) {
        size_t base = leaf.root * perRoot;
        if (leaf.depth >= reference.depth) {
            uint32_t a = leaf.element;
            while (forest.Depth(a) > reference.depth)
                a = forest.Parent(a);
            size_t k = base + forest.Position(a);
            power[k] += leaf.measure * leaf.radiosity;
            area[k] += leaf.measure;
            // The reference is constant on the element: so is its projection on the
            // leaves inside it, and their mean.
            projected[k] = ref[k].radiosity;
        } else {
            // The leaf covers a whole block of reference elements; the projection is the
            // reference's area-weighted mean over them, with the same measures as the norms.
            uint64_t span = perRoot;
            for (int d = 0; d < leaf.depth; ++d)
                span /= uint64_t(forest.Arity());
            size_t first = base + leaf.position * span, last = first + span;
            double refPower = 0, refArea = 0;
            for (size_t k = first; k < last; ++k)
                refPower += ref[k].measure * ref[k].radiosity, refArea += ref[k].measure;
            for (size_t k = first; k < last; ++k)
                power[k] = leaf.radiosity, area[k] = 1, projected[k] = refPower / refArea;
        }
    }
    double largest = 0;
    std::vector<double> solved(ref.size()), exact(ref.size());
    for (size_t k = 0; k < ref.size(); ++k) {
        largest = std::max(largest, std::abs(ref[k].radiosity));
        solved[k] = power[k] / area[k];
        exact[k] = ref[k].radiosity;
    }
    if (!(largest > 0))
        return {};  // unreachable: SolveMaterials refuses a scene where nothing emits
    // On each element, solved - exact = (solved - projected) + (projected - exact): the
    // first is constant on each coarse leaf, where the second has mean 0, and the second
    // is 0 under finer leaves, so the two are orthogonal in the area-weighted L2 norm.
    return {Norms(solved, exact, ref, largest), Norms(projected, exact, ref, largest),
            Norms(solved, projected, ref, largest)};
}

template UniformSolution SolveReference(const Patches<Segment> &, int, const RefineOptions &,
                                        const std::vector<Material> &);
template UniformSolution SolveReference(const Patches<Polygon> &, int, const RefineOptions &,
                                        const std::vector<Material> &);
template ReferenceComparison Compare(const Forest<Segment> &, const SolveResult &,
                                     const UniformSolution &);
template ReferenceComparison Compare(const Forest<Polygon> &, const SolveResult &,
                                     const UniformSolution &);

UniformSolution SolveUniform(const Scene &scene, int depth, const RefineOptions &refine,
                             const SolveOptions &options) {
    ValidateSolveOptions(options);
    ValidateScene(scene);
    if (refine.threads < 1 || refine.threads > 256)
        throw InputError("--threads must be between 1 and 256");
    if (scene.Dimension() == 2 && refine.subdivision != Subdivision::Binary)
        throw InputError("--subdivision quadtree applies to 3D scenes only (segments are halved)");
    std::vector<Material> materials = SolveMaterials(scene, options);
    CheckReferenceSize(scene, depth, refine);
    double unit = EmissionUnit(materials);
    UniformSolution solution = std::visit(
        [&](const auto &patches) {
            return SolveUniformOf(patches, depth, refine, InEmissionUnits(materials, unit));
        },
        scene.patches);
    ToEmissionScale(solution.elements, solution.emittedPower, solution.absorbedPower, unit);
    return solution;
}

}  // namespace hrbench
