// Viewport: a rectangle of the framebuffer in image coordinates (origin top-left, y down), the
// convention of Camera::project and of screenshots. A plain value with no GL and no ImGui, so that
// the GL scene renderer, the layout, picking and the panels all name it without including each
// other.
#pragma once

namespace penumbra::viewer {

struct Viewport {
    int x = 0, y = 0, width = 1, height = 1;
    bool contains(double px, double py) const {
        return px >= x && py >= y && px < x + width && py < y + height;
    }
};

}  // namespace penumbra::viewer
