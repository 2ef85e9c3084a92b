#include "refine/progress.h"

namespace hrbench {

std::string ProgressLine(int pass, uint64_t pair, uint64_t rootPairs, double seconds) {
    char elapsed[32];
    std::snprintf(elapsed, sizeof elapsed, "%.1f s", seconds);
    if (pair == 0)
        return std::string("starting, ") + elapsed;
    return "root pair " + std::to_string(pair) +
           (rootPairs ? " of " + std::to_string(rootPairs) : std::string()) +
           (pass == 1 ? " (first pass), " : ", ") + elapsed;
}

ProgressDisplay::ProgressDisplay(const RefineProgress &progress, std::FILE *out,
                                 std::chrono::milliseconds delay,
                                 std::chrono::milliseconds interval)
    : progress_(progress), out_(out), start_(std::chrono::steady_clock::now()) {
    thread_ = std::thread([this, delay, interval] { Run(delay, interval); });
}

ProgressDisplay::~ProgressDisplay() {
    {
        std::lock_guard<std::mutex> lock(mutex_);
        stop_ = true;
    }
    wake_.notify_one();
    thread_.join();
    if (shown_) {
        std::fputs("\r\033[K", out_);  // back to the line's start, erase it
        std::fflush(out_);
    }
}

void ProgressDisplay::Run(std::chrono::milliseconds delay, std::chrono::milliseconds interval) {
    std::unique_lock<std::mutex> lock(mutex_);
    auto next = start_ + delay;
    while (!wake_.wait_until(lock, next, [this] { return stop_; })) {
        double seconds =
            std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
        std::string line =
            ProgressLine(progress_.pass.load(std::memory_order_relaxed),
                         progress_.pair.load(std::memory_order_relaxed),
                         progress_.rootPairs.load(std::memory_order_relaxed), seconds);
        // "\033[K" erases what a longer line before left on the right.
        std::fprintf(out_, "\rhrbench: %s\033[K", line.c_str());
        std::fflush(out_);
        shown_ = true;
        next = std::chrono::steady_clock::now() + interval;
    }
}

}  // namespace hrbench
