// Radiosity on the hierarchy of a refinement (Hanrahan, Salzman & Aupperle 1991): form
// factors on the stored links, gathering over links, push-pull through the element
// trees, iterated by Jacobi or Gauss-Seidel; and a dense reference on a uniform mesh.
// docs/solve.md states every definition used here.
// Defined in src/solve/: solve.cpp, link_coefficients.cpp (ComputeCoefficients) and
// reference_solve.cpp (SolveUniform).
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

#include <nlohmann/json_fwd.hpp>

#include "hrbench/forest.h"
#include "hrbench/link_buffer.h"
#include "hrbench/record.h"
#include "hrbench/refine.h"
#include "hrbench/refine_options.h"
#include "hrbench/scene.h"

namespace hrbench {

class Occluders;  // visibility.h

// How the linear system is iterated (`solve --solver`).
enum class SolveMethod {
    Jacobi,       // every root patch gathers from the previous sweep's radiosity
    GaussSeidel,  // root patch by root patch, each gathering the latest radiosity
};

struct SolveMethodInfo {
    const char *name;  // "jacobi" or "gauss-seidel"
    const char *doc;   // one line
    SolveMethod method;
};

// Every solver method, the default first: the CLI's choices and capabilities read it.
const std::vector<SolveMethodInfo> &SolveMethods();

// The method named _name_; throws InputError listing the names.
SolveMethod ParseSolveMethod(const std::string &name);
std::string SolveMethodName(SolveMethod method);

// How light crosses a cluster link (`solve --cluster-transfer`; docs/solve.md, Clusters):
// what stands for a cluster end's cosine toward the other end.
enum class ClusterTransferKind {
    Projected,  // the cluster's projected area toward the other end, tabled over directions
    Isotropic,  // Sillion's isotropic cluster: the mean cosine, 1/4 (3D) or 1/pi (2D)
};

struct ClusterTransferInfo {
    const char *name;  // "projected" or "isotropic"
    const char *doc;   // one line
    ClusterTransferKind kind;
};

// Every cluster transfer, the default first: the CLI's choices and capabilities read it.
const std::vector<ClusterTransferInfo> &ClusterTransfers();

// The transfer named _name_; throws InputError listing the names.
ClusterTransferKind ParseClusterTransfer(const std::string &name);
std::string ClusterTransferName(ClusterTransferKind kind);

// The largest uniform mesh the dense reference solves (a dense n x n matrix).
constexpr uint64_t kMaxReferenceElements = 8192;

struct SolveOptions {
    SolveMethod method = SolveMethod::Jacobi;
    double tolerance = 1e-6;            // stop when the residual is below it; in (0, 1)
    int maxIterations = 1000;           // sweeps allowed before LimitError; 1 .. 1000000
    std::optional<double> emission;     // replaces every patch's emission; finite, >= 0
    std::optional<double> reflectance;  // replaces every patch's reflectance; [0, 1)
    int referenceDepth = -1;  // >= 0: also solve the uniform mesh of this depth, and compare
    // The bf oracle's refine-solve passes at most (1 .. kMaxPasses; kDefaultPasses when
    // not given): each pass after the first refines with B from the previous solution.
    // Given with another oracle, an InputError: the others do not read B.
    std::optional<int> passes;
    // HSA91's gather as published: a leaf's irradiance is what its chain's links gather,
    // without the consistency scale (docs/solve.md).
    bool plainGather = false;
    // How cluster links carry light (read only when the refinement has cluster links).
    ClusterTransferKind clusterTransfer = ClusterTransferKind::Projected;
};

constexpr int kDefaultPasses = 4;
constexpr int kMaxPasses = 100;

// Throws InputError naming the option when _options_ are out of range.
void ValidateSolveOptions(const SolveOptions &options);

// Each root patch's material after the overrides of _options_, in scene order. Throws
// InputError when nothing emits.
std::vector<Material> SolveMaterials(const Scene &scene, const SolveOptions &options);

// The coefficients of one stored link {i, j}: the form factor from i to j and from j to
// i, each times the pair's visible fraction (1 with --visibility none).
struct LinkCoefficients {
    double ij, ji;
};

// HSA91's "all form factors are calculated to the same precision", measured on a
// refinement's links: each link's larger exact (unoccluded) form factor,
// max(F(i->j), F(j->i)) with FormFactor of the two elements' shapes (docs/solve.md).
struct LinkFormFactors {
    double max = 0;       // the largest over the links; 0 without links
    double aboveEps = 0;  // the share (0..1) of links whose larger one exceeds eps; 0 without
};

// Adds them to a run or solve record: link_form_factor_max, link_form_factor_above_eps.
void AddLinkFormFactors(const LinkFormFactors &formFactors, nlohmann::json &record);

// The coefficients of every link, in link order: F_ij = FormFactor(i, j), F_ji by
// reciprocity A_i F_ij / A_j, each weighed by the pair's visible fraction when
// _occluders_ (the scene's, under options.visibility) are given. Computed on
// options.threads threads; each value depends on its link only, so the result is the
// same for every thread count. With _formFactors_, also the links' LinkFormFactors
// against options.eps, from the same form factors (before the visible fraction weighs
// them). With _visible_, one fraction per link as the refinement sampled them
// (Refinement::visible), the links are weighed by those, the same values, without
// casting their rays again.
template <typename Shape>
std::vector<LinkCoefficients>
ComputeCoefficients(const Forest<Shape> &forest, const LinkBuffer &links,
                    const RefineOptions &options, const Occluders *occluders = nullptr,
                    LinkFormFactors *formFactors = nullptr,
                    const std::vector<double> *visible = nullptr);

extern template std::vector<LinkCoefficients>
ComputeCoefficients(const Forest<Segment> &, const LinkBuffer &, const RefineOptions &,
                    const Occluders *, LinkFormFactors *, const std::vector<double> *);
extern template std::vector<LinkCoefficients>
ComputeCoefficients(const Forest<Polygon> &, const LinkBuffer &, const RefineOptions &,
                    const Occluders *, LinkFormFactors *, const std::vector<double> *);

// The LinkFormFactors of a stored refinement's links against options.eps, on
// options.threads threads (`run --link-form-factors`). LimitError when the elements'
// shapes, beside the refinement, exceed the memory budget.
LinkFormFactors MeasureLinkFormFactors(const AnyRefinement &refinement,
                                       const RefineOptions &options);

// The consistency scale of every element, by id: for a leaf x, its exact form factor to
// every other root patch, sum over r of FormFactor(x, r), over what the links of x and of
// its ancestors give it, the sum of their coefficients; 1 for inner elements, for a leaf
// its chain links to nothing, and under --visibility fraction or refine (the exact
// occluded sum is not known). Multiplying a leaf's gathered irradiance by it makes a
// uniform radiosity exact: B = E / (1 - rho) in a closed scene at any eps. With
// _rootCoefficients_ (by root patch: what its cluster links give it per unit radiosity,
// ClusterTransfer), they count in the chain of every element of that root's tree.
template <typename Shape>
std::vector<double> ConsistencyScales(const Patches<Shape> &patches, const Forest<Shape> &forest,
                                      const LinkBuffer &links,
                                      const std::vector<LinkCoefficients> &coefficients,
                                      const RefineOptions &options,
                                      const std::vector<double> *rootCoefficients = nullptr);

extern template std::vector<double> ConsistencyScales(const Patches<Segment> &,
                                                      const Forest<Segment> &, const LinkBuffer &,
                                                      const std::vector<LinkCoefficients> &,
                                                      const RefineOptions &,
                                                      const std::vector<double> *);
extern template std::vector<double> ConsistencyScales(const Patches<Polygon> &,
                                                      const Forest<Polygon> &, const LinkBuffer &,
                                                      const std::vector<LinkCoefficients> &,
                                                      const RefineOptions &,
                                                      const std::vector<double> *);

// Each leaf's exact form factor to every other root patch, sum over r of
// FormFactor(x, r), by element id (0 for inner elements, and for the leaves that
// _wanted_, by id, leaves out), on _threads_ threads.
template <typename Shape>
std::vector<double> LeafFormFactorSums(const Patches<Shape> &patches, const Forest<Shape> &forest,
                                       int threads, const std::vector<char> *wanted = nullptr);

extern template std::vector<double> LeafFormFactorSums(const Patches<Segment> &,
                                                       const Forest<Segment> &, int,
                                                       const std::vector<char> *);
extern template std::vector<double> LeafFormFactorSums(const Patches<Polygon> &,
                                                       const Forest<Polygon> &, int,
                                                       const std::vector<char> *);

// One element of a solution: a leaf of the hierarchy, or an element of a uniform mesh.
struct ElementRadiosity {
    uint32_t element;   // id in its forest
    uint32_t root;      // root patch, in scene order
    int depth;          // roots have depth 0
    uint64_t position;  // Forest::Position: index among its depth's elements of its tree
    Vec3 centroid;      // z = 0 in 2D
    double measure;     // length (2D) or area (3D)
    double radiosity;   // B
    double irradiance;  // H, the radiosity gathered from other patches: B = E + rho H
    // The element's outline: numCorners of corners are used, in 2D the end points a, b
    // (z = 0), in 3D the polygon's 3 or 4 corners in order.
    std::array<Vec3, 4> corners{};
    int numCorners = 0;
};

// Wall and CPU (all threads of the process) seconds of one stage.
struct StageTime {
    double wall = 0, cpu = 0;
};

// The dense reference: every root split to one depth, every pair of elements of
// different root patches linked with its form factor, solved by BiCGSTAB (LU with
// partial pivoting where BiCGSTAB does not converge).
struct UniformSolution {
    int depth = 0;
    std::vector<ElementRadiosity> elements;  // by root patch, then position
    double emittedPower = 0, absorbedPower = 0;
    // Solve's reference from depth 1 on: the estimate of its own discretisation error,
    // max over the elements of depth - 1 of |this solution's area-weighted mean over the
    // element - the depth - 1 solution's B| / max |B| (docs/solve.md).
    std::optional<double> change;
    StageTime time;  // with _change_, of both solves
};

// The hierarchical solution against a reference: the hierarchy's leaves are averaged
// (area-weighted) onto the reference's elements, exactly, since both trees split by the
// same rule, and each element's error e = |B_h - B_ref| / max |B_ref| is relative to the
// reference's largest radiosity. The three are norms of the same errors over the same
// elements, so meanError <= l2Error <= maxError, and none depends on the scale of E.
struct ErrorNorms {
    double maxError = 0;   // max over reference elements of e
    double meanError = 0;  // sum of A e over sum of A (area-weighted mean)
    double l2Error = 0;    // sqrt(sum of A e^2 over sum of A) (area-weighted root mean square)
};

// Its own norms are the hierarchy's against the reference (reference_error_*), split in
// two with the projection P of the reference onto the leaves (on each leaf the
// area-weighted mean of the reference over it), each measured on the reference's
// elements as the hierarchy is: _projection_, P against the reference, the error of any
// piecewise-constant radiosity on these leaves; _hierarchy_, the hierarchy against P,
// the links' own. In the area-weighted L2 norm the two are orthogonal:
// l2Error^2 = projection.l2Error^2 + hierarchy.l2Error^2 (docs/solve.md).
struct ReferenceComparison : ErrorNorms {
    ErrorNorms projection;
    ErrorNorms hierarchy;
};

// The cluster links' part in a solve (`--clusters`; docs/solve.md, Clusters).
struct ClusterFigures {
    uint64_t clusters = 0;  // of the tree
    uint64_t links = 0;     // cluster links gathered over
    // Of the power gathered in the last sweep (before the consistency scale), the share
    // that came over cluster links: sum of A H over cluster links' receivers / over all.
    double transferShare = 0;
    uint64_t rays = 0;           // segments cast for the cluster links' visible fractions
    uint64_t occludedLinks = 0;  // cluster links whose every segment was blocked
};

struct SolveResult {
    RunRecord record;                      // the last pass's counters; kernel time of all
    std::vector<ElementRadiosity> leaves;  // by root patch, then preorder of its tree
    std::vector<Material> materials;       // each root patch's, after the overrides
    int iterations = 0;                    // sweeps done
    double residual = 0;                   // of the last sweep
    double emittedPower = 0;               // sum over leaves of E A
    double absorbedPower = 0;              // sum over leaves of (1 - rho) H A
    // Each stage's time, summed over the passes.
    StageTime refine, coefficients, solve;
    // Refine-solve passes made (1 but with the bf oracle), and each pass's refinement's
    // links and nodes; the last pass's are the record's.
    int passes = 0;
    std::vector<uint64_t> passLinks, passNodes;
    std::optional<UniformSolution> reference;  // with SolveOptions::referenceDepth
    std::optional<ReferenceComparison> comparison;
    LinkFormFactors linkFormFactors;         // of the last pass's links
    std::optional<ClusterFigures> clusters;  // when the refinement has a cluster tree
    // The gather of the last pass: "plain" (HSA91's), "consistent" (the leaves scaled to
    // their exact form factor sums) or "reciprocal" (with cluster links: the leaves'
    // rows scaled to them both ways, docs/solve.md, Clusters), with the reciprocal
    // scale's steps and the largest relative error of a leaf's row it left.
    std::string gather;
    int reciprocalSteps = 0;
    double reciprocalError = 0;
    // EnergyBalanceWarning's line: occlusion ignored where the scene has some, or more
    // energy absorbed than the discretisation explains; "" otherwise.
    std::string energyWarning;
};

// `solve`'s visibility when none is given: VisibilityMode::Fraction when some patch can
// block the light between two others (CanOcclude, culling.h), else VisibilityMode::None,
// the papers' setting, which is then exact.
VisibilityMode DefaultSolveVisibility(const Scene &scene);

// The excess of absorbed over emitted power, relative to the emitted, that a solve may
// show without a warning: the discretisation's own (the gathers' rows at a coarse eps,
// up to 2.1% measured on closed rooms where nothing occludes; docs/solve.md).
constexpr double kEnergyExcessAllowance = 0.05;

// A warning (one line, "" for none) on a solve's energy balance, with its powers: when
// --visibility none lets light pass through a scene that can occlude (CanOcclude), and
// otherwise when the absorbed power exceeds the emitted power by more than
// kEnergyExcessAllowance of it. The iteration never makes energy (B starts at E and
// every coefficient is >= 0, so the absorbed power grows toward the solution's): an
// excess is the coefficients'.
std::string EnergyBalanceWarning(const Scene &scene, const RefineOptions &refine,
                                 const SolveResult &result);

// Refines _scene_ (storing links), computes the link coefficients and solves for the
// radiosity of every leaf. With the bf oracle, repeats that with B from the solution
// until a refinement has the links and nodes of the one before, or SolveOptions::passes
// were made (docs/solve.md). Throws InputError for bad input (nothing emits, options out
// of range), LimitError when the memory budget is reached or the iteration does not
// converge within SolveOptions::maxIterations.
SolveResult Solve(const Scene &scene, const RefineOptions &refine, const SolveOptions &options);

// Solves the links of _refinement_, a refinement of _scene_ made with _refine_ (element
// links and cluster links), once: what Solve does for one pass, without the dense
// reference. For refinements made otherwise than by Solve (tests, other kernels).
template <typename Shape>
SolveResult SolveRefinement(const Scene &scene, const Refinement<Shape> &refinement,
                            const RefineOptions &refine, const SolveOptions &options);

extern template SolveResult SolveRefinement(const Scene &, const Refinement<Segment> &,
                                            const RefineOptions &, const SolveOptions &);
extern template SolveResult SolveRefinement(const Scene &, const Refinement<Polygon> &,
                                            const RefineOptions &, const SolveOptions &);

// The dense reference of _scene_ at _depth_ (refine supplies threads, visibility, rays,
// subdivision and the memory budget). InputError above kMaxReferenceElements elements.
UniformSolution SolveUniform(const Scene &scene, int depth, const RefineOptions &refine,
                             const SolveOptions &options);

// The JSON of one solve: the run record's fields (RunToJson) and the solution's.
nlohmann::json SolveToJson(const Scene &scene, const RefineOptions &refine,
                           const SolveOptions &options, const SolveResult &result);

// A short human table of a solve's JSON.
void PrintSolveTable(const nlohmann::json &solve, std::ostream &out);

// One CSV row per leaf (docs/solve.md): element,root,depth,position, the centroid,
// measure,radiosity,irradiance, the root's reflectance,emission and display colour
// red,green,blue, and the outline: x0,y0,x1,y1 in 2D; corners,x0,y0,z0,..,x3,y3,z3 in 3D.
void WriteSolveCsv(const SolveResult &result, int dimension, std::ostream &out);

}  // namespace hrbench
