#include "app/viewer/panels/scene_panel.h"

#include <algorithm>
#include <cstddef>
#include <string>
#include <system_error>
#include <utility>

#include "app/viewer/panels/flow_layout.h"
#include "app/viewer/panels/panel.h"
#include "engine/io/scene_loader.h"

namespace penumbra::viewer {

std::vector<std::filesystem::path> listSceneFiles(const std::filesystem::path& assets) {
    std::vector<std::filesystem::path> files;
    for (const std::filesystem::path& dir : {assets, assets / "scenes"}) {
        const size_t first = files.size();
        std::error_code ec;
        for (const auto& entry : std::filesystem::directory_iterator(dir, ec))
            if (entry.is_regular_file(ec) &&
                isSupportedSceneExtension(entry.path().extension().string()))
                files.push_back(entry.path());
        std::sort(files.begin() + static_cast<std::ptrdiff_t>(first), files.end());
    }
    return files;
}

ScenePanel::ScenePanel(std::filesystem::path assets)
    : assets_(std::move(assets)), files_(listSceneFiles(assets_)) {}

ScenePanel::Actions ScenePanel::draw(const LoadedScene* scene) {
    Actions actions;
    if (ImGui::Begin("Scene", nullptr, kPanelWindow)) {
        if (scene) {
            ImGui::TextWrapped("%s", scene->path.string().c_str());
            ImGui::TextWrapped("%u faces, %zu area lights, %zu trees (%s)",
                               scene->scene.faceCount(), scene->scene.lights.size(),
                               scene->store->treeCount(),
                               humanBytes(scene->store->bytes()).c_str());
            // What the loader repaired (or skipped), one line per kind and file: in a scrolled
            // box of at most half the room left, so that the scene list keeps the other half.
            const std::vector<std::string>& warnings = scene->scene.warnings;
            if (!warnings.empty()) {
                ImGui::PushStyleColor(ImGuiCol_Text, ImVec4(1.0f, 0.8f, 0.3f, 1.0f));
                ImGui::Text("%zu loader warning%s (repairs):", warnings.size(),
                            warnings.size() == 1 ? "" : "s");
                const float line = ImGui::GetTextLineHeightWithSpacing();
                const float height =
                    std::clamp(0.5f * ImGui::GetContentRegionAvail().y, 2.5f * line, 6.5f * line);
                ImGui::BeginChild("##warnings", ImVec2(-1, height), true);
                for (const std::string& w : warnings) ImGui::TextWrapped("- %s", w.c_str());
                ImGui::EndChild();
                ImGui::PopStyleColor();
            }
        } else {
            ImGui::TextUnformatted("No scene: pick one below or drop a scene file here.");
        }
        if (ImGui::Button("Fit (F)")) actions.fit = true;
        ImGui::SameLine();
        if (ImGui::Button("Move light (M)")) actions.moveLight = true;
        const char* open = "open (or drag and drop a file):";
        sameLineIfFits(ImGui::CalcTextSize(open).x);
        ImGui::TextWrapped("%s", open);
        if (ImGui::BeginListBox("##scenes", ImVec2(-1, -1))) {
            for (const auto& file : files_) {
                const bool current = scene && scene->path == file;
                // Named from the assets directory: "scenes/cornell_box.json".
                const std::string name = file.lexically_relative(assets_).generic_string();
                if (ImGui::Selectable(name.c_str(), current) && !current) actions.open = file;
            }
            ImGui::EndListBox();
        }
    }
    ImGui::End();
    return actions;
}

}  // namespace penumbra::viewer
