#include "engine/studies/precompute_run.h"

#include <array>
#include <thread>

#include "engine/precompute/precompute_scheduler.h"
#include "engine/render/cpu_time.h"
#include "engine/studies/study_harness.h"

namespace penumbra {

PairKinds pairKinds(const VisibilityStore& store) {
    const std::array<size_t, vis::kPairKindCount> k = store.kindCounts();
    return {k[0], k[1], k[2], k[3], store.partialCount()};
}

size_t treeNodes(const VisibilityStore& store) {
    size_t n = 0;
    store.forEach([&](const PairKey&, const PairRecord& r) { n += r.tree.nodes.size(); });
    return n;
}

PrecomputeRun precomputePairs(VisibilityStore& store, const std::vector<PairKey>* keys,
                              double limit) {
    const double c0 = processCpuSeconds();
    const auto t0 = StudyClock::now();
    PrecomputeScheduler scheduler(store);
    if (keys)
        scheduler.request(*keys);
    else
        scheduler.requestAll();
    bool over = false;
    for (;;) {
        const PrecomputeProgress p = scheduler.progress();
        if (p.state != PrecomputeProgress::State::Running && p.done >= p.total) break;
        if (p.state == PrecomputeProgress::State::Failed)
            throw StudyError("precompute failed: " + p.error);
        if (p.state != PrecomputeProgress::State::Running &&
            p.state != PrecomputeProgress::State::Idle)
            break;
        if (secondsBetween(t0, StudyClock::now()) > limit) {
            scheduler.cancel();
            over = true;
            break;
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(50));
    }
    scheduler.wait();
    const PrecomputeProgress p = scheduler.progress();
    PrecomputeRun run;
    run.seconds = secondsBetween(t0, StudyClock::now());
    run.cpu = processCpuSeconds() - c0;
    run.pairs = p.total;
    run.done = p.done;
    run.complete = !over && p.done >= p.total;
    run.trees = store.treeCount();
    run.nodes = treeNodes(store);
    run.bytes = store.bytes();
    run.kinds = pairKinds(store);
    return run;
}

}  // namespace penumbra
