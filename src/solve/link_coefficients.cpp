// ComputeCoefficients: the form factor and visible fraction of every stored link;
// MeasureLinkFormFactors: the links' exact form factors alone (run --link-form-factors);
// ConsistencyScales: what makes each leaf's coefficients sum to its exact form factor.
#include "link_coefficients.h"

#include <algorithm>
#include <atomic>
#include <stdexcept>
#include <string>

#include "hrbench/util/error.h"
#include "util/parallel_for.h"

namespace hrbench {

namespace {

// Runs body(pair, k) for every link k on options.threads threads, each worker with its
// own PairCoefficients, and takes the exact form factors both ways that each call
// returns into the LinkFormFactors against options.eps. The largest value and the count
// above eps do not depend on which worker saw which link, nor on the order.
template <typename Shape, typename Body>
LinkFormFactors ForEachLink(const std::vector<Shape> &shapes, const Occluders *occluders,
                            const LinkBuffer &links, const RefineOptions &options, Body body) {
    struct Tally {
        double max = 0;
        uint64_t above = 0;
    };
    struct Worker {
        PairCoefficients<Shape> pair;
        Tally *tally;
    };
    // One tally per worker, handed out as the workers start (at most options.threads).
    std::vector<Tally> tallies(size_t(std::max(1, options.threads)));
    std::atomic<size_t> started{0};
    ParallelFor(
        links.size(), 256, options.threads,
        [&] {
            return Worker{PairCoefficients<Shape>(shapes, occluders, options), &tallies[started++]};
        },
        [&](Worker &worker, size_t k) {
            LinkCoefficients exact = body(worker.pair, k);
            double larger = std::max(exact.ij, exact.ji);
            worker.tally->max = std::max(worker.tally->max, larger);
            worker.tally->above += larger > options.eps;
        });
    LinkFormFactors result;
    uint64_t above = 0;
    for (const Tally &t : tallies)
        result.max = std::max(result.max, t.max), above += t.above;
    result.aboveEps = links.size() > 0 ? double(above) / double(links.size()) : 0;
    return result;
}

template <typename Shape>
LinkFormFactors MeasureOf(const Refinement<Shape> &refinement, const RefineOptions &options) {
    const Forest<Shape> &forest = refinement.forest;
    const LinkBuffer &links = refinement.links;
    // The shapes beside the refinement, within the budget it was given (without
    // --max-memory the budget is read from the free memory, which excludes the refinement).
    size_t used = options.memoryBudget > 0 ? links.size() * StoredLinkBytes(options) +
                                                 forest.Size() * Forest<Shape>::kBytesPerElement
                                           : 0;
    size_t budget = EffectiveBudget(options);
    if (forest.Size() * sizeof(Shape) > budget - std::min(budget, used))
        throw LimitError("the form factors of " + std::to_string(links.size()) +
                         " links would exceed the memory budget; raise --max-memory or eps");
    std::vector<Shape> shapes = forest.AllShapes();
    return ForEachLink(shapes, nullptr, links, options,
                       [&](PairCoefficients<Shape> &pair, size_t k) {
                           uint32_t i = links[k].i, j = links[k].j;
                           return pair.Weighted(forest, i, j, pair.FormFactorOf(i, j), 1.0);
                       });
}

}  // namespace

template <typename Shape>
std::vector<LinkCoefficients>
ComputeCoefficients(const Forest<Shape> &forest, const LinkBuffer &links,
                    const RefineOptions &options, const Occluders *occluders,
                    LinkFormFactors *formFactors, const std::vector<double> *visible) {
    if (visible && visible->size() != links.size())
        throw std::logic_error("ComputeCoefficients: a visible fraction per link, or none");
    std::vector<LinkCoefficients> coefficients(links.size());
    std::vector<Shape> shapes = forest.AllShapes();
    LinkFormFactors measured = ForEachLink(
        shapes, occluders, links, options, [&](PairCoefficients<Shape> &pair, size_t k) {
            uint32_t i = links[k].i, j = links[k].j;
            double ij = pair.FormFactorOf(i, j);
            double v = visible ? (*visible)[k] : pair.Visible(forest, i, j);
            coefficients[k] = pair.Weighted(forest, i, j, ij, v);
            return pair.Weighted(forest, i, j, ij, 1.0);
        });
    if (formFactors)
        *formFactors = measured;
    return coefficients;
}

LinkFormFactors MeasureLinkFormFactors(const AnyRefinement &refinement,
                                       const RefineOptions &options) {
    return std::visit([&](const auto &r) { return MeasureOf(r, options); }, refinement);
}

template <typename Shape>
std::vector<double>
ConsistencyScales(const Patches<Shape> &patches, const Forest<Shape> &forest,
                  const LinkBuffer &links, const std::vector<LinkCoefficients> &coefficients,
                  const RefineOptions &options, const std::vector<double> *rootCoefficients) {
    size_t n = forest.Size();
    std::vector<double> scale(n, 1.0);
    if (options.visibility != VisibilityMode::None)
        return scale;
    // What each element gathers per unit radiosity, then down each chain: an element's
    // children come after it, so a pass in id order sees every parent first.
    std::vector<double> chain(n, 0.0);
    for (size_t k = 0; k < links.size(); ++k)
        chain[links[k].i] += coefficients[k].ij, chain[links[k].j] += coefficients[k].ji;
    if (rootCoefficients)  // the roots are the first ids, in scene order
        for (size_t r = 0; r < rootCoefficients->size(); ++r)
            chain[r] += (*rootCoefficients)[r];
    for (uint32_t e = 0; e < n; ++e)
        if (forest.Parent(e) != e)
            chain[e] += chain[forest.Parent(e)];
    std::vector<char> wanted(n);
    for (uint32_t e = 0; e < n; ++e)
        wanted[e] = chain[e] > 0;
    std::vector<double> exact = LeafFormFactorSums(patches, forest, options.threads, &wanted);
    for (uint32_t e = 0; e < n; ++e)
        if (forest[e].firstChild == kNoChildren && chain[e] > 0)
            scale[e] = exact[e] / chain[e];
    return scale;
}

template <typename Shape>
std::vector<double> LeafFormFactorSums(const Patches<Shape> &patches, const Forest<Shape> &forest,
                                       int threads, const std::vector<char> *wanted) {
    size_t n = forest.Size();
    std::vector<double> sums(n, 0.0);
    ParallelFor(
        n, 64, threads, [] { return 0; },
        [&](int, size_t k) {
            uint32_t e = uint32_t(k);
            if (forest[e].firstChild != kNoChildren || (wanted && !(*wanted)[e]))
                return;
            Shape shape = forest.ShapeOf(e);  // made down from the root: once, not per patch
            double exact = 0;
            for (size_t r = 0; r < patches.size(); ++r)
                if (r != forest[e].root)
                    exact += FormFactor(shape, patches[r].shape);
            sums[e] = exact;
        });
    return sums;
}

template std::vector<double> LeafFormFactorSums(const Patches<Segment> &, const Forest<Segment> &,
                                                int, const std::vector<char> *);
template std::vector<double> LeafFormFactorSums(const Patches<Polygon> &, const Forest<Polygon> &,
                                                int, const std::vector<char> *);

template std::vector<double> ConsistencyScales(const Patches<Segment> &, const Forest<Segment> &,
                                               const LinkBuffer &,
                                               const std::vector<LinkCoefficients> &,
                                               const RefineOptions &, const std::vector<double> *);
template std::vector<double> ConsistencyScales(const Patches<Polygon> &, const Forest<Polygon> &,
                                               const LinkBuffer &,
                                               const std::vector<LinkCoefficients> &,
                                               const RefineOptions &, const std::vector<double> *);

template std::vector<LinkCoefficients>
ComputeCoefficients(const Forest<Segment> &, const LinkBuffer &, const RefineOptions &,
                    const Occluders *, LinkFormFactors *, const std::vector<double> *);
template std::vector<LinkCoefficients>
ComputeCoefficients(const Forest<Polygon> &, const LinkBuffer &, const RefineOptions &,
                    const Occluders *, LinkFormFactors *, const std::vector<double> *);

}  // namespace hrbench
