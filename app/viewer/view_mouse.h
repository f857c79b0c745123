// ViewMouse: the mouse over the 3D view. A press on the view's first or last 5 pixels drags that
// column's edge (the layout's column widths); in the rendered side-by-side view, a press within 6
// pixels of the split line drags the line; the release that ends either drag does nothing else.
// Otherwise a left drag orbits the camera, a right or middle drag pans it, the wheel zooms it, and
// a left click (a release after less than 3 pixels of motion) asks to pick the point under the
// mouse. Reads Dear ImGui's input of the frame; the mouse over a window belongs to the window.
#pragma once

#include "app/viewer/layout.h"
#include "app/viewer/orbit_camera.h"
#include "app/viewer/viewport.h"

namespace penumbra::viewer {

class ViewMouse {
  public:
    struct Result {
        // A column's edge or the split line took the mouse this frame (the drag or its release):
        // the frame's other input is left alone.
        bool dragged = false;
        bool resized = false;  // a column's edge moved: the view's size changes
        bool moved = false;    // the camera orbited, panned or zoomed
        bool pick = false;     // a click: pick the point under the mouse
    };

    // One frame: `view` the 3D view, `width` the framebuffer's; `splitShown`: the view shows the
    // split line (at `split`, a fraction of its width). Drags edit `columns`, `split` and `camera`.
    Result update(const Viewport& view, int width, bool splitShown, LayoutSettings& columns,
                  double& split, OrbitCamera& camera);
    bool draggingSplit() const { return draggingSplit_; }

  private:
    bool draggingSplit_ = false;
    int draggingColumn_ = 0;  // -1: the left column's edge, +1: the right one's
};

}  // namespace penumbra::viewer
