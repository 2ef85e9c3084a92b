// ComputeCoefficients: the form factor and visible fraction of every stored link;
// ConsistencyScales: what makes each leaf's coefficients sum to its exact form factor.
#include "link_coefficients.h"

#include "hrbench/util/parallel_for.h"

namespace hrbench {

template <typename Shape>
std::vector<LinkCoefficients>
ComputeCoefficients(const Patches<Shape> &patches, const Forest<Shape> &forest,
                    const LinkBuffer &links, const RefineOptions &options) {
    std::vector<LinkCoefficients> coefficients(links.size());
    std::unique_ptr<Occluders> occluders = OccludersFor(patches, options);
    std::vector<Shape> shapes = forest.AllShapes();
    ParallelFor(
        links.size(), 256, options.threads,
        [&] { return PairCoefficients<Shape>(shapes, occluders.get(), options); },
        [&](PairCoefficients<Shape> &pair, size_t k) {
            uint32_t i = links[k].i, j = links[k].j;
            coefficients[k] = pair(forest, i, j, pair.Visible(forest, i, j));
        });
    return coefficients;
}

template <typename Shape>
std::vector<double> ConsistencyScales(const Patches<Shape> &patches, const Forest<Shape> &forest,
                                      const LinkBuffer &links,
                                      const std::vector<LinkCoefficients> &coefficients,
                                      const RefineOptions &options) {
    size_t n = forest.Size();
    std::vector<double> scale(n, 1.0);
    if (options.visibility != VisibilityMode::None)
        return scale;
    // What each element gathers per unit radiosity, then down each chain: an element's
    // children come after it, so a pass in id order sees every parent first.
    std::vector<double> chain(n, 0.0);
    for (size_t k = 0; k < links.size(); ++k)
        chain[links[k].i] += coefficients[k].ij, chain[links[k].j] += coefficients[k].ji;
    for (uint32_t e = 0; e < n; ++e)
        if (forest.Parent(e) != e)
            chain[e] += chain[forest.Parent(e)];
    ParallelFor(
        n, 64, options.threads, [] { return 0; },
        [&](int, size_t k) {
            uint32_t e = uint32_t(k);
            if (forest[e].firstChild != kNoChildren || !(chain[e] > 0))
                return;
            Shape shape = forest.ShapeOf(e);  // made down from the root: once, not per patch
            double exact = 0;
            for (size_t r = 0; r < patches.size(); ++r)
                if (r != forest[e].root)
                    exact += FormFactor(shape, patches[r].shape);
            scale[e] = exact / chain[e];
        });
    return scale;
}

template std::vector<double> ConsistencyScales(const Patches<Segment> &, const Forest<Segment> &,
                                               const LinkBuffer &,
                                               const std::vector<LinkCoefficients> &,
                                               const RefineOptions &);
template std::vector<double> ConsistencyScales(const Patches<Polygon> &, const Forest<Polygon> &,
                                               const LinkBuffer &,
                                               const std::vector<LinkCoefficients> &,
                                               const RefineOptions &);

template std::vector<LinkCoefficients> ComputeCoefficients(const Patches<Segment> &,
                                                           const Forest<Segment> &,
                                                           const LinkBuffer &,
                                                           const RefineOptions &);
template std::vector<LinkCoefficients> ComputeCoefficients(const Patches<Polygon> &,
                                                           const Forest<Polygon> &,
                                                           const LinkBuffer &,
                                                           const RefineOptions &);

}  // namespace hrbench
