// AccuracyJob: the "Accuracy vs time" study (engine/studies/accuracy_study.h) of the current
// scene and view, measured on a background task: start, cancel, progress, and the result once it
// is done. A study belongs to the scene it measured: opening another scene drops it.
#pragma once

#include <tbb/task_group.h>

#include <atomic>
#include <memory>
#include <optional>

#include "app/viewer/loaded_scene.h"
#include "engine/studies/accuracy_study.h"

namespace penumbra::viewer {

class AccuracyJob {
  public:
    // Small images: the study renders 12 sampled images and a 2 x 2048-ray reference.
    static constexpr int kSize = 64, kSpp = 2;

    // Starts a study of `scene` seen from `camera` on a task of `tasks` (ignored while one runs).
    void start(std::shared_ptr<LoadedScene> scene, const Camera& camera, tbb::task_group& tasks);
    void cancel();
    // Cancels and forgets the study (its task keeps the old scene alive until it stops).
    void drop();
    bool running() const { return state_ && !state_->done; }
    double progress() const { return state_ ? state_->progress.load() : 0.0; }
    // The finished study, once (nullopt while running, after a cancel, or when already taken).
    std::optional<AccuracyStudy> takeResult();

  private:
    struct State {
        std::shared_ptr<LoadedScene> scene;  // kept alive while the study runs
        std::atomic<bool> cancel{false};
        std::atomic<bool> done{false};
        std::atomic<double> progress{0};
        AccuracyStudy result;  // written by the task before `done`, read after
    };
    std::shared_ptr<State> state_;
};

}  // namespace penumbra::viewer
