#include "app/viewer/panels/point_panel.h"

#include <cstdio>

#include "app/viewer/panels/panel.h"

namespace penumbra::viewer {

bool PointPanel::draw(Selection& selection) {
    bool changed = false;
    if (ImGui::Begin("Point", nullptr, kPanelWindow)) {
        if (selection.pending() && !selection.inspection())
            ImGui::TextUnformatted("computing the point query...");
        if (selection.inspection() && selection.inspection()->treesPending)
            ImGui::TextUnformatted(
                "answered without a tree; the history trees and paths are being built...");
        if (!selection.inspection()) {
            if (!selection.pending())
                ImGui::TextUnformatted("Click a surface point in the 3D view.");
        } else {
            const PointInspection& p = *selection.inspection();
            ImGui::Text("face %u  x = (%.4g, %.4g, %.4g)", p.face, p.point.x, p.point.y, p.point.z);
            ImGui::Text("normal (%.3f, %.3f, %.3f)", p.normal.x, p.normal.y, p.normal.z);
            // (A line of its own, wrapped: beside the normal it was cut off in a narrow column.)
            ImGui::TextWrapped("time*: the history tree was built by this query");
            if (ImGui::BeginTable("lights", 6,
                                  // Columns as wide as their headers and values: "form factor" was
                                  // cut off in six equal columns of the default right column.
                                  ImGuiTableFlags_Borders | ImGuiTableFlags_RowBg |
                                      ImGuiTableFlags_ScrollY | ImGuiTableFlags_SizingFixedFit)) {
                ImGui::TableSetupColumn("light");
                ImGui::TableSetupColumn("visible");
                ImGui::TableSetupColumn("form factor");
                ImGui::TableSetupColumn("frags");
                ImGui::TableSetupColumn("nodes");
                ImGui::TableSetupColumn("time");
                ImGui::TableHeadersRow();
                for (size_t k = 0; k < p.lights.size(); ++k) {
                    const LightInspection& li = p.lights[k];
                    ImGui::TableNextRow();
                    ImGui::TableNextColumn();
                    char label[32];
                    std::snprintf(label, sizeof label, "%u", li.result.light);
                    if (ImGui::Selectable(label, selection.light() == k,
                                          ImGuiSelectableFlags_SpanAllColumns)) {
                        selection.selectLight(k);
                        changed = true;
                    }
                    ImGui::TableNextColumn();
                    ImGui::Text("%.2f%%", 100 * li.result.fraction);
                    ImGui::TableNextColumn();
                    ImGui::Text("%.4g", li.result.formFactor);
                    if (ImGui::IsItemHovered())
                        ImGui::SetTooltip("unoccluded: %.6g (light face %u)",
                                          li.result.unoccludedFormFactor, li.result.lightFace);
                    ImGui::TableNextColumn();
                    ImGui::Text("%zu", li.result.fragments.size());
                    ImGui::TableNextColumn();
                    if (li.result.fromTree)
                        ImGui::Text("%u", li.result.nodesVisited);
                    else
                        ImGui::TextUnformatted("-");
                    ImGui::TableNextColumn();
                    ImGui::Text("%.1f ms%s", 1e3 * li.seconds, li.treeWasBuilt ? "*" : "");
                }
                ImGui::EndTable();
            }
        }
    }
    ImGui::End();
    return changed;
}

}  // namespace penumbra::viewer
