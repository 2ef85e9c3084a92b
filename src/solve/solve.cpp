// The hierarchical solve: HierarchySolver (gather, push-pull, Jacobi or Gauss-Seidel),
// the bf oracle's refine-solve passes and the options. The link coefficients are in
// link_coefficients.cpp, the cluster links' transfer in cluster_transfer.cpp, the dense
// reference in reference_solve.cpp, the output (JSON, table, CSV) in solve_output.cpp.
#include "hrbench/solve.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "cluster/cluster_transfer.h"
#include "hrbench/radiosity_estimate.h"
#include "hrbench/refine.h"
#include "hrbench/util/error.h"
#include "link_coefficients.h"
#include "reference_solve.h"
#include "solve_internal.h"
#include "util/format.h"
#include "util/named.h"
#include "visibility/culling.h"

namespace hrbench {

namespace {

// Every element of each tree in preorder (first child first), tree by tree, with the
// offset of each tree's first element: parents come before their children.
template <typename Shape>
void Preorder(const Forest<Shape> &forest, std::vector<uint32_t> &order,
              std::vector<size_t> &treeStart) {
    order.clear();
    treeStart.assign(1, 0);
    std::vector<uint32_t> stack;
    for (uint32_t root = 0; root < forest.NumRoots(); ++root) {
        stack.push_back(root);
        while (!stack.empty()) {
            uint32_t e = stack.back();
            stack.pop_back();
            order.push_back(e);
            if (uint32_t first = forest[e].firstChild; first != kNoChildren)
                for (int c = forest.Arity() - 1; c >= 0; --c)
                    stack.push_back(first + c);
        }
        treeStart.push_back(order.size());
    }
}

// The hierarchical system (HSA91) of one refinement and its iteration, with the cluster
// links of _clusters_ when given.
template <typename Shape>
class HierarchySolver {
  public:
    HierarchySolver(const Forest<Shape> &forest, const LinkBuffer &links,
                    const std::vector<LinkCoefficients> &coefficients, std::vector<double> scale,
                    const std::vector<Material> &materials, ClusterTransfer<Shape> *clusters)
        : forest_(forest), n_(forest.Size()), scale_(std::move(scale)), clusters_(clusters) {
        Preorder(forest, order_, treeStart_);
        area_.resize(n_), rho_.resize(n_), emission_.resize(n_);
        for (uint32_t e = 0; e < n_; ++e) {
            area_[e] = forest[e].Size();
            rho_[e] = materials[forest[e].root].reflectance;
            emission_[e] = materials[forest[e].root].emission;
        }
        // Each link gathers both ways: half-links grouped by the root of the gathering
        // element, in link order, so that a root patch gathers in one pass.
        size_t roots = forest.NumRoots();
        start_.assign(roots + 1, 0);
        for (const Link &l : links)
            ++start_[forest[l.i].root + 1], ++start_[forest[l.j].root + 1];
        for (size_t r = 0; r < roots; ++r)
            start_[r + 1] += start_[r];
        half_.resize(2 * links.size());
        std::vector<size_t> fill(start_.begin(), start_.end() - 1);
        for (size_t k = 0; k < links.size(); ++k) {
            const Link &l = links[k];
            half_[fill[forest[l.i].root]++] = {l.i, l.j, coefficients[k].ij};
            half_[fill[forest[l.j].root]++] = {l.j, l.i, coefficients[k].ji};
        }
    }

    // Bytes of the solver's arrays for _links_ links and _elements_ elements, and of the
    // elements' shapes that the form factors are computed from (Forest::AllShapes()).
    static size_t Bytes(size_t links, size_t elements) {
        return links * (sizeof(LinkCoefficients) + 2 * sizeof(HalfLink)) +
               elements * (8 * sizeof(double) + sizeof(uint32_t) + sizeof(Shape));
    }

    // Every element's radiosity by id, inner elements the pulled means of their leaves.
    const std::vector<double> &Radiosity() const { return radiosity_; }

