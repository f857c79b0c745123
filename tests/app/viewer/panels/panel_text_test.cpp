// What the viewer's panels say (app/viewer/panels/panel_text.h records it), checked against the
// scene itself in the state before any render, where the panels once said what no render had
// seen ("area lights: none" on a scene with a light): in process on the panels (a headless Dear
// ImGui context, no GL), and through `penumbra screenshot --no-preview --state-out` on the whole
// viewer (a generated scene whose counts the test chooses, the committed table scene, and the
// dragon when the meshes are fetched).
#include "app/viewer/panels/panel_text.h"

#include <gtest/gtest.h>
#include <imgui.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "app/viewer/panels/help_panel.h"
#include "app/viewer/panels/precompute_panel.h"
#include "engine/io/scene_loader.h"
#include "tests/app/viewer/viewer_test_support.h"
#include "tools/devkit/headless_imgui.h"

namespace penumbra {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

bool has(const std::string& text, const std::string& part) {
    return text.find(part) != std::string::npos;
}

// One headless frame in which `draw` draws panels and records their text.
template <class Draw>
void frame(devkit::HeadlessImGui& imgui, viewer::PanelText& text, Draw&& draw) {
    imgui.frame([&] {
        text.begin();
        draw();
        text.end();
    });
}

TEST(PanelText, RecordsEachPanelsTextAndOpensNoTreeNode) {
    devkit::HeadlessImGui imgui;
    viewer::PanelText text;
    for (int i = 0; i < 2; ++i) {
        frame(imgui, text, [&] {
            ImGui::Begin("First");
            ImGui::Text("one %d", 1);
            if (ImGui::TreeNode("closed node")) {
                ImGui::Text("inside the node");
                ImGui::TreePop();
            }
            ImGui::End();
            text.take("First");
            ImGui::Begin("Second");
            ImGui::TextWrapped("two");
            ImGui::End();
            text.take("Second");
            ImGui::Begin("Third");
            ImGui::Text("dropped: drawn after the last take");
            ImGui::End();
        });
    }
    ASSERT_EQ(text.texts().size(), 2u);
    const std::string& first = text.texts().at("First");
    EXPECT_TRUE(has(first, "one 1")) << first;
    EXPECT_TRUE(has(first, "closed node")) << first;
    // A log at another depth would have opened the node (and drawn its content).
    EXPECT_FALSE(has(first, "inside the node")) << first;
    EXPECT_FALSE(has(first, "two")) << first;
    EXPECT_TRUE(has(text.texts().at("Second"), "two"));
    EXPECT_FALSE(has(text.texts().at("Second"), "one 1"));
}

TEST(PanelText, PrecomputePanelBeforeAnyRenderCountsTheScenesLights) {
    devkit::HeadlessImGui imgui;
    viewer::PanelText text;
    const viewer::PanelRect rect{0, 0, 600, 400};
    const std::optional<PrecomputeProgress> job;  // never started
    Scene scene;
    for (size_t area : {size_t{0}, size_t{1}, size_t{3}}) {
        scene.lights.assign(area, 0);
        scene.pointLights.assign(2, PointLight{});
        frame(imgui, text, [&] {
            (void)viewer::PrecomputePanel::draw(rect, job, EffectsSummary{}, &scene);
            text.take("Precompute");
        });
        const std::string& said = text.texts().at("Precompute");
        EXPECT_TRUE(has(said, "nothing rendered yet")) << said;
        EXPECT_TRUE(has(said, "point lights: 2")) << said;
        if (area == 0) {
            EXPECT_TRUE(has(said, "area lights: none")) << said;
        } else {
            EXPECT_TRUE(has(said, "area lights: " + std::to_string(area) + "\n")) << said;
            EXPECT_FALSE(has(said, "none")) << said;
        }
    }
    // After a render, the render's own summary.
    EffectsSummary rendered;
    rendered.method = "sampled";
    rendered.lightSamples = 16;
    rendered.areaLights = 3;
    rendered.materialsAnalytic = 1;
    frame(imgui, text, [&] {
        (void)viewer::PrecomputePanel::draw(rect, job, rendered, &scene);
        text.take("Precompute");
    });
    EXPECT_TRUE(has(text.texts().at("Precompute"), "16 stratified shadow rays"));
    EXPECT_FALSE(has(text.texts().at("Precompute"), "nothing rendered yet"));
    // No scene: nothing to count.
    frame(imgui, text, [&] {
        (void)viewer::PrecomputePanel::draw(rect, job, EffectsSummary{}, nullptr);
        text.take("Precompute");
    });
    EXPECT_TRUE(has(text.texts().at("Precompute"), "no scene open"));
    EXPECT_FALSE(has(text.texts().at("Precompute"), "area lights"));
}

TEST(PanelText, StatusBarClaimsNoFrameTimeBeforeTheFirstFrame) {
    devkit::HeadlessImGui imgui;
    viewer::PanelText text;
    const viewer::Viewport view{0, 0, 800, 600};
    viewer::FrameStats frames;  // none drawn yet
    frame(imgui, text, [&] {
        text.take("before");  // nothing yet
        viewer::StatusBar::draw(view, "opened", frames);
        text.take("Status");
    });
    EXPECT_TRUE(has(text.texts().at("Status"), "opened"));
    EXPECT_FALSE(has(text.texts().at("Status"), " ms")) << text.texts().at("Status");
    frames.frames = 1;
    frames.lastSeconds = frames.maxSeconds = frames.sumSeconds = 0.0125;
    frame(imgui, text, [&] {
        viewer::StatusBar::draw(view, "opened", frames);
        text.take("Status");
    });
    EXPECT_TRUE(has(text.texts().at("Status"), "frame 12.5 ms")) << text.texts().at("Status");
}

// A scene whose counts the test sets: a 4 x 4 floor, three quad lights above it facing down, two
// point lights.
fs::path writeThreeLightScene(const fs::path& dir) {
    const fs::path path = dir / "three_lights.json";
    std::ofstream out(path);
    out << R"({
  "polygons": [
    {"vertices": [[-2, 0, -2], [-2, 0, 2], [2, 0, 2], [2, 0, -2]], "material": {"kd": 0.7}}
  ],
  "area_lights": [
    {"vertices": [[-1.5, 2, 0], [-1.1, 2, 0], [-1.1, 2, 0.4], [-1.5, 2, 0.4]], "emission": 10},
    {"vertices": [[-0.2, 2, 0], [0.2, 2, 0], [0.2, 2, 0.4], [-0.2, 2, 0.4]], "emission": 10},
    {"vertices": [[1.1, 2, 0], [1.5, 2, 0], [1.5, 2, 0.4], [1.1, 2, 0.4]], "emission": 10}
  ],
  "point_lights": [{"position": [0, 1, 0]}, {"position": [1, 1, 1]}],
  "camera": {"eye": [0, 3, 5], "target": [0, 0.5, 0], "up": [0, 1, 0], "fov_y": 50}
}
)";
    return path;
}

