// The naive baselines of docs/benchmarks.md ("The naive baseline and where the limit
// is"): a recursive ProjectKernel over two parallel plates as a naive programmer would
// write it (flat arrays of elements: centre, size, first-child index; children built
// lazily; the garmann oracle, in 2D with one square root per call; the larger element
// split), next to hrbench's own Refine() on the same configuration, single-threaded and
// count-only, in one binary so that bench/compare_naive.sh can interleave them.
//
// Headline configuration: parallel l=1024 d=1, eps = 0.01, garmann, count-only:
// 67,783,288 links and 135,566,575 oracle calls. In 3D: parallel3d l=32 d=1, eps 0.01,
// binary subdivision: 64,156,080 links and 128,312,159 oracle calls, over the same
// 524,286 elements. The naive rows check these counts and fail the run
// (SkipWithError) if they differ.
//
//   build-perf/naive_kernel_bench                                  # all rows
//   bench/compare_naive.sh build-perf 7                            # paired ratios
#include <cmath>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include <benchmark/benchmark.h>

#include "generators.h"
#include "hrbench/hrbench.h"

namespace {

constexpr double kL = 1024, kD = 1, kEps = 0.01;
constexpr uint64_t kExpectedLinks = 67783288, kExpectedCalls = 135566575;
constexpr double kL3 = 32;
constexpr uint64_t kExpectedLinks3 = 64156080, kExpectedCalls3 = 128312159;

// How the naive kernel decides a pair.
enum class Form {
    Sqrt,     // max(len_i, len_j) <= eps * sqrt(r^2): one square root per call
    Squares,  // max(len_i, len_j)^2 <= eps^2 * r^2: no square root (ties may differ)
};

// One element: 32 bytes, as hrbench's hot record.
struct Elem {
    double cx, cy, len;
    uint32_t child;  // first of two consecutive children; 0 = not split yet
};

template <Form kForm>
class NaiveKernel {
  public:
    NaiveKernel(double l, double d, double eps) : eps_(eps), eps2_(eps * eps) {
        // P: (0,0) -> (l,0); Q: (l,d) -> (0,d), as hrbench's `parallel` (offset 0).
        elems_.reserve(1 << 20);
        elems_.push_back({0.5 * l, 0.0, l, 0});
        elems_.push_back({0.5 * l, d, l, 0});
        dir_[0] = 1, dir_[1] = -1;  // x direction of P and of Q (both axis-aligned)
    }

    void Run() { Recurse(0, 1); }

    // Runs the recursion and records the first _n_ pairs it evaluates.
    std::vector<std::pair<uint32_t, uint32_t>> Record(size_t n) {
        record_ = n;
        trace_.reserve(n);
        Run();
        return std::move(trace_);
    }
    const std::vector<Elem> &Elems() const { return elems_; }

    uint64_t links = 0, calls = 0;
    size_t Nodes() const { return elems_.size(); }
    size_t Bytes() const { return elems_.capacity() * sizeof(Elem); }

  private:
    // Children of _e_ (side 0 = P, 1 = Q), built the first time they are asked for:
    // first child from the start of the segment, second from its end.
    uint32_t Children(uint32_t e, int side) {
        if (elems_[e].child)
            return elems_[e].child;
        Elem p = elems_[e];
        double q = 0.25 * p.len * dir_[side], h = 0.5 * p.len;
        uint32_t c = uint32_t(elems_.size());
        elems_.push_back({p.cx - q, p.cy, h, 0});
        elems_.push_back({p.cx + q, p.cy, h, 0});
        elems_[e].child = c;
        return c;
    }

    void Recurse(uint32_t i, uint32_t j) {
        ++calls;
        if (record_ && trace_.size() < record_)
            trace_.push_back({i, j});
        const Elem &a = elems_[i], &b = elems_[j];
        double dx = a.cx - b.cx, dy = a.cy - b.cy;
        double m = a.len >= b.len ? a.len : b.len;
        bool ok;
        if constexpr (kForm == Form::Sqrt)
            ok = m <= eps_ * std::sqrt(dx * dx + dy * dy);
        else
            ok = m * m <= eps2_ * (dx * dx + dy * dy);
        if (ok) {
            ++links;
            return;
        }
        if (a.len >= b.len) {
            uint32_t c = Children(i, 0);
            Recurse(c, j);
            Recurse(c + 1, j);
        } else {
            uint32_t c = Children(j, 1);
            Recurse(i, c);
            Recurse(i, c + 1);
        }
    }