    // The reciprocal scale (docs/solve.md, Clusters): the scale d of every leaf, by id (1
    // for inner elements), such that the leaves' coefficients, each taken as d_i K_ij d_j,
    // sum to _target_ (by id) in every leaf's row, found by the symmetric Sinkhorn
    // iteration d_i <- sqrt(d_i t_i / (K d)_i), each step one gather of d over every link.
    // Stops when every row is within kReciprocalTolerance of its target, or after
    // kReciprocalSteps steps; _steps_ and _error_ say where it stopped. A leaf whose row
    // or target is 0 keeps d = 1. The solve then scales each leaf's gathered irradiance
    // and its radiosity as gathered from by d: A_i d_i K_ij d_j is symmetric, so the
    // power that goes over every link is the same both ways.
    void ReciprocalScale(const std::vector<double> &target, int &steps, double &error) {
        std::vector<double> d(n_, 1.0), x, y(n_);
        gathered_.assign(n_, 0);
        for (steps = 0;; ++steps) {
            x = d;
            Multiply(x, y);
            error = 0;
            for (uint32_t e = 0; e < n_; ++e)
                if (forest_[e].firstChild == kNoChildren && target[e] > 0 && y[e] > 0)
                    error = std::max(error, std::abs(d[e] * y[e] / target[e] - 1));
            if (error < kReciprocalTolerance || steps >= kReciprocalSteps)
                break;
            for (uint32_t e = 0; e < n_; ++e)
                if (forest_[e].firstChild == kNoChildren && target[e] > 0 && y[e] > 0)
                    d[e] = std::sqrt(d[e] * target[e] / y[e]);
        }
        scale_ = d;
        emit_ = std::move(d);
    }

    static constexpr double kReciprocalTolerance = 1e-10;
    static constexpr int kReciprocalSteps = 1000;

    // Iterates until the residual is below the tolerance; LimitError after
    // options.maxIterations sweeps, or if the radiosity overflows.
    void Run(const SolveOptions &options, SolveResult &result) {
        radiosity_ = emission_;  // the pulled means of E are E: it is uniform per root
        std::vector<double> next(n_), sentNext;
        if (!emit_.empty()) {  // what the elements send: d B at the leaves, pulled
            sent_.resize(n_), sentNext.resize(n_);
            for (uint32_t e = 0; e < n_; ++e)
                sent_[e] = emit_[e] * emission_[e];
            for (size_t r = 0; r < forest_.NumRoots(); ++r)
                Pull(r, sent_);
        }
        gathered_.assign(n_, 0), irradiance_.assign(n_, 0);
        bool jacobi = options.method == SolveMethod::Jacobi;
        for (int k = 1;; ++k) {
            double change = 0, largest = 0;
            std::vector<double> &out = jacobi ? next : radiosity_;
            std::vector<double> &sentOut = jacobi ? sentNext : sent_;
            const std::vector<double> &source = emit_.empty() ? radiosity_ : sent_;
            // The cluster links first, from the radiosity of the sweep before, either method.
            if (clusters_)
                clusters_->Gather(source, clusterIrradiance_);
            for (size_t r = 0; r < forest_.NumRoots(); ++r) {
                Gather(r, source);
                if (!jacobi)
                    PushPull(r, out, sentOut, change, largest);
            }
            if (jacobi) {
                for (size_t r = 0; r < forest_.NumRoots(); ++r)
                    PushPull(r, out, sentOut, change, largest);
                radiosity_.swap(next);
                sent_.swap(sentNext);
            }
            result.iterations = k;
            result.residual = largest > 0 ? change / largest : 0;
            if (!std::isfinite(result.residual))
                throw LimitError("solve diverged after " + std::to_string(k) +
                                 " iterations (residual " + Short(result.residual) + ")");
            if (result.residual < options.tolerance)
                break;
            if (k >= options.maxIterations)
                throw LimitError("solve did not converge in " + std::to_string(k) +
                                 " iterations (residual " + Short(result.residual) +
                                 "); raise --max-iterations or --tolerance");
        }
        Collect(result);
    }

  private:
    struct HalfLink {
        uint32_t to, from;  // the gathering element and the one it gathers from
        double coefficient;
    };

    // Gathering for root patch _r_: each element sums F B over its half-links, B read
    // from _source_ by id.
    void Gather(size_t r, const std::vector<double> &source) {
        for (size_t k = treeStart_[r]; k < treeStart_[r + 1]; ++k)
            gathered_[order_[k]] = 0;
        for (size_t h = start_[r]; h < start_[r + 1]; ++h)
            gathered_[half_[h].to] += half_[h].coefficient * source[half_[h].from];
        if (clusters_)  // the root's element id is its patch index
            gathered_[r] += clusterIrradiance_[r];
    }

