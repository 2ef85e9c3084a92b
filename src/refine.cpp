#include "hrbench/refine.h"

#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <cmath>
#include <exception>
#include <numeric>
#include <optional>
#include <string>
#include <thread>

#include "cluster/traversal.h"
#include "hrbench/culling.h"
#include "refine/kernel.h"
#include "hrbench/oracles/registry.h"
#include "hrbench/translation_count.h"
#include "hrbench/util/error.h"
#include "hrbench/util/parallel_for.h"

namespace hrbench {

namespace {

// A run's memory budget in bytes, and how many elements (per forest) and links it may
// hold: SplitBudget's shares of it.
struct Budget {
    size_t bytes;
    size_t maxElements;
    size_t maxLinks;
};

// Splits _bytes_ of memory: a quarter for the element trees (one copy per worker and
// the merged one) when links are stored, the rest for links.
template <typename Shape>
Budget SplitBudget(size_t bytes, const RefineOptions &options) {
    size_t forests = size_t(options.threads) + 1;
    size_t elementBytes = Forest<Shape>::kBytesPerElement;
    return {bytes, (options.storeLinks ? bytes / 4 : bytes) / elementBytes / forests,
            bytes / 4 * 3 / sizeof(Link)};
}

// What the second pass keeps of a task: the worker that ran it, the run of sibling
// groups it made in that worker's forest (for ForestUnion), its links (their end in the
// worker's buffer, and their number) and its oracle calls.
struct TaskRecord {
    size_t worker;
    uint32_t begin, end;  // the task's elements in its worker's forest: [begin, end)
    size_t linksEnd;
    uint64_t links, oracleCalls;
};

// Grows the canonical forest, the union of the workers' forests, and maps each worker's
// element ids to canonical ones. Every worker's forest began as a copy of the sequential
// pass's forest, which the canonical one starts as too, so the ids of its elements are
// the same in all. Beyond them, each task's worker made a run of sibling groups, in the
// order of the task's recursion; replaying the runs in task order, splitting each
// parent unless an earlier task already has, makes the groups in the order one worker
// running every task would have made them (docs/conventions.md). A group new to the
// union is new to its worker too, since the worker ran only earlier tasks before it.
template <typename Forest>
class ForestUnion {
  public:
    // _splits_: each worker's Forest::SplitElements(); _tasks_: the tasks' records, in
    // task order. _canonical_ holds the sequential pass's forest and grows to the union.
    ForestUnion(const std::vector<std::vector<uint32_t>> &splits,
                const std::vector<TaskRecord> &tasks, Forest &canonical)
        : maps_(splits.size()) {
        const size_t topSize = canonical.Size();
        const uint32_t numRoots = uint32_t(canonical.NumRoots()), arity = canonical.Arity();
        // The union has at most as many elements as the workers' forests together:
        // reserve that, so that growing it copies nothing.
        size_t bound = topSize;
        for (size_t w = 0; w < splits.size(); ++w) {
            maps_[w].resize(numRoots + splits[w].size() * arity);
            std::iota(maps_[w].begin(), maps_[w].begin() + ptrdiff_t(topSize), 0u);
            bound += maps_[w].size() - topSize;
        }
        canonical.Reserve(bound);
        for (const TaskRecord &run : tasks) {
            std::vector<uint32_t> &map = maps_[run.worker];
            for (uint32_t first = run.begin; first < run.end; first += arity) {
                uint32_t parent = splits[run.worker][(first - numRoots) / arity];
                uint32_t canonicalFirst = canonical.Children(map[parent]);
                for (uint32_t c = 0; c < arity; ++c)
                    map[first + c] = canonicalFirst + c;
            }
        }
    }

    uint32_t Canonical(size_t worker, uint32_t local) const { return maps_[worker][local]; }

