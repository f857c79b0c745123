#include "app/viewer/light_move_job.h"

#include <algorithm>
#include <exception>
#include <utility>

namespace penumbra::viewer {

void LightMoveJob::request(std::shared_ptr<const LoadedScene> from, std::vector<LightMove> moves,
                           const ExactOptions& exact, tbb::task_group& tasks) {
    const std::lock_guard lock(mutex_);
    versions_ = std::max(versions_ + 1, from->version + 1);
    waiting_ = Request{std::move(from), std::move(moves), exact, generation_, versions_};
    if (building_) return;  // the running task takes it next
    building_ = true;
    tasks.run([this] { work(); });
}

void LightMoveJob::work() {
    for (;;) {
        Request r;
        {
            const std::lock_guard lock(mutex_);
            if (!waiting_) {
                building_ = false;
                return;
            }
            r = std::move(*waiting_);
            waiting_.reset();
        }
        Result result;
        result.moves = r.moves;
        try {
            result.scene = withLightMoves(*r.from, r.moves, r.exact, r.version);
        } catch (const std::exception& e) {
            result.error = e.what();
        }
        const std::lock_guard lock(mutex_);
        if (r.generation == generation_) done_ = std::move(result);
    }
}

std::optional<LightMoveJob::Result> LightMoveJob::take() {
    const std::lock_guard lock(mutex_);
    std::optional<Result> out = std::move(done_);
    done_.reset();
    return out;
}

bool LightMoveJob::busy() const {
    const std::lock_guard lock(mutex_);
    return building_ || waiting_.has_value();
}

void LightMoveJob::drop() {
    const std::lock_guard lock(mutex_);
    ++generation_;
    waiting_.reset();
    done_.reset();
}

}  // namespace penumbra::viewer
