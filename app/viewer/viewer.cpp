#include "app/viewer/viewer.h"

#include <imgui.h>
#include <imgui_impl_opengl3.h>
#include <imgui_internal.h>  // the window under the mouse (E enlarges it)

#include <algorithm>
#include <chrono>

#include "app/viewer/overlay_geometry.h"
#include "app/viewer/palette.h"
#include "app/viewer/panels/colour_scale.h"
#include "app/viewer/panels/light_plane_panel.h"
#include "app/viewer/panels/panel.h"
#include "app/viewer/panels/panel_fit.h"
#include "app/viewer/panels/path_panel.h"
#include "app/viewer/panels/point_panel.h"
#include "app/viewer/panels/precompute_panel.h"
#include "app/viewer/panels/preview_panel.h"
#include "app/viewer/picking.h"
#include "app/viewer/viewer_settings.h"
#include "engine/precompute/point_query.h"
#include "engine/render/default_camera.h"

namespace penumbra::viewer {

Viewer::Viewer(ViewerOptions options)
    : options_(std::move(options)),
      renderer_({kBackground.r / 255.0f, kBackground.g / 255.0f, kBackground.b / 255.0f}),
      preview_(options_),
      visibility_(options_.visibilityFile, {}),
      scenePanel_(options_.assetsDirectory),
      helpPanel_(options_.showHelp) {
    if (options_.layout.scale != 1 && ImGui::GetCurrentContext() != nullptr) {
        ImGui::GetStyle().ScaleAllSizes(options_.layout.scale);
        ImGui::GetIO().FontGlobalScale = options_.layout.scale;
    }
    // Panels move by their title bars only: a drag inside one (the tree's canvas, a plot) is the
    // panel's own.
    if (ImGui::GetCurrentContext() != nullptr)
        ImGui::GetIO().ConfigWindowsMoveFromTitleBarOnly = true;
    if (!options_.settingsFile.empty()) {
        SettingsRead read = readViewerSettings(options_.settingsFile);
        settingsWarning_ = read.warning;
        settingsReadable_ = read.warning.empty();
        if (settingsReadable_) {
            arrangement_ = std::move(read.settings.panels);
            options_.layout.leftWidth = read.settings.leftWidth;
            options_.layout.rightWidth = read.settings.rightWidth;
            // Help opens on the first run only.
            if (read.settings.helpSeen) helpPanel_.hide();
        }
        status_ = settingsWarning_;
    }
    const std::string stem = "out/saved_view";
    std::copy(stem.begin(), stem.end(), saveStem_.begin());
}

Viewer::~Viewer() {
    accuracy_.cancel();
    precompute_.cancel();
    preview_.runner().stop();
    tasks_.wait();
    preview_.runner().wait();
    precompute_.dispose(tasks_);
    tasks_.wait();
}

bool Viewer::openScene(const std::filesystem::path& path) {
    std::shared_ptr<LoadedScene> loaded;
    try {
        loaded = loadScene(path, options_.exact, options_.load);
    } catch (const std::exception& e) {
        status_ = "cannot open " + path.string() + ": " + e.what();
        return false;
    }
    clearSelection();
    // The old scene's preview image and effects say nothing of this one.
    preview_.clear();
    // An accuracy study belongs to the scene it measured: a running one is dropped (its task
    // keeps the old scene alive until it stops), a finished one is no longer shown.
    accuracy_.drop();
    // The old scheduler's destructor waits for its builds: a task does that (keeping the old
    // scene, whose store they use, until then).
    precompute_.dispose(tasks_, scene_);
    // Light moves of the old scene say nothing of this one.
    lightJob_.drop();
    rebuildPairs_.clear();
    lightRebuild_ = false;
    lightStatus_ = {};
    scene_ = std::move(loaded);
    renderer_.setScene(scene_->scene);
    orbit_.set(defaultCamera(scene_->scene, *scene_->bvh));
    preview_.cameraJumped();
    status_ = "opened " + path.string() + ": " + std::to_string(scene_->scene.faceCount()) +
              " faces, " + std::to_string(scene_->scene.lights.size()) + " area lights";
    if (!settingsWarning_.empty() && !settingsWarned_) {
        status_ += "; warning: " + settingsWarning_;
        settingsWarned_ = true;
    }
    if (const auto& light = scene_->scene.defaultLight)
        status_ += "; " + light->announcement(path.filename().string());
    if (visibility_.follows(path))
        status_ += "; " + visibility_.load(*scene_->store);
    else if (visibility_.state() == "detached")
        status_ += "; " + visibility_.status();
    const std::vector<std::string>& warnings = scene_->scene.warnings;
    if (!warnings.empty())
        status_ += "; " + std::to_string(warnings.size()) +
                   (warnings.size() == 1 ? " warning: " : " warnings, the first: ") +
                   warnings.front();
    return true;
}

void Viewer::setCamera(const Camera& camera) {
    orbit_.set(camera);
    preview_.cameraJumped();
}

void Viewer::fitCamera() {
    if (!scene_) return;
    orbit_.fit(scene_->bounds);
    preview_.viewChanging();
}

bool Viewer::pickPixel(double px, double py, int width, int height) {
    if (!scene_) return false;
    layout_ = computeLayout(width, height, options_.layout);
    const std::optional<PickedPoint> hit =
        pickSurface(scene_->scene, *scene_->bvh, orbit_.camera(), layout_.view, px, py);
    if (!hit) {
        status_ = "nothing under pixel (" + std::to_string(static_cast<int>(px)) + ", " +
                  std::to_string(static_cast<int>(py)) + ")";
        return false;
    }
    return selectPoint(hit->point, hit->face);
}

bool Viewer::selectPoint(const Vec3& x, std::optional<uint32_t> face) {
    if (!scene_) return false;
    if (!face) {
        const FaceLookup lookup = findFaceContaining(scene_->scene, x);
        if (!lookup.ok()) {
            status_ = lookup.error;
            return false;
        }
        face = lookup.face;
    }
    if (selection_.select(scene_, *face, x, tasks_)) {
        status_ = "point on face " + std::to_string(*face) +
                  ": fragments from the tree-less query; building its history trees...";
    } else {
        status_ = "inspecting the point on face " + std::to_string(*face) + "...";
    }
    updateOverlay();
    return true;
}

void Viewer::clearSelection() {
    selection_.clear();
    treePanel_.setTree(nullptr, {});
    renderer_.clearOverlay();
}

void Viewer::updateOverlay() {
    const LightInspection* li = selection_.selectedLight();
    if (!selection_.inspection() || !scene_) {
        renderer_.clearOverlay();
        treePanel_.setTree(nullptr, {});
        return;
    }
    const OverlayGeometry overlay =
        buildOverlay(*selection_.inspection(), scene_->bounds.diagonal(), selection_.light());
    renderer_.setOverlay(overlay.fragmentTriangles, overlay.lines, overlay.linesOnTop);
    if (!li || !li->tree) {
        treePanel_.setTree(nullptr, {});
    } else {
        treePanel_.setMesh(&scene_->scene.mesh);
        treePanel_.setTree(li->tree, vis::traceNodes(li->result.trace));
    }
}

bool Viewer::moveLight(uint32_t light, const LightMove& move) {
    if (!scene_) return false;
    const size_t lights = scene_->scene.lights.size();
    if (light >= lights) {
        status_ = "move light: no light " + std::to_string(light) + " (the scene has " +
                  std::to_string(lights) + ")";
        return false;
    }
    if (const std::optional<std::string> problem = lightMoveProblem(move)) {
        lightStatus_.refused = *problem;
        status_ = "move light " + std::to_string(light) + ": refused: " + *problem;
        return false;
    }
    std::vector<LightMove> moves = scene_->lightMoves;
    moves.resize(lights);
    moves[light] = move;
    lightStatus_.refused.clear();
    lightJob_.request(scene_, std::move(moves), options_.exact, tasks_);
    return true;
}

void Viewer::lightMoveArrived(std::shared_ptr<LoadedScene> moved) {
    // The moved scene's store holds the trees the move left true (moved->kept: those of other
    // lights' pairs whose shaft the moved light crosses neither before nor after the move,
    // engine/precompute/moved_light_trees.h). The others are stale: the moved light's own pairs,
    // and the pairs it occludes or occluded (it is a face of the scene like any other). They go
    // with the old store, and their (receiver, light) pairs, with those of an earlier move not
    // rebuilt yet, are rebuilt in the moved scene in the background (a refined sub-patch's tree,
    // a cache of the render, is built again where the render asks).
    size_t dropped = 0;
    scene_->store->forEach([&](const PairKey& key, const PairRecord&) {
        if (moved->store->find(key) != nullptr) return;  // kept
        if (PatchLayout::refineLevel(key) == 0) rebuildPairs_.insert({key.receiver, key.lightFace});
        ++dropped;
    });
    uint32_t which = 0;  // the light whose move changed (for the status line)
    for (uint32_t i = 0; i < moved->lightMoves.size(); ++i)
        if (moved->lightMove(i) != scene_->lightMove(i)) which = i;
    std::optional<std::pair<Vec3, uint32_t>> point;
    if (const std::optional<PointInspection>& p = selection_.inspection())
        if (std::find(moved->scene.lights.begin(), moved->scene.lights.end(), p->face) ==
            moved->scene.lights.end())
            point = {p->point, p->face};  // (a point on a light that moved is no longer on it)
    clearSelection();
    precompute_.dispose(tasks_, scene_);
    accuracy_.drop();  // its study measured the scene before
    scene_ = std::move(moved);
    renderer_.setScene(scene_->scene);
    std::vector<PairKey> keys;
    for (const auto& [receiver, lightFace] : rebuildPairs_) {
        const auto patches = static_cast<uint32_t>(scene_->store->layout().patchCount(receiver));
        for (uint32_t patch = 0; patch < patches; ++patch)
            keys.push_back({receiver, patch, lightFace});
    }
    lightStatus_.invalidated += dropped;
    lightStatus_.kept = scene_->kept.kept;
    lightRebuild_ = !keys.empty();
    if (lightRebuild_) precompute_.start(*scene_->store, std::move(keys));
    precomputeWatched_ = false;
    preview_.lightMoved();
    preview_.setTreeLess(lightRebuild_);  // (nothing to rebuild: the preview builds as it needs)
    if (point) selectPoint(point->first, point->second);
    status_ = "light " + std::to_string(which) + " moved: the preview" +
              (point ? " and the point answer" : "") + " from the tree-less query; " +
              std::to_string(scene_->kept.kept) + " trees of other lights kept, " +
              std::to_string(dropped) + " trees of the position before dropped" +
              (lightRebuild_ ? ", " + std::to_string(rebuildPairs_.size()) +
                                   " (receiver, light) pairs rebuilding in the background"
                             : "");
}

void Viewer::pollBackground() {
    std::string message;
    // A moved scene first: what follows polls it.
    if (std::optional<LightMoveJob::Result> moved = lightJob_.take()) {
        if (moved->scene) {
            lightMoveArrived(std::move(moved->scene));
        } else {
            lightStatus_.refused = moved->error;
            status_ = "move light: refused: " + moved->error;
        }
    }
    if (selection_.poll(message) != Selection::Event::None) {
        status_ = message;
        updateOverlay();
    }
    preview_.poll(scene_, orbit_.camera(), layout_);
    // The precompute's progress, one reading for the frame (the panel, the status, the state).
    precomputeNow_.reset();
    if (precompute_.started()) precomputeNow_ = precompute_.progress();
    // The status line said the precompute was running: once it ends, how it ended.
    const bool running =
        precomputeNow_ && precomputeNow_->state == PrecomputeProgress::State::Running;
    // The trees of a moved light: once rebuilt, the preview may use them again as it builds.
    if (lightRebuild_ && !running) {
        lightRebuild_ = false;
        preview_.setTreeLess(false);
        if (precomputeNow_ && precomputeNow_->state == PrecomputeProgress::State::Idle)
            rebuildPairs_.clear();
        if (precomputeNow_)
            status_ = "trees of the moved light's pairs: " +
                      PrecomputePanel::progressLine(*precomputeNow_);
    }
    if (precomputeWatched_ && !running) {
        precomputeWatched_ = false;
        if (precomputeNow_)
            status_ = "precompute " + PrecomputePanel::progressLine(*precomputeNow_);
        // What the precompute built (all of it, or up to a cancel) goes to the file.
        if (precomputeNow_ && precomputeNow_->done > 0 && visibility_.attached())
            status_ += "; " + saveVisibility();
    }
}

void Viewer::resetLayout() {
    arrangement_.reset();
    options_.layout.leftWidth = options_.layout.rightWidth = 0;
    showTree_ = true;
    status_ = "layout reset: every panel in its default place";
}

std::string Viewer::saveSettings() const {
    if (options_.settingsFile.empty() || !settingsReadable_) return {};
    ViewerSettings s;
    s.panels = arrangement_;
    s.leftWidth = options_.layout.leftWidth;
    s.rightWidth = options_.layout.rightWidth;
    s.helpSeen = true;
    try {
        writeViewerSettings(options_.settingsFile, s);
    } catch (const std::exception& e) {
        return e.what();
    }
    return {};
}

void Viewer::enlargeHovered() {
    const ImGuiContext& g = *ImGui::GetCurrentContext();
    std::string name;
    if (g.HoveredWindow != nullptr) {
        const char* title = g.HoveredWindow->RootWindow->Name;
        for (const PanelName& p : arrangeablePanels())
            if (std::string_view(title) == p.title) name = p.name;
    }
    if (name.empty())
        name = arrangement_.enlarged().empty() ? "History tree" : arrangement_.enlarged();
    if (name == "History tree") showTree_ = true;
    arrangement_.toggleEnlarged(name);
}

int Viewer::drawMenuBar() {
    int height = 0;
    if (!ImGui::BeginMainMenuBar()) return height;
    height = static_cast<int>(ImGui::GetWindowHeight());
    if (ImGui::BeginMenu("Panels")) {
        for (const PanelName& p : arrangeablePanels()) {
            const std::string item = std::string("Enlarge ") + p.name;
            if (ImGui::MenuItem(item.c_str(),
                                p.name == std::string_view("History tree") ? "E" : nullptr,
                                arrangement_.enlarged() == p.name)) {
                if (p.name == std::string_view("History tree")) showTree_ = true;
                if (p.name == std::string_view("Help") && !helpPanel_.visible())
                    helpPanel_.toggle();
                arrangement_.toggleEnlarged(p.name);
            }
        }
        ImGui::Separator();
        if (ImGui::MenuItem("History tree", "T", showTree_)) showTree_ = !showTree_;
        if (ImGui::MenuItem("Help", "H", helpPanel_.visible())) helpPanel_.toggle();
        ImGui::Separator();
        if (ImGui::MenuItem("Reset layout", "Ctrl+L")) resetLayout();
        ImGui::EndMenu();
    }
    ImGui::EndMainMenuBar();
    return height;
}

void Viewer::startPrecompute() {
    if (!scene_) return;
    precompute_.start(*scene_->store);
    lightRebuild_ = false;  // (the light's pairs are among every pair)
    preview_.setTreeLess(false);
    rebuildPairs_.clear();
    status_ = "precomputing every (receiver patch, light) pair in the background";
    precomputeWatched_ = true;
}

std::string Viewer::loadVisibility() {
    if (!scene_ || !visibility_.attached()) return "no visibility file (--visibility FILE.pvis)";
    if (scene_->version != 0) return "the lights were moved: the file holds the scene as opened";
    return visibility_.load(*scene_->store);
}

std::string Viewer::saveVisibility() {
    if (!scene_ || !visibility_.attached()) return "no visibility file (--visibility FILE.pvis)";
    if (scene_->version != 0)
        return "not written: the lights were moved, the file holds the scene as opened";
    return visibility_.save(*scene_->store);
}

void Viewer::openAccuracyStudy() { accuracy_.open(scene_, orbit_.camera(), tasks_); }

void Viewer::waitForLightMove() {
    tasks_.wait();
    pollBackground();
}

void Viewer::waitForBackground() {
    tasks_.wait();
    pollBackground();  // a light move built meanwhile replaces the scene first
    preview_.restartPending(scene_, orbit_.camera(), layout_);
    tasks_.wait();
    preview_.runner().wait();
    pollBackground();
}

void Viewer::handleInput(int width, int height) {
    ImGuiIO& io = ImGui::GetIO();
    if (!scene_) return;
    const bool split = preview_.splitShown(orbit_.camera(), layout_.view);
    const ViewMouse::Result mouse =
        mouse_.update(layout_.view, width, split, options_.layout, options_.split, orbit_);
    if (mouse.resized) preview_.viewChanging();  // the view's size changed: anew once it rests
    if (mouse.dragged) return;  // a column's edge or the split line has the mouse this frame
    if (mouse.pick) pickPixel(io.MousePos.x, io.MousePos.y, width, height);
    if (!io.WantCaptureKeyboard) {
        if (ImGui::IsKeyPressed('F')) fitCamera();
        if (ImGui::IsKeyPressed('H')) helpPanel_.toggle();
        if (ImGui::IsKeyPressed('T')) showTree_ = !showTree_;
        if (ImGui::IsKeyPressed('M')) lightPanel_.toggle();
        if (ImGui::IsKeyPressed('A')) accuracy_.toggle();
        if (ImGui::IsKeyPressed(ImGui::GetKeyIndex(ImGuiKey_Escape))) clearSelection();
        if (ImGui::IsKeyPressed('L') && io.KeyCtrl) resetLayout();
        if (ImGui::IsKeyPressed('E') && !io.KeyCtrl) enlargeHovered();
        if (ImGui::IsKeyPressed('L') && !io.KeyCtrl && selection_.selectedLight()) {
            selection_.nextLight();
            updateOverlay();
        }
        const PreviewMode modes[] = {PreviewMode::Exact, PreviewMode::Sampled,
                                     PreviewMode::SideBySide, PreviewMode::Difference,
                                     PreviewMode::Answers};
        for (int i = 0; i < 5; ++i)
            if (ImGui::IsKeyPressed('1' + i)) {
                options_.previewSettings.mode = modes[i];
                preview_.markDirty();
            }
        if (ImGui::IsKeyPressed('R')) preview_.markDirty();
        if (ImGui::IsKeyPressed('V')) {
            options_.view =
                options_.view == ViewMode::Raster ? ViewMode::Rendered : ViewMode::Raster;
            preview_.markDirty();
        }
        if (ImGui::IsKeyPressed('P')) startPrecompute();
        if (ImGui::IsKeyPressed('C')) precompute_.cancel();
        if (ImGui::IsKeyPressed('Q') && io.KeyCtrl) quit_ = true;
    }
    if (mouse.moved) preview_.viewChanging();
}

void Viewer::frame(int width, int height, double deltaSeconds) {
    const auto start = std::chrono::steady_clock::now();
    options_.layout.tree = showTree_;
    layout_ = computeLayout(width, height, options_.layout);
    ImGuiIO& io = ImGui::GetIO();
    io.DisplaySize = ImVec2(static_cast<float>(width), static_cast<float>(height));
    io.DeltaTime = static_cast<float>(std::max(deltaSeconds, 1e-4));
    pollBackground();

    ImGui_ImplOpenGL3_NewFrame();
    ImGui::NewFrame();
    // The menu bar first: the panels and the view lie below it.
    options_.layout.top = drawMenuBar();
    layout_ = computeLayout(width, height, options_.layout);
    handleInput(width, height);
    options_.layout.tree = showTree_;
    layout_ = computeLayout(width, height, options_.layout);
    drawPanels();
    ImGui::Render();

    glViewport(0, 0, width, height);
    glClearColor(0.1f, 0.1f, 0.12f, 1.0f);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    if (scene_) {
        double nearDistance = 0, farDistance = 1;
        orbit_.clipRange(scene_->bounds, nearDistance, farDistance);
        renderer_.draw(orbit_.camera(), nearDistance, farDistance, layout_.view, height,
                       preview_.viewImage(orbit_.camera(), layout_.view));
    }
    glViewport(0, 0, width, height);
    ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());

    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    ++frameStats_.frames;
    frameStats_.lastSeconds = seconds;
    frameStats_.sumSeconds += seconds;
    frameStats_.maxSeconds = std::max(frameStats_.maxSeconds, seconds);
}

