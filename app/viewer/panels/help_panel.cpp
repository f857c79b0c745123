#include "app/viewer/panels/help_panel.h"

#include <imgui.h>

#include "app/viewer/panels/panel.h"

namespace penumbra::viewer {

void HelpPanel::draw() {
    if (!visible_) return;
    // Opaque: it opens over the Path panel, whose text must not show through.
    ImGui::SetNextWindowBgAlpha(1.0f);
    if (ImGui::Begin("Help (H)", &visible_, kPanelWindow)) {
        // Wrapped to the window's width: it opens over the Path panel (empty until a point is
        // inspected), never over the 3D view; the user moves and resizes it like any panel.
        ImGui::TextWrapped("left drag: orbit   right/middle drag: pan   wheel: zoom");
        ImGui::TextWrapped("click: inspect point   L: next light   Esc: clear   M: move a light");
        ImGui::TextWrapped("F: fit scene   T: tree panel   H: this help");
        ImGui::TextWrapped(
            "1-5: preview exact / sampled / side by side / difference / answers   R: restart");
        ImGui::TextWrapped(
            "V: the rendered view (the preview in the 3D view; side by side: drag the split "
            "line) or flat colours");
        ImGui::TextWrapped("P: precompute all   C: cancel   A: accuracy vs time");
        ImGui::TextWrapped(
            "Panels: drag the title to move, an edge to resize, the arrow to collapse; E over "
            "a panel enlarges it (E again restores it); Ctrl+L resets the layout (Panels "
            "menu); drag the 3D view's side edges to resize the columns");
        ImGui::TextWrapped("Ctrl+Q: quit   drop a scene file: open it");
    }
    ImGui::End();
}

PanelRect StatusBar::draw(const Viewport& vp, const std::string& status, const FrameStats& frames) {
    PanelRect rect;
    ImGui::SetNextWindowPos(ImVec2(static_cast<float>(vp.x + 8), static_cast<float>(vp.y + 8)),
                            ImGuiCond_Always);
    ImGui::SetNextWindowBgAlpha(0.6f);
    if (ImGui::Begin("##status", nullptr,
                     ImGuiWindowFlags_NoDecoration | ImGuiWindowFlags_AlwaysAutoResize |
                         ImGuiWindowFlags_NoSavedSettings | ImGuiWindowFlags_NoFocusOnAppearing |
                         ImGuiWindowFlags_NoNav | ImGuiWindowFlags_NoInputs)) {
        ImGui::PushTextWrapPos(static_cast<float>(vp.width) - 32);  // within the 3D view
        ImGui::TextUnformatted(status.c_str());
        if (frames.frames == 0)
            ImGui::TextUnformatted("first frame (not timed yet)");
        else
            ImGui::Text("frame %.1f ms (max %.1f ms)", 1e3 * frames.lastSeconds,
                        1e3 * frames.maxSeconds);
        ImGui::PopTextWrapPos();
        const ImVec2 pos = ImGui::GetWindowPos(), size = ImGui::GetWindowSize();
        rect = {pos.x, pos.y, size.x, size.y};
    }
    ImGui::End();
    return rect;
}

}  // namespace penumbra::viewer
