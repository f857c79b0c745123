// The Help window (H): the keys and mouse actions, over the bottom left of the 3D view; and the
// status line over its top left (the last action's message and the frame time).
#pragma once

#include <string>

#include "app/viewer/gl/scene_renderer.h"

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
    void draw(const Viewport& view);  // when visible (its close button hides it)

  private:
    bool visible_;
};

struct StatusBar {
    static void draw(const Viewport& view, const std::string& status, const FrameStats& frames);
};

}  // namespace penumbra::viewer
