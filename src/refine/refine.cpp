#include "hrbench/refine.h"

#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <cmath>
#include <functional>
#include <numeric>
#include <optional>
#include <string>

#include "cluster/traversal.h"
#include "hrbench/oracles/registry.h"
#include "hrbench/util/error.h"
#include "refine/kernel.h"
#include "util/parallel_for.h"
#include "util/stopwatch.h"
#include "visibility/culling.h"

namespace hrbench {

namespace {

// Refines root pair (p, q), p < q; calls one for each root pair a run refines.
using RootPairVisit = std::function<void(uint32_t, uint32_t)>;
using RootPairTraversal = std::function<void(const RootPairVisit &)>;

// A run's memory budget in bytes, and how many elements (per forest) and links it may
// hold: SplitBudget's shares of it.
struct Budget {
    size_t bytes;
    size_t maxElements;
    size_t maxLinks;
};

// Splits _bytes_ of memory: a quarter for the element trees when links are stored, the
// rest for links (with visibility, each with its visible fraction). The trees are one
// forest on one thread (its worker takes the sequential pass's over), else a copy per
// worker and the pass's, into which they are merged.
template <typename Shape>
Budget SplitBudget(size_t bytes, const RefineOptions &options) {
    size_t forests = options.threads == 1 ? 1 : size_t(options.threads) + 1;
    size_t elementBytes = Forest<Shape>::kBytesPerElement;
    return {bytes, (options.storeLinks ? bytes / 4 : bytes) / elementBytes / forests,
            bytes / 4 * 3 / StoredLinkBytes(options)};
}

// What a task left in its worker (RunTasks): its worker, the run of sibling groups it
// made there (the elements [begin, end) of the worker's forest), where its links end in
// the worker's buffer, and how many links and oracle calls it made.
struct TaskResult {
    size_t worker;
    uint32_t begin, end;
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
    // _splits_: each worker's Forest::SplitElements(); _tasks_: the tasks' results, with
    // their runs, in task order. _canonical_ holds the sequential pass's forest and grows
    // to the union.
    ForestUnion(const std::vector<std::vector<uint32_t>> &splits,
                const std::vector<TaskResult> &tasks, Forest &canonical)
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
        for (const TaskResult &run : tasks) {
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

// Clustered count-only runs keep the record of a refined pair only while a task refers
// to it, and none once counted: the pairs reached can be many more than the links.
template <bool kStoreLinks>
bool PairsForTasksOnly(const RefineOptions &options) {
    return options.clusters && !kStoreLinks;
}

// What the sequential pass leaves (RefineToTaskDepth): the trees and links down to the
// task depth, their counts, the tasks below it, and (with progress) each refined pair's
// ordinal among all root pairs, from 1.
template <typename F>
struct TaskDepthPass {
    F forest;
    LinkBuffer links;
    std::vector<double> visible;  // each link's visible fraction, with visibility
    Tally tally;
    std::vector<Task> tasks;
    std::vector<uint64_t> pairOrdinal;

    // Bytes of the records per refined root pair (_pairs_) and per task, at capacity.
    size_t RecordBytes(const std::vector<PairTally> &pairs) const {
        return pairs.capacity() * sizeof(PairTally) + pairOrdinal.capacity() * sizeof(uint64_t) +
               tasks.capacity() * sizeof(Task) + tasks.size() * sizeof(TaskResult);
    }
};

// The sequential pass: classifies the root pairs that _traverse_ gives (every one in
// scene order, or those the cluster traversal reaches, in its order), refines those that
// need it down to the task depth, recording them in _result_.pairs and the pairs at that
// depth as tasks, and throws LimitError when this exceeds _budget_. Without _kFrontier_
// it refines them whole and leaves no task: a count-only run on one thread, where no
// element id is seen (the elements made are the same, in another order) and no other
// worker could take a task, so that nothing is kept per task.
template <int kArity, bool kStoreLinks, bool kFrontier, typename Shape, typename Oracle,
          typename Visibility>
TaskDepthPass<Forest<Shape>>
RefineToTaskDepth(const Patches<Shape> &patches, const Oracle &oracle, const RefineOptions &options,
                  const Budget &budget, const Visibility &visibility,
                  const RootPairTraversal &traverse, Refinement<Shape> &result) {
    using F = Forest<Shape>;
    Counters &counters = result.record.counters;
    TaskDepthPass<F> pass{F(patches, budget.maxElements, options.subdivision), {}, {}, {}, {}, {}};
    ProjectKernel<F, kArity, Oracle, kStoreLinks, kFrontier, Visibility> kernel(
        pass.forest, oracle, options, budget.maxLinks, visibility);
    const uint32_t numPatches = uint32_t(patches.size());
    RefineProgress *progress = options.progress;
    if (progress) {
        // With clusters, how many root pairs the traversal reaches is not known ahead.
        progress->rootPairs = options.clusters ? 0 : uint64_t(numPatches) * (numPatches - 1) / 2;
        progress->StartPass(kFrontier ? 1 : 2);  // a pass that leaves no task is the last
    }
    // Besides the trees and links, the budget counts what the run keeps per refined root
    // pair and per task, at its arrays' capacity (RecordBytes); the pair records grow
    // here, so that the old and the new array, held at once while growing, are counted
    // before they are taken. A scene of many patches can hold more in them than in its
    // trees (24 bytes per refined pair).
    const bool ordinals = kFrontier && progress;  // a task's pair's ordinal, for progress
    const size_t pairBytes = sizeof(PairTally) + (ordinals ? sizeof(uint64_t) : 0);
    auto check = [&](size_t growing) {
        if (pass.RecordBytes(result.pairs) + growing + pass.forest.Size() * F::kBytesPerElement +
                pass.links.size() * StoredLinkBytes(options) >
            budget.bytes)
            throw LimitError("the records of " + std::to_string(result.pairs.size()) +
                             " refined root pairs and " + std::to_string(pass.tasks.size()) +
                             " tasks would exceed the memory budget; raise --max-memory or eps");
    };
    const bool pairsForTasksOnly = PairsForTasksOnly<kStoreLinks>(options);
    // The initial linking's time: the traversal's, less the refinement it hands down.
    using Clock = std::chrono::steady_clock;
    Clock::duration refining{};
    const Clock::time_point linkingStart = Clock::now();
    traverse([&](uint32_t p, uint32_t q) {
        ++counters.rootPairs;
        if (progress)
            progress->At(counters.rootPairs);
        PairRelation relation = ClassifyPair(patches[p].shape, patches[q].shape);
        if (!RefinesRootPair(relation, p, q, options)) {
            ++counters.culledPairs;
            return;
        }
        if (result.pairs.size() == result.pairs.capacity()) {
            size_t grown = std::max<size_t>(2 * result.pairs.capacity(), 1024);
            check(grown * pairBytes);
            result.pairs.reserve(grown);
            if (ordinals)
                pass.pairOrdinal.reserve(grown);
        }
        Tally before = kernel.tally;
        size_t tasksBefore = pass.tasks.size();
        Clock::time_point refineStart = Clock::now();
        kernel.Project({p, q, 0, 0}, uint32_t(result.pairs.size()), pass.links, pass.visible,
                       &pass.tasks);
        refining += Clock::now() - refineStart;
        if (pairsForTasksOnly && pass.tasks.size() == tasksBefore)
            return;
        result.pairs.push_back({p, q, kernel.tally.Links() - before.Links(),
                                kernel.tally.oracleCalls - before.oracleCalls});
        if (ordinals)
            pass.pairOrdinal.push_back(counters.rootPairs);
        check(0);
    });
    result.record.linkingSeconds =
        std::chrono::duration<double>(Clock::now() - linkingStart - refining).count();
    pass.tally = kernel.tally;
    return pass;
}

// What RunTasks leaves: per worker its forest, links and their visible fractions (store
// mode) and counts; per task its result.
template <typename F>
struct WorkerResults {
    std::vector<F> forests;
    std::vector<LinkBuffer> links;
    std::vector<std::vector<double>> visible;
    std::vector<Tally> tallies;
    std::vector<TaskResult> tasks;
};

// Runs the tasks of _pass_ on max(1, min(threads, tasks)) workers, each taking the next
// task in order and refining it fully in its own forest, within _budget_; rethrows the
// error of the earliest failed task. One worker takes the pass's forest over, with
// nothing left to read it; several start from copies of it.
template <int kArity, bool kStoreLinks, typename F, typename Oracle, typename Visibility>
WorkerResults<F> RunTasks(TaskDepthPass<F> &pass, const Oracle &oracle,
                          const RefineOptions &options, const Budget &budget,
                          const Visibility &visibility) {
    using Kernel = ProjectKernel<F, kArity, Oracle, kStoreLinks, false, Visibility>;
    const std::vector<Task> &tasks = pass.tasks;
    const size_t numWorkers = std::max<size_t>(1, std::min<size_t>(options.threads, tasks.size()));
    WorkerResults<F> out;
    if (numWorkers == 1)
        out.forests.push_back(std::move(pass.forest));
    else
        out.forests.assign(numWorkers, pass.forest);
    for (F &forest : out.forests)
        forest.LimitBudget(budget.maxElements);
    // Each worker appends its links to one buffer; a task's links are a range of it.
    // The first worker's buffer starts with the sequential pass's links, whose ids are
    // the same in every worker's forest.
    out.links.resize(kStoreLinks ? numWorkers : 0);
    out.visible.resize(kStoreLinks ? numWorkers : 0);
    if constexpr (kStoreLinks)
        out.links[0] = std::move(pass.links), out.visible[0] = std::move(pass.visible);
    out.tallies.resize(numWorkers);
    out.tasks.resize(tasks.size());

    // Worker _index_'s kernel, on forest _index_. Its counts go to out.tallies when its
    // work ends, also after a failure, where they are not read.
    struct Worker {
        size_t index;
        Kernel kernel;
        Tally &tally;
        LinkBuffer countOnly = {};  // the links of a count-only run, which keeps none
        std::vector<double> noVisible = {};
        ~Worker() { tally = kernel.tally; }
    };
    RefineProgress *progress = options.progress;
    if (progress && !tasks.empty())
        progress->StartPass(2);
    ParallelFor(  // with numWorkers workers, one task a chunk
        tasks.size(), 1, int(numWorkers),
        [&](size_t w) {
            size_t maxLinks = budget.maxLinks / numWorkers;
            return Worker{w, Kernel(out.forests[w], oracle, options, maxLinks, visibility),
                          out.tallies[w]};
        },
        [&](Worker &worker, size_t t) {
            if (progress)
                progress->At(pass.pairOrdinal[tasks[t].pair]);
            const size_t w = worker.index;
            LinkBuffer &links = kStoreLinks ? out.links[w] : worker.countOnly;
            std::vector<double> &visible = kStoreLinks ? out.visible[w] : worker.noVisible;
            const Tally &tally = worker.kernel.tally;
            uint64_t linksBefore = tally.Links(), callsBefore = tally.oracleCalls;
            uint32_t begin = uint32_t(out.forests[w].Size());
            worker.kernel.Project(tasks[t].call, tasks[t].pair, links, visible, nullptr);
            uint32_t end = uint32_t(out.forests[w].Size());
            uint64_t made = tally.Links() - linksBefore, calls = tally.oracleCalls - callsBefore;
            out.tasks[t] = {w, begin, end, links.size(), made, calls};
        });
    return out;
}

// Sums the counts of the sequential pass and the workers into _result_: the run's
// counters, and each refined pair's links and oracle calls.
template <typename F, typename Shape>
void SumCounts(const TaskDepthPass<F> &pass, const WorkerResults<F> &workers,
               const RefineOptions &options, Refinement<Shape> &result) {
    Counters &counters = result.record.counters;
    Tally total = pass.tally;
    for (const Tally &t : workers.tallies)
        total.Add(t);
    for (size_t t = 0; t < pass.tasks.size(); ++t) {
        PairTally &pair = result.pairs[pass.tasks[t].pair];
        pair.links += workers.tasks[t].links;
        pair.oracleCalls += workers.tasks[t].oracleCalls;
    }
    // With --clusters, links and oracle calls count the cluster ones too.
    counters.oracleCalls = total.oracleCalls + counters.clusterOracleCalls;
    counters.links = total.Links() + counters.clusterLinks;
    if (options.clusters)
        counters.elementLinks = total.Links();
    counters.forcedLinks = total.forcedLinks;
    counters.rays = total.visibility.rays;
    counters.visibilityQueries = total.visibility.queries;
    counters.occludedPairs = total.visibility.occludedPairs;
    counters.linksPerDepth.assign(total.linksPerDepth.begin(), total.linksPerDepth.end());
    DropTrailingZeros(counters.linksPerDepth);
}

// Links the store-mode merge copies before giving their source back (MergeWorkers).
constexpr size_t kMergeBlock = size_t(1) << 17;  // 1 MiB of links

// Refuses, before any of it is taken, a merge of several workers' results whose peak
// would exceed the budget: what the run holds now (records, every forest, the links)
// plus what the merge holds beside it at most. Store mode: the split lists and id maps
// of the workers' elements (4 bytes each per element), the copy of the links' visible
// fractions, and the blocks of links copied but not yet given back; count-only: the
// list of the pass's leaves that CountUnion walks from. The union forest is no larger
// than the forests it replaces, which are given back first.
template <bool kStoreLinks, typename F>
void CheckMergeBudget(const TaskDepthPass<F> &pass, const WorkerResults<F> &workers,
                      const RefineOptions &options, const std::vector<PairTally> &pairs,
                      size_t budget) {
    size_t elements = pass.forest.Size(), workerElements = 0, links = 0;
    for (const F &forest : workers.forests)
        workerElements += forest.Size();
    for (const LinkBuffer &buffer : workers.links)
        links += buffer.size();
    size_t held = pass.RecordBytes(pairs) + (elements + workerElements) * F::kBytesPerElement +
                  links * StoredLinkBytes(options);
    size_t merge = elements * sizeof(uint32_t);  // count-only: the leaves' list
    if constexpr (kStoreLinks) {
        size_t splits = workerElements / size_t(pass.forest.Arity());
        size_t inFlight = std::min(links, size_t(options.threads) * 2 * kMergeBlock);
        merge = (splits + workerElements) * sizeof(uint32_t) +
                (options.visibility != VisibilityMode::None ? links * sizeof(double) : 0) +
                inFlight * sizeof(Link);
    }
    if (held + merge > budget)
        throw LimitError("merging the workers' trees and links would exceed the memory budget (" +
                         std::to_string(held + merge) +
                         " bytes at its peak); raise --max-memory "
                         "or eps, or use fewer --threads");
}

// The workers' trees as one, counted, and (store mode) the result's forest and links in
// the ids that one worker running every task in order would have made.
template <bool kStoreLinks, typename F, typename Shape>
void MergeWorkers(const Patches<Shape> &patches, TaskDepthPass<F> &pass, WorkerResults<F> &workers,
                  const RefineOptions &options, Refinement<Shape> &result) {
    Counters &counters = result.record.counters;
    const std::vector<TaskResult> &tasks = workers.tasks;
    // One worker ran every task in order: its ids are canonical, as made.
    if (workers.forests.size() == 1) {
        if constexpr (kStoreLinks) {
            result.links = std::move(workers.links[0]);
            result.links.ShrinkToFit();
            result.visible = std::move(workers.visible[0]);
        }
        result.forest = std::move(workers.forests[0]);
        result.forest.LiftBudget();
        return CountTrees(result.forest, counters);
    }

    // Several workers, without links: no element id is seen, so their trees are
    // counted as one instead of merged, and the result keeps only the roots.
    if constexpr (!kStoreLinks) {
        CountUnion(pass.forest, workers.forests, options.threads, counters);
        result.forest = F(patches, SIZE_MAX, options.subdivision);
    } else {
        // Merge the trees into canonical ids and translate the links to them.
        std::vector<std::vector<uint32_t>> splits;
        for (const F &forest : workers.forests)
            splits.push_back(forest.SplitElements());
        std::vector<F>().swap(workers.forests);
        result.forest = std::move(pass.forest);
        result.forest.LiftBudget();
        ForestUnion<F> merged(splits, tasks, result.forest);
        std::vector<std::vector<uint32_t>>().swap(splits);  // the maps replace them
        CountTrees(result.forest, counters);

        // Concatenate the tasks' ranges in task order, translating each worker's ids:
        // every task's range has its place known in advance, so the tasks are copied
        // on the run's threads, each giving its source range back to the system.
        size_t topCount = workers.links[0].size();
        for (const TaskResult &task : tasks)
            if (task.worker == 0)
                topCount -= task.links;
        std::vector<size_t> taskStart(tasks.size());
        size_t total = topCount;
        for (size_t t = 0; t < tasks.size(); ++t)
            taskStart[t] = total, total += tasks[t].links;
        result.links.Reserve(total);
        result.links.Resize(total);
        const bool visible = options.visibility != VisibilityMode::None;
        result.visible.resize(visible ? total : 0);
        auto copy = [&](size_t w, size_t begin, size_t end, size_t to) {
            if (visible)  // the fractions as they are: they name no element
                std::copy(workers.visible[w].begin() + begin, workers.visible[w].begin() + end,
                          result.visible.begin() + to);
            // Block by block, each given back once copied, so that the source and the
            // copy together hold little more than one of them (a task's range can be
            // tens of MB). Each give-back reaches half a block back, over the page the
            // previous one rounded off, but not below the task's first link.
            constexpr size_t kBlock = kMergeBlock;
            for (size_t block = begin; block < end; block += kBlock) {
                size_t blockEnd = std::min(end, block + kBlock);
                result.links.Populate(to, to + (blockEnd - block));  // one call, not a fault a page
                for (size_t k = block; k < blockEnd; ++k, ++to) {
                    const Link &link = workers.links[w][k];
                    result.links[to] = {merged.Canonical(w, link.i), merged.Canonical(w, link.j)};
                }
                workers.links[w].Discard(block - std::min(block - begin, kBlock / 2), blockEnd);
            }
        };
        copy(0, 0, topCount, 0);
        ParallelFor(
            tasks.size(), 16, options.threads, [] { return 0; },
            [&](int, size_t t) {
                const TaskResult &task = tasks[t];
                copy(task.worker, task.linksEnd - task.links, task.linksEnd, taskStart[t]);
            });
    }
}

// Runs the kernel over the root pairs that _traverse_ gives: a sequential pass down to
// the task depth, then the tasks on worker threads, each with its own copy of the trees,
// within what the pass's records leave of the budget. A count-only run on one thread
// refines every pair whole in the sequential pass.
template <typename Shape, int kArity, typename Oracle, bool kStoreLinks, typename Visibility>
void RefineAllPairs(const Patches<Shape> &patches, const Oracle &oracle,
                    const RefineOptions &options, const Budget &budget,
                    const Visibility &visibility, const RootPairTraversal &traverse,
                    Refinement<Shape> &result) {
    TaskDepthPass<Forest<Shape>> pass = [&] {
        if constexpr (!kStoreLinks)
            if (options.threads == 1)
                return RefineToTaskDepth<kArity, kStoreLinks, false>(
                    patches, oracle, options, budget, visibility, traverse, result);
        return RefineToTaskDepth<kArity, kStoreLinks, true>(patches, oracle, options, budget,
                                                            visibility, traverse, result);
    }();
    const Budget left = SplitBudget<Shape>(budget.bytes - pass.RecordBytes(result.pairs), options);
    WorkerResults<Forest<Shape>> workers =
        RunTasks<kArity, kStoreLinks>(pass, oracle, options, left, visibility);
    SumCounts(pass, workers, options, result);
    if (PairsForTasksOnly<kStoreLinks>(options))  // counted: none is kept
        std::vector<PairTally>().swap(result.pairs);
    if (workers.forests.size() > 1)  // one worker's results are the run's as they are
        CheckMergeBudget<kStoreLinks>(pass, workers, options, result.pairs, budget.bytes);
    MergeWorkers<kStoreLinks>(patches, pass, workers, options, result);
}

// Every root pair (p, q), p < q, in order.
RootPairTraversal EveryRootPair(uint32_t numPatches) {
    return [numPatches](const RootPairVisit &visit) {
        for (uint32_t p = 0; p < numPatches; ++p)
            for (uint32_t q = p + 1; q < numPatches; ++q)
                visit(p, q);
    };
}

// The root pairs that the cluster traversal of _result_.clusters reaches under the
// cluster form of _Oracle_, the traversal's counters and (store mode) its links going
// to _result_. Throws InputError for an oracle without a cluster form.
template <typename Oracle, typename Shape>
RootPairTraversal ClusteredRootPairs(const Patches<Shape> &patches, const RefineOptions &options,
                                     Refinement<Shape> &result) {
    if constexpr (!ClusterForm<Oracle>::kExists) {
        throw InputError("--clusters: the oracle " + std::string(Oracle::kInfo.name) +
                         " has no cluster form");
    } else {
        return [&patches, &options, &result](const RootPairVisit &visit) {
            ClusterForm<Oracle> form(options, patches, result.clusters);
            NodeViews<Shape> views(patches, result.clusters);
            ClusterTraversal<Shape, ClusterForm<Oracle>, const RootPairVisit> traversal(
                result.clusters, views, form, options.clusterBound, visit,
                options.storeLinks ? &result.clusterLinks : nullptr);
            traversal.Run(result.record.counters);
            result.record.linkingBytes = result.clusters.Bytes() + views.Bytes() +
                                         result.clusterLinks.size() * sizeof(ClusterLink);
        };
    }
}

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
            RootPairTraversal traverse = EveryRootPair(uint32_t(patches.size()));
            if (options.clusters)
                traverse = ClusteredRootPairs<Oracle>(patches, options, result);
            WithVisibility(patches, options, [&](const auto &visibility) {
                using Visibility = std::decay_t<decltype(visibility)>;
                auto run = [&](auto arity, auto store) {
                    RefineAllPairs<Shape, decltype(arity)::value, Oracle, decltype(store)::value,
                                   Visibility>(patches, oracle, options, budget, visibility,
                                               traverse, result);
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

    Refinement<Shape> result{Forest<Shape>(options.subdivision),  // set by Dispatch
                             {},
                             {},
                             {"enumerate", {}, 0, {}, {}, 0, {}, 0},
                             {},
                             {},
                             {}};
    Stopwatch watch;
    if (options.clusters)
        result.clusters = ClusterTree<Shape>(patches);
    Dispatch(patches, options, SplitBudget<Shape>(EffectiveBudget(options), options), result);
    result.record.seconds = watch.WallSeconds();
    result.record.cpuSeconds = watch.CpuSeconds();

    Counters &c = result.record.counters;
    c.maxDepth = c.nodesPerDepth.size() - 1;
    CountInitialLinking(c);
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

}  // namespace hrbench
