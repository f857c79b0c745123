// PrecomputeScheduler: builds history trees in the background on oneTBB.
//
// Requests are served in order (the caller puts the receivers the camera sees first). A later
// request() goes to the FRONT of the queue, ahead of everything still pending: the viewer
// re-requests what the camera sees whenever it moves, and that must not wait behind an older,
// larger request. requestAll() goes to the BACK (a background fill). Keys already built, already
// queued or being built are skipped (a queued key asked for again moves to the front).
//
// The scheduler never blocks its caller: request(), requestAll(), progress() and cancel() take a
// short lock (no build runs under it) and cost O(keys given) / O(1) / O(queue). cancel() makes
// every running build stop within a fraction of a second (vis::BuildOptions::cancel) and drops the
// queue; a cancelled build publishes nothing and can be built again later. A memory budget stops
// the precompute (state OverBudget, queue dropped) once the store's trees exceed it.
//
// Threads: the builds run in a private tbb::task_arena of threads() slots, none reserved for the
// caller, so they progress while the caller does something else. threads() is the requested count
// capped by the TBB worker threads the process may have, max_allowed_parallelism - 1 (by default
// cores - 1: TBB keeps a core for the thread that waits, here the UI thread). A command that only
// polls may raise that cap with a tbb::global_control it holds while the scheduler runs (made
// before the scheduler).
#pragma once

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "engine/precompute/visibility_store.h"

namespace penumbra {

struct PrecomputeProgress {
    // A batch: the keys requested since the scheduler was last idle (or cancelled / stopped).
    // A request while a batch runs joins it (total grows), so done/total only ever grow.
    size_t done = 0;         // pairs of the batch built (or found already built)
    size_t total = 0;        // distinct pairs of the batch
    double seconds = 0;      // elapsed since the batch began (frozen when it ends)
    double secondsLeft = 0;  // estimate: (total - done) at the batch's rate so far; 0 if unknown
    size_t bytes = 0;        // VisibilityStore::bytes() (all trees of the store)
    size_t nodes = 0;        // tree nodes of the batch's pairs that are done
    enum class State { Idle, Running, Cancelled, OverBudget, Failed } state = State::Idle;
    std::string error;  // for Failed: the first build error, naming the pair
};
const char* toString(PrecomputeProgress::State state);

struct PrecomputeOptions {
    size_t memoryBudgetBytes = 0;  // 0 = unlimited
    int threads = 0;               // concurrent builds; 0 = the cores (capped: see above)
};

// Every (receiver face, patch, light face) pair of the store's scene with receiver != light face,
// for every light, in face order: what requestAll() builds (and the cluster's precompute hands
// out, engine/cluster/). Costs O(faces x lights); computes the receivers' patches.
std::vector<PairKey> everyPairKey(const VisibilityStore& store);

class PrecomputeScheduler {
  public:
    // memoryBudgetBytes: 0 = unlimited.
    explicit PrecomputeScheduler(VisibilityStore& store, size_t memoryBudgetBytes = 0);
    PrecomputeScheduler(VisibilityStore& store, const PrecomputeOptions& options);
    ~PrecomputeScheduler();  // cancels and waits for running tasks
    PrecomputeScheduler(const PrecomputeScheduler&) = delete;
    PrecomputeScheduler& operator=(const PrecomputeScheduler&) = delete;

    void request(std::vector<PairKey> keys);  // in priority order, to the front; duplicates skipped
    // everyPairKey(store), to the back, computed on the calling thread.
    void requestAll();
    PrecomputeProgress progress() const;
    void cancel();        // returns at once; running builds stop within a fraction of a second
    void wait();          // blocks until no build runs (never call on the UI thread)
    int threads() const;  // the concurrent builds it really runs

  private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

}  // namespace penumbra
