#include "app/viewer/panels/light_panel.h"

#include <imgui.h>

#include <algorithm>
#include <string>

#include "app/viewer/panels/panel.h"

namespace penumbra::viewer {
namespace light_panel_detail {

bool dragVec(const char* label, Vec3& v, float speed, double lo, double hi, const char* format) {
    double values[3] = {v.x, v.y, v.z};
    const bool changed =
        ImGui::DragScalarN(label, ImGuiDataType_Double, values, 3, speed, lo < hi ? &lo : nullptr,
                           lo < hi ? &hi : nullptr, format, ImGuiSliderFlags_AlwaysClamp);
    if (changed) v = {values[0], values[1], values[2]};
    return changed;
}

}  // namespace light_panel_detail

std::optional<LightPanel::Move> LightPanel::draw(const Viewport& view, const LoadedScene* scene,
                                                 const LightMoveStatus& status, PanelRect& rect) {
    using light_panel_detail::dragVec;
    rect = {};
    if (!visible_) return std::nullopt;
    std::optional<Move> out;
    // Its text wraps at this width, which bounds the window's: the fields' rows are narrower.
    const float wrap = ImGui::GetFontSize() * 22;
    // At the view's top right when it opens (its width from the last time it was drawn, else the
    // wrap width and the padding: the first time, so that it covers no panel beside the view),
    // never left of the view; movable after.
    const float width = lastWidth_ > 0 ? lastWidth_ : wrap + 2 * ImGui::GetStyle().WindowPadding.x;
    const float right = static_cast<float>(view.x + view.width - 8);
    const float left = std::max(static_cast<float>(view.x + 8), right - width);
    ImGui::SetNextWindowPos(ImVec2(left, static_cast<float>(view.y + 8)), ImGuiCond_Appearing);
    ImGui::SetNextWindowBgAlpha(0.85f);
    if (ImGui::Begin("Move light (M)", &visible_,
                     ImGuiWindowFlags_AlwaysAutoResize | ImGuiWindowFlags_NoSavedSettings)) {
        const size_t lights = scene ? scene->scene.lights.size() : 0;
        if (lights == 0) {
            ImGui::TextUnformatted(scene ? "The scene has no area light." : "No scene.");
        } else {
            if (light_ >= lights) light_ = 0;
            // The fields follow the scene (a new version, another scene) unless being dragged.
            if ((scene != shownScene_ || scene->version != shownVersion_) &&
                !ImGui::IsAnyItemActive()) {
                edit_ = scene->lightMove(light_);
                shownScene_ = scene;
                shownVersion_ = scene->version;
            }
            ImGui::PushItemWidth(ImGui::GetFontSize() * 12);
            const std::string current = "light " + std::to_string(light_) + " (face " +
                                        std::to_string(scene->scene.lights[light_]) + ")";
            if (ImGui::BeginCombo("light", current.c_str())) {
                for (uint32_t i = 0; i < lights; ++i) {
                    const std::string name = "light " + std::to_string(i) + " (face " +
                                             std::to_string(scene->scene.lights[i]) + ")";
                    if (ImGui::Selectable(name.c_str(), i == light_)) {
                        light_ = i;
                        edit_ = scene->lightMove(i);
                    }
                }
                ImGui::EndCombo();
            }
            const vis::Bounds3 b = scene->bounds;
            const float speed = static_cast<float>(0.002 * b.diagonal());
            bool changed = dragVec("translate", edit_.translate, speed, 0, 0, "%.4g");
            changed |= dragVec("rotate (deg)", edit_.rotateDegrees, 0.5f, -360, 360, "%.2f");
            changed |= dragVec("scale", edit_.scale, 0.005f, 0.01, 100, "%.3f");
            ImGui::PopItemWidth();
            if (ImGui::Button("Reset this light")) {
                edit_ = LightMove{};
                changed = true;
            }
            if (changed) out = Move{light_, edit_};
            // (Every line below wraps: a long count or refusal widened the window over the
            // panels beside the view.)
            ImGui::PushTextWrapPos(ImGui::GetCursorPosX() + wrap);
            ImGui::TextUnformatted(
                "rotation about x, then y, then z; scale along the axes; both about the light's "
                "centre");
            // What is true now.
            const LightMove now = scene->lightMove(light_);
            ImGui::TextUnformatted(now.isIdentity() ? "where the file put it"
                                                    : "moved (save view keeps the move)");
            if (status.building) ImGui::TextUnformatted("building the moved scene...");
            if (!status.refused.empty()) {
                ImGui::PushStyleColor(ImGuiCol_Text, ImVec4(1.0f, 0.6f, 0.4f, 1.0f));
                ImGui::Text("refused: %s", status.refused.c_str());
                ImGui::PopStyleColor();
            }
            if (scene->version > 0) {
                if (status.kept > 0) ImGui::Text("%zu trees of other lights kept", status.kept);
                if (status.invalidated == 0)
                    ImGui::TextUnformatted(status.kept > 0
                                               ? "no tree went stale: none to rebuild"
                                               : "no tree was built before the move: none to "
                                                 "rebuild");
                else if (status.rebuild &&
                         status.rebuild->state == PrecomputeProgress::State::Running)
                    ImGui::Text(
                        "%zu stale trees dropped; rebuilt %zu of their receivers' %zu trees",
                        status.invalidated, status.rebuild->done, status.rebuild->total);
                else if (status.rebuild && status.rebuild->state == PrecomputeProgress::State::Idle)
                    ImGui::Text("%zu stale trees dropped; their receivers' %zu trees rebuilt",
                                status.invalidated, status.rebuild->total);
                else if (status.rebuild)
                    ImGui::Text("%zu stale trees dropped; rebuild %s at %zu of %zu trees",
                                status.invalidated, toString(status.rebuild->state),
                                status.rebuild->done, status.rebuild->total);
                ImGui::TextUnformatted(status.treeLess
                                           ? "preview: tree-less exact query until they are rebuilt"
                                           : "preview: exact, with the rebuilt trees");
            }
            ImGui::PopTextWrapPos();
        }
        const ImVec2 pos = ImGui::GetWindowPos(), size = ImGui::GetWindowSize();
        rect = {pos.x, pos.y, size.x, size.y};
        lastWidth_ = size.x;
    }
    ImGui::End();
    return out;
}

}  // namespace penumbra::viewer
