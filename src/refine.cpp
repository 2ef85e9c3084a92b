#include "refine.h"

#include <chrono>
#include <cmath>
#include <fstream>
#include <string>

#include "culling.h"
#include "oracles.h"
#include "util/error.h"

namespace hrbench {

namespace {

// The recursion of DESIGN section 2 for one element kind, one oracle type and one
// storage mode, so that subdivision, the oracle and the link sink are inlined.
template <typename Forest, typename Oracle, bool kStoreLinks>
class ProjectKernel {
  public:
    ProjectKernel(Forest &forest, const Oracle &oracle, const RefineOptions &options,
                  Counters &counters, std::vector<Link> &links, size_t maxLinks)
        : forest_(forest), oracle_(oracle), minArea_(options.minArea),
          depthLimit_(options.maxDepth >= 0 ? options.maxDepth : kSafetyDepth),
          userDepthLimit_(options.maxDepth >= 0), counters_(counters), links_(links),
          maxLinks_(maxLinks), linksPerDepth_(2 * kSafetyDepth + 1, 0) {}

    void Project(uint32_t i, uint32_t j, int depthI, int depthJ) {
        ++counters_.oracleCalls;
        const auto &ei = forest_[i], &ej = forest_[j];
        if (oracle_.Acceptable(ei, ej))
            return AddLink(i, j, depthI + depthJ);

        // Pick the larger element (ties: the first) and apply the recursion limit to it.
        bool splitI = ei.size >= ej.size;
        double preferredSize = splitI ? ei.size : ej.size;
        int preferredDepth = splitI ? depthI : depthJ;
        if (preferredSize < minArea_ || preferredDepth >= depthLimit_) {
            if (!userDepthLimit_ && preferredDepth >= depthLimit_)
                ThrowSafetyCap(i, j);
            ++counters_.forcedLinks;
            return AddLink(i, j, depthI + depthJ);
        }

        // Recurse into the children of the preferred element, first child first.
        if (splitI) {
            uint32_t child = forest_.Children(i);
            for (int c = 0; c < Forest::kArity; ++c)
                Project(child + c, j, depthI + 1, depthJ);
        } else {
            uint32_t child = forest_.Children(j);
            for (int c = 0; c < Forest::kArity; ++c)
                Project(i, child + c, depthI, depthJ + 1);
        }
    }

    // Moves the per-depth link histogram into the counters, trimmed.
    void Finish() {
        while (!linksPerDepth_.empty() && linksPerDepth_.back() == 0)
            linksPerDepth_.pop_back();
        counters_.linksPerDepth = std::move(linksPerDepth_);
    }

  private:
    void AddLink(uint32_t i, uint32_t j, int depth) {
        ++counters_.links;
        ++linksPerDepth_[depth];
        if constexpr (kStoreLinks) {
            if (links_.size() == links_.capacity() && 2 * links_.size() + 1 > maxLinks_)
                throw LimitError("stored links would exceed the memory budget (" +
                                 std::to_string(links_.size()) +
                                 " links); use --count-only, a larger eps or --max-memory");
            links_.push_back({i, j});
        }
    }

    [[noreturn]] void ThrowSafetyCap(uint32_t i, uint32_t j) const {
        throw LimitError("refinement of elements " + std::to_string(i) + " (patch " +
                         std::to_string(forest_[i].root) + ") and " + std::to_string(j) +
                         " (patch " + std::to_string(forest_[j].root) +
                         ") reached the safety depth " + std::to_string(kSafetyDepth) +
                         " without an acceptable link; set a recursion limit with --min-area "
                         "or --max-depth");
    }

