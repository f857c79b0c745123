// PrecomputeScheduler: builds history trees in the background on oneTBB (issue 3).
//
// CONTRACT HEADER: declared here so that the viewer and the commands can be written against it
// while it is implemented in engine/precompute_scheduler.cpp. Additions are fine; changes need a
// reason.
//
// Requests are served in order (the caller puts the receivers the camera sees first). The
// scheduler never blocks its caller: request*() enqueue and return; progress() is a snapshot.
// cancel() makes every running build stop within a fraction of a second
// (vis::BuildOptions::cancel) and drops the queue. A memory budget stops the precompute (state
// OverBudget) when the store's trees exceed it.
#pragma once

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <vector>

#include "engine/visibility_store.h"

namespace penumbra {

struct PrecomputeProgress {
    size_t done = 0;        // pairs built (or found already built) since the last request
    size_t total = 0;       // pairs requested
    double seconds = 0;     // elapsed since the first pending request
    double secondsLeft = 0; // estimate (done / elapsed rate); 0 when unknown or finished
    size_t bytes = 0;       // VisibilityStore::bytes()
    size_t nodes = 0;       // tree nodes built so far
    enum class State { Idle, Running, Cancelled, OverBudget, Failed } state = State::Idle;
    std::string error;      // for Failed
};

class PrecomputeScheduler {
public:
    // memoryBudgetBytes: 0 = unlimited.
    explicit PrecomputeScheduler(VisibilityStore& store, size_t memoryBudgetBytes = 0);
    ~PrecomputeScheduler();  // cancels and waits for running tasks
    PrecomputeScheduler(const PrecomputeScheduler&) = delete;
    PrecomputeScheduler& operator=(const PrecomputeScheduler&) = delete;

    void request(std::vector<PairKey> keys);  // in priority order; duplicates are skipped
    void requestAll();                         // every (patch, light) pair of the scene
    PrecomputeProgress progress() const;
    void cancel();  // returns at once; running builds stop within a fraction of a second
    void wait();    // blocks until idle (never call on the UI thread)

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

}  // namespace penumbra
