// The "Move light" window (M, or the Scene panel's button): pick an area light, drag its
// translation, rotation and scale (engine/scene/light_move.h: about the light's centre, from where
// the file put it; a scale factor of 0 or below is refused by the fields and by the move), reset
// it. Over the 3D view's top right, movable. It says what is true of the move now: whether the
// moved scene is still being built, refused and why, and the trees of the position before: how
// many were invalidated and how many are rebuilt in the background; the preview meanwhile answers
// from the tree-less query.
#pragma once

#include <cstdint>
#include <optional>
#include <string>

#include "app/viewer/layout.h"
#include "app/viewer/loaded_scene.h"
#include "engine/precompute/precompute_scheduler.h"

namespace penumbra::viewer {

// What the window reports besides the scene (the viewer's state of the move).
struct LightMoveStatus {
    bool building = false;  // a moved scene is being built (LightMoveJob::busy)
    std::string refused;    // the last move refused, and why ("" when none)
    // The trees of the position before the move: how many were invalidated (0: none had been
    // built), and the background rebuild of those pairs in the moved scene (nullopt: none).
    size_t invalidated = 0;
    size_t kept = 0;  // the trees the last move left true, kept (moved_light_trees.h)
    std::optional<PrecomputeProgress> rebuild;
    bool treeLess = false;  // the preview evaluates without trees (Preview::treeLess)
};

class LightPanel {
  public:
    bool visible() const { return visible_; }
    void toggle() { visible_ = !visible_; }
    void show() { visible_ = true; }
    uint32_t light() const { return light_; }

    struct Move {
        uint32_t light = 0;
        LightMove move;
    };
    // Draws the window over `view` when visible; returns the move the user made this frame.
    // `rect` receives the window's rectangle (for the viewer's record of panels).
    std::optional<Move> draw(const Viewport& view, const LoadedScene* scene,
                             const LightMoveStatus& status, PanelRect& rect);

  private:
    bool visible_ = false;
    uint32_t light_ = 0;
    LightMove edit_;                        // what the fields show
    uint64_t shownVersion_ = ~uint64_t{0};  // the scene version edit_ was taken from
    const LoadedScene* shownScene_ = nullptr;
    float lastWidth_ = 0;  // the window's width when last drawn (where it opens; 0: never)
};

}  // namespace penumbra::viewer
