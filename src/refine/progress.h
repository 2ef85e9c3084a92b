// A progress line for long refinements on a terminal: which root pair a run is at and
// how long it has run, rewritten in place and erased at the end.
#pragma once

#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <cstdio>
#include <mutex>
#include <string>
#include <thread>

#include "hrbench/refine.h"

namespace hrbench {

// The text of the progress line: "root pair 37 of 136, 12.4 s", with "(first pass)"
// after the pair in the first pass, "starting" before the first pair; without "of 136"
// where the number of root pairs is not known ahead (_rootPairs_ 0: --clusters).
std::string ProgressLine(int pass, uint64_t pair, uint64_t rootPairs, double seconds);

// Shows _progress_ on _out_ while it lives: nothing for the first _delay_ (short runs
// print nothing), then "\rhrbench: LINE" at most once per _interval_; the destructor
// stops it and erases the line if it wrote one. Reads _progress_ from its own thread,
// so the refinement only stores to it.
class ProgressDisplay {
  public:
    ProgressDisplay(const RefineProgress &progress, std::FILE *out,
                    std::chrono::milliseconds delay = std::chrono::milliseconds(2000),
                    std::chrono::milliseconds interval = std::chrono::milliseconds(250));
    ~ProgressDisplay();
    ProgressDisplay(const ProgressDisplay &) = delete;
    ProgressDisplay &operator=(const ProgressDisplay &) = delete;

  private:
    void Run(std::chrono::milliseconds delay, std::chrono::milliseconds interval);

    const RefineProgress &progress_;
    std::FILE *out_;
    std::chrono::steady_clock::time_point start_;
    std::mutex mutex_;
    std::condition_variable wake_;
    bool stop_ = false;
    bool shown_ = false;
    std::thread thread_;
};

}  // namespace hrbench