    // Every inner element of root patch _r_'s tree takes the area-weighted mean of its
    // children's _values_.
    void Pull(size_t r, std::vector<double> &values) const {
        for (size_t k = treeStart_[r + 1]; k-- > treeStart_[r];) {
            uint32_t e = order_[k];
            uint32_t first = forest_[e].firstChild;
            if (first == kNoChildren)
                continue;
            double power = 0, area = 0;
            for (int c = 0; c < forest_.Arity(); ++c) {
                power += area_[first + c] * values[first + c];
                area += area_[first + c];
            }
            values[e] = power / area;
        }
    }

    // y = K x over the leaves, both by id: the leaves of _x_ are pulled up their trees
    // (its inner elements overwritten), gathered over every link and cluster link, and
    // pushed down, without scale.
    void Multiply(std::vector<double> &x, std::vector<double> &y) {
        for (size_t r = 0; r < forest_.NumRoots(); ++r)
            Pull(r, x);
        if (clusters_)
            clusters_->Gather(x, clusterIrradiance_);
        for (size_t r = 0; r < forest_.NumRoots(); ++r) {
            Gather(r, x);
            for (size_t k = treeStart_[r]; k < treeStart_[r + 1]; ++k) {
                uint32_t e = order_[k];
                uint32_t parent = forest_.Parent(e);
                y[e] = gathered_[e] + (parent == e ? 0 : y[parent]);
            }
        }
    }

    // Push-pull for root patch _r_ into _out_: each element's irradiance is the sum of
    // what it and its ancestors gathered, a leaf's times its consistency scale (1 with
    // --plain-gather); a leaf's radiosity is E + rho H; an inner
    // element's the area-weighted mean of its children's. Tracks the largest change of
    // a leaf's radiosity and the largest leaf radiosity.
    void PushPull(size_t r, std::vector<double> &out, std::vector<double> &sentOut, double &change,
                  double &largest) {
        for (size_t k = treeStart_[r]; k < treeStart_[r + 1]; ++k) {
            uint32_t e = order_[k];
            uint32_t parent = forest_.Parent(e);
            irradiance_[e] = gathered_[e] + (parent == e ? 0 : irradiance_[parent]);
        }
        for (size_t k = treeStart_[r + 1]; k-- > treeStart_[r];) {
            uint32_t e = order_[k];
            uint32_t first = forest_[e].firstChild;
            double b;
            if (first == kNoChildren) {
                irradiance_[e] *= scale_[e];  // a leaf: no child reads it
                b = emission_[e] + rho_[e] * irradiance_[e];
                change = std::max(change, std::abs(b - radiosity_[e]));
                largest = std::max(largest, std::abs(b));
                if (!emit_.empty())
                    sentOut[e] = emit_[e] * b;
            } else {
                double power = 0, sent = 0, area = 0;
                for (int c = 0; c < forest_.Arity(); ++c) {
                    power += area_[first + c] * out[first + c];
                    if (!emit_.empty())
                        sent += area_[first + c] * sentOut[first + c];
                    area += area_[first + c];
                }
                b = power / area;
                if (!emit_.empty())
                    sentOut[e] = sent / area;
            }
            out[e] = b;
        }
    }

    // The leaves, tree by tree in preorder, and the powers.
    void Collect(SolveResult &result) const {
        if (clusters_) {
            double all = 0, clustered = 0;
            for (uint32_t e : order_)
                all += gathered_[e] * area_[e];
            for (size_t r = 0; r < forest_.NumRoots(); ++r)
                clustered += clusterIrradiance_[r] * area_[r];
            result.clusters->transferShare = all > 0 ? clustered / all : 0;
        }
        for (uint32_t e : order_) {
            if (forest_[e].firstChild != kNoChildren)
                continue;
            result.leaves.push_back(Describe(forest_, e, radiosity_[e], irradiance_[e]));
            result.emittedPower += emission_[e] * area_[e];
            result.absorbedPower += (1 - rho_[e]) * irradiance_[e] * area_[e];
        }
    }

