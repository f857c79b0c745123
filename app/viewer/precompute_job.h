// PrecomputeJob: the viewer's "precompute every pair" in the background (a PrecomputeScheduler
// on the scene's store). Starting, cancelling and the progress; a job of a scene that is closed is
// handed to a task to finish (the scheduler's destructor waits for its builds), never waited for on
// the UI thread.
#pragma once

#include <tbb/task_group.h>

#include <memory>

#include "engine/precompute/precompute_scheduler.h"
#include "engine/precompute/visibility_store.h"

namespace penumbra::viewer {

class PrecomputeJob {
  public:
    // Every (receiver patch, light) pair of `store` (the store must outlive the job).
    void start(VisibilityStore& store);
    void cancel();
    bool running() const;
    bool started() const { return scheduler_ != nullptr; }
    PrecomputeProgress progress() const;
    // Cancels and lets a task of `tasks` destroy the scheduler (the job is then not started).
    void dispose(tbb::task_group& tasks);

  private:
    std::shared_ptr<PrecomputeScheduler> scheduler_;
};

}  // namespace penumbra::viewer
