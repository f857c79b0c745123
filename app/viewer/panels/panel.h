// What the viewer's panels share: the panels' window flags and the formatting of sizes.
#pragma once

#include <imgui.h>

#include <cstddef>
#include <string>

#include "app/viewer/layout.h"
#include "app/viewer/palette.h"

namespace penumbra::viewer {

// A panel's window: the user moves, resizes and collapses it; the viewer places it
// (panel_arrangement.h) and saves where it is in its own settings file, not in imgui.ini.
constexpr ImGuiWindowFlags kPanelWindow = ImGuiWindowFlags_NoSavedSettings;

// "12.3 KiB" / "4.5 MiB".
std::string humanBytes(size_t bytes);

inline ImU32 toImU32(Rgb c, int alpha = 255) { return IM_COL32(c.r, c.g, c.b, alpha); }

}  // namespace penumbra::viewer
