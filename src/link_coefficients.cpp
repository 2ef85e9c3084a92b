// ComputeCoefficients: the form factor and visible fraction of every stored link.
#include "link_coefficients.h"

#include "hrbench/util/parallel_for.h"

namespace hrbench {

template <typename Shape>
std::vector<LinkCoefficients>
ComputeCoefficients(const Patches<Shape> &patches, const Forest<Shape> &forest,
                    const LinkBuffer &links, const RefineOptions &options) {
    std::vector<LinkCoefficients> coefficients(links.size());
    std::unique_ptr<Occluders> occluders = OccludersFor(patches, options);
    ParallelFor(
        links.size(), 256, options.threads,
        [&] { return PairFraction<Shape>(occluders.get(), options); },
        [&](PairFraction<Shape> &fraction, size_t k) {
            uint32_t i = links[k].i, j = links[k].j;
            coefficients[k] = PairCoefficients(forest, i, j, fraction(forest, i, j));
        });
    return coefficients;
}

template std::vector<LinkCoefficients> ComputeCoefficients(const Patches<Segment> &,
                                                           const Forest<Segment> &,
                                                           const LinkBuffer &,
                                                           const RefineOptions &);
template std::vector<LinkCoefficients> ComputeCoefficients(const Patches<Polygon> &,
                                                           const Forest<Polygon> &,
                                                           const LinkBuffer &,
                                                           const RefineOptions &);

}  // namespace hrbench
