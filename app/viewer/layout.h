// Layout: where the docked panels and the 3D view go in a framebuffer of a given size. The left
// column holds the scene, precompute, history-tree and preview panels (top to bottom), the right
// column the point, light-plane and path panels; the 3D view lies between. The floating windows
// (help, status, accuracy) are placed over the 3D view by their panels.
#pragma once

#include "app/viewer/viewport.h"

namespace penumbra::viewer {

struct PanelRect {
    float x = 0, y = 0, width = 0, height = 0;
};

struct Layout {
    Viewport view;       // the 3D view
    int leftWidth = 0;   // left column: scene, precompute, history tree, preview
    int rightWidth = 0;  // right column: point, light plane, path
    int width = 0, height = 0;
    PanelRect scene, precompute, tree, preview;  // the left column, top to bottom
    PanelRect point, lightPlane, path;           // the right column, top to bottom
};
// What shapes the layout besides the framebuffer's size: the monitor's content scale (HiDPI:
// GLFW's window content scale; panel sizes and text grow with it) and the columns' widths the
// user dragged (0: the default, a share of the width capped at 340 and 440 pixels times the
// scale). The view keeps at least kMinViewWidth pixels times the scale: wider columns are narrowed.
struct LayoutSettings {
    float scale = 1;
    int leftWidth = 0, rightWidth = 0;
};
inline constexpr int kMinViewWidth = 240;

// Every docked rectangle lies inside the framebuffer, none overlaps another or the view, and
// together with the view they tile it (tests/app/viewer/viewer_test.cpp checks sizes from 1280x720 to
// 3840x2160 at scales 1 to 2).
Layout computeLayout(int width, int height, const LayoutSettings& settings = {});

}  // namespace penumbra::viewer
