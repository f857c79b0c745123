// ParallelLoops: how the visibility core runs independent pieces of one build concurrently
// without a threading library of its own (visibility/ depends on GMP only): the engine hands in
// oneTBB's loops (engine/scene/tbb_loops.h); a default-constructed one runs everything serially
// on the calling thread. A build given either produces the same result: its pieces write disjoint
// parts of the output, and nothing depends on the order they run in.
#pragma once

#include <cstddef>
#include <functional>

namespace penumbra::vis {

struct ParallelLoops {
    // Calls body(begin, end) for disjoint ranges that together cover [0, count), possibly
    // concurrently; ranges hold about `grain` items (at least 1). Empty: one call, [0, count).
    std::function<void(size_t count, size_t grain, const std::function<void(size_t, size_t)>&)>
        forRange;
    // Calls a() and b(), possibly concurrently. Empty: a() then b().
    std::function<void(const std::function<void()>&, const std::function<void()>&)> invoke;

    void run(size_t count, size_t grain, const std::function<void(size_t, size_t)>& body) const {
        if (count == 0) return;
        if (forRange && count > grain)
            forRange(count, grain, body);
        else
            body(0, count);
    }
    void both(const std::function<void()>& a, const std::function<void()>& b) const {
        if (invoke) {
            invoke(a, b);
        } else {
            a();
            b();
        }
    }
};

}  // namespace penumbra::vis
