#include "count/sweep_count.h"

#include <algorithm>
#include <numeric>
#include <variant>

#include "hrbench/forest.h"
#include "hrbench/oracles/registry.h"
#include "hrbench/util/error.h"
#include "refine/decisions.h"
#include "util/format.h"
#include "util/stopwatch.h"
#include "visibility/culling.h"
#include "visibility/visibility.h"

namespace hrbench {

namespace {

// A counter per value, kept as a difference array over the value index k (0 = the
// smallest): an event that counts at every k in [begin, end) costs two additions, and
// Values() sums them up.
class PerValue {
  public:
    explicit PerValue(size_t n = 0) : diff_(n + 1, 0) {}
    void Add(int begin, int end, uint64_t amount = 1) {
        diff_[begin] += amount;
        diff_[end] -= amount;
    }
    std::vector<uint64_t> Values() const {
        std::vector<uint64_t> values(diff_.size() - 1);
        uint64_t sum = 0;  // modulo 2^64, as the differences are
        for (size_t k = 0; k < values.size(); ++k)
            values[k] = sum += diff_[k];
        return values;
    }

  private:
    std::vector<uint64_t> diff_;
};

// What the kernel counts, per value.
struct SweepTally {
    explicit SweepTally(size_t n)
        : oracleCalls(n), links(n), forcedLinks(n), rays(n), queries(n), occludedPairs(n),
          linksPerDepth(2 * kSafetyDepth + 1, PerValue(n)) {}
    PerValue oracleCalls, links, forcedLinks, rays, queries, occludedPairs;
    std::vector<PerValue> linksPerDepth;
};

// ProjectKernel (kernel.h) at the smallest value, each pair carrying _reached_, the
// number of values (from the smallest) at which it is reached at all. Either one
// oracle per value of eps and one bound, or one oracle and one bound per --min-area.
template <typename F, typename Oracle, typename Visibility>
class SweepKernel {
  public:
    SweepKernel(F &forest, std::vector<Oracle> oracles, std::vector<double> bounds,
                const RefineOptions &options, const Visibility &visibility, SweepTally &tally)
        : forest_(forest), oracles_(std::move(oracles)), bounds_(std::move(bounds)),
          visibility_(visibility), tally_(tally), limits_(options),
          values_(int(std::max(oracles_.size(), bounds_.size()))) {}

    void Project(uint32_t p, uint32_t q) { Visit(p, q, 0, 0, values_); }

    // For each element, the number of values (from the smallest) at which it is split.
    std::vector<uint8_t> splitAt;

  private:
    void Visit(uint32_t i, uint32_t j, int depthI, int depthJ, int reached) {
        tally_.oracleCalls.Add(0, reached);
        double visible = 1;
        if constexpr (Visibility::kEnabled) {
            VisibilityTally query;
            visible = visibility_.Fraction(forest_, i, j, query);
            tally_.rays.Add(0, reached, query.rays);
            tally_.queries.Add(0, reached, query.queries);
            if (visible == 0)
                return tally_.occludedPairs.Add(0, reached);
        }
        const auto &ei = forest_[i], &ej = forest_[j];
        int accepted = FirstAccepting(ei, ej, visible, reached);
        if (accepted < reached)
            Link(depthI + depthJ, accepted, reached);

        // Rejected below _accepted_: the recursion limit of each value, as the kernel
        // applies it, splits or links by force.
        bool splitI = SplitsFirst(ei, ej);
        double preferredSizeSquared = splitI ? ei.sizeSquared : ej.sizeSquared;
        int preferredDepth = splitI ? depthI : depthJ;
        int split = accepted;
        if (split > 0 && limits_.DepthStops(preferredDepth, ei.root, ej.root))
            split = 0;
        auto belowMinArea = [&](int k) {
            return RecursionLimits::BelowMinArea(preferredSizeSquared, bounds_[k]);
        };
        if (bounds_.size() == 1)
            split = belowMinArea(0) ? 0 : split;
        else
            while (split > 0 && belowMinArea(split - 1))
                --split;
        if (split < accepted) {
            tally_.forcedLinks.Add(split, accepted);
            Link(depthI + depthJ, split, accepted);
        }
        if (split == 0)
            return;
        uint32_t parent = splitI ? i : j;
        uint32_t child = forest_.Children(parent);  // may move the arena
        if (splitAt.size() < forest_.Size())
            splitAt.resize(forest_.Size(), 0);
        splitAt[parent] = uint8_t(std::max<int>(splitAt[parent], split));
        for (int c = 0; c < forest_.Arity(); ++c) {
            if (splitI)
                Visit(child + c, j, depthI + 1, depthJ, split);
            else
                Visit(i, child + c, depthI, depthJ + 1, split);
        }
    }