  private:
    std::vector<std::vector<uint32_t>> maps_;  // per worker: local id -> canonical id
};

// The tree counters of a forest: elements, leaves, elements per depth.
template <typename Forest>
void CountTrees(const Forest &forest, Counters &c) {
    c.nodes = forest.Size();
    c.leaves = forest.NumLeaves();
    c.nodesPerDepth = forest.NodesPerDepth();
}

// The tree counters of the union of the workers' forests, counted without building it
// (for count-only runs, where no link refers to an element). Every worker's forest
// began as a copy of _top_, so an element of _top_ has its id in all of them: _top_'s
// split elements are counted directly, and the subtrees below its leaves are walked in
// all forests at once, on up to _threads_ threads. The walk takes the elements it has
// yet to visit kBatch at a time, so that their children, which lie anywhere in the
// forests, are looked up together rather than each after the last.
template <typename Forest>
void CountUnion(const Forest &top, const std::vector<Forest> &forests, int threads, Counters &c) {
    constexpr uint32_t kAbsent = UINT32_MAX;
    constexpr size_t kBatch = 64;
    const size_t numWorkers = forests.size(), frame = numWorkers + 1;
    const uint32_t arity = uint32_t(forests[0].Arity());
    struct Walk {
        uint64_t leaves = 0;
        std::vector<uint64_t> perDepth;
        void Count(uint32_t depth, bool split) {
            if (depth >= perDepth.size())
                perDepth.resize(depth + 1);
            ++perDepth[depth];
            leaves += !split;
        }
        std::vector<uint32_t> pending;  // per element to visit: its depth, its id per forest
        std::vector<uint32_t> batch;    // the next elements to visit, as pending holds them
        std::vector<uint32_t> first;    // their first child per forest
    };
    std::vector<Walk> walks(static_cast<size_t>(threads) + 1);  // the last: _top_'s own
    std::vector<uint32_t> leaves;
    for (uint32_t e = 0; e < top.Size(); ++e) {
        if (top[e].firstChild == kNoChildren)
            leaves.push_back(e);
        else
            walks.back().Count(top.Depth(e), true);
    }
    std::atomic<size_t> nextWalk{0};
    ParallelFor(
        leaves.size(), 1, threads, [&] { return &walks[nextWalk++]; },
        [&](Walk *walk, size_t leaf) {
            std::vector<uint32_t> &pending = walk->pending, &batch = walk->batch,
                                  &first = walk->first;
            pending.push_back(uint32_t(top.Depth(leaves[leaf])));
            pending.insert(pending.end(), numWorkers, leaves[leaf]);
            while (!pending.empty()) {
                size_t n = std::min(pending.size() / frame, kBatch);
                batch.assign(pending.end() - n * frame, pending.end());
                pending.resize(pending.size() - n * frame);
                first.resize(n * numWorkers);
                for (size_t e = 0; e < n; ++e)
                    for (size_t w = 0; w < numWorkers; ++w) {
                        uint32_t local = batch[e * frame + 1 + w];
                        first[e * numWorkers + w] =
                            local == kAbsent ? kNoChildren : forests[w][local].firstChild;
                    }
                for (size_t e = 0; e < n; ++e) {
                    uint32_t depth = batch[e * frame];
                    const uint32_t *f = &first[e * numWorkers];
                    bool split =
                        std::any_of(f, f + numWorkers, [](uint32_t x) { return x != kNoChildren; });
                    walk->Count(depth, split);
                    for (uint32_t k = 0; split && k < arity; ++k) {
                        pending.push_back(depth + 1);
                        for (size_t w = 0; w < numWorkers; ++w)
                            pending.push_back(f[w] == kNoChildren ? kAbsent : f[w] + k);
                    }
                }
            }
        });
    c.nodes = c.leaves = 0;
    c.nodesPerDepth.clear();
    for (const Walk &walk : walks) {
        c.leaves += walk.leaves;
        if (walk.perDepth.size() > c.nodesPerDepth.size())
            c.nodesPerDepth.resize(walk.perDepth.size());
        for (size_t d = 0; d < walk.perDepth.size(); ++d)
            c.nodes += walk.perDepth[d], c.nodesPerDepth[d] += walk.perDepth[d];
    }
}

// Bytes of _tasks_ at their array's capacity, and of the record the second pass keeps
// of each.
size_t TaskBytes(const std::vector<Task> &tasks) {
    return tasks.capacity() * sizeof(Task) + tasks.size() * sizeof(TaskRecord);
}

// The counters that a kernel's tally, summed over a run, gives. With --clusters, links
// and oracle calls count the cluster ones too, already in _c_.
void CountTally(const Tally &total, bool clusters, Counters &c) {
    c.oracleCalls = total.oracleCalls + c.clusterOracleCalls;
    c.links = total.Links() + c.clusterLinks;
    if (clusters)
        c.elementLinks = total.Links();
    c.forcedLinks = total.forcedLinks;
    c.rays = total.visibility.rays;
    c.visibilityQueries = total.visibility.queries;
    c.occludedPairs = total.visibility.occludedPairs;
    c.linksPerDepth.assign(total.linksPerDepth.begin(), total.linksPerDepth.end());
    while (!c.linksPerDepth.empty() && c.linksPerDepth.back() == 0)
        c.linksPerDepth.pop_back();
}

// Runs the kernel over the root pairs that a traversal gives (every one in scene order,
// or those the cluster traversal reaches, in its order), in phases: a sequential pass
// down to the task depth, the tasks on worker threads, each with its own copy of the
// trees, then the sum of the counts and the merge of the trees and links.
template <typename Shape, int kArity, typename Oracle, bool kStoreLinks, typename Visibility>
class AllPairs {
    using F = Forest<Shape>;
    template <bool kFrontier>
    using Kernel = ProjectKernel<F, kArity, Oracle, kStoreLinks, kFrontier, Visibility>;