    Forest &forest_;
    const Oracle oracle_;
    const double minArea_;
    const int depthLimit_;
    const bool userDepthLimit_;
    Counters &counters_;
    std::vector<Link> &links_;
    const size_t maxLinks_;
    std::vector<uint64_t> linksPerDepth_;
};

// Runs the kernel over all root pairs in scene order.
template <typename Oracle, bool kStoreLinks>
void RefineAllPairs(const Scene &scene, const Oracle &oracle, const RefineOptions &options,
                    size_t maxLinks, Refinement &result) {
    ProjectKernel<SegmentForest, Oracle, kStoreLinks> kernel(result.forest, oracle, options, result.counters,
                                              result.links, maxLinks);
    const auto &patches = scene.segments;
    for (uint32_t p = 0; p < patches.size(); ++p) {
        for (uint32_t q = p + 1; q < patches.size(); ++q) {
            ++result.counters.rootPairs;
            PairRelation relation = ClassifyPair(patches[p], patches[q]);
            if (relation == PairRelation::Culled) {
                ++result.counters.culledPairs;
                continue;
            }
            if (relation == PairRelation::Touching && !options.HasRecursionLimit())
                throw InputError("patches " + std::to_string(p) + " and " + std::to_string(q) +
                                 " touch, so refinement cannot terminate; set a recursion "
                                 "limit with --min-area or --max-depth");
            uint64_t links = result.counters.links, calls = result.counters.oracleCalls;
            kernel.Project(p, q, 0, 0);
            result.pairs.push_back(
                {p, q, result.counters.links - links, result.counters.oracleCalls - calls});
        }
    }
    kernel.Finish();
}

template <typename Oracle>
void RefineWith(const Scene &scene, const Oracle &oracle, const RefineOptions &options,
                size_t maxLinks, Refinement &result) {
    if (options.storeLinks)
        RefineAllPairs<Oracle, true>(scene, oracle, options, maxLinks, result);
    else
        RefineAllPairs<Oracle, false>(scene, oracle, options, maxLinks, result);
}

size_t EffectiveBudget(const RefineOptions &options) {
    return options.memoryBudget > 0 ? options.memoryBudget : AvailableMemoryBytes() / 10 * 9;
}

}  // namespace

void ValidateOptions(const RefineOptions &o) {
    if (!(o.eps > 0) || !std::isfinite(o.eps))
        throw InputError("--eps must be a finite number greater than 0");
    if (!(o.minArea >= 0) || !std::isfinite(o.minArea))
        throw InputError("--min-area must be a finite number >= 0");
    if (o.maxDepth < -1 || o.maxDepth > kSafetyDepth)
        throw InputError("--max-depth must be between 0 and " + std::to_string(kSafetyDepth));
}

size_t AvailableMemoryBytes() {
    std::ifstream meminfo("/proc/meminfo");
    std::string key;
    size_t kib = 0;
    while (meminfo >> key >> kib) {
        if (key == "MemAvailable:")
            return kib * 1024;
        meminfo.ignore(256, '\n');
    }
    return size_t(4) << 30;  // 4 GiB when the system does not say
}

Refinement Refine(const Scene &scene, const RefineOptions &options) {
    ValidateOptions(options);
    ValidateScene(scene);

    // Split the memory budget: elements cost about 100 bytes each, links 8.
    size_t budget = EffectiveBudget(options);
    size_t elementBytes = sizeof(Element<2>) + 2 * sizeof(Vec2) + sizeof(uint8_t) + sizeof(uint32_t) + sizeof(uint64_t);
    size_t maxElements = options.storeLinks ? budget / 4 / elementBytes : budget / elementBytes;
    size_t maxLinks = budget / 4 * 3 / sizeof(Link);

    Refinement result{SegmentForest(scene, maxElements), {}, {}, {}, 0};
    auto start = std::chrono::steady_clock::now();
    switch (options.oracle) {
    case OracleKind::Garmann:
        RefineWith(scene, GarmannOracle(options.eps), options, maxLinks, result);
        break;
    case OracleKind::Hanrahan: {
        std::vector<Vec2> normals;
        for (const Segment &s : scene.segments)
            normals.push_back(s.Normal());
        RefineWith(scene, HanrahanOracle(options.eps, std::move(normals)), options, maxLinks,
                   result);
        break;
    }
    }
    result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

    // Summarise the trees.
    Counters &c = result.counters;
    c.nodes = result.forest.Size();
    c.leaves = result.forest.NumLeaves();
    c.nodesPerDepth = result.forest.NodesPerDepth();
    c.maxDepth = int(c.nodesPerDepth.size()) - 1;
    return result;
}

}  // namespace hrbench