struct Counts {
    size_t faces = 0, areaLights = 0, pointLights = 0;
};

// Every panel of `penumbra screenshot SCENE --no-preview` (no render ever runs) against the
// scene's counts.
void checkPanelsBeforeAnyRender(const fs::path& scene, const Counts& counts, const fs::path& dir) {
    SCOPED_TRACE(scene.string());
    const fs::path stateFile = dir / "state.json";
    const test::ProcessResult r = test::runPenumbraGl(
        {"screenshot", scene.string(), "--no-preview", "--size", "1280x800", "--out",
         (dir / "shot.png").string(), "--state-out", stateFile.string()});
    ASSERT_EQ(r.exitCode, 0) << r.err;
    const json state = test::readJson(stateFile);
    ASSERT_TRUE(state.contains("panelText")) << "the state names no panel's text";
    const json& panels = state["panelText"];
    for (const char* name : {"Scene", "Precompute", "History tree", "Preview", "Point",
                             "Light plane", "Path", "Help", "Status"})
        EXPECT_TRUE(panels.contains(name)) << name;
    const std::string area = std::to_string(counts.areaLights);
    const std::string faces = std::to_string(counts.faces);
    // Said of the scene itself: right from the start.
    const std::string sceneText = panels.value("Scene", "");
    EXPECT_TRUE(has(sceneText, faces + " faces, " + area + " area lights")) << sceneText;
    const std::string status = panels.value("Status", "");
    EXPECT_TRUE(has(status, faces + " faces, " + area + " area lights")) << status;
    // Of what the renderer simulates: nothing rendered, the lights the scene holds.
    const std::string precompute = panels.value("Precompute", "");
    EXPECT_TRUE(has(precompute, "nothing rendered yet")) << precompute;
    EXPECT_TRUE(has(precompute, "area lights: " + (counts.areaLights ? area : "none")))
        << precompute;
    EXPECT_TRUE(
        has(precompute,
            "point lights: " + (counts.pointLights ? std::to_string(counts.pointLights) : "none")))
        << precompute;
    const std::string preview = panels.value("Preview", "");
    EXPECT_TRUE(has(preview, "0 / ")) << preview;
    // No panel claims a render that never ran.
    for (const auto& [name, text] : panels.items()) {
        const std::string said = text.get<std::string>();
        EXPECT_FALSE(has(said, "(done)")) << name << ": " << said;
        if (counts.areaLights > 0) {
            EXPECT_FALSE(has(said, "area lights: none")) << name << ": " << said;
        }
    }
}

TEST(ViewerPanelText, BeforeAnyRenderEveryPanelTellsTheScene) {
    const fs::path dir = test::scratchDir("panel_text");
    checkPanelsBeforeAnyRender(writeThreeLightScene(dir), {4, 3, 2}, dir);
    // The committed scenes: their counts as the scene loader reads them.
    std::vector<fs::path> scenes = {test::sourceDir() / "assets" / "scenes" / "table.json"};
    if (fs::exists(test::sourceDir() / "assets" / "external" / "dragon_vrip.ply"))
        scenes.push_back(test::sourceDir() / "assets" / "scenes" / "dragon.json");
    for (const fs::path& path : scenes) {
        const Scene scene = loadScene(path);
        checkPanelsBeforeAnyRender(
            path, {scene.faceCount(), scene.lights.size(), scene.pointLights.size()}, dir);
    }
}

}  // namespace
}  // namespace penumbra
