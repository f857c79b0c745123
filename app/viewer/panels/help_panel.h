// The Help window (H): the keys and mouse actions, a panel placed like the others (it opens over
// the Path panel: layout.h); and the status line over the 3D view's top left (the last action's
// message and the frame time).
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
    void hide() { visible_ = false; }
    // When visible (its close button hides it), where the viewer placed it; the text wraps at the
    // window's width.
    void draw();

  private:
    bool visible_;
};

struct StatusBar {
    // Returns the window's rectangle, inside the 3D view (its text wraps at the view's width).
    static PanelRect draw(const Viewport& view, const std::string& status,
                          const FrameStats& frames);
};

}  // namespace penumbra::viewer
