#include "app/viewer/precompute_job.h"

#include <utility>

namespace penumbra::viewer {

void PrecomputeJob::start(VisibilityStore& store) {
    if (!scheduler_) scheduler_ = std::make_shared<PrecomputeScheduler>(store);
    scheduler_->requestAll();
}

void PrecomputeJob::start(VisibilityStore& store, std::vector<PairKey> keys) {
    if (!scheduler_) scheduler_ = std::make_shared<PrecomputeScheduler>(store);
    scheduler_->request(std::move(keys));
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

void PrecomputeJob::dispose(tbb::task_group& tasks, std::shared_ptr<const void> keepAlive) {
    if (!scheduler_) return;
    scheduler_->cancel();
    // Members go in reverse order: the scheduler (which waits for its builds) before the store.
    struct Disposal {
        std::shared_ptr<const void> keepAlive;
        std::shared_ptr<PrecomputeScheduler> old;
        void operator()() const {}
    };
    tasks.run(Disposal{std::move(keepAlive), std::move(scheduler_)});
}

}  // namespace penumbra::viewer
