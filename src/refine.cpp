#include "refine.h"

#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <cmath>
#include <exception>
#include <fstream>
#include <numeric>
#include <string>
#include <thread>

#include "culling.h"
#include "oracles.h"
#include "oracles3d.h"
#include "util/error.h"

namespace hrbench {

namespace {

// Pairs whose depths add up to this are handed to the worker threads as tasks.
// A constant, not a function of the thread count, so that the task list (and with
// it the order of links) is the same for every thread count.
constexpr int kTaskDepth = 10;

// A pending ProjectKernel call.
struct Call {
    uint32_t i, j;
    int32_t depthI, depthJ;
};

// A subtree of the refinement left to a worker, with the root pair it belongs to.
struct Task {
    Call call;
    uint32_t pair;
};

// What one kernel instance counted.
struct Tally {
    uint64_t oracleCalls = 0, links = 0, forcedLinks = 0;
    VisibilityTally visibility;
    std::array<uint64_t, 2 * kSafetyDepth + 1> linksPerDepth{};

    void Add(const Tally &other) {
        oracleCalls += other.oracleCalls, links += other.links, forcedLinks += other.forcedLinks;
        visibility.Add(other.visibility);
        for (size_t d = 0; d < linksPerDepth.size(); ++d)
            linksPerDepth[d] += other.linksPerDepth[d];
    }
};

// The recursion of DESIGN section 2 for one element kind, one oracle type and one
// storage mode, so that subdivision, the oracle and the link sink are inlined. It
// runs depth-first, first child first. With _kFrontier_ it stops at kTaskDepth and
// records the pairs there as tasks instead. _Visibility_ is NoVisibility (occlusion
// ignored, compiled out) or SampledVisibility (docs/3d.md).
template <typename Forest, typename Oracle, bool kStoreLinks, bool kFrontier,
          typename Visibility = NoVisibility>
class ProjectKernel {
  public:
    ProjectKernel(Forest &forest, const Oracle &oracle, const RefineOptions &options,
                  size_t maxLinks, const Visibility &visibility = Visibility())
        : forest_(forest), oracle_(oracle), visibility_(visibility), minArea_(options.minArea),
          depthLimit_(options.maxDepth >= 0 ? options.maxDepth : kSafetyDepth),
          userDepthLimit_(options.maxDepth >= 0), maxLinks_(maxLinks) {}

    // Refines _start_ completely (below the frontier), appending links to _links_
    // and frontier pairs to _tasks_.
    void Project(Call start, uint32_t pair, LinkBuffer &links, std::vector<Task> *tasks) {
        links_ = &links;
        tasks_ = tasks;
        pair_ = pair;
        Recurse(start.i, start.j, start.depthI, start.depthJ);
    }

    Tally tally;

  private:
    // One ProjectKernel call. Plain recursion with scalar arguments: measured with
    // fewer instructions per call than an explicit stack, a packed argument struct,
    // or a separate function for rejected pairs.
    void Recurse(uint32_t i, uint32_t j, int depthI, int depthJ) {
        if constexpr (kFrontier) {
            if (depthI + depthJ >= kTaskDepth)
                return tasks_->push_back({{i, j, depthI, depthJ}, pair_});
        }
        ++tally.oracleCalls;
        const auto &ei = forest_[i], &ej = forest_[j];
        if constexpr (Visibility::kEnabled) {
            // Estimate the visible fraction: drop occluded pairs, weight or refine partial ones.
            double visible = visibility_.Fraction(forest_, i, j, tally.visibility);
            if (visible == 0) {
                ++tally.visibility.occludedPairs;
                return;
            }
            bool acceptable = visible == 1 ? oracle_.Acceptable(ei, ej)
                              : visibility_.Mode() == VisibilityMode::Fraction
                                  ? oracle_.AcceptableVisible(ei, ej, visible)
                                  : false;  // refine: partially visible pairs go to the limit
            if (acceptable)
                return AddLink(i, j, depthI + depthJ);
        } else {
            if (oracle_.Acceptable(ei, ej))
                return AddLink(i, j, depthI + depthJ);
        }

        // Pick the larger element (ties: the first) and apply the recursion limit to it.
        bool splitI = ei.size >= ej.size;
        double preferredSize = splitI ? ei.size : ej.size;
        int preferredDepth = splitI ? depthI : depthJ;
        if (preferredSize < minArea_ || preferredDepth >= depthLimit_) {
            if (!userDepthLimit_ && preferredDepth >= depthLimit_)
                ThrowSafetyCap(i, j);
            ++tally.forcedLinks;
            return AddLink(i, j, depthI + depthJ);
        }

        // Recurse into the children of the preferred element, first child first.
        if (splitI) {
            uint32_t child = forest_.Children(i);
            for (int c = 0; c < Forest::kArity; ++c)
                Recurse(child + c, j, depthI + 1, depthJ);
        } else {
            uint32_t child = forest_.Children(j);
            for (int c = 0; c < Forest::kArity; ++c)
                Recurse(i, child + c, depthI, depthJ + 1);
        }
    }

