#include "app/viewer/panels/accuracy_windows.h"

#include <imgui.h>

#include <algorithm>
#include <optional>
#include <utility>

namespace penumbra::viewer {

void AccuracyWindows::open(std::shared_ptr<LoadedScene> scene, const Camera& camera,
                           tbb::task_group& tasks) {
    shown_ = true;
    job_.start(std::move(scene), camera, tasks);
}

void AccuracyWindows::drop() {
    job_.drop();
    plot_.clear();
}

bool AccuracyWindows::draw(const Viewport& vp, const std::shared_ptr<LoadedScene>& scene,
                           const Camera& camera, tbb::task_group& tasks) {
    if (std::optional<AccuracyStudy> result = job_.takeResult()) plot_.setResult(*result);
    // First shown over the 3D view: the controls at its top left, the plot beside them.
    const float vx = static_cast<float>(vp.x), vy = static_cast<float>(vp.y);
    ImGui::SetNextWindowPos(ImVec2(vx + 8, vy + 64), ImGuiCond_FirstUseEver);
    if (ImGui::Begin("Accuracy controls", &shown_,
                     ImGuiWindowFlags_NoSavedSettings | ImGuiWindowFlags_AlwaysAutoResize)) {
        if (job_.running()) {
            ImGui::ProgressBar(static_cast<float>(job_.progress()), ImVec2(-1, 0),
                               "measuring exact vs 1..1024 shadow rays");
            if (ImGui::Button("Cancel")) job_.cancel();
        } else if (ImGui::Button("Measure this view (64x64, 2 spp)")) {
            job_.start(scene, camera, tasks);
        }
    }
    ImGui::End();
    if (!plot_.hasResult()) return false;
    ImGui::SetNextWindowPos(
        ImVec2(vx + std::max(8.0f, 0.5f * (static_cast<float>(vp.width) - 640)), vy + 110),
        ImGuiCond_FirstUseEver);
    plot_.draw("Accuracy vs time");
    return true;
}

}  // namespace penumbra::viewer
