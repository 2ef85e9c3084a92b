// Google Benchmark suite of the translation method (src/count/translation_count.h): exact
// counts of the parallel-plate families (2D and 3D) with the garmann oracle, far past
// enumeration.
// Its cost is the number of distinct pair states, about 4 / eps per level over
// log2(g / eps) levels, a few additions each, not the number of links.
//
// Run: build/translation_count_bench --benchmark_out=F.json --benchmark_out_format=json
#include <cmath>
#include <cstdint>

#include <benchmark/benchmark.h>

#include "count/translation_count.h"
#include "generators.h"
#include "hrbench/hrbench.h"
#include "record_counters.h"

namespace hrbench {
namespace {

constexpr double kEpsSweepG = 1024;  // geometry ratio l / d of the eps sweep

// Counts the scene once per iteration and attaches the counts and the work to the row.
void RunTranslation(benchmark::State &state, double l, double eps,
                    const char *family = "parallel") {
    Scene scene = MakeScene(family, {{"l", l}, {"d", 1}});
    RefineOptions options;
    options.eps = eps;
    options.storeLinks = false;
    TranslationCount count;
    for (auto _ : state) {
        count = CountByTranslation(scene, options);
        benchmark::DoNotOptimize(count.record.counters.links);
    }
    double iterations = double(state.iterations());
    AddRecordCounters(state, count.record.counters);
    state.counters["pair_states"] = double(count.pairStates);
    state.counters["element_states"] = double(count.elementStates);
    state.counters["oracle_evaluations"] = double(count.oracleEvaluations);
    state.counters["links_per_second"] = benchmark::Counter(
        double(count.record.counters.links) * iterations, benchmark::Counter::kIsRate);
}

// Fixed g = 1024, eps = 1 / inv_eps shrinking to 2^-18 (3.9e14 links, the quadratic
// regime): about 4 / eps states on each of log2(g / eps) levels, so the time grows as
// n log2(g n) with n = 1 / eps.
void BM_TranslationEpsSweep(benchmark::State &state) {
    RunTranslation(state, kEpsSweepG, 1.0 / double(state.range(0)));
    state.SetComplexityN(state.range(0));
}

// Fixed eps = 0.01, g = l / d growing to 2^40 (7e16 links): the states per level stay
// bounded, the levels grow as log2 g.
void BM_TranslationGeometrySweep(benchmark::State &state) {
    RunTranslation(state, double(state.range(0)), 0.01);
    state.SetComplexityN(state.range(0));
}

// In 3D: two 1024 x 1024 squares at distance 1, eps = 1 / inv_eps shrinking to 2^-20
// (7.4e18 links): a grid of about 4 / eps states per level (the offsets within the
// rejected disc, or all offsets of the plates above it) over log2(g^2 / eps) levels.
void BM_Translation3dEpsSweep(benchmark::State &state) {
    RunTranslation(state, kEpsSweepG, 1.0 / double(state.range(0)), "parallel3d");
    state.SetComplexityN(state.range(0));
}

BENCHMARK(BM_TranslationEpsSweep)
    ->ArgNames({"inv_eps"})
    ->RangeMultiplier(4)
    ->Range(16, 1 << 18)
    ->Complexity([](benchmark::IterationCount n) {
        return double(n) * std::log2(kEpsSweepG * double(n));
    })
    ->Unit(benchmark::kMillisecond);

BENCHMARK(BM_TranslationGeometrySweep)
    ->ArgNames({"g"})
    ->RangeMultiplier(1024)
    ->Range(int64_t(1) << 10, int64_t(1) << 40)
    ->Complexity(benchmark::oLogN)
    ->Unit(benchmark::kMillisecond);

BENCHMARK(BM_Translation3dEpsSweep)
    ->ArgNames({"inv_eps"})
    ->RangeMultiplier(4)
    ->Range(16, 1 << 20)
    ->Complexity([](benchmark::IterationCount n) {
        return double(n) * std::log2(kEpsSweepG * kEpsSweepG * double(n));
    })
    ->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace hrbench
