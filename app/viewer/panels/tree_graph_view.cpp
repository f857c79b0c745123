#include "app/viewer/panels/tree_graph_view.h"

#include <algorithm>
#include <cmath>

namespace penumbra::ui {

void TreeGraphView::centreOn(double x, double y, double pixelsPerUnitX, double pixelsPerUnitY) {
    zoomX_ = std::clamp(pixelsPerUnitX, kMinZoom, kMaxZoom);
    zoomY_ = std::clamp(pixelsPerUnitY, kMinZoom, kMaxZoom);
    pendingCenter_ = {x, y};
    fitPending_ = false;
}

void TreeGraphView::beginFrame(ImVec2 origin, ImVec2 size, const GraphRect& bounds) {
    canvasOrigin_ = origin;
    canvasSize_ = size;
    if (fitPending_) fitTo(bounds);
    if (pendingCenter_) {
        viewX0_ = pendingCenter_->first - 0.5 * size.x / zoomX_;
        viewY0_ = pendingCenter_->second - 0.5 * size.y / zoomY_;
        pendingCenter_.reset();
    }
}

void TreeGraphView::fitTo(const GraphRect& b) {
    fitPending_ = false;
    const double margin = 12.0;
    const double w = std::max(b.x1 - b.x0, 1e-9), h = std::max(b.y1 - b.y0, 1e-9);
    const double zx = std::max(1.0, canvasSize_.x - 2 * margin) / w;
    const double zy = std::max(1.0, canvasSize_.y - 2 * margin) / h;
    // Each axis fitted on its own, neither beyond 60 px per unit (a tiny tree stays small).
    zoomX_ = std::clamp(std::min(zx, 60.0), kMinZoom, kMaxZoom);
    zoomY_ = std::clamp(std::min(zy, 60.0), kMinZoom, kMaxZoom);
    viewX0_ = 0.5 * (b.x0 + b.x1) - 0.5 * canvasSize_.x / zoomX_;
    viewY0_ = 0.5 * (b.y0 + b.y1) - 0.5 * canvasSize_.y / zoomY_;
}

void TreeGraphView::pan(ImVec2 delta) {
    viewX0_ -= delta.x / zoomX_;
    viewY0_ -= delta.y / zoomY_;
}

void TreeGraphView::zoomAt(ImVec2 at, double steps, bool alongX, bool alongY) {
    const double mx = at.x - canvasOrigin_.x, my = at.y - canvasOrigin_.y;
    const double lx = viewX0_ + mx / zoomX_, ly = viewY0_ + my / zoomY_;
    const double f = std::pow(1.2, steps);
    if (alongX) zoomX_ = std::clamp(zoomX_ * f, kMinZoom, kMaxZoom);
    if (alongY) zoomY_ = std::clamp(zoomY_ * f, kMinZoom, kMaxZoom);
    viewX0_ = lx - mx / zoomX_;
    viewY0_ = ly - my / zoomY_;
}

void TreeGraphView::sameScale() {
    const double cy = viewY0_ + 0.5 * canvasSize_.y / zoomY_;
    zoomY_ = zoomX_;
    viewY0_ = cy - 0.5 * canvasSize_.y / zoomY_;
}

ImVec2 TreeGraphView::toScreen(double x, double y) const {
    return ImVec2(canvasOrigin_.x + float((x - viewX0_) * zoomX_),
                  canvasOrigin_.y + float((y - viewY0_) * zoomY_));
}

std::pair<double, double> TreeGraphView::toLayout(ImVec2 p) const {
    return {viewX0_ + (p.x - canvasOrigin_.x) / zoomX_, viewY0_ + (p.y - canvasOrigin_.y) / zoomY_};
}

GraphRect TreeGraphView::visible() const {
    return {viewX0_, viewY0_, viewX0_ + canvasSize_.x / zoomX_, viewY0_ + canvasSize_.y / zoomY_};
}

}  // namespace penumbra::ui