    void AddLink(uint32_t i, uint32_t j, int depth) {
        ++tally.links;
        ++tally.linksPerDepth[depth];
        if constexpr (kStoreLinks) {
            if (links_->size() == links_->capacity())
                GrowLinks();
            links_->Append({i, j});
        }
    }

    // Doubles the link buffer, within the budget. Out of line: it runs log(L) times.
    [[gnu::noinline]] void GrowLinks() {
        size_t capacity = std::max<size_t>(2 * links_->capacity(), 1 << 16);
        if (capacity > maxLinks_)
            throw LimitError("stored links would exceed the memory budget (" +
                             std::to_string(links_->size()) +
                             " links); use --count-only, a larger eps or --max-memory");
        links_->Reserve(capacity);
    }

    [[noreturn]] void ThrowSafetyCap(uint32_t i, uint32_t j) const {
        throw LimitError("refinement of patches " + std::to_string(forest_[i].root) +
                         " and " + std::to_string(forest_[j].root) +
                         " reached the safety depth " + std::to_string(kSafetyDepth) +
                         " without an acceptable link; set a recursion limit with --min-area "
                         "or --max-depth");
    }

    Forest &forest_;
    const Oracle oracle_;
    Visibility visibility_;
    const double minArea_;
    const int depthLimit_;
    const bool userDepthLimit_;
    const size_t maxLinks_;
    LinkBuffer *links_ = nullptr;
    std::vector<Task> *tasks_ = nullptr;
    uint32_t pair_ = 0;
};

// Builds the canonical forest, the union of the workers' forests (DESIGN: children
// are created once), and for each worker the map from its element ids to canonical ids.
template <typename Forest, typename Merged = Forest>
class ForestUnion {
  public:
    ForestUnion(const std::vector<Forest> &workers, Merged &canonical, bool buildMaps)
        : workers_(workers), canonical_(canonical), scratch_(kSafetyDepth + 2) {
        if (buildMaps)
            for (const Forest &w : workers)
                maps_.emplace_back(w.Size(), UINT32_MAX);
        for (auto &level : scratch_)
            level.resize(workers.size());
        for (uint32_t root = 0; root < canonical.NumRoots(); ++root) {
            std::fill(scratch_[0].begin(), scratch_[0].end(), root);
            Visit(root, 0);
        }
    }

    uint32_t Canonical(size_t worker, uint32_t local) const { return maps_[worker][local]; }

  private:
    static constexpr uint32_t kAbsent = UINT32_MAX;

    // _scratch_[level] holds the element's id in each worker's forest, or kAbsent.
    void Visit(uint32_t id, int level) {
        const std::vector<uint32_t> &local = scratch_[level];
        bool subdivided = false;
        for (size_t w = 0; w < workers_.size(); ++w) {
            if (local[w] == kAbsent)
                continue;
            if (!maps_.empty())
                maps_[w][local[w]] = id;
            subdivided |= workers_[w][local[w]].firstChild != kNoChildren;
        }
        if (!subdivided)
            return;
        uint32_t child = canonical_.Children(id);
        for (int c = 0; c < Forest::kArity; ++c) {
            for (size_t w = 0; w < workers_.size(); ++w) {
                uint32_t first = local[w] == kAbsent ? kNoChildren : workers_[w][local[w]].firstChild;
                scratch_[level + 1][w] = first == kNoChildren ? kAbsent : first + c;
            }
            Visit(child + c, level + 1);
        }
    }

