#include "hrbench/min_area_sweep.h"

#include <algorithm>
#include <chrono>
#include <numeric>
#include <string>
#include <variant>

#include "hrbench/culling.h"
#include "hrbench/forest.h"
#include "hrbench/oracles/registry.h"
#include "hrbench/util/error.h"
#include "hrbench/util/format.h"

namespace hrbench {

namespace {

// A counter per threshold, kept as a difference array over the threshold index k
// (0 = the smallest): an event that counts at every k in [begin, end) costs two
// additions, and Values() sums them up.
class PerThreshold {
  public:
    explicit PerThreshold(size_t n = 0) : diff_(n + 1, 0) {}
    void Add(int begin, int end) {
        ++diff_[begin];
        --diff_[end];
    }
    std::vector<uint64_t> Values() const {
        std::vector<uint64_t> values(diff_.size() - 1);
        int64_t sum = 0;
        for (size_t k = 0; k < values.size(); ++k)
            values[k] = uint64_t(sum += diff_[k]);
        return values;
    }

  private:
    std::vector<int64_t> diff_;
};

// What the kernel counts, per threshold.
struct SweepTally {
    explicit SweepTally(size_t n)
        : oracleCalls(n), links(n), forcedLinks(n),
          linksPerDepth(2 * kSafetyDepth + 1, PerThreshold(n)) {}
    PerThreshold oracleCalls, links, forcedLinks;
    std::vector<PerThreshold> linksPerDepth;
};

// ProjectKernel (kernel.h) at the smallest threshold, each pair carrying _reached_, the
// number of thresholds (from the smallest) at which it is reached at all.
template <typename F, typename Oracle>
class SweepKernel {
  public:
    SweepKernel(F &forest, const Oracle &oracle, const RefineOptions &options,
                const std::vector<double> &bounds, SweepTally &tally)
        : forest_(forest), oracle_(oracle), bounds_(bounds), tally_(tally),
          depthLimit_(options.maxDepth >= 0 ? options.maxDepth : kSafetyDepth),
          userDepthLimit_(options.maxDepth >= 0) {}

    void Project(uint32_t p, uint32_t q) { Visit(p, q, 0, 0, int(bounds_.size())); }

  private:
    void Visit(uint32_t i, uint32_t j, int depthI, int depthJ, int reached) {
        tally_.oracleCalls.Add(0, reached);
        const auto &ei = forest_[i], &ej = forest_[j];
        if (oracle_.Acceptable(ei, ej))
            return Link(depthI + depthJ, 0, reached);

        // The kernel's recursion limit, at every threshold: split where A^2 reaches
        // the bound, link by force above that.
        bool splitI = ei.sizeSquared >= ej.sizeSquared;
        double preferredSizeSquared = splitI ? ei.sizeSquared : ej.sizeSquared;
        int preferredDepth = splitI ? depthI : depthJ;
        int split = reached;
        if (preferredDepth >= depthLimit_) {
            if (!userDepthLimit_)
                throw LimitError("refinement of patches " + std::to_string(ei.root) + " and " +
                                 std::to_string(ej.root) + " reached the safety depth " +
                                 std::to_string(kSafetyDepth) +
                                 " without an acceptable link; set a recursion limit with "
                                 "--min-area or --max-depth");
            split = 0;
        }
        while (split > 0 && preferredSizeSquared < bounds_[split - 1])
            --split;
        if (split < reached) {
            tally_.forcedLinks.Add(split, reached);
            Link(depthI + depthJ, split, reached);
        }
        if (split == 0)
            return;
        if (splitI) {
            uint32_t child = forest_.Children(i);  // may move the arena
            for (int c = 0; c < forest_.Arity(); ++c)
                Visit(child + c, j, depthI + 1, depthJ, split);
        } else {
            uint32_t child = forest_.Children(j);
            for (int c = 0; c < forest_.Arity(); ++c)
                Visit(i, child + c, depthI, depthJ + 1, split);
        }
    }

    void Link(int depth, int begin, int end) {
        tally_.links.Add(begin, end);
        tally_.linksPerDepth[depth].Add(begin, end);
    }