  public:
    AllPairs(const Patches<Shape> &patches, const Oracle &oracle, const RefineOptions &options,
             const Budget &budget, const Visibility &visibility, Refinement<Shape> &result)
        : patches_(patches), oracle_(oracle), options_(options), budget_(budget),
          visibility_(visibility), result_(result), counters_(result.record.counters),
          top_(patches, budget.maxElements, options.subdivision),
          topKernel_(top_, oracle, options, budget.maxLinks, visibility) {}

    // _traverse_(visit) calls visit(p, q), p < q, for each root pair to refine.
    template <typename Traverse>
    void Run(const Traverse &traverse) {
        FirstPass(traverse);
        RunTasks();
        SumCounts();
        Merge();
    }

  private:
    // Classifies every root pair the traversal gives and refines it down to the task
    // depth, on this thread, recording the pairs there as tasks.
    template <typename Traverse>
    void FirstPass(const Traverse &traverse) {
        const uint32_t numPatches = uint32_t(patches_.size());
        RefineProgress *progress = options_.progress;
        if (progress) {
            // With clusters, how many root pairs the traversal reaches is not known ahead.
            progress->rootPairs =
                options_.clusters ? 0 : uint64_t(numPatches) * (numPatches - 1) / 2;
            progress->StartPass(1);
        }
        // The pair records grow here, so that the old and the new array, held at once
        // while growing, are counted (CheckRecords) before they are taken.
        const size_t pairBytes = sizeof(PairTally) + (progress ? sizeof(uint64_t) : 0);
        // Clustered count-only runs keep the record of a refined pair only while a task
        // refers to it: the pairs reached can be many more than the links.
        const bool pairsForTasksOnly = options_.clusters && !kStoreLinks;
        std::vector<PairTally> &pairs = result_.pairs;
        traverse([&](uint32_t p, uint32_t q) {
            ++counters_.rootPairs;
            if (progress)
                progress->At(counters_.rootPairs);
            PairRelation relation = ClassifyPair(patches_[p].shape, patches_[q].shape);
            if (!RefinesRootPair(relation, p, q, options_)) {
                ++counters_.culledPairs;
                return;
            }
            if (pairs.size() == pairs.capacity()) {
                size_t grown = std::max<size_t>(2 * pairs.capacity(), 1024);
                CheckRecords(grown * pairBytes);
                pairs.reserve(grown);
                if (progress)
                    pairOrdinal_.reserve(grown);
            }
            Tally before = topKernel_.tally;
            size_t tasksBefore = tasks_.size();
            topKernel_.Project({p, q, 0, 0}, uint32_t(pairs.size()), topLinks_, &tasks_);
            if (pairsForTasksOnly && tasks_.size() == tasksBefore)
                return;
            pairs.push_back({p, q, topKernel_.tally.Links() - before.Links(),
                             topKernel_.tally.oracleCalls - before.oracleCalls});
            if (progress)
                pairOrdinal_.push_back(counters_.rootPairs);
            CheckRecords(0);
        });
    }

    // Besides the trees and links, the budget counts what the run keeps per refined
    // root pair and per task, at its arrays' capacity: a scene of many patches can hold
    // more in them than in its trees (24 bytes per refined pair).
    size_t RecordsBytes() const {
        return result_.pairs.capacity() * sizeof(PairTally) +
               pairOrdinal_.capacity() * sizeof(uint64_t) + TaskBytes(tasks_);
    }

