#include "engine/studies/study_harness.h"

#include <tbb/global_control.h>
#include <tbb/info.h>
#include <tbb/task_arena.h>
#include <tbb/task_group.h>

#include <algorithm>
#include <cmath>
#include <cstdarg>
#include <cstdio>
#include <thread>

namespace penumbra {

StudyWorkers::StudyWorkers()
    : control_(std::make_shared<tbb::global_control>(
          tbb::global_control::max_allowed_parallelism,
          std::max(1, tbb::info::default_concurrency()) + 1)) {}

bool runWithLimit(double limit, std::atomic<bool>& cancel, const std::function<void()>& work) {
    // An arena with a worker slot per core and none kept for this thread (it only polls).
    tbb::task_arena arena(std::max(1, tbb::info::default_concurrency()), 0);
    std::atomic<bool> done{false};
    tbb::task_group group;
    arena.execute([&] {
        group.run([&] {
            work();
            done = true;
        });
    });
    const auto t0 = StudyClock::now();
    while (!done.load()) {
        std::this_thread::sleep_for(std::chrono::milliseconds(50));
        if (!cancel.load() && secondsBetween(t0, StudyClock::now()) > limit) cancel = true;
    }
    arena.execute([&] { group.wait(); });
    return !cancel.load();
}

void runOnWorkers(const std::function<void()>& work) {
    std::atomic<bool> never{false};
    runWithLimit(INFINITY, never, work);
}

void logLine(const StudyLog& log, const char* format, ...) {
    if (!log) return;
    va_list args;
    va_start(args, format);
    va_list copy;
    va_copy(copy, args);
    const int n = std::vsnprintf(nullptr, 0, format, copy);
    va_end(copy);
    std::string line(static_cast<size_t>(std::max(n, 0)), '\0');
    std::vsnprintf(line.data(), line.size() + 1, format, args);
    va_end(args);
    log(line);
}

}  // namespace penumbra
