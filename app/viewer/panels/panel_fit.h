// Whether every panel's text fits its panel: for each window drawn this frame, how many pixels its
// widest item (a label, a value, a button) reaches past the right edge where Dear ImGui clips the
// window, and for each table column past the column's edge, its header's label included (ImGui
// shortens a header too wide for its cell with an ellipsis: the overflow is how much wider the
// whole label is). 0 where everything fits; a label cut off shows as a positive overflow. Read
// after the panels are drawn, before ImGui::Render (the windows' and tables' extents of the frame
// are still there).
#pragma once

#include <map>
#include <string>

namespace penumbra::viewer {

// Top-level window title -> its largest horizontal overflow in pixels (0 when all fits), over the
// window, its child windows and its tables. Collapsed windows are left out.
std::map<std::string, float> measureHorizontalOverflow();

}  // namespace penumbra::viewer