    // The first value below _reached_ at which the oracle accepts the pair (_reached_
    // if none): with one oracle, it decides for all; with one per eps, acceptance is
    // monotone in eps, so bisection finds the first.
    template <typename E>
    int FirstAccepting(const E &ei, const E &ej, double visible, int reached) const {
        auto accepts = [&](int k) {
            return AcceptsVisible(oracles_[oracles_.size() == 1 ? 0 : k], visibility_, ei, ej,
                                  visible);
        };
        if (oracles_.size() == 1)
            return accepts(0) ? 0 : reached;
        int lo = 0, hi = reached;
        while (lo < hi) {
            int mid = lo + (hi - lo) / 2;
            if (accepts(mid))
                hi = mid;
            else
                lo = mid + 1;
        }
        return lo;
    }

    void Link(int depth, int begin, int end) {
        tally_.links.Add(begin, end);
        tally_.linksPerDepth[depth].Add(begin, end);
    }

    F &forest_;
    const std::vector<Oracle> oracles_;
    const std::vector<double> bounds_;  // SquaredSizeBound of --min-area, one or per value
    Visibility visibility_;
    SweepTally &tally_;
    const RecursionLimits limits_;
    const int values_;
};

// The records of each value in ascending order (_options_ per value).
template <typename Shape>
std::vector<RunRecord> Sweep(const Patches<Shape> &patches,
                             const std::vector<RefineOptions> &perValue, bool sweepsEps) {
    const RefineOptions &options = perValue[0];
    const size_t n = perValue.size();
    using F = Forest<Shape>;
    // The element budget of Refine() on one thread, which holds two forests.
    F forest(patches, EffectiveBudget(options) / F::kBytesPerElement / 2, options.subdivision);
    Counters shared;
    SweepTally tally(n);
    std::vector<uint8_t> splitAt;
    std::vector<double> bounds;
    for (size_t k = 0; k < (sweepsEps ? 1 : n); ++k)
        bounds.push_back(SquaredSizeBound(perValue[k].minArea));
    AllOracles::ForEach([&](auto tag) {
        using Oracle = typename decltype(tag)::template Type<Shape>;
        if (options.oracle != Oracle::kInfo.name)
            return;
        if constexpr (Oracle::kInfo.Supports(Shape::kDimension)) {
            std::vector<Oracle> oracles;
            for (size_t k = 0; k < (sweepsEps ? n : 1); ++k)
                oracles.push_back(MakeOracle<Oracle>(perValue[k], patches));
            WithVisibility(patches, options, [&](const auto &visibility) {
                SweepKernel<F, Oracle, std::decay_t<decltype(visibility)>> kernel(
                    forest, oracles, bounds, options, visibility, tally);
                const uint32_t numPatches = uint32_t(patches.size());
                for (uint32_t p = 0; p < numPatches; ++p) {
                    for (uint32_t q = p + 1; q < numPatches; ++q) {
                        ++shared.rootPairs;
                        PairRelation relation = ClassifyPair(patches[p].shape, patches[q].shape);
                        if (RefinesRootPair(relation, p, q, options))
                            kernel.Project(p, q);
                        else
                            ++shared.culledPairs;
                    }
                }
                splitAt = std::move(kernel.splitAt);
            });
        }
    });

    // Each split element's children, at the values where it is split.
    PerValue splitElements(n);
    std::vector<PerValue> childrenPerDepth(kSafetyDepth + 2, PerValue(n));
    for (uint32_t e = 0; e < splitAt.size(); ++e) {
        if (splitAt[e] == 0)
            continue;
        splitElements.Add(0, splitAt[e]);
        childrenPerDepth[forest.Depth(e) + 1].Add(0, splitAt[e], forest.Arity());
    }

    auto calls = tally.oracleCalls.Values(), linked = tally.links.Values();
    auto forced = tally.forcedLinks.Values(), split = splitElements.Values();
    auto rays = tally.rays.Values(), queries = tally.queries.Values();
    auto occluded = tally.occludedPairs.Values();
    std::vector<std::vector<uint64_t>> linksAt, childrenAt;
    for (const PerValue &d : tally.linksPerDepth)
        linksAt.push_back(d.Values());
    for (const PerValue &d : childrenPerDepth)
        childrenAt.push_back(d.Values());
    CountInitialLinking(shared);
    std::vector<RunRecord> records(n, RunRecord{"enumerate", shared, 0, {}, {}, 0, {}, 0});
    for (size_t k = 0; k < n; ++k) {
        (sweepsEps ? records[k].sweptEps : records[k].sweptMinArea) =
            sweepsEps ? perValue[k].eps : perValue[k].minArea;
        Counters &c = records[k].counters;
        c.oracleCalls = calls[k], c.links = linked[k], c.forcedLinks = forced[k];
        c.rays = rays[k], c.visibilityQueries = queries[k], c.occludedPairs = occluded[k];
        c.nodes = forest.NumRoots() + forest.Arity() * split[k];
        c.leaves = c.nodes - split[k];
        c.nodesPerDepth = {forest.NumRoots()};
        for (size_t d = 1; d < childrenAt.size(); ++d)
            c.nodesPerDepth.push_back(childrenAt[d][k]);
        DropTrailingZeros(c.nodesPerDepth);
        c.maxDepth = c.nodesPerDepth.size() - 1;
        for (const auto &d : linksAt)
            c.linksPerDepth.push_back(d[k]);
        DropTrailingZeros(c.linksPerDepth);
    }
    return records;
}

}  // namespace

std::vector<RunRecord> CountSweep(const Scene &scene, const RefineOptions &options,
                                  const SweepValues &sweep) {
    const std::vector<double> &values = sweep.values;
    bool sweepsEps = sweep.param == "eps";
    if (!sweepsEps && sweep.param != "min_area")
        throw InputError("--sweep varies eps or min_area, not " + sweep.param);
    if (values.empty() || values.size() > kMaxSweepValues)
        throw InputError("--sweep takes 1 to " + std::to_string(kMaxSweepValues) + " values");
    if (options.storeLinks)
        throw InputError("--sweep counts only: add --count-only");
    if (options.clusters)
        throw InputError("--sweep refines every root pair: drop --clusters");
    if (options.threads != 1)
        throw InputError("--sweep runs on one thread: drop --threads");

    // The values in ascending order, each with the options of its run.
    std::vector<size_t> order(values.size());
    std::iota(order.begin(), order.end(), 0);
    std::sort(order.begin(), order.end(),
              [&](size_t a, size_t b) { return values[a] < values[b]; });
    std::vector<RefineOptions> perValue;
    for (size_t k = 0; k < order.size(); ++k) {
        double value = values[order[k]];
        if (k > 0 && value == values[order[k - 1]])
            throw InputError("--sweep lists " + sweep.param + "=" + FormatDouble(value) + " twice");
        perValue.push_back(options);
        (sweepsEps ? perValue.back().eps : perValue.back().minArea) = value;
        ValidateOptions(perValue.back(), scene.Dimension());
        if (!sweepsEps && !(value > 0))
            throw InputError("--sweep min_area values must be greater than 0");
    }
    ValidateScene(scene);

    Stopwatch watch;
    std::vector<RunRecord> sorted = std::visit(
        [&](const auto &patches) { return Sweep(patches, perValue, sweepsEps); }, scene.patches);
    double seconds = watch.WallSeconds(), cpuSeconds = watch.CpuSeconds();
    std::vector<RunRecord> records(values.size());
    for (size_t k = 0; k < order.size(); ++k) {
        records[order[k]] = std::move(sorted[k]);
        records[order[k]].seconds = seconds / double(order.size());
        records[order[k]].cpuSeconds = cpuSeconds / double(order.size());
    }
    return records;
}

}  // namespace hrbench
