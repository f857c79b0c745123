#include "app/viewer/panels/help_panel.h"

#include <imgui.h>

namespace penumbra::viewer {

void HelpPanel::draw(const Viewport& vp) {
    if (!visible_) return;
    ImGui::SetNextWindowPos(
        ImVec2(static_cast<float>(vp.x + 8), static_cast<float>(vp.y + vp.height - 8)),
        ImGuiCond_Always, ImVec2(0, 1));
    ImGui::SetNextWindowBgAlpha(0.75f);
    if (ImGui::Begin("Help (H)", &visible_,
                     ImGuiWindowFlags_AlwaysAutoResize | ImGuiWindowFlags_NoSavedSettings |
                         ImGuiWindowFlags_NoMove)) {
        ImGui::TextUnformatted(
            "left drag: orbit     right/middle drag: pan     wheel: zoom\n"
            "click: inspect point   L: next light   Esc: clear\n"
            "F: fit scene   T: tree panel   H: this help\n"
            "1-4: preview exact / sampled / side by side / difference   R: restart\n"
            "P: precompute all   C: cancel   A: accuracy vs time   Ctrl+Q: quit   drop scene: "
            "open");
    }
    ImGui::End();
}

void StatusBar::draw(const Viewport& vp, const std::string& status, const FrameStats& frames) {
    ImGui::SetNextWindowPos(ImVec2(static_cast<float>(vp.x + 8), static_cast<float>(vp.y + 8)),
                            ImGuiCond_Always);
    ImGui::SetNextWindowBgAlpha(0.6f);
    if (ImGui::Begin("##status", nullptr,
                     ImGuiWindowFlags_NoDecoration | ImGuiWindowFlags_AlwaysAutoResize |
                         ImGuiWindowFlags_NoSavedSettings | ImGuiWindowFlags_NoFocusOnAppearing |
                         ImGuiWindowFlags_NoNav | ImGuiWindowFlags_NoInputs)) {
        ImGui::TextUnformatted(status.c_str());
        ImGui::Text("frame %.1f ms (max %.1f ms)", 1e3 * frames.lastSeconds,
                    1e3 * frames.maxSeconds);
    }
    ImGui::End();
}

}  // namespace penumbra::viewer
