#include "app/viewer/panels/path_panel.h"

#include <string>

#include "app/viewer/panels/panel.h"

namespace penumbra::viewer {

void PathPanel::draw(const Selection& selection) {
    if (ImGui::Begin("Path", nullptr, kPanelWindow)) {
        const LightInspection* li = selection.selectedLight();
        if (!li) {
            ImGui::TextUnformatted("The history-tree path of the selected light.");
        } else if (!li->result.fromTree) {
            ImGui::TextWrapped("light %u: building the pair's history tree; its path follows.",
                               li->result.light);
            if (li->result.faceGroups > 0)
                ImGui::TextWrapped(
                    "answered without the tree: %u groups of faces seen all from one side were "
                    "taken whole (only their boundaries were clipped)",
                    li->result.faceGroups);
            if (li->result.hiddenBySolid)
                ImGui::TextWrapped(
                    "the point lies inside a closed surface (or the light does): no segment to "
                    "the light leaves it");
            else if (li->result.solidGroupsLeftOut + li->result.solidFacesLeftOut > 0)
                ImGui::TextWrapped(
                    "closed surfaces taken as solids: %u groups and %u faces seen from behind "
                    "left out (a segment that crosses such a surface crosses it from the front)",
                    li->result.solidGroupsLeftOut, li->result.solidFacesLeftOut);
        } else {
            const std::string kind(vis::describeKind(li->result.kind, li->result.horizonClipped));
            ImGui::TextWrapped("light %u, tree %s: %zu nodes visited (L cycles lights)",
                               li->result.light, kind.c_str(), li->steps.size());
            if (li->result.horizonClipped)
                ImGui::TextWrapped(
                    "the point's horizon (its face's plane) cuts the light: %.2f%% of it is "
                    "visible%s",
                    100 * li->result.fraction,
                    li->result.kind == vis::PairKind::FullyVisible
                        ? ", the part above, with nothing in the pair's shaft"
                        : "");
            if (li->result.deferredOccluders > 0)
                ImGui::TextWrapped(
                    "partial tree: %u deferred occluders, %u clipped from this point "
                    "(%u clips changed a fragment)",
                    li->result.deferredOccluders, li->result.deferredActive,
                    li->result.deferredClips);
            if (li->result.answeredOnContact)
                ImGui::TextWrapped(
                    "x lies in the plane of an occluder touching the receiver: answered from the "
                    "pair's occluders directly (the contact rule), no path");
            if (ImGui::BeginTable("path", 5,
                                  // Columns as wide as their headers and values ("edge v0 -> v1"
                                  // and the vertex ids were cut off in five equal columns).
                                  ImGuiTableFlags_Borders | ImGuiTableFlags_RowBg |
                                      ImGuiTableFlags_ScrollY | ImGuiTableFlags_SizingFixedFit)) {
                ImGui::TableSetupScrollFreeze(0, 1);
                ImGui::TableSetupColumn("depth");
                ImGui::TableSetupColumn("node");
                ImGui::TableSetupColumn("edge v0 -> v1");
                ImGui::TableSetupColumn("occluder");
                ImGui::TableSetupColumn("side");
                ImGui::TableHeadersRow();
                ImGuiListClipper clipper;
                clipper.Begin(static_cast<int>(li->steps.size()));
                while (clipper.Step())
                    for (int i = clipper.DisplayStart; i < clipper.DisplayEnd; ++i) {
                        const PathStep& s = li->steps[static_cast<size_t>(i)];
                        ImGui::TableNextRow();
                        ImGui::TableNextColumn();
                        ImGui::Text("%u", s.depth);
                        ImGui::TableNextColumn();
                        ImGui::Text("%u", s.node);
                        ImGui::TableNextColumn();
                        ImGui::Text("%u -> %u", s.v0, s.v1);
                        ImGui::TableNextColumn();
                        if (s.occluderFace == PathStep::kNoOccluder)
                            ImGui::TextUnformatted("?");
                        else
                            ImGui::Text("face %u", s.occluderFace);
                        ImGui::TableNextColumn();
                        ImGui::TextUnformatted(vis::toString(s.side));
                    }
                ImGui::EndTable();
            }
        }
    }
    ImGui::End();
}

}  // namespace penumbra::viewer