    double eps_, eps2_;
    double dir_[2];
    std::vector<Elem> elems_;
    size_t record_ = 0;
    std::vector<std::pair<uint32_t, uint32_t>> trace_;
};

// The same in 3D, for `parallel3d` with square plates: P = [0,l]^2 at z = 0, Q the same
// at z = d. An element is an axis-aligned rectangle: centre, the sides along x and y,
// first-child index (48 bytes). Its area sx * sy is made again for each call, and
// compared as the 3D garmann oracle does: max(A_i, A_j) <= eps r^2, no square root.
// Splits halve the longer side (ties: x); the first child is the one at the plate's
// first corner: the low half, except along y on Q, whose corners run from high y.
// Every coordinate is a dyadic number, so the arithmetic is exact and the order of the
// operations cannot change a decision.
struct Elem3 {
    double cx, cy, cz, sx, sy;
    uint32_t child;  // first of two consecutive children; 0 = not split yet
};

class NaiveKernel3d {
  public:
    NaiveKernel3d(double l, double d, double eps) : eps_(eps) {
        elems_.reserve(1 << 20);
        elems_.push_back({0.5 * l, 0.5 * l, 0.0, l, l, 0});
        elems_.push_back({0.5 * l, 0.5 * l, d, l, l, 0});
        firstY_[0] = -1, firstY_[1] = 1;  // which way along y the first child lies
    }

    void Run() { Recurse(0, 1); }

    uint64_t links = 0, calls = 0;
    size_t Nodes() const { return elems_.size(); }

  private:
    uint32_t Children(uint32_t e, int side) {
        if (elems_[e].child)
            return elems_[e].child;
        Elem3 p = elems_[e];
        uint32_t c = uint32_t(elems_.size());
        if (p.sx >= p.sy) {
            double q = 0.25 * p.sx;
            elems_.push_back({p.cx - q, p.cy, p.cz, 0.5 * p.sx, p.sy, 0});
            elems_.push_back({p.cx + q, p.cy, p.cz, 0.5 * p.sx, p.sy, 0});
        } else {
            double q = 0.25 * p.sy * firstY_[side];
            elems_.push_back({p.cx, p.cy + q, p.cz, p.sx, 0.5 * p.sy, 0});
            elems_.push_back({p.cx, p.cy - q, p.cz, p.sx, 0.5 * p.sy, 0});
        }
        elems_[e].child = c;
        return c;
    }

    void Recurse(uint32_t i, uint32_t j) {
        ++calls;
        const Elem3 &a = elems_[i], &b = elems_[j];
        double dx = a.cx - b.cx, dy = a.cy - b.cy, dz = a.cz - b.cz;
        double areaI = a.sx * a.sy, areaJ = b.sx * b.sy;
        if ((areaI >= areaJ ? areaI : areaJ) <= eps_ * (dx * dx + dy * dy + dz * dz)) {
            ++links;
            return;
        }
        if (areaI >= areaJ) {
            uint32_t c = Children(i, 0);
            Recurse(c, j);
            Recurse(c + 1, j);
        } else {
            uint32_t c = Children(j, 1);
            Recurse(i, c);
            Recurse(i, c + 1);
        }
    }

