// Selection: the inspected surface point. A selection starts a background inspection
// (point_inspection.h: per light the exact answer, the path, the tree), which may build history
// trees and so never runs on the UI thread; poll() takes its result once it has arrived. Also
// which light of the inspection the panels and the overlay show.
#pragma once

#include <tbb/task_group.h>

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <mutex>
#include <optional>
#include <string>

#include "app/viewer/loaded_scene.h"
#include "app/viewer/point_inspection.h"

namespace penumbra::viewer {

class Selection {
  public:
    // Inspects x on `face` of `scene` on a task of `tasks` (which must outlive it); a previous
    // pending inspection is dropped (its task finishes into nothing).
    void select(std::shared_ptr<LoadedScene> scene, uint32_t face, const Vec3& x,
                tbb::task_group& tasks);
    void clear();

    // What poll() saw.
    enum class Event { None, Arrived, Failed };
    // Takes the pending inspection's result when it has arrived; `message` gets a status line.
    Event poll(std::string& message);

    bool pending() const { return pending_ != nullptr; }
    const std::optional<PointInspection>& inspection() const { return inspection_; }
    // The selected light, an index into inspection()->lights (0 when there are none).
    size_t light() const { return light_; }
    void selectLight(size_t k);
    void nextLight();
    // The selected light's inspection; nullptr with no inspection or no light.
    const LightInspection* selectedLight() const;

  private:
    struct Pending;
    std::shared_ptr<Pending> pending_;
    std::optional<PointInspection> inspection_;
    size_t light_ = 0;
};

}  // namespace penumbra::viewer
