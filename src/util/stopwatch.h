// Wall and process CPU time of a stage, for the records' seconds and cpu_seconds.
#pragma once

#include <chrono>
#include <ctime>

namespace hrbench {

// CPU time of the process so far, every thread's, in seconds.
inline double ProcessCpuSeconds() {
    timespec ts;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return double(ts.tv_sec) + 1e-9 * double(ts.tv_nsec);
}

// Wall and process CPU time since construction.
class Stopwatch {
  public:
    double WallSeconds() const {
        return std::chrono::duration<double>(Clock::now() - wall_).count();
    }
    double CpuSeconds() const { return ProcessCpuSeconds() - cpu_; }

  private:
    using Clock = std::chrono::steady_clock;
    Clock::time_point wall_ = Clock::now();
    double cpu_ = ProcessCpuSeconds();
};

}  // namespace hrbench
