// What the bench's studies share to measure: the wall clock, work run on every core under a time
// limit, nearest-rank quantiles (engine/scene/quantiles.h), the progress lines a study prints as
// it goes, and the error a study stops with. The numbers are measurements of one run on one
// machine (shared machines vary 10-25% from run to run): nothing here is exact but the counts.
#pragma once

#include <atomic>
#include <chrono>
#include <functional>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "engine/scene/quantiles.h"  // (the studies' medians and 99th percentiles)

namespace penumbra {

using StudyClock = std::chrono::steady_clock;

inline double secondsBetween(StudyClock::time_point a, StudyClock::time_point b) {
    return std::chrono::duration<double>(b - a).count();
}

// While one lives, oneTBB may run a worker on every core besides the thread that waits (its
// default keeps one core for that thread): the studies' waiting thread only polls the clock
// (runWithLimit) or sleeps, so every core computes. The bench holds one for its whole run, so
// that every study and every precompute runs on the same workers.
class StudyWorkers {
  public:
    StudyWorkers();

  private:
    std::shared_ptr<void> control_;  // the tbb::global_control
};

// Runs `work` on oneTBB (an arena with a slot per core, none kept for this thread, which only
// polls) and raises `cancel` once `limit` seconds have passed; `work` stops early by watching
// it. True when the work finished before the limit. Every timed run of the studies goes through
// here or runOnWorkers.
bool runWithLimit(double limit, std::atomic<bool>& cancel, const std::function<void()>& work);

// The same without a limit.
void runOnWorkers(const std::function<void()>& work);

// Where a study reports its progress, one line at a time (what `penumbra bench` prints as it
// measures); empty: nowhere.
using StudyLog = std::function<void(const std::string& line)>;

// A printf-formatted line to `log`, when there is one.
void logLine(const StudyLog& log, const char* format, ...) __attribute__((format(printf, 2, 3)));

// Why a study cannot go on: a precompute that failed, an image it cannot write. The bench reports
// it as an input error (exit status 1).
struct StudyError : std::runtime_error {
    using std::runtime_error::runtime_error;
};

}  // namespace penumbra
