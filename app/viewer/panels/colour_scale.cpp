#include "app/viewer/panels/colour_scale.h"

#include <imgui.h>

#include <algorithm>
#include <array>
#include <cstdio>

#include "app/viewer/palette.h"
#include "app/viewer/panels/panel.h"
#include "engine/render/answers.h"

namespace penumbra::viewer {

void drawDifferenceScale(const PreviewImage& image) {
    const double white = image.differenceWhite;
    ImGui::TextUnformatted("|sampled - exact| luminance:");
    const float width = std::max(40.0f, ImGui::GetContentRegionAvail().x);
    const float height = ImGui::GetTextLineHeight();
    const ImVec2 p = ImGui::GetCursorScreenPos();
    ImDrawList* draw = ImGui::GetWindowDrawList();
    constexpr int kSteps = 48;
    for (int i = 0; i < kSteps; ++i) {
        const float x0 = p.x + width * static_cast<float>(i) / kSteps;
        const float x1 = p.x + width * static_cast<float>(i + 1) / kSteps;
        const Rgb c = heatColour((i + 0.5) / kSteps);
        draw->AddRectFilled(ImVec2(x0, p.y), ImVec2(x1, p.y + height), toImU32(c));
    }
    draw->AddRect(p, ImVec2(p.x + width, p.y + height), IM_COL32(160, 160, 160, 255));
    ImGui::Dummy(ImVec2(width, height));
    // The ticks' numbers under the bar: at 0, 1/3 and 2/3 left-aligned, the top right-aligned.
    const float y = ImGui::GetCursorPosY();
    const float x = ImGui::GetCursorPosX();
    for (int k = 0; k <= 3; ++k) {
        char label[32];
        std::snprintf(label, sizeof label, "%.3g", white * k / 3);
        const float w = ImGui::CalcTextSize(label).x;
        float at = x + width * static_cast<float>(k) / 3;
        at = k == 3 ? at - w : (k == 0 ? at : at - 0.5f * w);
        ImGui::SetCursorPos(ImVec2(at, y));
        ImGui::TextUnformatted(label);
    }
    if (image.meanExactLuminance > 0)
        ImGui::TextWrapped("white: %.3g, 25%% of the exact image's mean luminance %.3g", white,
                           image.meanExactLuminance);
}

void drawAnswersLegend(const PreviewImage& image) {
    const std::array<double, kAnswers> shares = answerShares(totalAnswers(image.answers));
    const float swatch = ImGui::GetTextLineHeight();
    for (size_t i = 0; i < kAnswers; ++i) {
        const auto a = static_cast<Answer>(i);
        const Vec3 c = answerColour(a).rgb;
        ImGui::ColorButton(
            toString(a),
            ImVec4(static_cast<float>(c.x), static_cast<float>(c.y), static_cast<float>(c.z), 1.0f),
            ImGuiColorEditFlags_NoTooltip, ImVec2(swatch, swatch));
        ImGui::SameLine();
        ImGui::Text("%5.1f%% %s", shares[i], toString(a));
    }
}

PanelRect ColourScaleOverlay::draw(const Viewport& vp, PreviewMode mode,
                                   const PreviewImage& image) {
    const bool difference = mode == PreviewMode::Difference && image.differenceWhite > 0;
    const bool answers = mode == PreviewMode::Answers && !image.answers.empty();
    if (!difference && !answers) return {};
    PanelRect rect;
    const float width = std::min(static_cast<float>(vp.width) - 16, 22 * ImGui::GetFontSize());
    ImGui::SetNextWindowPos(
        ImVec2(static_cast<float>(vp.x + vp.width - 8), static_cast<float>(vp.y + vp.height - 8)),
        ImGuiCond_Always, ImVec2(1, 1));
    ImGui::SetNextWindowSize(ImVec2(width, 0), ImGuiCond_Always);
    ImGui::SetNextWindowBgAlpha(0.75f);
    if (ImGui::Begin("Colour scale", nullptr,
                     ImGuiWindowFlags_NoDecoration | ImGuiWindowFlags_NoSavedSettings |
                         ImGuiWindowFlags_NoFocusOnAppearing | ImGuiWindowFlags_NoNav |
                         ImGuiWindowFlags_NoInputs)) {
        if (difference)
            drawDifferenceScale(image);
        else
            drawAnswersLegend(image);
        const ImVec2 pos = ImGui::GetWindowPos(), size = ImGui::GetWindowSize();
        rect = {pos.x, pos.y, size.x, size.y};
    }
    ImGui::End();
    return rect;
}

}  // namespace penumbra::viewer
