// TreeGraphView: which part of the history-tree graph's layout plane (tree_graph_layout.h) the
// canvas of the tree browser shows, and at what scale. Layout units become screen pixels with a
// scale per axis: fit() stretches x and y independently, since a 50k-node tree is ~400 times wider
// than deep. The panel pans it with a drag, zooms it at the mouse with the wheel, fits it and sets
// 1:1 from its buttons. A fit or a centre asked for between frames takes effect when the next
// frame gives the canvas (beginFrame), so that it needs no canvas size to be asked for.
#pragma once

#include <imgui.h>

#include <optional>
#include <utility>

#include "app/viewer/panels/tree_graph_layout.h"

namespace penumbra::ui {

class TreeGraphView {
  public:
    static constexpr double kMinZoom = 1e-5, kMaxZoom = 400.0;  // pixels per layout unit

    // The whole layout in view at the next frame, each axis fitted on its own.
    void fit() { fitPending_ = true; }
    // Centred on layout point (x, y) at `pixelsPerUnit` along both axes, or at its own scale along
    // each (from the next frame; a pending fit is dropped).
    void centreOn(double x, double y, double pixelsPerUnit) {
        centreOn(x, y, pixelsPerUnit, pixelsPerUnit);
    }
    void centreOn(double x, double y, double pixelsPerUnitX, double pixelsPerUnitY);

    // The canvas of this frame, on screen; applies a pending fit (to `bounds`, the layout's) and
    // then a pending centre.
    void beginFrame(ImVec2 origin, ImVec2 size, const GraphRect& bounds);
    // Moved with the mouse by `delta` pixels (the layout follows the mouse).
    void pan(ImVec2 delta);
    // Moved by (dx, dy) layout units (what was at x is then shown where x - dx was).
    void moveBy(double dx, double dy) {
        viewX0_ += dx;
        viewY0_ += dy;
    }
    // Zoomed by `steps` wheel steps (1.2 times each) about the screen point `at`, which keeps its
    // layout point; along x only when `alongY` is false, along y only when `alongX` is false.
    void zoomAt(ImVec2 at, double steps, bool alongX, bool alongY);
    // 1:1: the vertical scale set to the horizontal one, about the canvas's centre.
    void sameScale();

    ImVec2 toScreen(double x, double y) const;
    // The layout point under screen point p.
    std::pair<double, double> toLayout(ImVec2 p) const;
    // The part of the layout plane the canvas shows.
    GraphRect visible() const;
    // The layout point at the canvas's top-left corner, and the pixels per layout unit.
    double x0() const { return viewX0_; }
    double y0() const { return viewY0_; }
    double zoomX() const { return zoomX_; }
    double zoomY() const { return zoomY_; }
    // The canvas of the last beginFrame.
    ImVec2 canvasOrigin() const { return canvasOrigin_; }
    ImVec2 canvasSize() const { return canvasSize_; }

  private:
    void fitTo(const GraphRect& bounds);

    double viewX0_ = 0, viewY0_ = 0, zoomX_ = 40, zoomY_ = 40;
    bool fitPending_ = true;
    std::optional<std::pair<double, double>> pendingCenter_;
    ImVec2 canvasOrigin_{0, 0}, canvasSize_{0, 0};
};

}  // namespace penumbra::ui