    F &forest_;
    const Oracle oracle_;
    const std::vector<double> &bounds_;  // SquaredSizeBound of each threshold, ascending
    SweepTally &tally_;
    const int depthLimit_;
    const bool userDepthLimit_;
};

// Drops the trailing zeros of a histogram, as the kernel's counters do.
std::vector<uint64_t> Trimmed(std::vector<uint64_t> histogram) {
    while (!histogram.empty() && histogram.back() == 0)
        histogram.pop_back();
    return histogram;
}

template <typename Shape>
std::vector<RunRecord> Sweep(const Patches<Shape> &patches, const RefineOptions &options,
                             const std::vector<double> &bounds) {
    const size_t n = bounds.size();
    using F = Forest<Shape>;
    // The element budget of Refine() on one thread, which holds two forests.
    F forest(patches, EffectiveBudget(options) / F::kBytesPerElement / 2, options.subdivision);
    Counters shared;
    SweepTally tally(n);
    bool found = false;
    AllOracles::ForEach([&](auto tag) {
        using Oracle = typename decltype(tag)::template Type<Shape>;
        if (found || options.oracle != Oracle::kInfo.name)
            return;
        found = true;
        if constexpr (Oracle::kInfo.Supports(Shape::kDimension)) {
            SweepKernel<F, Oracle> kernel(forest, MakeOracle<Oracle>(options, patches), options,
                                          bounds, tally);
            const uint32_t numPatches = uint32_t(patches.size());
            for (uint32_t p = 0; p < numPatches; ++p) {
                for (uint32_t q = p + 1; q < numPatches; ++q) {
                    ++shared.rootPairs;
                    PairRelation relation = ClassifyPair(patches[p].shape, patches[q].shape);
                    if (relation == PairRelation::Culled)
                        ++shared.culledPairs;
                    else
                        kernel.Project(p, q);
                }
            }
        }
    });
    if (!found)
        FindOracle(options.oracle);  // throws, listing the oracles

    // An element split at the smallest threshold is split at every threshold up to
    // its size: count its children there.
    PerThreshold splitElements(n);
    std::vector<PerThreshold> childrenPerDepth(kSafetyDepth + 2, PerThreshold(n));
    for (uint32_t e = 0; e < forest.Size(); ++e) {
        if (forest[e].firstChild == kNoChildren)
            continue;
        int split = int(std::upper_bound(bounds.begin(), bounds.end(), forest[e].sizeSquared) -
                        bounds.begin());
        splitElements.Add(0, split);
        for (int c = 0; c < forest.Arity(); ++c)
            childrenPerDepth[forest.Depth(e) + 1].Add(0, split);
    }

    std::vector<RunRecord> records(n, RunRecord{"enumerate", shared, 0});
    auto calls = tally.oracleCalls.Values(), linked = tally.links.Values();
    auto forced = tally.forcedLinks.Values(), split = splitElements.Values();
    std::vector<std::vector<uint64_t>> linksAt, childrenAt;
    for (const PerThreshold &d : tally.linksPerDepth)
        linksAt.push_back(d.Values());
    for (const PerThreshold &d : childrenPerDepth)
        childrenAt.push_back(d.Values());
    for (size_t k = 0; k < n; ++k) {
        Counters &c = records[k].counters;
        c.oracleCalls = calls[k], c.links = linked[k], c.forcedLinks = forced[k];
        c.nodes = forest.NumRoots() + forest.Arity() * split[k];
        c.leaves = c.nodes - split[k];
        c.nodesPerDepth = {forest.NumRoots()};
        for (size_t d = 1; d < childrenAt.size(); ++d)
            c.nodesPerDepth.push_back(childrenAt[d][k]);
        c.nodesPerDepth = Trimmed(c.nodesPerDepth);
        c.maxDepth = c.nodesPerDepth.size() - 1;
        for (const auto &d : linksAt)
            c.linksPerDepth.push_back(d[k]);
        c.linksPerDepth = Trimmed(c.linksPerDepth);
    }
    return records;
}

}  // namespace

std::vector<RunRecord> CountMinAreaSweep(const Scene &scene, const RefineOptions &options,
                                         const std::vector<double> &minAreas) {
    if (minAreas.empty())
        throw InputError("--min-areas needs at least one value");
    if (options.storeLinks)
        throw InputError("--min-areas counts only: add --count-only");
    if (options.threads != 1)
        throw InputError("--min-areas runs on one thread: drop --threads");
    if (options.visibility != VisibilityMode::None)
        throw InputError("--min-areas does not apply with --visibility");
    for (double m : minAreas) {
        RefineOptions one = options;
        one.minArea = m;
        ValidateOptions(one, scene.Dimension());
        if (!(m > 0))
            throw InputError("--min-areas values must be greater than 0");
    }
    ValidateScene(scene);

    // The thresholds in ascending order, as the bounds the kernel compares A^2 with.
    std::vector<size_t> order(minAreas.size());
    std::iota(order.begin(), order.end(), 0);
    std::sort(order.begin(), order.end(),
              [&](size_t a, size_t b) { return minAreas[a] < minAreas[b]; });
    std::vector<double> bounds;
    for (size_t k = 0; k < order.size(); ++k) {
        if (k > 0 && minAreas[order[k]] == minAreas[order[k - 1]])
            throw InputError("--min-areas lists " + FormatDouble(minAreas[order[k]]) + " twice");
        bounds.push_back(SquaredSizeBound(minAreas[order[k]]));
    }

    auto start = std::chrono::steady_clock::now();
    std::vector<RunRecord> sorted = std::visit(
        [&](const auto &patches) { return Sweep(patches, options, bounds); }, scene.patches);
    double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    std::vector<RunRecord> records(minAreas.size());
    for (size_t k = 0; k < order.size(); ++k) {
        records[order[k]] = std::move(sorted[k]);
        records[order[k]].seconds = seconds / double(order.size());
    }
    return records;
}

}  // namespace hrbench
