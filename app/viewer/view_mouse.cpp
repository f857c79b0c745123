#include "app/viewer/view_mouse.h"

#include <imgui.h>

#include <algorithm>
#include <cmath>

namespace penumbra::viewer {

ViewMouse::Result ViewMouse::update(const Viewport& vp, int width, bool splitShown,
                                    LayoutSettings& columns, double& split, OrbitCamera& camera) {
    const ImGuiIO& io = ImGui::GetIO();
    Result result;
    const bool overView = vp.contains(io.MousePos.x, io.MousePos.y) && !io.WantCaptureMouse;
    // The columns' edges: a press on the view's first or last 5 pixels drags that column's edge.
    if (overView && ImGui::IsMouseClicked(ImGuiMouseButton_Left)) {
        if (io.MousePos.x < vp.x + 5) draggingColumn_ = -1;
        if (io.MousePos.x >= vp.x + vp.width - 5) draggingColumn_ = +1;
    }
    if (draggingColumn_ != 0) {
        result.dragged = true;
        if (ImGui::IsMouseDown(ImGuiMouseButton_Left)) {
            const int x = static_cast<int>(io.MousePos.x);
            if (draggingColumn_ < 0)
                columns.leftWidth = std::clamp(x, 60, width);
            else
                columns.rightWidth = std::clamp(width - x, 60, width);
            result.resized = true;
            return result;
        }
        draggingColumn_ = 0;
        return result;  // the release ends the drag, it picks nothing
    }
    // The split line of the rendered side-by-side view: a press within 6 pixels of it drags it.
    const double splitX = vp.x + split * vp.width;
    if (splitShown && overView && ImGui::IsMouseClicked(ImGuiMouseButton_Left) &&
        std::fabs(io.MousePos.x - splitX) <= 6)
        draggingSplit_ = true;
    if (draggingSplit_) {
        result.dragged = true;
        if (ImGui::IsMouseDown(ImGuiMouseButton_Left) && splitShown) {
            split = std::clamp((static_cast<double>(io.MousePos.x) - vp.x) / std::max(1, vp.width),
                               0.0, 1.0);
            return result;
        }
        draggingSplit_ = false;
        return result;  // the release ends the drag, it picks nothing
    }
    if (overView || ImGui::IsMouseDragging(ImGuiMouseButton_Left) ||
        ImGui::IsMouseDragging(ImGuiMouseButton_Right)) {
        if (!io.WantCaptureMouse) {
            if (ImGui::IsMouseDragging(ImGuiMouseButton_Left, 2.0f)) {
                camera.orbit(io.MouseDelta.x, io.MouseDelta.y);
                result.moved = io.MouseDelta.x != 0 || io.MouseDelta.y != 0;
            } else if (ImGui::IsMouseDragging(ImGuiMouseButton_Right, 2.0f) ||
                       ImGui::IsMouseDragging(ImGuiMouseButton_Middle, 2.0f)) {
                camera.pan(io.MouseDelta.x, io.MouseDelta.y, vp.height);
                result.moved = io.MouseDelta.x != 0 || io.MouseDelta.y != 0;
            }
        }
    }
    if (overView && io.MouseWheel != 0) {
        camera.zoom(io.MouseWheel);
        result.moved = true;
    }
    // A click (release without a drag) picks.
    result.pick = overView && ImGui::IsMouseReleased(ImGuiMouseButton_Left) &&
                  io.MouseDragMaxDistanceSqr[ImGuiMouseButton_Left] < 9.0f;
    return result;
}

}  // namespace penumbra::viewer
