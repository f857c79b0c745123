#include "app/viewer/panels/light_plane_panel.h"

#include <algorithm>
#include <vector>

#include "app/viewer/panels/panel.h"

namespace penumbra::viewer {

void LightPlanePanel::draw(const Selection& selection, const vis::PolygonMesh* mesh) {
    if (ImGui::Begin("Light plane", nullptr, kPanelWindow)) {
        const LightInspection* li = selection.selectedLight();
        if (!li || !mesh) {
            ImGui::TextUnformatted("The selected light's visible fragments, in its plane.");
        } else {
            const auto face = mesh->face(li->result.lightFace);
            ImGui::TextWrapped("light %u: %zu fragments, %.2f%% visible", li->result.light,
                               li->result.fragments.size(), 100 * li->result.fraction);
            const size_t loops = li->result.outline.loops.size();
            ImGui::TextWrapped("boundary: %zu loop%s, %zu edges", loops, loops == 1 ? "" : "s",
                               li->result.outline.edges());
            // A frame of the light's plane: u along its first edge, v = n x u (the light seen from
            // its front, counter-clockwise stays counter-clockwise).
            const Vec3 o = mesh->vertices[face[0]];
            const Vec3 n = normalize(mesh->faceAreaNormal(li->result.lightFace));
            const Vec3 u = normalize(mesh->vertices[face[1]] - o);
            const Vec3 v = cross(n, u);
            double lo[2] = {1e300, 1e300}, hi[2] = {-1e300, -1e300};
            for (uint32_t id : face) {
                const Vec3 d = mesh->vertices[id] - o;
                const double c[2] = {dot(d, u), dot(d, v)};
                for (int i = 0; i < 2; ++i) {
                    lo[i] = std::min(lo[i], c[i]);
                    hi[i] = std::max(hi[i], c[i]);
                }
            }
            const ImVec2 avail = ImGui::GetContentRegionAvail();
            const ImVec2 origin = ImGui::GetCursorScreenPos();
            const double span = std::max(hi[0] - lo[0], hi[1] - lo[1]);
            const double scale = span > 0 ? (std::min(avail.x, avail.y) - 16) / span : 1.0;
            auto toScreen = [&](const Vec3& p) {
                const Vec3 d = p - o;
                return ImVec2(origin.x + 8 + static_cast<float>((dot(d, u) - lo[0]) * scale),
                              origin.y + 8 + static_cast<float>((hi[1] - dot(d, v)) * scale));
            };
            ImDrawList* draw = ImGui::GetWindowDrawList();
            std::vector<ImVec2> pts;
            for (uint32_t id : face) pts.push_back(toScreen(mesh->vertices[id]));
            draw->AddConvexPolyFilled(pts.data(), static_cast<int>(pts.size()),
                                      IM_COL32(60, 60, 60, 255));
            for (size_t i = 0; i < li->result.fragments.size(); ++i) {
                pts.clear();
                for (const Vec3& p : li->result.fragments[i]) pts.push_back(toScreen(p));
                draw->AddConvexPolyFilled(pts.data(), static_cast<int>(pts.size()),
                                          toImU32(fragmentColour(i)));
                draw->AddPolyline(pts.data(), static_cast<int>(pts.size()),
                                  toImU32(kPieceEdgeColour), ImDrawFlags_Closed, 1.0f);
            }
            pts.clear();
            for (uint32_t id : face) pts.push_back(toScreen(mesh->vertices[id]));
            draw->AddPolyline(pts.data(), static_cast<int>(pts.size()),
                              IM_COL32(255, 255, 255, 255), ImDrawFlags_Closed, 1.5f);
            // The visible region's boundary, over its pieces.
            for (const vis::Polygon3& loop : li->result.outline.loops) {
                pts.clear();
                for (const Vec3& p : loop) pts.push_back(toScreen(p));
                draw->AddPolyline(pts.data(), static_cast<int>(pts.size()), toImU32(kOutlineColour),
                                  ImDrawFlags_Closed, 2.5f);
            }
            ImGui::Dummy(avail);
        }
    }
    ImGui::End();
}

}  // namespace penumbra::viewer
