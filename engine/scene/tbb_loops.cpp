#include "engine/scene/tbb_loops.h"

#include <oneapi/tbb/blocked_range.h>
#include <oneapi/tbb/parallel_for.h>
#include <oneapi/tbb/parallel_invoke.h>

namespace penumbra {

vis::ParallelLoops tbbLoops() {
    vis::ParallelLoops loops;
    loops.forRange = [](size_t count, size_t grain,
                        const std::function<void(size_t, size_t)>& body) {
        tbb::parallel_for(tbb::blocked_range<size_t>(0, count, grain < 1 ? 1 : grain),
                          [&](const tbb::blocked_range<size_t>& r) { body(r.begin(), r.end()); });
    };
    loops.invoke = [](const std::function<void()>& a, const std::function<void()>& b) {
        tbb::parallel_invoke(a, b);
    };
    return loops;
}

}  // namespace penumbra
