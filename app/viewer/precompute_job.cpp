#include "app/viewer/precompute_job.h"

#include <utility>

namespace penumbra::viewer {

void PrecomputeJob::start(VisibilityStore& store) {
    if (!scheduler_) scheduler_ = std::make_shared<PrecomputeScheduler>(store);
    scheduler_->requestAll();
}

void PrecomputeJob::cancel() {
    if (scheduler_) scheduler_->cancel();
}

bool PrecomputeJob::running() const {
    return scheduler_ && scheduler_->progress().state == PrecomputeProgress::State::Running;
}

PrecomputeProgress PrecomputeJob::progress() const {
    return scheduler_ ? scheduler_->progress() : PrecomputeProgress{};
}

void PrecomputeJob::dispose(tbb::task_group& tasks) {
    if (!scheduler_) return;
    scheduler_->cancel();
    tasks.run([old = std::move(scheduler_)] {});
}

}  // namespace penumbra::viewer
