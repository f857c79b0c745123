// Selection: the inspected surface point. A selection starts a background inspection
// (engine/precompute/point_inspection.h: per light the exact answer, the path, the tree), which
// may build history trees and so never runs on the UI thread; poll() takes its result once it has
// arrived. Also which light of the inspection the panels and the overlay show.
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
#include "engine/precompute/point_inspection.h"

namespace penumbra::viewer {

class Selection {
  public:
    // Inspects x on `face` of `scene`: at once, on this thread, with the tree-less query
    // (inspectPointDirect: fragments and numbers, inspection()->treesPending), unless it needs
    // more than kClickWork plane tests (clickWorkPerLight: divided evenly among the lights); then
    // in full (trees, paths) on a task of `tasks` (which must outlive it), which poll() takes when
    // it arrives. A previous pending inspection is dropped (its task finishes into nothing).
    // Returns true when the immediate answer is in.
    bool select(std::shared_ptr<LoadedScene> scene, uint32_t face, const Vec3& x,
                tbb::task_group& tasks);
    void clear();

    // What poll() saw.
    enum class Event { None, Arrived, Failed };
    // Takes the pending inspection's result when it has arrived; `message` gets a status line.
    Event poll(std::string& message);

    // The full inspection has not arrived yet (inspection() may hold the immediate answer).
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
