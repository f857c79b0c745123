#include "app/viewer/panels/precompute_panel.h"

#include <cstdio>
#include <string>

#include "app/viewer/panels/panel.h"

namespace penumbra::viewer {
namespace {

const char* stateName(const PrecomputeProgress& p) {
    switch (p.state) {
        case PrecomputeProgress::State::Idle:
            // Idle after a batch: every pair of it built.
            return p.total > 0 && p.done == p.total ? "done" : "idle";
        case PrecomputeProgress::State::Running:
            return "running";
        case PrecomputeProgress::State::Cancelled:
            return "cancelled";
        case PrecomputeProgress::State::OverBudget:
            return "over budget";
        case PrecomputeProgress::State::Failed:
            return "failed";
    }
    return "idle";
}

// The text under the buttons: the render's EffectsSummary, or before any render of the scene
// what the scene itself says (an EffectsSummary counts what a render saw).
std::string effectsText(const EffectsSummary& effects, const Scene* scene) {
    if (!effects.method.empty()) return effects.text();
    if (scene == nullptr) return "no scene open\n";
    const auto count = [](size_t n) { return n == 0 ? std::string("none") : std::to_string(n); };
    std::string s = "nothing rendered yet\narea lights: " + count(scene->lights.size());
    if (scene->lights.empty()) s += " - no soft shadows to compute, no history trees";
    if (scene->defaultLight) s += " (" + std::string(kDefaultLightNote) + ")";
    s += "\npoint lights: " + count(scene->pointLights.size()) + "\n";
    return s;
}

}  // namespace

std::string PrecomputePanel::progressLine(const PrecomputeProgress& p) {
    char line[160];
    std::snprintf(line, sizeof line, "%s: %zu of %zu pairs, %zu nodes, %s, %.1f s", stateName(p),
                  p.done, p.total, p.nodes, humanBytes(p.bytes).c_str(), p.seconds);
    return line;
}

PrecomputePanel::Action PrecomputePanel::draw(const std::optional<PrecomputeProgress>& progress,
                                              const EffectsSummary& effects, const Scene* scene,
                                              const VisibilityLink& visibility) {
    Action action = Action::None;
    if (ImGui::Begin("Precompute", nullptr, kPanelWindow)) {
        if (progress) {
            const PrecomputeProgress& p = *progress;
            const float fraction =
                p.total > 0 ? static_cast<float>(p.done) / static_cast<float>(p.total) : 0.0f;
            char overlay[96];
            std::snprintf(overlay, sizeof overlay, "%zu / %zu pairs, %.0f s left", p.done, p.total,
                          p.secondsLeft);
            ImGui::ProgressBar(fraction, ImVec2(-1, 0), overlay);
            ImGui::TextUnformatted(progressLine(p).c_str());
            if (!p.error.empty()) ImGui::TextWrapped("error: %s", p.error.c_str());
            if (p.state == PrecomputeProgress::State::Running) {
                if (ImGui::Button("Cancel (C)")) action = Action::Cancel;
            } else if (ImGui::Button("Precompute all (P)")) {
                action = Action::Start;
            }
        } else if (ImGui::Button("Precompute all (P)")) {
            action = Action::Start;
        }
        // The visibility file: where the trees come from and go.
        if (visibility.attached()) {
            ImGui::TextWrapped("Trees file: %s", visibility.file().string().c_str());
            if (ImGui::Button("Load")) action = Action::LoadFile;
            ImGui::SameLine();
            if (ImGui::Button("Save")) action = Action::SaveFile;
            if (!visibility.status().empty()) ImGui::TextWrapped("%s", visibility.status().c_str());
        } else {
            ImGui::TextWrapped("Trees file: not given (%s)",
                               visibility.status().empty() ? "view SCENE --visibility FILE.pvis"
                                                           : visibility.status().c_str());
        }
        // Below the precompute, the preview's: what its render simulated, said as such.
        ImGui::Separator();
        if (!effects.method.empty())
            ImGui::TextWrapped("What the preview's %s image simulates:", effects.method.c_str());
        ImGui::TextWrapped("%s", effectsText(effects, scene).c_str());
    }
    ImGui::End();
    return action;
}

}  // namespace penumbra::viewer
