// Layout: the default places of the panels and of the 3D view in a framebuffer of a given size,
// below the menu bar. The left column holds the scene, precompute, history-tree and preview panels
// (top to bottom), the right column the point, light-plane and path panels; the 3D view lies
// between. Help opens over the Path panel (empty until a point is inspected), never over the 3D
// view; the status line and the colour scale float over the view. The user moves, resizes,
// collapses and enlarges the panels from there (panel_arrangement.h); an enlarged panel fills the
// `enlarged` rectangle, most of the window.
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
    PanelRect help;                              // over the Path panel
    PanelRect enlarged;  // an enlarged panel: the window below the menu bar, less a margin
};
// What shapes the layout besides the framebuffer's size: the monitor's content scale (HiDPI:
// GLFW's window content scale; panel sizes and text grow with it) and the columns' widths the
// user dragged (0: the default, a share of the width capped at 340 and 440 pixels times the
// scale). The view keeps at least kMinViewWidth pixels times the scale: wider columns are narrowed.
// `top`: the menu bar's height (the panels and the view lie below it). Without the history tree
// (`tree` false: T hides it) the Preview panel takes its place.
struct LayoutSettings {
    float scale = 1;
    int leftWidth = 0, rightWidth = 0;
    int top = 0;
    bool tree = true;
};
inline constexpr int kMinViewWidth = 240;

// Every docked rectangle lies inside the framebuffer below `top`, none overlaps another or the
// view, and together with the view they tile it (tests/app/viewer/viewer_test.cpp checks sizes from
// 1280x720 to 3840x2160 at scales 1 to 2).
Layout computeLayout(int width, int height, const LayoutSettings& settings = {});

}  // namespace penumbra::viewer
