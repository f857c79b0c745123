// What the viewer's panels say (app/viewer/panels/panel_text.h records it), checked against the
// scene itself in the state before any render, where the panels once said what no render had
// seen ("area lights: none" on a scene with a light): in process on the panels (a headless Dear
// ImGui context, no GL), and through `penumbra screenshot --no-preview --state-out` on the whole
// viewer (a generated scene whose counts the test chooses, the committed table scene, and the
// dragon when the meshes are fetched). And every word against the state it is said in: the whole
// viewer in this process (an OSMesa context), walked frame by frame through its states (before
// any render, the coarse pass, the render running, done, each preview mode, a camera jump, a
// click, the mouse over a pixel, the precompute), each frame's panel text checked against what the
// same frame's state says is shown.
#include "app/viewer/panels/panel_text.h"

#include <gtest/gtest.h>
#include <imgui.h>

#include <cfloat>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <functional>
#include <memory>
#include <set>
#include <string>
#include <vector>

#include "app/viewer/gl/offscreen_context.h"
#include "app/viewer/host/imgui_session.h"
#include "app/viewer/panels/help_panel.h"
#include "app/viewer/panels/precompute_panel.h"
#include "app/viewer/viewer.h"
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

// The window the next panel draws in (the viewer places panels with panel_arrangement.h).
void placeTestPanel(const viewer::PanelRect& r) {
    ImGui::SetNextWindowPos(ImVec2(r.x, r.y), ImGuiCond_Always);
    ImGui::SetNextWindowSize(ImVec2(r.width, r.height), ImGuiCond_Always);
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
            placeTestPanel(rect);
            (void)viewer::PrecomputePanel::draw(job, EffectsSummary{}, &scene,
                                                viewer::VisibilityLink{});
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
        placeTestPanel(rect);
        (void)viewer::PrecomputePanel::draw(job, rendered, &scene, viewer::VisibilityLink{});
        text.take("Precompute");
    });
    EXPECT_TRUE(has(text.texts().at("Precompute"), "16 stratified shadow rays"));
    EXPECT_FALSE(has(text.texts().at("Precompute"), "nothing rendered yet"));
    // No scene: nothing to count.
    frame(imgui, text, [&] {
        placeTestPanel(rect);
        (void)viewer::PrecomputePanel::draw(job, EffectsSummary{}, nullptr,
                                            viewer::VisibilityLink{});
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

// The whole viewer in this process, drawn into an offscreen OSMesa context one frame at a time,
// with the keys and the mouse the test sets: every state it passes through can be looked at.
class LiveViewer {
  public:
    LiveViewer(int width, int height, viewer::ViewerOptions options)
        : width_(width),
          height_(height),
          context_(makeContext(width, height)),
          scope_(context_->api()),
          viewer_(std::make_unique<viewer::Viewer>(std::move(options))) {
        ImGui::GetIO().MousePos = ImVec2(-FLT_MAX, -FLT_MAX);  // nowhere until the test says
    }
    ~LiveViewer() { viewer_.reset(); }  // (before the ImGui session and the GL context)
    LiveViewer(const LiveViewer&) = delete;
    LiveViewer& operator=(const LiveViewer&) = delete;

    viewer::Viewer& viewer() { return *viewer_; }
    int width() const { return width_; }
    int height() const { return height_; }
    // One frame; the state it leaves.
    json frame() {
        viewer_->frame(width_, height_, 1.0 / 60);
        return viewer_->stateJson();
    }
    // A key pressed for one frame (ImGui's legacy key indices: GLFW's, '1' for the key 1).
    json press(int key) {
        ImGui::GetIO().KeysDown[key] = true;
        const json state = frame();
        ImGui::GetIO().KeysDown[key] = false;
        return state;
    }
    void mouseAt(double x, double y) {
        ImGui::GetIO().MousePos = ImVec2(static_cast<float>(x), static_cast<float>(y));
    }

  private:
    static std::unique_ptr<gl::OffscreenContext> makeContext(int width, int height) {
        gl::preferUiThreadSoftwareRasteriser();
        return gl::createOffscreenContext(gl::OffscreenBackend::OsMesa, width, height);
    }

    int width_, height_;
    std::unique_ptr<gl::OffscreenContext> context_;
    gl::ScopedGlApi scope_;
    viewer::ImGuiSession imgui_;
    std::unique_ptr<viewer::Viewer> viewer_;
};

std::string panel(const json& state, const char* name) {
    return state["panelText"].value(name, std::string());
}

// What a frame's panels say, against what the same frame's state says is shown. Returns the
// names of the states recognised ("no image", "coarse", "running", "done", ...), for the walk to
// check that it went through them.
std::set<std::string> checkWordsAgainstState(const json& state) {
    std::set<std::string> seen;
    const std::string preview = panel(state, "Preview");
    const std::string precompute = panel(state, "Precompute");
    const std::string status = state["status"].get<std::string>();
    const json& p = state["preview"];
    const json& view = state["view"];
    const json& viewport = state["viewport"];
    const int passes = p["passes"].get<int>();
    const bool running = p["running"].get<bool>(), coarse = p["coarse"].get<bool>();
    const bool finished = p["finished"].get<bool>();
    SCOPED_TRACE("Preview: " + preview + "\nPrecompute: " + precompute + "\nstatus: " + status +
                 "\nstate preview: " + p.dump() + "\nview: " + view.dump());
    // The 3D view: the image, a coarser one, or flat colours, and the Preview panel says which.
    const int oneWidth =
        p["imageMode"] == "side by side" ? p["width"].get<int>() / 2 : p["width"].get<int>();
    const bool full = oneWidth == viewport["width"].get<int>() &&
                      p["height"].get<int>() == viewport["height"].get<int>();
    if (view["mode"] == "rendered") {
        if (!view["showsImage"].get<bool>()) {
            seen.insert(passes == 0 ? "no image" : "image of another view");
            EXPECT_TRUE(has(preview, "3D view: flat colours"));
            EXPECT_EQ(has(preview, "until the render's first pass"), passes == 0);
        } else if (!full) {
            seen.insert("coarser image");
            EXPECT_TRUE(has(preview, "3D view: a coarser image"));
        } else {
            EXPECT_FALSE(has(preview, "3D view:"));
        }
    }
    // The passes: a coarse pass says so; "(done)" only of a finished render, no longer running.
    if (coarse) {
        seen.insert("coarse pass");
        EXPECT_TRUE(has(preview, "a coarse pass"));
    }
    if (passes > 0 && !coarse && running) seen.insert("running");
    const bool done = passes > 0 && !coarse && finished && !running;
    if (done) seen.insert("done");
    EXPECT_EQ(has(preview, "(done)"), done);
    if (passes > 0 && !coarse) {
        EXPECT_TRUE(has(preview, std::to_string(passes) + " / ")) << passes;
    }
    // The effects: the preview's, named as such; the exact image's wherever one is rendered.
    const std::string simulates = p["simulates"].get<std::string>();
    if (simulates.empty()) {
        seen.insert("nothing simulated");
        EXPECT_TRUE(has(precompute, "nothing rendered yet"));
    } else {
        EXPECT_TRUE(has(precompute, "What the preview's " + simulates + " image simulates:"));
        EXPECT_TRUE(has(precompute, "method: " + simulates));
        EXPECT_FALSE(has(precompute, "nothing rendered yet"));
    }
    if (p["mode"] == p["imageMode"] && !simulates.empty()) {
        EXPECT_EQ(simulates, p["mode"] == "sampled" ? "sampled" : "exact") << p["mode"];
    }
    // The status line: no work it names is still said to run once it has ended.
    if (state.contains("precompute") && !state["precompute"]["running"].get<bool>()) {
        EXPECT_FALSE(has(status, "precomputing"));
        EXPECT_TRUE(has(status, "precompute done: ")) << status;
        EXPECT_TRUE(has(precompute, "done: ")) << precompute;
        seen.insert("precompute done");
    }
    if (!state["point"].is_null() && !state["inspectionPending"].get<bool>() &&
        !state["point"]["trees_pending"].get<bool>()) {
        EXPECT_FALSE(has(status, "building"));
    }
    // The inspected point: "fully visible" only of a light seen whole.
    if (!state["point"].is_null()) {
        const json& point = state["point"];
        const json& light = point["lights"][point["selected_light"].get<size_t>()];
        const std::string path = panel(state, "Path"), tree = panel(state, "History tree");
        SCOPED_TRACE("Path: " + path + "\nHistory tree: " + tree);
        if (light["fraction"].get<double>() < 1) {
            for (const std::string& text : {path, tree}) {
                EXPECT_FALSE(has(text, "fully-visible"));
                EXPECT_FALSE(has(text, "fully visible"));
            }
        }
        if (light.value("horizon_clipped", false) && light["pair"] == "fully-visible") {
            seen.insert("horizon-clipped point");
            EXPECT_TRUE(has(path, "tree unoccluded, horizon-clipped"));
            EXPECT_TRUE(has(tree, "unoccluded, horizon-clipped"));
        }
    }
    // The pixel under the mouse: where its numbers come from, and no "fully visible" of a light
    // the point under it sees only part of.
    if (state.contains("pixel")) {
        const json& pixel = state["pixel"];
        const std::string hover = panel(state, "Pixel inspector");
        SCOPED_TRACE("Pixel inspector: " + hover + "\npixel: " + pixel.dump());
        const std::string source = pixel["source"].get<std::string>();
        seen.insert("hover " + source);
        EXPECT_EQ(has(hover, "exact    L = ("), !pixel["exact"].is_null());
        EXPECT_EQ(has(hover, "sampled  L = ("), !pixel["sampled"].is_null());
        EXPECT_FALSE(has(hover, "not rendered (the preview's mode or size)"));
        if (source == "coarse") {
            EXPECT_TRUE(has(hover, "coarse pass: image pixel"));
        } else if (source == "other view") {
            EXPECT_TRUE(has(hover, "of the view before it moved"));
        } else if (source == "none") {
            EXPECT_TRUE(has(hover, "no rendered image"));
        }
        if ((source == "view" || source == "coarse") && pixel["exact"].is_null()) {
            EXPECT_TRUE(has(hover, "exact    not rendered in the sampled mode"));
        }
        bool allPartial = !pixel["lights"].empty();
        for (const json& l : pixel["lights"])
            allPartial = allPartial && l["fraction"].get<double>() < 1;
        if (allPartial) {
            EXPECT_FALSE(has(hover, "fully visible"));
        }
    }
    return seen;
}

TEST(ViewerPanelText, EveryStateSaysWhatTheViewShows) {
    viewer::ViewerOptions options;  // the defaults: the rendered view, exact
    options.showHelp = false;
    options.previewSettings.passes = 6;
    options.previewSettings.lightSamples = 4;
    std::unique_ptr<LiveViewer> live;
    try {
        live = std::make_unique<LiveViewer>(800, 500, options);
    } catch (const std::runtime_error& e) {
        GTEST_SKIP() << "no OSMesa context: " << e.what();
    }
    viewer::Viewer& v = live->viewer();
    ASSERT_TRUE(v.openScene(test::sourceDir() / "assets" / "cornell_box.obj")) << v.status();
    std::set<std::string> seen;
    int frames = 0;
    const auto check = [&](const json& state) {
        ++frames;
        const std::set<std::string> now = checkWordsAgainstState(state);
        seen.insert(now.begin(), now.end());
        return state;
    };
    // Frames until `until` holds of the state (two minutes at most).
    const auto frameUntil = [&](const std::function<bool(const json&)>& until) {
        const auto start = std::chrono::steady_clock::now();
        json state = check(live->frame());
        while (!until(state)) {
            if (std::chrono::steady_clock::now() - start > std::chrono::minutes(2)) {
                ADD_FAILURE() << "the state did not come within two minutes: " << state["preview"];
                break;
            }
            state = check(live->frame());
        }
        return state;
    };
    const auto doneIn = [](const std::string& mode) {
        return [mode](const json& s) {
            const json& p = s["preview"];
            return p["imageMode"] == mode && p["finished"].get<bool>() &&
                   !p["running"].get<bool>() && !p["coarse"].get<bool>() &&
                   s["view"]["showsImage"].get<bool>();
        };
    };

    // Before any render: the first frame starts it (its panels are drawn before any pass).
    const json first = check(live->frame());
    EXPECT_EQ(first["preview"]["passes"], 0);
    EXPECT_EQ(first["view"]["mode"], "rendered");  // the default: the exact render
    EXPECT_TRUE(seen.count("no image") && seen.count("nothing simulated"));
    // During (a coarse pass first, then the full render's passes) and after.
    frameUntil(doneIn("exact"));
    EXPECT_TRUE(seen.count("done"));

    // A click on the tall box's face that the horizon clips the light for (nothing between).
    const Vec3 x{277.343042, 269.125015, 292.172095};
    ASSERT_TRUE(v.selectPoint(x, 21)) << v.status();
    json state = frameUntil([](const json& s) {
        return !s["inspectionPending"].get<bool>() && !s["point"].is_null() &&
               !s["point"]["trees_pending"].get<bool>();
    });
    EXPECT_TRUE(seen.count("horizon-clipped point")) << state["point"]["lights"][0]["pair"];
    // The mouse over that point in the view.
    const json& vp = state["viewport"];
    double px = 0, py = 0;
    ASSERT_TRUE(v.camera().project(x, vp["width"].get<int>(), vp["height"].get<int>(), px, py));
    live->mouseAt(vp["x"].get<int>() + px, vp["y"].get<int>() + py);
    state = frameUntil([](const json& s) { return s.contains("pixel"); });

    // Each preview mode, the mouse still over the point.
    for (const auto& [key, mode] : std::vector<std::pair<int, std::string>>{{'2', "sampled"},
                                                                            {'3', "side by side"},
                                                                            {'4', "difference"},
                                                                            {'5', "answers"},
                                                                            {'1', "exact"}}) {
        SCOPED_TRACE(mode);
        check(live->press(key));
        state = frameUntil(doneIn(mode));
        EXPECT_EQ(state["preview"]["mode"], mode);
    }
    EXPECT_TRUE(seen.count("hover view"));

    // The camera set elsewhere: the image is of the view before until the new one comes.
    Camera moved = v.camera();
    moved.eye = moved.eye + Vec3{40, 0, 0};
    v.setCamera(moved);
    frameUntil(doneIn("exact"));
    EXPECT_TRUE(seen.count("hover other view") || seen.count("hover coarse"));
    EXPECT_TRUE(seen.count("coarse pass"));

    // The precompute: the status line says how it ended.
    check(live->press('P'));
    frameUntil([](const json& s) {
        return s.contains("precompute") && !s["precompute"]["running"].get<bool>();
    });
    check(live->frame());
    EXPECT_TRUE(seen.count("precompute done"));
    std::string all;
    for (const std::string& name : seen) all += name + "; ";
    RecordProperty("states", all);
    RecordProperty("frames", frames);
}

}  // namespace
}  // namespace penumbra