    // Throws the budget's LimitError where the records, _growing_ more bytes, the trees
    // and the links would exceed it.
    void CheckRecords(size_t growing) const {
        if (RecordsBytes() + growing + top_.Size() * F::kBytesPerElement +
                topLinks_.size() * sizeof(Link) >
            budget_.bytes)
            throw LimitError("the records of " + std::to_string(result_.pairs.size()) +
                             " refined root pairs and " + std::to_string(tasks_.size()) +
                             " tasks would exceed the memory budget; raise --max-memory or eps");
    }

    // Runs the tasks: each worker takes the next task in order and refines it fully, its
    // trees and links within what the records leave of the budget. Each task's record
    // goes to its index, whichever worker ran it; the earliest failed task's error
    // surfaces (ParallelFor).
    void RunTasks() {
        numWorkers_ = std::max<size_t>(1, std::min<size_t>(options_.threads, tasks_.size()));
        const Budget left = SplitBudget<Shape>(budget_.bytes - RecordsBytes(), options_);
        // One worker takes the first pass's forest over, with nothing left to read it;
        // several start from copies of it.
        if (numWorkers_ == 1)
            forests_.push_back(std::move(top_));
        else
            forests_.assign(numWorkers_, top_);
        for (F &forest : forests_)
            forest.LimitBudget(left.maxElements);
        // Each worker appends its links to one buffer; a task's links are a range of it.
        // The first worker's buffer starts with the sequential pass's links, whose ids
        // are the same in every worker's forest.
        workerLinks_.resize(kStoreLinks ? numWorkers_ : 0);
        if constexpr (kStoreLinks)
            workerLinks_[0] = std::move(topLinks_);
        records_.assign(tasks_.size(), TaskRecord{});
        std::vector<std::optional<Kernel<false>>> kernels(numWorkers_);
        std::vector<LinkBuffer> unused(kStoreLinks ? 0 : numWorkers_);
        RefineProgress *progress = options_.progress;
        if (progress)
            progress->StartPass(2);
        std::atomic<size_t> nextWorker{0};
        ParallelFor(
            tasks_.size(), 1, options_.threads,
            [&] {
                size_t w = nextWorker++;
                kernels[w].emplace(forests_[w], oracle_, options_, left.maxLinks / numWorkers_,
                                   visibility_);
                return w;
            },
            [&](size_t w, size_t t) {
                if (progress)
                    progress->At(pairOrdinal_[tasks_[t].pair]);
                Kernel<false> &kernel = *kernels[w];
                LinkBuffer &links = kStoreLinks ? workerLinks_[w] : unused[w];
                uint64_t linksBefore = kernel.tally.Links(), calls = kernel.tally.oracleCalls;
                uint32_t elementsBefore = uint32_t(forests_[w].Size());
                kernel.Project(tasks_[t].call, tasks_[t].pair, links, nullptr);
                records_[t] = {w, elementsBefore, uint32_t(forests_[w].Size()), links.size(),
                               kernel.tally.Links() - linksBefore,
                               kernel.tally.oracleCalls - calls};
            });
        for (const std::optional<Kernel<false>> &kernel : kernels)
            if (kernel)
                workerTally_.Add(kernel->tally);
    }

    // Sums the counts: the sequential pass, then the workers; each task's to its pair.
    void SumCounts() {
        Tally total = topKernel_.tally;
        total.Add(workerTally_);
        for (size_t t = 0; t < tasks_.size(); ++t) {
            result_.pairs[tasks_[t].pair].links += records_[t].links;
            result_.pairs[tasks_[t].pair].oracleCalls += records_[t].oracleCalls;
        }
        CountTally(total, options_.clusters, counters_);
    }

    // The trees and links of the result, in canonical ids (refine.h), and the tree
    // counters.
    void Merge() {
        // One worker ran every task in order: its ids are canonical, as made.
        if (numWorkers_ == 1) {
            if constexpr (kStoreLinks) {
                result_.links = std::move(workerLinks_[0]);
                result_.links.ShrinkToFit();
            }
            result_.forest = std::move(forests_[0]);
            result_.forest.LiftBudget();
            return CountTrees(result_.forest, counters_);
        }
        // Several workers, without links: no element id is seen, so their trees are
        // counted as one instead of merged, and the result keeps only the roots.
        if constexpr (!kStoreLinks)
            CountUnion(top_, forests_, options_.threads, counters_);
        else
            MergeStored();
    }

