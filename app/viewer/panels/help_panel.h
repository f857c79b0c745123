// The Help window (H): the keys and mouse actions, over the bottom left of the 3D view; and the
// status line over its top left (the last action's message and the frame time).
#pragma once

#include <string>

#include "app/viewer/layout.h"
#include "app/viewer/viewport.h"

namespace penumbra::viewer {

struct FrameStats {
    size_t frames = 0;
    double maxSeconds = 0, sumSeconds = 0, lastSeconds = 0;
};

class HelpPanel {
  public:
    explicit HelpPanel(bool visible) : visible_(visible) {}
    bool visible() const { return visible_; }
    void toggle() { visible_ = !visible_; }
    // When visible (its close button hides it). Returns the window's rectangle (empty when hidden),
    // always inside the 3D view: its text wraps at the view's width.
    PanelRect draw(const Viewport& view);

  private:
    bool visible_;
};

struct StatusBar {
    // Returns the window's rectangle, inside the 3D view as the Help's.
    static PanelRect draw(const Viewport& view, const std::string& status,
                          const FrameStats& frames);
};

}  // namespace penumbra::viewer