    const Forest<Shape> &forest_;
    size_t n_;
    std::vector<double> scale_;
    std::vector<double> emit_;  // with the reciprocal scale: each leaf's d, by id
    std::vector<double> sent_;  // with it: d B at the leaves, pulled to inner elements
    std::vector<uint32_t> order_;
    std::vector<size_t> treeStart_;
    std::vector<double> area_, rho_, emission_;
    std::vector<size_t> start_;
    std::vector<HalfLink> half_;
    std::vector<double> radiosity_, gathered_, irradiance_;
    ClusterTransfer<Shape> *clusters_;
    std::vector<double> clusterIrradiance_;  // by root patch
};

// The bytes the cluster links of _refinement_ add to the solver's; with _reciprocal_
// (the reciprocal scale may apply), also its arrays: the targets, d, the Sinkhorn
// iteration's two vectors and what the leaves send, twice (a double each per element).
template <typename Shape>
size_t ClusterBytes(const Refinement<Shape> &refinement, bool reciprocal) {
    size_t clusters = refinement.clusters.NumClusters();
    if (clusters == 0)
        return 0;
    return ClusterTransfer<Shape>::Bytes(clusters, refinement.forest.NumRoots(),
                                         refinement.clusterLinks.size()) +
           (reciprocal && !refinement.clusterLinks.empty()
                ? 6 * sizeof(double) * refinement.forest.Size()
                : 0);
}

// One solve of _refinement_'s links into _result_, in the units of _unitMaterials_: the
// coefficients, the consistency scales, the iteration and its times. With _radiosity_,
// also every element's radiosity by id.
template <typename Shape>
void SolveLinks(const Patches<Shape> &patches, const Refinement<Shape> &refinement,
                const RefineOptions &refine, const SolveOptions &options,
                const std::vector<Material> &unitMaterials, bool closed, SolveResult &result,
                std::vector<double> *radiosity) {
    Stopwatch coefficientWatch;
    // One set of occluders weighs the element links and the cluster links alike.
    std::unique_ptr<Occluders> occluders = OccludersFor(patches, refine);
    // The links' visible fractions as the refinement sampled them, where it kept them.
    const std::vector<double> *visible = refinement.visible.empty() ? nullptr : &refinement.visible;
    std::vector<LinkCoefficients> coefficients =
        ComputeCoefficients(refinement.forest, refinement.links, refine, occluders.get(),
                            &result.linkFormFactors, visible);
    std::optional<ClusterTransfer<Shape>> clusters;
    std::vector<double> clusterCoefficients;
    if (refinement.clusters.NumClusters() > 0) {
        clusters.emplace(patches, refinement.clusters, refinement.clusterLinks,
                         options.clusterTransfer, occluders.get(), refine.raysPerSide,
                         refine.threads);
        clusterCoefficients = clusters->UnitIrradiance();
        result.clusters =
            ClusterFigures{refinement.clusters.NumClusters(), refinement.clusterLinks.size(), 0,
                           clusters->Rays(), clusters->OccludedLinks()};
    }
    // With cluster links, the reciprocal scale where each leaf's exact row is known: its
    // exact form factor sum without occlusion, 1 in a closed scene. Else HSA91's
    // consistency scale (1 under occlusion), or none with --plain-gather.
    bool reciprocal = !options.plainGather && clusters && clusters->NumLinks() > 0 &&
                      (refine.visibility == VisibilityMode::None || closed);
    std::vector<double> target;
    if (reciprocal)
        target = refine.visibility == VisibilityMode::None
                     ? LeafFormFactorSums(patches, refinement.forest, refine.threads)
                     : std::vector<double>(refinement.forest.Size(), 1.0);
    std::vector<double> scale =
        options.plainGather || reciprocal
            ? std::vector<double>(refinement.forest.Size(), 1.0)
            : ConsistencyScales(patches, refinement.forest, refinement.links, coefficients, refine,
                                clusters ? &clusterCoefficients : nullptr);
    result.gather = reciprocal ? "reciprocal"
                    : options.plainGather || refine.visibility != VisibilityMode::None
                        ? "plain"
                        : "consistent";
    AddTime(result.coefficients, Elapsed(coefficientWatch));

    // Each pass solves from B = E: only the last pass's solution is reported.
    result.leaves.clear();
    result.emittedPower = result.absorbedPower = 0;
    Stopwatch solveWatch;
    {
        HierarchySolver<Shape> solver(refinement.forest, refinement.links, coefficients,
                                      std::move(scale), unitMaterials,
                                      clusters ? &*clusters : nullptr);
        if (reciprocal)
            solver.ReciprocalScale(target, result.reciprocalSteps, result.reciprocalError);
        solver.Run(options, result);
        if (radiosity)
            *radiosity = solver.Radiosity();
    }
    AddTime(result.solve, Elapsed(solveWatch));
}

}  // namespace

double EmissionUnit(const std::vector<Material> &materials) {
    double unit = 0;
    for (const Material &m : materials)
        unit = std::max(unit, m.emission);
    return unit;
}

std::vector<Material> InEmissionUnits(const std::vector<Material> &materials, double unit) {
    std::vector<Material> scaled = materials;
    for (Material &m : scaled)
        m.emission /= unit;
    return scaled;
}

void ToEmissionScale(std::vector<ElementRadiosity> &elements, double &emittedPower,
                     double &absorbedPower, double unit) {
    bool finite = std::isfinite(emittedPower *= unit) && std::isfinite(absorbedPower *= unit);
    for (ElementRadiosity &e : elements)
        finite &= std::isfinite(e.radiosity *= unit) && std::isfinite(e.irradiance *= unit);
    if (!finite)
        throw LimitError("the radiosity or a power exceeds the largest double (1.8e308) at "
                         "emission " +
                         Short(unit) + "; lower the emission");
}

namespace {

// _options_ less the _held_ bytes that an earlier bf pass's solution still holds. Only
// an explicit budget: without one, the budget is read from the free memory, which already
// excludes them. LimitError when they leave nothing of it.
RefineOptions WithoutHeld(const RefineOptions &options, size_t held) {
    RefineOptions left = options;
    if (options.memoryBudget == 0)
        return left;
    if (held >= options.memoryBudget)
        throw LimitError("the previous bf pass's solution (" + std::to_string(held) +
                         " bytes) would exceed the memory budget; raise --max-memory or eps");
    left.memoryBudget -= held;
    return left;
}

template <typename Shape>
void SolveShape(const Scene &scene, const RefineOptions &refine, const SolveOptions &options,
                const std::vector<Material> &materials, SolveResult &result) {
    const Patches<Shape> &patches = scene.Get<Shape>();
    // The solvers work in units of the largest emission (EmissionUnit); the refinement,
    // whose bf oracle compares B F with eps, reads E and B at their own scale.
    const double unit = EmissionUnit(materials);
    const std::vector<Material> unitMaterials = InEmissionUnits(materials, unit);
    RefineOptions storing = refine;
    storing.storeLinks = true;
    // The first pass reads E after the overrides: the bf oracle would read the scene's.
    std::vector<double> emission;
    for (const Material &m : materials)
        emission.push_back(m.emission);
    std::optional<RadiosityEstimate<Shape>> estimate(std::in_place, std::move(emission));
    bool bf = refine.oracle == "bf";
    // Whether the reciprocal scale may take every leaf's row to 1 under occlusion.
    const bool closed = refine.clusters && !options.plainGather &&
                        refine.visibility != VisibilityMode::None && IsClosed(scene);
    int passes = bf ? options.passes.value_or(kDefaultPasses) : 1;
    double kernelSeconds = 0, kernelCpuSeconds = 0;

    for (int pass = 1;; ++pass) {
        // The estimate, with the previous pass's forest, stays in memory all pass long.
        RefineOptions passOptions = WithoutHeld(storing, bf ? estimate->Bytes() : 0);
        if (bf)
            passOptions.estimate = &*estimate;
        Stopwatch refineWatch;
        Refinement<Shape> refinement = Refine<Shape>(scene, passOptions);
        AddTime(result.refine, Elapsed(refineWatch));
        kernelSeconds += refinement.record.seconds;
        result.record = refinement.record;
        kernelCpuSeconds += refinement.record.cpuSeconds;
        result.record.seconds = kernelSeconds;
        result.record.cpuSeconds = kernelCpuSeconds;
        result.passes = pass;
        const Counters &counters = refinement.record.counters;
        // Same links and nodes as the pass before: B has settled as far as bf can tell.
        bool last = pass >= passes || (pass > 1 && counters.links == result.passLinks.back() &&
                                       counters.nodes == result.passNodes.back());
        result.passLinks.push_back(counters.links);
        result.passNodes.push_back(counters.nodes);

        // The solver's arrays within what the budget leaves after the refinement.
        size_t links = refinement.links.size(), elements = refinement.forest.Size();
        size_t used = passOptions.memoryBudget > 0
                          ? links * StoredLinkBytes(passOptions) +
                                elements * Forest<Shape>::kBytesPerElement +
                                refinement.pairs.capacity() * sizeof(PairTally)
                          : 0;
        size_t budget = EffectiveBudget(passOptions);
        if (HierarchySolver<Shape>::Bytes(links, elements) +
                ClusterBytes(refinement, !options.plainGather) >
            budget - std::min(budget, used))
            throw LimitError("solving " + std::to_string(links) + " links and " +
                             std::to_string(elements) +
                             " elements would exceed the memory budget; raise --max-memory or "
                             "eps");

        std::vector<double> radiosity;
        SolveLinks(patches, refinement, refine, options, unitMaterials, closed, result,
                   last ? nullptr : &radiosity);
        for (double &b : radiosity)
            b *= unit;

        if (!last) {
            // The next pass reads this solution; the refinement it was read by is done.
            estimate.emplace(std::move(refinement.forest), std::move(radiosity));
            continue;
        }
        estimate.reset();  // no longer read: free it before the dense reference
        if (options.referenceDepth >= 0) {
            result.reference =
                SolveReference(patches, options.referenceDepth, refine, unitMaterials);
            result.comparison = Compare(refinement.forest, result, *result.reference);
            UniformSolution &ref = *result.reference;
            ToEmissionScale(ref.elements, ref.emittedPower, ref.absorbedPower, unit);
        }
        ToEmissionScale(result.leaves, result.emittedPower, result.absorbedPower, unit);
        break;
    }
}

}  // namespace

const std::vector<SolveMethodInfo> &SolveMethods() {
    static const std::vector<SolveMethodInfo> methods = {
        {"jacobi", "every sweep gathers from the previous sweep's radiosity", SolveMethod::Jacobi},
        {"gauss-seidel", "root patch by root patch, each gathering the latest radiosity",
         SolveMethod::GaussSeidel},
    };
    return methods;
}

SolveMethod ParseSolveMethod(const std::string &name) {
    return FindNamed(SolveMethods(), name, "solve method").method;
}

std::string SolveMethodName(SolveMethod method) {
    return NameOf(SolveMethods(), &SolveMethodInfo::method, method);
}

const std::vector<ClusterTransferInfo> &ClusterTransfers() {
    static const std::vector<ClusterTransferInfo> transfers = {
        {"projected", "a cluster end's projected area, tabled over directions",
         ClusterTransferKind::Projected},
        {"isotropic", "Sillion's: a cluster's patches face every way alike",
         ClusterTransferKind::Isotropic},
    };
    return transfers;
}

ClusterTransferKind ParseClusterTransfer(const std::string &name) {
    return FindNamed(ClusterTransfers(), name, "cluster transfer").kind;
}

std::string ClusterTransferName(ClusterTransferKind kind) {
    return NameOf(ClusterTransfers(), &ClusterTransferInfo::kind, kind);
}

void ValidateSolveOptions(const SolveOptions &o) {
    if (!(o.tolerance > 0 && o.tolerance < 1))
        throw InputError("--tolerance must be a number in (0, 1), not " +
                         FormatDouble(o.tolerance));
    if (o.maxIterations < 1 || o.maxIterations > 1000000)
        throw InputError("--max-iterations must be between 1 and 1000000");
    if (o.emission && !(*o.emission >= 0 && std::isfinite(*o.emission)))
        throw InputError("--emission must be a finite number >= 0, not " +
                         FormatDouble(*o.emission));
    if (o.reflectance && !(*o.reflectance >= 0 && *o.reflectance < 1))
        throw InputError("--reflectance must be a number in [0, 1), not " +
                         FormatDouble(*o.reflectance));
    if (o.passes && (*o.passes < 1 || *o.passes > kMaxPasses))
        throw InputError("--passes must be between 1 and " + std::to_string(kMaxPasses));
}

std::vector<Material> SolveMaterials(const Scene &scene, const SolveOptions &options) {
    std::vector<Material> materials = std::visit(
        [](const auto &patches) {
            std::vector<Material> m;
            for (const auto &patch : patches)
                m.push_back(patch.material);
            return m;
        },
        scene.patches);
    bool emits = false;
    for (Material &m : materials) {
        m.emission = options.emission.value_or(m.emission);
        m.reflectance = options.reflectance.value_or(m.reflectance);
        emits |= m.emission > 0;
    }
    if (!emits)
        throw InputError("nothing emits: give --emission or a scene with an emitter");
    return materials;
}

SolveResult Solve(const Scene &scene, const RefineOptions &refine, const SolveOptions &options) {
    ValidateSolveOptions(options);
    ValidateScene(scene);
    ValidateOptions(refine, scene.Dimension());
    if (options.passes && refine.oracle != "bf")
        throw InputError("--passes applies to the bf oracle only: the " + refine.oracle +
                         " oracle does not read a radiosity, so one refinement is final");
    std::vector<Material> materials = SolveMaterials(scene, options);
    if (options.referenceDepth >= 0)
        CheckReferenceSize(scene, options.referenceDepth, refine);
    SolveResult result;
    result.materials = materials;
    std::visit(
        [&](const auto &patches) {
            using Shape = std::decay_t<decltype(patches.front().shape)>;
            SolveShape<Shape>(scene, refine, options, materials, result);
        },
        scene.patches);
    result.energyWarning = EnergyBalanceWarning(scene, refine, result);
    return result;
}

template <typename Shape>
SolveResult SolveRefinement(const Scene &scene, const Refinement<Shape> &refinement,
                            const RefineOptions &refine, const SolveOptions &options) {
    ValidateSolveOptions(options);
    ValidateScene(scene);
    SolveResult result;
    result.materials = SolveMaterials(scene, options);
    result.record = refinement.record;
    result.passes = 1;
    result.passLinks = {refinement.record.counters.links};
    result.passNodes = {refinement.record.counters.nodes};
    const double unit = EmissionUnit(result.materials);
    bool closed = refinement.clusterLinks.size() > 0 && !options.plainGather &&
                  refine.visibility != VisibilityMode::None && IsClosed(scene);
    SolveLinks(scene.Get<Shape>(), refinement, refine, options,
               InEmissionUnits(result.materials, unit), closed, result, nullptr);
    ToEmissionScale(result.leaves, result.emittedPower, result.absorbedPower, unit);
    result.energyWarning = EnergyBalanceWarning(scene, refine, result);
    return result;
}

template SolveResult SolveRefinement(const Scene &, const Refinement<Segment> &,
                                     const RefineOptions &, const SolveOptions &);
template SolveResult SolveRefinement(const Scene &, const Refinement<Polygon> &,
                                     const RefineOptions &, const SolveOptions &);

VisibilityMode DefaultSolveVisibility(const Scene &scene) {
    return CanOcclude(scene) ? VisibilityMode::Fraction : VisibilityMode::None;
}

std::string EnergyBalanceWarning(const Scene &scene, const RefineOptions &refine,
                                 const SolveResult &result) {
    double excess = result.absorbedPower - result.emittedPower;
    char change[32];
    std::snprintf(change, sizeof change, "%+.3g%%", 100 * excess / result.emittedPower);
    std::string powers = "absorbed power " + Short(result.absorbedPower) +
                         " against emitted power " + Short(result.emittedPower) + " (" + change +
                         ")";
    // Light let through an occluder is light absorbed twice, an excess: the balance is
    // quoted as its sign shows it, or as not showing it, never against the reason.
    if (refine.visibility == VisibilityMode::None && CanOcclude(scene))
        return "--visibility none lets light pass through the patches between others, which "
               "this scene has (without --visibility, solve weighs each link by its visible "
               "fraction; docs/solve.md, Occlusion)" +
               (excess > 0 ? ": " + powers + ", light let through among it"
                           : "; the energy balance alone does not show it here (" + powers +
                                 ": the discretisation's error outweighs it)");
    if (!(excess > kEnergyExcessAllowance * result.emittedPower))
        return "";
    return powers + ", beyond the " + Short(100 * kEnergyExcessAllowance) +
           "% a discretisation may account for: refine further (a smaller eps or --min-area" +
           (refine.visibility != VisibilityMode::None ? ", more --rays-per-side" : "") +
           "; docs/solve.md, Energy balance)";
}

}  // namespace hrbench
