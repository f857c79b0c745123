// AccuracyWindows: the viewer's "Accuracy vs time" study as it is shown: the "Accuracy controls"
// window (measure this view, the progress, cancel) and, once a study has finished, the "Accuracy
// vs time" window (its plot: ui::AccuracyPanel), both first placed over the 3D view; shown or
// hidden (the A key), with the background job they drive (AccuracyJob, edited here).
#pragma once

#include <tbb/task_group.h>

#include <memory>

#include "app/viewer/accuracy_job.h"
#include "app/viewer/loaded_scene.h"
#include "app/viewer/panels/accuracy_panel.h"
#include "app/viewer/viewport.h"
#include "engine/scene/camera.h"

namespace penumbra::viewer {

class AccuracyWindows {
  public:
    // Shows the windows and starts the study of `scene` seen from `camera` on a task of `tasks`
    // (AccuracyJob::start: ignored while one runs).
    void open(std::shared_ptr<LoadedScene> scene, const Camera& camera, tbb::task_group& tasks);
    void toggle() { shown_ = !shown_; }
    bool shown() const { return shown_; }
    bool running() const { return job_.running(); }
    void cancel() { job_.cancel(); }
    // Another scene: the study measured the old one (a running one is dropped, a finished one is
    // no longer shown).
    void drop();

    // Draws the windows (call while shown()), first placed over `view`; the controls' button
    // measures `scene` from `camera` on a task of `tasks`. True when the plot was drawn
    // (plot().windowRect() is then this frame's).
    bool draw(const Viewport& view, const std::shared_ptr<LoadedScene>& scene, const Camera& camera,
              tbb::task_group& tasks);
    const ui::AccuracyPanel& plot() const { return plot_; }

  private:
    AccuracyJob job_;
    ui::AccuracyPanel plot_;
    bool shown_ = false;
};

}  // namespace penumbra::viewer