    // Merges the workers' trees into canonical ids and translates the links to them.
    void MergeStored() {
        std::vector<std::vector<uint32_t>> splits;
        for (const F &forest : forests_)
            splits.push_back(forest.SplitElements());
        std::vector<F>().swap(forests_);
        result_.forest = std::move(top_);
        result_.forest.LiftBudget();
        ForestUnion<F> merged(splits, records_, result_.forest);
        CountTrees(result_.forest, counters_);

        // Concatenate the tasks' ranges in task order, translating each worker's ids:
        // every task's range has its place known in advance, so the tasks are copied
        // on the run's threads, each giving its source range back to the system.
        size_t topCount = workerLinks_[0].size();
        for (const TaskRecord &record : records_)
            if (record.worker == 0)
                topCount -= record.links;
        std::vector<size_t> taskStart(tasks_.size());
        size_t total = topCount;
        for (size_t t = 0; t < tasks_.size(); ++t)
            taskStart[t] = total, total += records_[t].links;
        LinkBuffer &out = result_.links;
        out.Reserve(total);
        out.Resize(total);
        auto copy = [&](size_t w, size_t begin, size_t end, size_t to) {
            // Block by block, each given back once copied, so that the source and the
            // copy together hold little more than one of them (a task's range can be
            // tens of MB). Each give-back reaches half a block back, over the page the
            // previous one rounded off, but not below the task's first link.
            constexpr size_t kBlock = size_t(1) << 17;  // 1 MiB of links
            for (size_t block = begin; block < end; block += kBlock) {
                size_t blockEnd = std::min(end, block + kBlock);
                out.Populate(to, to + (blockEnd - block));  // one call, not a fault a page
                for (size_t k = block; k < blockEnd; ++k, ++to) {
                    const Link &link = workerLinks_[w][k];
                    out[to] = {merged.Canonical(w, link.i), merged.Canonical(w, link.j)};
                }
                workerLinks_[w].Discard(block - std::min(block - begin, kBlock / 2), blockEnd);
            }
        };
        copy(0, 0, topCount, 0);
        ParallelFor(
            tasks_.size(), 16, options_.threads, [] { return 0; },
            [&](int, size_t t) {
                const TaskRecord &record = records_[t];
                copy(record.worker, record.linksEnd - record.links, record.linksEnd,
                     taskStart[t]);
            });
    }

