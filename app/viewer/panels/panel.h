// What the viewer's panels share: the docked panels' window flags and placement, and the
// formatting of sizes.
#pragma once

#include <imgui.h>

#include <cstddef>
#include <string>

#include "app/viewer/layout.h"
#include "app/viewer/palette.h"

namespace penumbra::viewer {

// A docked panel: placed by the layout every frame, not moved, resized or collapsed by the user.
constexpr ImGuiWindowFlags kDockedPanel = ImGuiWindowFlags_NoMove | ImGuiWindowFlags_NoResize |
                                          ImGuiWindowFlags_NoCollapse |
                                          ImGuiWindowFlags_NoSavedSettings;

// The next window goes to `r` (every frame).
inline void placeNextWindow(const PanelRect& r) {
    ImGui::SetNextWindowPos(ImVec2(r.x, r.y), ImGuiCond_Always);
    ImGui::SetNextWindowSize(ImVec2(r.width, r.height), ImGuiCond_Always);
}

// "12.3 KiB" / "4.5 MiB".
std::string humanBytes(size_t bytes);

inline ImU32 toImU32(Rgb c, int alpha = 255) { return IM_COL32(c.r, c.g, c.b, alpha); }

}  // namespace penumbra::viewer
