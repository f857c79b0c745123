#include "app/viewer/panels/panel_fit.h"

#include <imgui.h>
#include <imgui_internal.h>  // the windows' and tables' extents of the frame

#include <algorithm>

namespace penumbra::viewer {

std::map<std::string, float> measureHorizontalOverflow() {
    std::map<std::string, float> out;
    ImGuiContext& g = *GImGui;
    const auto note = [&](const ImGuiWindow* w, float overflow) {
        const ImGuiWindow* root = w->RootWindow != nullptr ? w->RootWindow : w;
        float& o = out[root->Name];
        o = std::max(o, std::max(0.0f, overflow));
    };
    for (const ImGuiWindow* w : g.Windows) {
        if (w->LastFrameActive != g.FrameCount || w->Hidden) continue;
        const ImGuiWindow* root = w->RootWindow != nullptr ? w->RootWindow : w;
        if (root->Collapsed || (root->Flags & ImGuiWindowFlags_Tooltip) ||
            (root->Flags & ImGuiWindowFlags_Popup))
            continue;
        // A window that scrolls horizontally shows what is past its edge by scrolling.
        if (w->ScrollbarX) {
            note(w, 0);
            continue;
        }
        note(w, w->DC.CursorMaxPos.x - w->InnerClipRect.Max.x);
    }
    for (int i = 0; i < g.Tables.GetMapSize(); ++i) {
        const ImGuiTable* t = g.Tables.TryGetMapData(i);
        if (t == nullptr || t->LastFrameActive != g.FrameCount || t->OuterWindow == nullptr)
            continue;
        const ImGuiWindow* root = t->OuterWindow->RootWindow;
        if (root == nullptr || root->Collapsed || t->InnerWindow->ScrollbarX) continue;
        for (int c = 0; c < t->ColumnsCount; ++c) {
            const ImGuiTableColumn& col = t->Columns[c];
            if (!col.IsEnabled) continue;
            // The cells' items: where the widest one ends, against the column's clip rectangle.
            note(t->OuterWindow,
                 std::max(col.ContentMaxXFrozen, col.ContentMaxXUnfrozen) - col.ClipRect.Max.x);
            // The header (TableHeader): a label wider than its cell is drawn shortened with an
            // ellipsis ("form fa..."), so the items' extent above never shows it cut. ImGui
            // records where the whole label (with its sort arrow) would end,
            // ContentMaxXHeadersIdeal (the column's WorkMinX without a header row); it shows
            // whole up to the column's right edge and its clip rectangle.
            if (col.ContentMaxXHeadersIdeal > col.WorkMinX)
                note(t->OuterWindow,
                     col.ContentMaxXHeadersIdeal - std::min(col.MaxX, col.ClipRect.Max.x));
        }
    }
    return out;
}

}  // namespace penumbra::viewer
