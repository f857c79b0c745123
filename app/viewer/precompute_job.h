// PrecomputeJob: the viewer's "precompute every pair" in the background (a PrecomputeScheduler
// on the scene's store). Starting, cancelling and the progress; a job of a scene that is closed is
// handed to a task to finish (the scheduler's destructor waits for its builds), never waited for on
// the UI thread.
#pragma once

#include <tbb/task_group.h>

#include <memory>
#include <vector>

#include "engine/precompute/precompute_scheduler.h"
#include "engine/precompute/visibility_store.h"

namespace penumbra::viewer {

class PrecomputeJob {
  public:
    // Every (receiver patch, light) pair of `store` (the store must outlive the job).
    void start(VisibilityStore& store);
    // These pairs of `store` only (a light moved: the pairs whose trees it had before).
    void start(VisibilityStore& store, std::vector<PairKey> keys);
    void cancel();
    bool running() const;
    bool started() const { return scheduler_ != nullptr; }
    PrecomputeProgress progress() const;
    // Cancels and lets a task of `tasks` destroy the scheduler (the job is then not started);
    // `keepAlive` (the store's owner) is released after it, so that the store outlives its builds.
    void dispose(tbb::task_group& tasks, std::shared_ptr<const void> keepAlive = nullptr);

  private:
    std::shared_ptr<PrecomputeScheduler> scheduler_;
};

}  // namespace penumbra::viewer
