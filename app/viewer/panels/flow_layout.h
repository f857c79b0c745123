// Flow layout for a panel's rows of buttons and legends: an item follows the previous one on its
// line while it fits the window's width, else it starts the next line, so that no label is cut off
// by a narrow panel (panels/panel_fit.h measures that none is).
#pragma once

#include <imgui.h>

namespace penumbra::viewer {

// Before an item `width` pixels wide that should follow the previous item on its line, `spacing`
// pixels after it (< 0: the style's item spacing), if it fits.
inline void sameLineIfFits(float width, float spacing = -1) {
    const float gap = spacing >= 0 ? spacing : ImGui::GetStyle().ItemSpacing.x;
    const float right = ImGui::GetWindowPos().x + ImGui::GetWindowContentRegionMax().x;
    if (ImGui::GetItemRectMax().x + gap + width <= right) ImGui::SameLine(0, gap);
}

// The width of a button with this label (as ImGui::Button sizes it).
inline float buttonWidth(const char* label) {
    return ImGui::CalcTextSize(label, nullptr, true).x + 2 * ImGui::GetStyle().FramePadding.x;
}

}  // namespace penumbra::viewer