    const Patches<Shape> &patches_;
    const Oracle &oracle_;
    const RefineOptions &options_;
    const Budget &budget_;
    const Visibility &visibility_;
    Refinement<Shape> &result_;
    Counters &counters_;
    // The first pass: its forest, kernel and links, the tasks it left, and (with a
    // progress line) each refined pair's ordinal among all root pairs, from 1.
    F top_;
    Kernel<true> topKernel_;
    LinkBuffer topLinks_;
    std::vector<Task> tasks_;
    std::vector<uint64_t> pairOrdinal_;
    // The tasks: the workers' forests, links and summed tally, and each task's record.
    size_t numWorkers_ = 1;
    std::vector<F> forests_;
    std::vector<LinkBuffer> workerLinks_;
    Tally workerTally_;
    std::vector<TaskRecord> records_;
};

// Every root pair (p, q), p < q, in order.
struct EveryRootPair {
    uint32_t numPatches;
    template <typename Visit>
    void operator()(Visit &&visit) const {
        for (uint32_t p = 0; p < numPatches; ++p)
            for (uint32_t q = p + 1; q < numPatches; ++q)
                visit(p, q);
    }
};

// The root pairs that the cluster traversal of _result_.clusters reaches under the
// cluster form of _Oracle_, the traversal's counters and (store mode) its links going
// to _result_.
template <typename Oracle, typename Shape>
struct ClusteredRootPairs {
    const Patches<Shape> &patches;
    const RefineOptions &options;
    Refinement<Shape> &result;
    template <typename Visit>
    void operator()(Visit &&visit) const {
        ClusterForm<Oracle> form(options, patches, result.clusters);
        NodeViews<Shape> views(patches, result.clusters);
        ClusterTraversal<Shape, ClusterForm<Oracle>, std::remove_reference_t<Visit>> traversal(
            result.clusters, views, form, visit,
            options.storeLinks ? &result.clusterLinks : nullptr);
        traversal.Run(result.record.counters);
    }
};

// The one dispatch of a run: picks the oracle, the arity, the storage mode and the
// visibility policy once, outside the recursion, and runs the kernel compiled for them.
template <typename Shape>
void Dispatch(const Patches<Shape> &patches, const RefineOptions &options, const Budget &budget,
              Refinement<Shape> &result) {
    bool found = false;
    AllOracles::ForEach([&](auto tag) {
        using Oracle = typename decltype(tag)::template Type<Shape>;
        if (found || options.oracle != Oracle::kInfo.name)
            return;
        found = true;
        if constexpr (Oracle::kInfo.Supports(Shape::kDimension)) {
            Oracle oracle = MakeOracle<Oracle>(options, patches);
            if constexpr (!ClusterForm<Oracle>::kExists) {
                if (options.clusters)
                    throw InputError("--clusters: the oracle " + std::string(Oracle::kInfo.name) +
                                     " has no cluster form");
            }
            WithVisibility(patches, options, [&](const auto &visibility) {
                using Visibility = std::decay_t<decltype(visibility)>;
                auto run = [&](auto arity, auto store) {
                    AllPairs<Shape, decltype(arity)::value, Oracle, decltype(store)::value,
                             Visibility>
                        all(patches, oracle, options, budget, visibility, result);
                    if constexpr (ClusterForm<Oracle>::kExists) {
                        if (options.clusters)
                            return all.Run(ClusteredRootPairs<Oracle, Shape>{patches, options,
                                                                             result});
                    }
                    all.Run(EveryRootPair{uint32_t(patches.size())});
                };
                using Binary = std::integral_constant<int, 2>;
                using Quadtree = std::integral_constant<int, 4>;
                bool quadtree = options.subdivision == Subdivision::Quadtree;
                if constexpr (Shape::kDimension == 3) {
                    if (quadtree)
                        return options.storeLinks ? run(Quadtree(), std::true_type())
                                                  : run(Quadtree(), std::false_type());
                }
                options.storeLinks ? run(Binary(), std::true_type())
                                   : run(Binary(), std::false_type());
            });
        }
    });
    if (!found)
        FindOracle(options.oracle);  // throws, listing the oracles
}

}  // namespace

template <typename Shape>
Refinement<Shape> Refine(const Scene &scene, const RefineOptions &options) {
    if (!std::holds_alternative<Patches<Shape>>(scene.patches))
        throw InputError(std::string("the scene does not hold ") + Shape::kName + "s");
    ValidateOptions(options, Shape::kDimension);
    ValidateScene(scene);
    const Patches<Shape> &patches = scene.Get<Shape>();

    Refinement<Shape> result{Forest<Shape>(patches, SIZE_MAX, options.subdivision),
                             {},
                             {},
                             {"enumerate", {}, 0, {}, {}},
                             {},
                             {}};
    auto start = std::chrono::steady_clock::now();
    if (options.clusters)
        result.clusters = ClusterTree<Shape>(patches);
    Dispatch(patches, options, SplitBudget<Shape>(EffectiveBudget(options), options), result);
    result.record.seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

    Counters &c = result.record.counters;
    c.maxDepth = c.nodesPerDepth.size() - 1;
    return result;
}

template Refinement<Segment> Refine(const Scene &, const RefineOptions &);
template Refinement<Polygon> Refine(const Scene &, const RefineOptions &);

AnyRefinement Refine(const Scene &scene, const RefineOptions &options) {
    return std::visit(
        [&](const auto &patches) -> AnyRefinement {
            using Shape = std::decay_t<decltype(patches.front().shape)>;
            return Refine<Shape>(scene, options);
        },
        scene.patches);
}

const std::vector<MethodInfo> &Methods() {
    static const std::vector<MethodInfo> methods = {
        {"enumerate", "run ProjectKernel pair by pair (any scene, oracle and option)",
         [](const Scene &scene, const RefineOptions &options) {
             return std::visit([](auto &&r) { return std::move(r.record); },
                               Refine(scene, options));
         }},
        {"translation",
         "exact counts of `parallel` with l2 = l and `parallel3d` with ox = oy = 0, garmann, "
         "--count-only, no recursion limit, from translation invariance (any number of links "
         "in milliseconds)",
         [](const Scene &scene, const RefineOptions &options) {
             return CountByTranslation(scene, options).record;
         }},
    };
    return methods;
}

RunRecord Count(const Scene &scene, const RefineOptions &options, const std::string &method) {
    for (const MethodInfo &m : Methods())
        if (m.name == method)
            return m.count(scene, options);
    throw InputError("unknown method '" + method + "'");
}

}  // namespace hrbench