    const std::vector<Forest> &workers_;
    Merged &canonical_;
    std::vector<std::vector<uint32_t>> scratch_;
    std::vector<std::vector<uint32_t>> maps_;
};

// The forest a refinement returns: _forest_ in 2D, _forest3d_ in 3D.
SegmentForest &MergedForest(Refinement &r, const SegmentForest &) { return r.forest; }
PolygonForest &MergedForest(Refinement &r, const PolygonForest &) { return r.forest3d; }

// Runs the kernel over all root pairs in scene order: a sequential pass down to the
// task depth, then the tasks on worker threads, each with its own copy of the trees.
template <typename Forest, typename Oracle, bool kStoreLinks, typename Visibility>
void RefineAllPairs(const Scene &scene, const Oracle &oracle, const RefineOptions &options,
                    size_t maxLinks, size_t maxElements, const Visibility &visibility,
                    Refinement &result) {
    Counters &counters = result.counters;
    Forest top(scene, maxElements);
    ProjectKernel<Forest, Oracle, kStoreLinks, true, Visibility> topKernel(top, oracle, options,
                                                                           maxLinks, visibility);
    LinkBuffer topLinks;
    std::vector<Task> tasks;

    // Classify every root pair and refine it down to the task depth.
    const uint32_t numPatches = uint32_t(scene.NumPatches());
    for (uint32_t p = 0; p < numPatches; ++p) {
        for (uint32_t q = p + 1; q < numPatches; ++q) {
            ++counters.rootPairs;
            PairRelation relation = ClassifyRootPair(scene, p, q);
            if (relation == PairRelation::Culled) {
                ++counters.culledPairs;
                continue;
            }
            if (relation == PairRelation::Touching && !options.HasRecursionLimit())
                throw InputError("patches " + std::to_string(p) + " and " + std::to_string(q) +
                                 " touch, so refinement cannot terminate; set a recursion "
                                 "limit with --min-area or --max-depth");
            Tally before = topKernel.tally;
            topKernel.Project({p, q, 0, 0}, uint32_t(result.pairs.size()), topLinks, &tasks);
            result.pairs.push_back({p, q, topKernel.tally.links - before.links,
                                    topKernel.tally.oracleCalls - before.oracleCalls});
        }
    }

    // Run the tasks: each worker takes the next task in order and refines it fully.
    size_t numWorkers = std::max<size_t>(1, std::min<size_t>(options.threads, tasks.size()));
    std::vector<Forest> forests(numWorkers, top);
    // Each worker appends its links to one buffer; a task's links are a range of it.
    // The first worker's buffer starts with the sequential pass's links, whose ids are
    // the same in every worker's forest.
    std::vector<LinkBuffer> workerLinks(kStoreLinks ? numWorkers : 0);
    if constexpr (kStoreLinks)
        workerLinks[0] = std::move(topLinks);
    std::vector<size_t> taskLinksEnd(tasks.size());
    std::vector<uint64_t> taskLinkCount(tasks.size()), taskCallCount(tasks.size());
    std::vector<size_t> taskWorker(tasks.size());
    std::vector<Tally> workerTally(numWorkers);
    std::atomic<size_t> next{0};
    std::atomic<bool> failed{false};
    std::vector<std::pair<size_t, std::exception_ptr>> errors(numWorkers, {SIZE_MAX, nullptr});
    auto work = [&](size_t w) {
        ProjectKernel<Forest, Oracle, kStoreLinks, false, Visibility> kernel(
            forests[w], oracle, options, maxLinks / numWorkers, visibility);
        LinkBuffer unused;
        LinkBuffer &links = kStoreLinks ? workerLinks[w] : unused;
        for (size_t t; !failed && (t = next++) < tasks.size();) {
            try {
                uint64_t linksBefore = kernel.tally.links, calls = kernel.tally.oracleCalls;
                kernel.Project(tasks[t].call, tasks[t].pair, links, nullptr);
                taskLinkCount[t] = kernel.tally.links - linksBefore;
                taskCallCount[t] = kernel.tally.oracleCalls - calls;
                taskLinksEnd[t] = links.size();
                taskWorker[t] = w;
            } catch (...) {
                errors[w] = {t, std::current_exception()};
                failed = true;
            }
        }
        workerTally[w] = kernel.tally;
    };
    std::vector<std::thread> threads;
    for (size_t w = 1; w < numWorkers; ++w)
        threads.emplace_back(work, w);
    work(0);
    for (std::thread &t : threads)
        t.join();

    // Report the error of the earliest failed task: every task before it has run,
    // so which error surfaces does not depend on timing.
    auto first = std::min_element(errors.begin(), errors.end(),
                                  [](const auto &a, const auto &b) { return a.first < b.first; });
    if (first->second)
        std::rethrow_exception(first->second);

    // Sum the counts: the sequential pass, then the workers.
    Tally total = topKernel.tally;
    for (const Tally &t : workerTally)
        total.Add(t);
    for (size_t t = 0; t < tasks.size(); ++t) {
        result.pairs[tasks[t].pair].links += taskLinkCount[t];
        result.pairs[tasks[t].pair].oracleCalls += taskCallCount[t];
    }
    counters.oracleCalls = total.oracleCalls;
    counters.links = total.links;
    counters.forcedLinks = total.forcedLinks;
    counters.rays = total.visibility.rays;
    counters.visibilityQueries = total.visibility.queries;
    counters.occludedPairs = total.visibility.occludedPairs;
    counters.linksPerDepth.assign(total.linksPerDepth.begin(), total.linksPerDepth.end());
    while (!counters.linksPerDepth.empty() && counters.linksPerDepth.back() == 0)
        counters.linksPerDepth.pop_back();

    // Merge the trees into canonical ids and translate the links to them.
    auto &canonical = MergedForest(result, top);
    ForestUnion<Forest, std::remove_reference_t<decltype(canonical)>> merged(forests, canonical,
                                                                             kStoreLinks);
    if constexpr (kStoreLinks) {
        if (numWorkers == 1) {
            // One worker ran every task in order: translate its buffer in place.
            for (Link &link : workerLinks[0])
                link = {merged.Canonical(0, link.i), merged.Canonical(0, link.j)};
            result.links = std::move(workerLinks[0]);
            result.links.ShrinkToFit();
            return;
        }
        // Concatenate the tasks' ranges in task order, translating each worker's ids.
        size_t total = 0;
        for (const auto &links : workerLinks)
            total += links.size();
        result.links.Reserve(total);
        size_t topCount =
            total - std::accumulate(taskLinkCount.begin(), taskLinkCount.end(), size_t(0));
        for (size_t k = 0; k < topCount; ++k) {
            const Link &link = workerLinks[0][k];
            result.links.Append({merged.Canonical(0, link.i), merged.Canonical(0, link.j)});
        }
        for (size_t t = 0; t < tasks.size(); ++t) {
            size_t w = taskWorker[t];
            for (size_t k = taskLinksEnd[t] - taskLinkCount[t]; k < taskLinksEnd[t]; ++k) {
                const Link &link = workerLinks[w][k];
                result.links.Append({merged.Canonical(w, link.i), merged.Canonical(w, link.j)});
            }
        }
    }
}

template <typename Oracle, typename Forest = SegmentForest, typename Visibility = NoVisibility>
void RefineWith(const Scene &scene, const Oracle &oracle, const RefineOptions &options,
                size_t maxLinks, size_t maxElements, Refinement &result,
                const Visibility &visibility = Visibility()) {
    if (options.storeLinks)
        RefineAllPairs<Forest, Oracle, true>(scene, oracle, options, maxLinks, maxElements,
                                             visibility, result);
    else
        RefineAllPairs<Forest, Oracle, false>(scene, oracle, options, maxLinks, maxElements,
                                              visibility, result);
}

// Chooses the visibility policy: compiled out for `none`, sampled otherwise.
template <int D, typename Forest, typename Oracle>
void RefineVisible(const Scene &scene, const Oracle &oracle, const RefineOptions &options,
                   size_t maxLinks, size_t maxElements, Refinement &result) {
    if (options.visibility == VisibilityMode::None)
        return RefineWith<Oracle, Forest>(scene, oracle, options, maxLinks, maxElements, result);
    Occluders occluders(scene);
    SampledVisibility<D> visibility(occluders, options.raysPerSide, options.visibility);
    RefineWith<Oracle, Forest>(scene, oracle, options, maxLinks, maxElements, result, visibility);
}

// Chooses the oracle of dimension _D_ (the weighted forms of oracles3d.h).
template <int D, typename Forest>
void RefineDimension(const Scene &scene, const RefineOptions &options, size_t maxLinks,
                     size_t maxElements, Refinement &result) {
    switch (options.oracle) {
    case OracleKind::Garmann:
        return RefineVisible<D, Forest>(scene, GarmannOracleND<D>(options.eps), options, maxLinks,
                                        maxElements, result);
    case OracleKind::Hanrahan: {
        std::vector<Eigen::Matrix<double, D, 1>> normals;
        for (uint32_t p = 0; p < scene.NumPatches(); ++p) {
            if constexpr (D == 3)
                normals.push_back(scene.faces[p].polygon.Normal());
            else
                normals.push_back(scene.segments[p].Normal());
        }
        return RefineVisible<D, Forest>(scene, HanrahanOracleND<D>(options.eps, std::move(normals)),
                                        options, maxLinks, maxElements, result);
    }
    }
}

// 3D scenes, and 2D scenes with visibility: the forest by dimension and subdivision,
// then the oracle and the visibility policy.
void RefineGeneral(const Scene &scene, const RefineOptions &options, size_t maxLinks,
                   size_t maxElements, Refinement &result) {
    if (scene.dimension == 2)
        return RefineDimension<2, SegmentForest>(scene, options, maxLinks, maxElements, result);
    if (options.subdivision == Subdivision::Binary)
        return RefineDimension<3, BinaryPolygonForest>(scene, options, maxLinks, maxElements,
                                                       result);
    RefineDimension<3, QuadtreePolygonForest>(scene, options, maxLinks, maxElements, result);
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
    if (o.threads < 1 || o.threads > 256)
        throw InputError("--threads must be between 1 and 256");
    if (o.raysPerSide < 1 || o.raysPerSide > 16)
        throw InputError("--rays-per-side must be between 1 and 16");
    if (o.visibility == VisibilityMode::Refine && !o.HasRecursionLimit())
        throw InputError("--visibility refine splits partially visible pairs down to the "
                         "recursion limit; set one with --min-area or --max-depth");
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

    // Split the memory budget: a quarter for the element trees (one copy per worker
    // and the merged one), the rest for links. An element costs about 100 bytes.
    size_t budget = EffectiveBudget(options);
    size_t elementBytes = sizeof(Element<2>) + 2 * sizeof(Vec2) + sizeof(uint8_t) +
                          sizeof(uint32_t) + sizeof(uint64_t);
    if (scene.dimension == 3)
        elementBytes = PolygonForest::kBytesPerElement;
    size_t forests = size_t(options.threads) + 1;
    size_t maxElements = (options.storeLinks ? budget / 4 : budget) / elementBytes / forests;
    size_t maxLinks = budget / 4 * 3 / sizeof(Link);

    Refinement result{SegmentForest(scene, SIZE_MAX), {}, {}, {}, 0};
    if (scene.dimension == 3)
        result.forest3d = PolygonForest(scene, SIZE_MAX, options.subdivision);
    else if (options.subdivision != Subdivision::Binary)
        throw InputError("--subdivision quadtree applies to 3D scenes only (segments are halved)");
    auto start = std::chrono::steady_clock::now();
    if (scene.dimension == 3 || options.visibility != VisibilityMode::None) {
        RefineGeneral(scene, options, maxLinks, maxElements, result);
    } else {
        // Flatland with occlusion ignored: the plain oracles of oracles.h.
        switch (options.oracle) {
        case OracleKind::Garmann:
            RefineWith(scene, GarmannOracle(options.eps), options, maxLinks, maxElements, result);
            break;
        case OracleKind::Hanrahan: {
            std::vector<Vec2> normals;
            for (const Segment &s : scene.segments)
                normals.push_back(s.Normal());
            RefineWith(scene, HanrahanOracle(options.eps, std::move(normals)), options, maxLinks,
                       maxElements, result);
            break;
        }
        }
    }
    result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

    // Summarise the trees.
    Counters &c = result.counters;
    bool is3d = scene.dimension == 3;
    c.nodes = is3d ? result.forest3d.Size() : result.forest.Size();
    c.leaves = is3d ? result.forest3d.NumLeaves() : result.forest.NumLeaves();
    c.nodesPerDepth = is3d ? result.forest3d.NodesPerDepth() : result.forest.NodesPerDepth();
    c.maxDepth = int(c.nodesPerDepth.size()) - 1;
    return result;
}

}  // namespace hrbench
