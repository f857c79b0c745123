#include "app/viewer/panels/preview_panel.h"

#include <algorithm>
#include <array>
#include <cstdint>
#include <utility>

#include "app/viewer/panels/colour_scale.h"
#include "app/viewer/panels/flow_layout.h"
#include "app/viewer/panels/panel.h"

namespace penumbra::viewer {

bool parseViewName(std::string_view name, ViewMode& view, PreviewMode& mode) {
    if (name == "raster") {
        view = ViewMode::Raster;
        return true;
    }
    const std::pair<std::string_view, PreviewMode> rendered[] = {{"rendered", PreviewMode::Exact},
                                                                 {"sampled", PreviewMode::Sampled},
                                                                 {"side", PreviewMode::SideBySide},
                                                                 {"diff", PreviewMode::Difference},
                                                                 {"answers", PreviewMode::Answers}};
    for (const auto& [n, m] : rendered)
        if (name == n) {
            view = ViewMode::Rendered;
            mode = m;
            return true;
        }
    return false;
}

PreviewPanel::Action PreviewPanel::draw(PreviewSettings& s, ViewMode& view, ExactOptions& exact,
                                        std::array<char, 256>& saveStem, const PreviewImage& image,
                                        bool running, uint32_t texture,
                                        const std::string& viewNote) {
    bool changed = false, save = false, reopen = false;
    if (ImGui::Begin("Preview", nullptr, kPanelWindow)) {
        bool rendered = view == ViewMode::Rendered;
        if (ImGui::Checkbox("in the 3D view (V)", &rendered)) {
            view = rendered ? ViewMode::Rendered : ViewMode::Raster;
            changed = true;
        }
        if (!viewNote.empty()) ImGui::TextWrapped("%s", viewNote.c_str());
        // The widgets leave room for their labels beside them (the longest), the vertical
        // scrollbar included: no label is cut off in a narrow panel.
        ImGui::PushItemWidth(-ImGui::CalcTextSize("light samples").x -
                             ImGui::GetStyle().ItemInnerSpacing.x);
        int mode = static_cast<int>(s.mode);
        const char* names[] = {"exact", "sampled", "side by side", "difference", "answers"};
        if (ImGui::Combo("mode (1-5)", &mode, names, 5)) {
            s.mode = static_cast<PreviewMode>(mode);
            changed = true;
        }
        if (ImGui::SliderInt("light samples", &s.lightSamples, 1, 256)) changed = true;
        if (ImGui::SliderInt("passes (spp)", &s.passes, 1, 256)) changed = true;
        ImGui::PopItemWidth();
        if (ImGui::TreeNode("exact options")) {
            ImGui::PushItemWidth(-ImGui::CalcTextSize("grouped shaft from").x -
                                 ImGui::GetStyle().ItemInnerSpacing.x);
            // The command line's --min-tree-samples, --grouped-shaft-min, --exact-work-limit,
            // --light-edge-work-limit, --chain-min-occluders, --max-lp-solves.
            const uint64_t step = 1;
            if (ImGui::InputScalar("min tree samples", ImGuiDataType_U64, &exact.minTreeSamples,
                                   &step))
                changed = true;
            if (ImGui::IsItemHovered())
                ImGui::SetTooltip(
                    "a pair the image samples fewer times gets no history tree (the "
                    "same answer; 0 = a tree for every pair)");
            const uint32_t step32 = 1;
            if (ImGui::InputScalar("grouped shaft from", ImGuiDataType_U32, &exact.groupedShaftMin,
                                   &step32))
                changed = true;
            if (ImGui::IsItemHovered())
                ImGui::SetTooltip(
                    "a pair whose shaft holds at least this many faces, a quarter of them in "
                    "face groups, gets no history tree: the groups answer its points (the same "
                    "answer; 0 = build it)");
            if (ImGui::InputScalar("work limit", ImGuiDataType_U64, &exact.exactWorkLimit, &step))
                changed = true;
            if (ImGui::IsItemHovered())
                ImGui::SetTooltip(
                    "plane tests one point may make before the light-edge path answers it "
                    "(0 = every point exact)");
            if (ImGui::InputScalar("light-edge limit", ImGuiDataType_U64, &exact.lightEdgeWorkLimit,
                                   &step))
                changed = true;
            if (ImGui::IsItemHovered())
                ImGui::SetTooltip(
                    "plane tests of the light-edge path on a point over the work limit (the "
                    "light's silhouette edges near it, the same answer); over them too it is "
                    "sampled and counted (0 = sampled at once)");
            if (ImGui::InputScalar("chain from", ImGuiDataType_U32, &exact.chainMinOccluders,
                                   &step32))
                changed = true;
            if (ImGui::IsItemHovered())
                ImGui::SetTooltip(
                    "a point clipped against at least this many occluders, most of whose edges "
                    "cancel, uses their silhouette and border edges only (the same answer; 0 = "
                    "never)");
            ImGui::InputScalar("build budget", ImGuiDataType_U64, &exact.maxLpSolves, &step);
            if (ImGui::IsItemHovered())
                ImGui::SetTooltip(
                    "linear programs one history tree may solve; a tree reaching it "
                    "is partial (the same answer; 0 = no limit)");
            sameLineIfFits(ImGui::CalcTextSize("apply").x + 2 * ImGui::GetStyle().FramePadding.x);
            if (ImGui::SmallButton("apply")) reopen = true;
            ImGui::PopItemWidth();
            ImGui::TreePop();
        }
        // Of the image shown (a restart pending after a change keeps it until the new one's first
        // pass): its own passes, and whether it is a coarse pass or the render of these settings.
        if (image.coarse)
            ImGui::TextWrapped("a coarse pass, %.2f s (the camera moved; the full render follows)",
                               image.seconds);
        else
            ImGui::Text("%d / %d passes, %.1f s%s", image.passes,
                        image.passesPlanned > 0 ? image.passesPlanned : s.passes, image.seconds,
                        // A finished image while a render runs is the last one's.
                        image.passes == 0 ? ""
                        : image.finished  ? (running ? " (rendering anew)" : " (done)")
                        : running         ? ""
                                          : " (stopped)");
        if (image.relativeRmsError >= 0)
            ImGui::Text("sampled vs exact: %.2f%% RMS", 100 * image.relativeRmsError);
        if (s.mode == PreviewMode::Answers && !image.answers.empty()) drawAnswersLegend(image);
        if (s.mode == PreviewMode::Difference && image.differenceWhite > 0)
            drawDifferenceScale(image);
        if (!image.error.empty()) ImGui::TextWrapped("error: %s", image.error.c_str());
        // Keep what you see: STEM.png, STEM.pfm, STEM.exr and STEM.json (the scene with this
        // camera).
        ImGui::SetNextItemWidth(std::max(
            4 * ImGui::GetFontSize(), ImGui::GetContentRegionAvail().x - buttonWidth("Save view") -
                                          ImGui::GetStyle().ItemSpacing.x));
        ImGui::InputText("##stem", saveStem.data(), saveStem.size());
        ImGui::SameLine();
        if (ImGui::Button("Save view") && saveStem[0] != 0) save = true;
        if (ImGui::IsItemHovered())
            ImGui::SetTooltip(
                "writes STEM.png, STEM.pfm and STEM.exr (linear) and STEM.json (this camera)");
        if (image.width > 0) {
            // The whole image in the space left, aspect kept.
            const ImVec2 avail = ImGui::GetContentRegionAvail();
            const float scale =
                std::max(0.0f, std::min(avail.x / static_cast<float>(image.width),
                                        avail.y / static_cast<float>(image.height)));
            ImGui::Image(reinterpret_cast<ImTextureID>(static_cast<intptr_t>(texture)),
                         ImVec2(scale * static_cast<float>(image.width),
                                scale * static_cast<float>(image.height)));
        }
    }
    ImGui::End();
    if (reopen) return Action::Reopen;
    if (save) return Action::SaveView;
    return changed ? Action::Restart : Action::None;
}

}  // namespace penumbra::viewer
