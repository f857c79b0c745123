// Layout: where the docked panels and the 3D view go in a framebuffer of a given size. The left
// column holds the scene, precompute, history-tree and preview panels (top to bottom), the right
// column the point, light-plane and path panels; the 3D view lies between. The floating windows
// (help, status, accuracy) are placed over the 3D view by their panels.
#pragma once

#include "app/viewer/gl/scene_renderer.h"

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
Layout computeLayout(int width, int height);

}  // namespace penumbra::viewer
