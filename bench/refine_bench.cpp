// Google Benchmark suite of the enumerating engine: Refine() on the 2D `parallel`
// family for each oracle, in count-only and store mode, swept over eps at a fixed
// geometry and over the geometry ratio g = l / d at a fixed eps, plus the headline
// configuration of docs/benchmarks.md. The engine's exact counters are attached to
// every row as user counters, and the complexity fit is reported per sweep.
//
// Run everything:       build/refine_bench --benchmark_out=F.json --benchmark_out_format=json
// Only the headline:    build/refine_bench --benchmark_filter=BM_Headline
// Visibility rays:      build/refine_bench --benchmark_filter=BM_CornellVisibility
// Sweeps (--sweep):     build/refine_bench --benchmark_filter=BM_Sweep
#include <malloc.h>

#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include <benchmark/benchmark.h>

#include "count/sweep_count.h"
#include "generators.h"
#include "hrbench/hrbench.h"
#include "record_counters.h"
#include "visibility/visibility.h"

namespace hrbench {
namespace {

// Bytes of heap in use, from the allocator (mmapped blocks included).
size_t HeapBytes() {
    struct mallinfo2 info = mallinfo2();
    return info.uordblks + info.hblkhd;
}

// Runs Refine() on _scene_ once per iteration and attaches its counters to the row:
// exact counts, rates (per second of wall time), and the bytes the result holds per
// stored link and per element, measured on the first iteration.
void RunRefine(benchmark::State &state, const Scene &scene, const RefineOptions &options) {
    Counters counters;
    size_t linkBytes = 0, otherBytes = 0;
    bool measured = false, wholeForest = false;
    for (auto _ : state) {
        size_t before = measured ? 0 : HeapBytes();
        Refinement<Segment> r = Refine<Segment>(scene, options);
        if (!measured) {
            // Count what the result keeps: the link array, then the trees (mapped
            // outside the heap) and the rest.
            linkBytes = r.links.capacity() * sizeof(Link);
            otherBytes = r.forest.Bytes() + (HeapBytes() - before - linkBytes);
            // Count-only on several threads keeps only the roots (refine.h): no figure.
            wholeForest = r.forest.Size() == r.record.counters.nodes;
            measured = true;
        }
        benchmark::DoNotOptimize(r.record.counters.links);
        counters = r.record.counters;
    }

    // Attach the counts of one refinement (identical on every iteration), then rates.
    double iterations = double(state.iterations());
    AddRecordCounters(state, counters);
    state.counters["oracle_calls_per_second"] =
        benchmark::Counter(double(counters.oracleCalls) * iterations, benchmark::Counter::kIsRate);
    state.counters["links_per_second"] =
        benchmark::Counter(double(counters.links) * iterations, benchmark::Counter::kIsRate);
    state.counters["bytes_per_link"] = double(linkBytes) / double(counters.links);
    if (wholeForest)
        state.counters["bytes_per_node"] = double(otherBytes) / double(counters.nodes);
    state.SetLabel(options.oracle + (options.storeLinks ? " store" : " count-only"));
}

// hanrahan's rows keep the centre-cosine estimate, the one of their history and of
// docs/benchmarks.md and docs/3d.md, unless a row names another.
RefineOptions Options(const std::string &oracle, bool store, double eps, int threads = 1,
                      FfEstimate estimate = FfEstimate::CentreCosine) {
    RefineOptions o;
    o.oracle = oracle;
    o.storeLinks = store;
    o.eps = eps;
    o.threads = threads;
    o.ffEstimate = estimate;
    return o;
}

Scene Parallel(double l, double d) { return MakeScene("parallel", {{"l", l}, {"d", d}}); }

// Fixed geometry g = l / d, eps = 1 / inv_eps shrinking: N = Theta(1/eps) elements and
// L = Theta(N^2) links (claim C4), so the time grows as N^2.
void BM_EpsSweep(benchmark::State &state, const std::string &oracle, bool store, double g,
                 FfEstimate estimate = FfEstimate::CentreCosine) {
    double eps = 1.0 / double(state.range(0));
    RunRefine(state, Parallel(g, 1), Options(oracle, store, eps, 1, estimate));
    state.SetComplexityN(int64_t(state.counters["nodes"].value));
}

// Fixed eps, geometry g = l / d growing: N and L both Theta(g) (claim C3), so the time
// grows linearly in the links.
void BM_GeometrySweep(benchmark::State &state, const std::string &oracle, bool store, double eps) {
    double g = double(state.range(0));
    RunRefine(state, Parallel(g, 1), Options(oracle, store, eps));
    state.SetComplexityN(int64_t(state.counters["links"].value));
}

// The headline configuration: 2D garmann, parallel l = 1024, d = 1, eps = 0.01
// (135,566,575 oracle calls, 67,783,288 links), count-only or store, on _threads_ threads.
void BM_Headline(benchmark::State &state, bool store) {
    int threads = int(state.range(0));
    RunRefine(state, Parallel(1024, 1), Options("garmann", store, 0.01, threads));
}

// Visibility on the Cornell box (docs/3d.md's example: hanrahan, eps 0.01, --min-area
// 1e-3, --visibility fraction, 5,964,111 rays), one thread. rays_per_second_per_core
// divides the rays by the CPU time, as the machine may be shared.
void BM_CornellVisibility(benchmark::State &state) {
    RefineOptions o = Options("hanrahan", false, 0.01);
    o.minArea = 1e-3;
    o.visibility = VisibilityMode::Fraction;
    Scene scene = MakeScene("cornell", {});
    Counters counters;
    for (auto _ : state)
        counters = Refine<Polygon>(scene, o).record.counters;
    AddRecordCounters(state, counters);
    state.counters["rays_per_second_per_core"] = benchmark::Counter(
        double(counters.rays) * double(state.iterations()), benchmark::Counter::kIsRate);
    state.SetLabel(HasEmbree() ? "embree" : "cgal");
}

// _n_ values from _from_ to _to_, evenly spaced in log scale, as a sweep of the
// analysis spaces them.
std::vector<double> LogValues(double from, double to, int n) {
    std::vector<double> values;
    for (int k = 0; k < n; ++k)
        values.push_back(from * std::pow(to / from, double(k) / (n - 1)));
    return values;
}

// A sweep of the quick reproduction, smaller: the Cornell box over --min-area (17
// values, 1e-4 to 1e-6, eps 0.1), or the occluded plates with visibility over eps (11
// values, 1 to 0.1). _shared_: counted from one enumeration (CountSweep(), `run
// --sweep`), else value by value (Count() per value). Both rows count the same links
// (links_all_values); the ratio of their times is what `--sweep` saves.
void BM_Sweep(benchmark::State &state, const std::string &which, bool shared) {
    bool cornell = which == "cornell_min_area";
    Scene scene = cornell ? MakeScene("cornell", {})
                          : MakeScene("occluded3d", {{"l", 8}, {"d", 1}, {"bl", 2}, {"h", 0.5}});
    RefineOptions options = Options("garmann", false, 0.1);
    if (!cornell) {
        options.visibility = VisibilityMode::Fraction;
        options.raysPerSide = 2;
    }
    SweepValues sweep = cornell ? SweepValues{"min_area", LogValues(1e-4, 1e-6, 17)}
                                : SweepValues{"eps", LogValues(1, 0.1, 11)};
    uint64_t links = 0;
    for (auto _ : state) {
        links = 0;
        if (shared) {
            for (const RunRecord &r : CountSweep(scene, options, sweep))
                links += r.counters.links;
        } else {
            for (double value : sweep.values) {
                (cornell ? options.minArea : options.eps) = value;
                links += Count(scene, options, "enumerate").counters.links;
            }
        }
    }
    state.counters["values"] = double(sweep.values.size());
    state.counters["links_all_values"] = double(links);
    state.SetLabel(shared ? "one enumeration" : "one run per value");
}

void EpsArgs(benchmark::internal::Benchmark *b, int64_t lowest, int64_t highest) {
    b->ArgNames({"inv_eps"})->RangeMultiplier(2)->Range(lowest, highest);
    b->Complexity(benchmark::oNSquared)->UseRealTime()->Unit(benchmark::kMillisecond);
}

void GeometryArgs(benchmark::internal::Benchmark *b, int64_t lowest, int64_t highest) {
    b->ArgNames({"g"})->RangeMultiplier(4)->Range(lowest, highest);
    b->Complexity(benchmark::oN)->UseRealTime()->Unit(benchmark::kMillisecond);
}

// One thread, and two: the engine's --threads (counts never depend on it).
void HeadlineArgs(benchmark::internal::Benchmark *b) {
    b->ArgNames({"threads"})->Arg(1)->Arg(2)->UseRealTime()->Unit(benchmark::kMillisecond);
}

// garmann: g = 64 for the eps sweep, eps = 0.05 for the geometry sweep.
void GarmannEps(benchmark::internal::Benchmark *b) { EpsArgs(b, 8, 128); }
void GarmannGeometry(benchmark::internal::Benchmark *b) { GeometryArgs(b, 16, 4096); }
// hanrahan: its cosines, taken at the midpoints, make two plates with g >> 1 look far
// apart (g = 64 at eps = 0.01 is 2 links), so smaller g and eps: g = 4 for the eps
// sweep, eps = 0.002 for the geometry sweep.
void HanrahanEps(benchmark::internal::Benchmark *b) { EpsArgs(b, 32, 1024); }
void HanrahanGeometry(benchmark::internal::Benchmark *b) { GeometryArgs(b, 1, 16); }

BENCHMARK_CAPTURE(BM_EpsSweep, garmann_count, "garmann", false, 64)->Apply(GarmannEps);
BENCHMARK_CAPTURE(BM_EpsSweep, garmann_store, "garmann", true, 64)->Apply(GarmannEps);
BENCHMARK_CAPTURE(BM_EpsSweep, hanrahan_count, "hanrahan", false, 4)->Apply(HanrahanEps);
BENCHMARK_CAPTURE(BM_EpsSweep, hanrahan_store, "hanrahan", true, 4)->Apply(HanrahanEps);
BENCHMARK_CAPTURE(BM_EpsSweep, hanrahan_clamped_count, "hanrahan", false, 4,
                  FfEstimate::ClampedCosine)
    ->Apply(HanrahanEps);
BENCHMARK_CAPTURE(BM_GeometrySweep, garmann_count, "garmann", false, 0.05)->Apply(GarmannGeometry);
BENCHMARK_CAPTURE(BM_GeometrySweep, garmann_store, "garmann", true, 0.05)->Apply(GarmannGeometry);
BENCHMARK_CAPTURE(BM_GeometrySweep, hanrahan_count, "hanrahan", false, 0.002)
    ->Apply(HanrahanGeometry);
BENCHMARK_CAPTURE(BM_GeometrySweep, hanrahan_store, "hanrahan", true, 0.002)
    ->Apply(HanrahanGeometry);
BENCHMARK_CAPTURE(BM_Headline, garmann_count, false)->Apply(HeadlineArgs);
BENCHMARK_CAPTURE(BM_Headline, garmann_store, true)->Apply(HeadlineArgs);
BENCHMARK(BM_CornellVisibility)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Sweep, cornell_min_area_shared, "cornell_min_area", true)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Sweep, cornell_min_area_separate, "cornell_min_area", false)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Sweep, occluded3d_eps_shared, "occluded3d_eps", true)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Sweep, occluded3d_eps_separate, "occluded3d_eps", false)
    ->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace hrbench