    double eps_;
    double firstY_[2];
    std::vector<Elem3> elems_;
};

void Attach(benchmark::State &state, uint64_t links, uint64_t calls, uint64_t nodes) {
    double it = double(state.iterations());
    state.counters["links"] = double(links);
    state.counters["oracle_calls"] = double(calls);
    state.counters["nodes"] = double(nodes);
    state.counters["oracle_calls_per_second"] =
        benchmark::Counter(double(calls) * it, benchmark::Counter::kIsRate);
    // CPU nanoseconds per oracle call (Google Benchmark divides rates by CPU time
    // unless UseRealTime is set; these rows use CPU time).
    state.counters["ns_per_oracle_call"] = benchmark::Counter(
        double(calls) * it, benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}

// Runs a naive kernel, made by _make_, once per iteration and attaches its counts; with
// _mustMatch_, fails the row if they are not the _links_ and _calls_ of hrbench.
template <typename Make>
void RunNaive(benchmark::State &state, Make make, uint64_t expectedLinks, uint64_t expectedCalls,
              bool mustMatch, const char *label) {
    uint64_t links = 0, calls = 0, nodes = 0;
    for (auto _ : state) {
        auto k = make();
        k.Run();
        benchmark::DoNotOptimize(k.links);
        links = k.links, calls = k.calls, nodes = k.Nodes();
    }
    Attach(state, links, calls, nodes);
    bool exact = links == expectedLinks && calls == expectedCalls;
    state.counters["counts_match"] = exact ? 1 : 0;
    if (mustMatch && !exact)
        state.SkipWithError(("naive counts differ from hrbench's: links " + std::to_string(links) +
                             ", oracle calls " + std::to_string(calls))
                                .c_str());
    state.SetLabel(label);
}

template <Form kForm>
void BM_Naive(benchmark::State &state) {
    RunNaive(
        state, [] { return NaiveKernel<kForm>(kL, kD, kEps); }, kExpectedLinks, kExpectedCalls,
        kForm == Form::Sqrt,
        kForm == Form::Sqrt ? "naive sqrt count-only" : "naive squares count-only");
}

void BM_Naive3d(benchmark::State &state) {
    RunNaive(
        state, [] { return NaiveKernel3d(kL3, kD, kEps); }, kExpectedLinks3, kExpectedCalls3, true,
        "naive 3D count-only");
}

// The oracle alone, branch-free, over the first 2^22 pairs the recursion evaluates
// (recorded once, in recursion order): the floor of the arithmetic and the loads with no
// recursion, no branch on the decision and no call. _Squares_ as BM_NaiveSquares; the
// AVX2 clone lets the compiler vectorise the loop (gathers), where the CPU has AVX2.
using Pairs = std::vector<std::pair<uint32_t, uint32_t>>;

// The loop of both streams, inlined into each so that each is compiled for its target.
template <bool kSqrt>
[[gnu::always_inline]] inline uint64_t Stream(const Elem *e, const Pairs &p, double eps) {
    uint64_t accepted = 0;
    for (const auto &[i, j] : p) {
        double dx = e[i].cx - e[j].cx, dy = e[i].cy - e[j].cy;
        double m = e[i].len >= e[j].len ? e[i].len : e[j].len;
        if constexpr (kSqrt)
            accepted += m <= eps * std::sqrt(dx * dx + dy * dy);
        else
            accepted += m * m <= eps * eps * (dx * dx + dy * dy);
    }
    return accepted;
}

template <bool kSqrt>
[[gnu::noinline]] uint64_t StreamScalar(const Elem *e, const Pairs &p, double eps) {
    return Stream<kSqrt>(e, p, eps);
}

template <bool kSqrt>
[[gnu::noinline, gnu::target("avx2")]] uint64_t StreamAvx2(const Elem *e, const Pairs &p,
                                                           double eps) {
    return Stream<kSqrt>(e, p, eps);
}

template <bool kSqrt, bool kAvx2>
void BM_OracleStream(benchmark::State &state) {
    if (kAvx2 && !__builtin_cpu_supports("avx2"))
        return state.SkipWithError("no AVX2 on this CPU");
    NaiveKernel<Form::Sqrt> k(kL, kD, kEps);
    Pairs pairs = k.Record(size_t(1) << 22);
    const Elem *e = k.Elems().data();
    uint64_t accepted = 0;
    for (auto _ : state) {
        accepted = kAvx2 ? StreamAvx2<kSqrt>(e, pairs, kEps) : StreamScalar<kSqrt>(e, pairs, kEps);
        benchmark::DoNotOptimize(accepted);
    }
    double it = double(state.iterations());
    state.counters["oracle_calls"] = double(pairs.size());
    state.counters["accepted"] = double(accepted);
    state.counters["ns_per_oracle_call"] = benchmark::Counter(
        double(pairs.size()) * it, benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}

// hrbench's own Refine() on _family_ with _params_ (1 thread, count-only, eps kEps,
// binary subdivision), once per iteration; fails the row if its counts are not _links_
// and _calls_.
template <typename Shape>
void RunHrbench(benchmark::State &state, const std::string &family, const hrbench::ParamMap &params,
                uint64_t links, uint64_t calls, const char *label) {
    hrbench::Scene scene = hrbench::MakeScene(family, params);
    hrbench::RefineOptions o;
    o.oracle = "garmann";
    o.storeLinks = false;
    o.eps = kEps;
    o.threads = 1;
    o.subdivision = hrbench::Subdivision::Binary;
    hrbench::Counters c;
    for (auto _ : state) {
        hrbench::Refinement<Shape> r = hrbench::Refine<Shape>(scene, o);
        benchmark::DoNotOptimize(r.record.counters.links);
        c = r.record.counters;
    }
    Attach(state, c.links, c.oracleCalls, c.nodes);
    if (c.links != links || c.oracleCalls != calls)
        state.SkipWithError(("hrbench counts differ from those of " + family).c_str());
    state.SetLabel(label);
}

// The headline configuration, and the 3D one (parallel3d l=32 d=1).
void BM_Hrbench(benchmark::State &state) {
    RunHrbench<hrbench::Segment>(state, "parallel", {{"l", kL}, {"d", kD}}, kExpectedLinks,
                                 kExpectedCalls, "hrbench Refine 1 thread count-only");
}

void BM_Hrbench3d(benchmark::State &state) {
    RunHrbench<hrbench::Polygon>(state, "parallel3d", {{"l", kL3}, {"d", kD}}, kExpectedLinks3,
                                 kExpectedCalls3, "hrbench Refine 3D 1 thread count-only");
}

// A naive-kernel run of the whole tree (for /usr/bin/time -v: peak RSS per element):
// `naive_kernel_bench --benchmark_filter=BM_NaiveSqrt$ --benchmark_min_time=0.001`.
BENCHMARK(BM_Naive<Form::Sqrt>)->Name("BM_NaiveSqrt")->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Naive<Form::Squares>)->Name("BM_NaiveSquares")->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Hrbench)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Naive3d)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Hrbench3d)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_OracleStream<true, false>)->Name("BM_OracleStream/sqrt");
BENCHMARK(BM_OracleStream<false, false>)->Name("BM_OracleStream/squares");
BENCHMARK(BM_OracleStream<true, true>)->Name("BM_OracleStream/sqrt_avx2");
BENCHMARK(BM_OracleStream<false, true>)->Name("BM_OracleStream/squares_avx2");

}  // namespace