void Viewer::drawPanels() {
    const Layout& l = layout_;
    panelRects_.clear();
    panelText_.begin();
    // Each panel: placed by the arrangement, drawn, what the user did to it read back, and its
    // window's rectangle and text recorded.
    const auto panel = [&](const char* name, const auto& draw) {
        arrangement_.place(name, l);
        draw();
        const char* title = name;
        for (const PanelName& p : arrangeablePanels())
            if (std::string_view(name) == p.name) title = p.title;
        arrangement_.observe(name, title);
        const PanelRect r = arrangement_.shown(name);
        panelRects_[name] = {r.x, r.y, r.width, r.height};
        panelText_.take(name);
    };
    const auto record = [&](const char* name, const PanelRect& r) {
        panelRects_[name] = {r.x, r.y, r.width, r.height};
        panelText_.take(name);
    };
    ScenePanel::Actions scene;
    panel("Scene", [&] { scene = scenePanel_.draw(scene_.get()); });
    panel("Precompute", [&] {
        switch (PrecomputePanel::draw(precomputeNow_, preview_.effects(),
                                      scene_ ? &scene_->scene : nullptr, visibility_)) {
            case PrecomputePanel::Action::Start:
                startPrecompute();
                break;
            case PrecomputePanel::Action::LoadFile:
                status_ = loadVisibility();
                break;
            case PrecomputePanel::Action::SaveFile:
                status_ = saveVisibility();
                break;
            case PrecomputePanel::Action::Cancel:
                precompute_.cancel();
                break;
            case PrecomputePanel::Action::None:
                break;
        }
    });
    if (showTree_) panel("History tree", [&] { treePanel_.draw("History tree"); });
    panel("Preview", [&] {
        switch (PreviewPanel::draw(options_.previewSettings, options_.view, options_.exact,
                                   saveStem_, preview_.image(), preview_.running(),
                                   preview_.texture(),
                                   preview_.viewNote(orbit_.camera(), layout_.view))) {
            case PreviewPanel::Action::Reopen:
                // The store's trees follow the build budget: a new store, the scene reopened.
                if (scene_) openAfterFrame_ = scene_->path;
                break;
            case PreviewPanel::Action::Restart:
                preview_.markDirty();
                break;
            case PreviewPanel::Action::SaveView:
                preview_.save(saveStem_.data(), scene_.get(), orbit_.camera(), status_);
                break;
            case PreviewPanel::Action::None:
                break;
        }
    });
    panel("Point", [&] {
        if (PointPanel::draw(selection_)) updateOverlay();
    });
    panel("Light plane",
          [&] { LightPlanePanel::draw(selection_, scene_ ? &scene_->scene.mesh : nullptr); });
    panel("Path", [&] { PathPanel::draw(selection_); });
    if (helpPanel_.visible()) panel("Help", [&] { helpPanel_.draw(); });
    // The overlays of the 3D view, recorded too (the tests check that they stay inside it). The
    // split line and the colour scale are drawn under the panels (the background draw list, a
    // window without focus).
    preview_.drawSplitLine(orbit_.camera(), l.view);
    if (options_.view == ViewMode::Rendered && preview_.showsImage(orbit_.camera(), l.view)) {
        const PanelRect r =
            ColourScaleOverlay::draw(l.view, options_.previewSettings.mode, preview_.image());
        if (r.width > 0) record("Colour scale", r);
    }
    if (lightPanel_.visible()) {
        lightStatus_.building = lightJob_.busy();
        lightStatus_.rebuild = lightStatus_.invalidated > 0 ? precomputeNow_ : std::nullopt;
        lightStatus_.treeLess = preview_.treeLess();
        PanelRect rect;
        const std::optional<LightPanel::Move> move =
            lightPanel_.draw(l.view, scene_.get(), lightStatus_, rect);
        record("Move light", rect);
        if (move) moveLight(move->light, move->move);
    }
    if (accuracy_.shown()) {
        if (accuracy_.draw(l.view, scene_, orbit_.camera(), tasks_)) {
            const std::array<float, 4>& r = accuracy_.plot().windowRect();
            panelRects_["Accuracy vs time"] = {r[0], r[1], r[2], r[3]};
        }
        panelText_.take("Accuracy");
    }
    record("Status", StatusBar::draw(l.view, status_, frameStats_));
    preview_.drawPixelInspector(scene_.get(), orbit_.camera(), layout_.view,
                                mouse_.draggingSplit());
    if (preview_.hover() != nullptr) panelText_.take("Pixel inspector");
    panelText_.end();
    panelOverflow_ = measureHorizontalOverflow();
    // Actions that replace what the panels drew from, after every panel is drawn.
    if (scene.fit) fitCamera();
    if (scene.moveLight) lightPanel_.show();
    if (scene.open) openScene(*scene.open);
    if (openAfterFrame_) {
        const std::filesystem::path path = *openAfterFrame_;
        openAfterFrame_.reset();
        const Camera camera = orbit_.camera();
        if (openScene(path)) setCamera(camera);  // the same view, with the new build budget
    }
}

}  // namespace penumbra::viewer
