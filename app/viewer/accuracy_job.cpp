#include "app/viewer/accuracy_job.h"

#include <exception>
#include <utility>

namespace penumbra::viewer {

void AccuracyJob::start(std::shared_ptr<LoadedScene> scene, const Camera& camera,
                        tbb::task_group& tasks) {
    if (!scene || running()) return;
    auto state = std::make_shared<State>();
    state->scene = std::move(scene);
    state_ = state;
    AccuracyStudyOptions options;
    options.width = options.height = kSize;
    options.spp = kSpp;
    tasks.run([state, camera, options] {
        try {
            state->result =
                runAccuracyStudy(state->scene->scene, *state->scene->bvh, *state->scene->store,
                                 camera, options, &state->cancel, &state->progress);
        } catch (const std::exception&) {
            state->result = {};  // reported as an incomplete study
        }
        state->done = true;
    });
}

void AccuracyJob::cancel() {
    if (state_) state_->cancel = true;
}

void AccuracyJob::drop() {
    cancel();
    state_.reset();
}

std::optional<AccuracyStudy> AccuracyJob::takeResult() {
    if (!state_ || !state_->done || state_->cancel) return std::nullopt;
    std::optional<AccuracyStudy> out = std::move(state_->result);
    state_.reset();
    return out;
}

}  // namespace penumbra::viewer
