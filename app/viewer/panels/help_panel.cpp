#include "app/viewer/panels/help_panel.h"

#include <imgui.h>

namespace penumbra::viewer {

namespace {

PanelRect currentWindowRect() {
    const ImVec2 pos = ImGui::GetWindowPos(), size = ImGui::GetWindowSize();
    return {pos.x, pos.y, size.x, size.y};
}

}  // namespace

PanelRect HelpPanel::draw(const Viewport& vp) {
    if (!visible_) return {};
    PanelRect rect;
    ImGui::SetNextWindowPos(
        ImVec2(static_cast<float>(vp.x + 8), static_cast<float>(vp.y + vp.height - 8)),
        ImGuiCond_Always, ImVec2(0, 1));
    ImGui::SetNextWindowBgAlpha(0.75f);
    if (ImGui::Begin("Help (H)", &visible_,
                     ImGuiWindowFlags_AlwaysAutoResize | ImGuiWindowFlags_NoSavedSettings |
                         ImGuiWindowFlags_NoMove)) {
        // Wrapped to the 3D view's width: an overlay of the view never covers a panel.
        ImGui::PushTextWrapPos(static_cast<float>(vp.width) - 32);
        ImGui::TextUnformatted(
            "left drag: orbit     right/middle drag: pan     wheel: zoom\n"
            "click: inspect point   L: next light   Esc: clear   M: move a light\n"
            "F: fit scene   T: tree panel   H: this help   drag the view's side edges: "
            "resize the columns\n"
            "1-5: preview exact / sampled / side by side / difference / answers   R: restart\n"
            "V: the rendered view (the preview in the 3D view; side by side: drag the split "
            "line) or flat colours\n"
            "P: precompute all   C: cancel   A: accuracy vs time   Ctrl+Q: quit   drop scene: "
            "open");
        ImGui::PopTextWrapPos();
        rect = currentWindowRect();
    }
    ImGui::End();
    return rect;
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
        rect = currentWindowRect();
    }
    ImGui::End();
    return rect;
}

}  // namespace penumbra::viewer
