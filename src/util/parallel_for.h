// A parallel loop whose result and error do not depend on the thread count or timing.
#pragma once

#include <algorithm>
#include <atomic>
#include <cstddef>
#include <cstdint>
#include <exception>
#include <thread>
#include <type_traits>
#include <utility>
#include <vector>

namespace hrbench {

// The state of worker _w_: make(w) where make takes the worker's index, else make().
template <typename Make>
auto MakeWorkerState(Make &make, size_t w) {
    if constexpr (std::is_invocable_v<Make &, size_t>)
        return make(w);
    else
        return make();
}

// Calls body(state, k) for every k in [0, n) on up to _threads_ (>= 1) threads, the
// calling one included, in chunks of _chunk_ (>= 1) indices taken in order; each worker
// makes its own state with make() (scratch space, so workers share nothing mutable),
// or with make(w) where make takes a size_t: w is the worker's index, each of
// [0, max(1, min(threads, chunks))) once, for what a worker keeps beyond the loop.
// Which worker computes k must not matter to the caller. After a failure no new chunk
// starts, and the error of the smallest failing k is rethrown: every chunk before it has
// run, so which error surfaces does not depend on timing either.
template <typename Make, typename Body>
void ParallelFor(size_t n, size_t chunk, int threads, Make make, Body body) {
    size_t chunks = (n + chunk - 1) / chunk;
    size_t workers = std::max<size_t>(1, std::min<size_t>(size_t(threads), chunks));
    std::atomic<size_t> next{0};
    std::atomic<bool> failed{false};
    std::vector<std::pair<size_t, std::exception_ptr>> errors(workers, {SIZE_MAX, nullptr});
    auto work = [&](size_t w) {
        auto state = MakeWorkerState(make, w);
        for (size_t c; !failed && (c = next++) < chunks;) {
            size_t k = c * chunk;
            try {
                for (; k < std::min(n, (c + 1) * chunk); ++k)
                    body(state, k);
            } catch (...) {
                errors[w] = {k, std::current_exception()};
                failed = true;
            }
        }
    };
    std::vector<std::thread> pool;
    for (size_t w = 1; w < workers; ++w)
        pool.emplace_back(work, w);
    work(0);
    for (std::thread &t : pool)
        t.join();
    auto first = std::min_element(errors.begin(), errors.end(),
                                  [](const auto &a, const auto &b) { return a.first < b.first; });
    if (first->second)
        std::rethrow_exception(first->second);
}

}  // namespace hrbench
