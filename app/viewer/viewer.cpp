#include "app/viewer/viewer.h"

#include <imgui.h>
#include <imgui_impl_opengl3.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <system_error>

#include "app/viewer/overlay_geometry.h"
#include "app/viewer/palette.h"
#include "app/viewer/panels/light_plane_panel.h"
#include "app/viewer/panels/panel.h"
#include "app/viewer/panels/path_panel.h"
#include "app/viewer/panels/point_panel.h"
#include "app/viewer/panels/precompute_panel.h"
#include "app/viewer/panels/preview_panel.h"
#include "app/viewer/picking.h"
#include "app/viewer/png_output.h"
#include "engine/io/scene_file.h"
#include "engine/precompute/point_query.h"
#include "engine/render/default_camera.h"

namespace penumbra::viewer {

Viewer::Viewer(ViewerOptions options)
    : options_(std::move(options)),
      renderer_({kBackground.r / 255.0f, kBackground.g / 255.0f, kBackground.b / 255.0f}),
      scenePanel_(options_.assetsDirectory),
      helpPanel_(options_.showHelp) {
    if (options_.layout.scale != 1 && ImGui::GetCurrentContext() != nullptr) {
        ImGui::GetStyle().ScaleAllSizes(options_.layout.scale);
        ImGui::GetIO().FontGlobalScale = options_.layout.scale;
    }
    const std::string stem = "out/saved_view";
    std::copy(stem.begin(), stem.end(), saveStem_.begin());
    glGenTextures(1, &previewTexture_);
    glBindTexture(GL_TEXTURE_2D, previewTexture_);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    glBindTexture(GL_TEXTURE_2D, 0);
}

Viewer::~Viewer() {
    accuracyJob_.cancel();
    precompute_.cancel();
    preview_.stop();
    tasks_.wait();
    preview_.wait();
    precompute_.dispose(tasks_);
    tasks_.wait();
    glDeleteTextures(1, &previewTexture_);
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
    previewImage_ = PreviewImage{};
    // An accuracy study belongs to the scene it measured: a running one is dropped (its task
    // keeps the old scene alive until it stops), a finished one is no longer shown.
    accuracyJob_.drop();
    accuracyPanel_.clear();
    // The old scheduler's destructor waits for its builds: a task does that.
    precompute_.dispose(tasks_);
    scene_ = std::move(loaded);
    renderer_.setScene(scene_->scene);
    orbit_.set(defaultCamera(scene_->scene, *scene_->bvh));
    previewDirty_ = true;
    lastCameraChange_ = {};
    status_ = "opened " + path.string() + ": " + std::to_string(scene_->scene.faceCount()) +
              " faces, " + std::to_string(scene_->scene.lights.size()) + " area lights";
    if (const auto& light = scene_->scene.defaultLight)
        status_ += "; " + light->announcement(path.filename().string());
    const std::vector<std::string>& warnings = scene_->scene.warnings;
    if (!warnings.empty())
        status_ += "; " + std::to_string(warnings.size()) +
                   (warnings.size() == 1 ? " warning: " : " warnings, the first: ") +
                   warnings.front();
    return true;
}

void Viewer::setCamera(const Camera& camera) {
    orbit_.set(camera);
    previewDirty_ = true;
    lastCameraChange_ = {};
}

void Viewer::fitCamera() {
    if (!scene_) return;
    orbit_.fit(scene_->bounds);
    previewDirty_ = true;
    lastCameraChange_ = std::chrono::steady_clock::now();
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

void Viewer::pollBackground() {
    std::string message;
    if (selection_.poll(message) != Selection::Event::None) {
        status_ = message;
        updateOverlay();
    }
    if (options_.preview && scene_ && previewDirty_) {
        // The full preview once the camera has rested for 200 ms; meanwhile, in the rendered
        // view, a coarse single pass at most every 100 ms, so that the view follows the camera
        // blockily without ever waiting for it.
        const auto now = std::chrono::steady_clock::now();
        if (now - lastCameraChange_ > std::chrono::milliseconds(200)) {
            restartPreview();
        } else if (options_.view == ViewMode::Rendered &&
                   now - lastCoarseRestart_ > std::chrono::milliseconds(100)) {
            lastCoarseRestart_ = now;
            restartPreview(true);
        }
    }
    if (std::optional<PreviewImage> image = preview_.takeUpdate()) uploadPreview(*image);
}

void Viewer::restartPreview(bool coarse) {
    if (!coarse) previewDirty_ = false;  // a coarse pass leaves the full one to come
    if (!scene_) return;
    PreviewSettings s = options_.previewSettings;
    s.exact = options_.exact;
    const Layout l = layout_.width > 0 ? layout_ : computeLayout(1280, 800, options_.layout);
    // The rendered view: one preview pixel per view pixel, so that the view shows what
    // `penumbra render` gives for this camera at the view's size.
    constexpr double kCoarseScale = 0.125;
    const double scale = coarse                                ? kCoarseScale
                         : options_.view == ViewMode::Rendered ? 1.0
                                                               : options_.previewScale;
    s.width = std::max(8, static_cast<int>(std::lround(l.view.width * scale)));
    s.height = std::max(8, static_cast<int>(std::lround(l.view.height * scale)));
    if (coarse) s.passes = 1;
    preview_.restart(scene_, orbit_.camera(), s);
}

const ViewImage* Viewer::viewImage() {
    if (options_.view != ViewMode::Rendered || previewImage_.width == 0 ||
        previewImage_.rgba.empty())
        return nullptr;  // no image yet: the rasterised scene meanwhile
    viewImage_.texture = previewTexture_;
    viewImage_.bands.clear();
    if (options_.previewSettings.mode == PreviewMode::SideBySide) {
        // Exact left of the split, sampled right of it: each half of the texture is one image of
        // the view's size.
        const float t = static_cast<float>(std::clamp(options_.split, 0.0, 1.0));
        viewImage_.bands.push_back({0, t, 0, 0.5f * t});
        viewImage_.bands.push_back({t, 1, 0.5f + 0.5f * t, 1});
    } else {
        viewImage_.bands.push_back({0, 1, 0, 1});
    }
    return &viewImage_;
}

void Viewer::uploadPreview(const PreviewImage& image) {
    previewImage_ = image;
    if (image.rgba.empty()) return;
    glBindTexture(GL_TEXTURE_2D, previewTexture_);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
    glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, image.width, image.height, 0, GL_RGBA,
                 GL_UNSIGNED_BYTE, image.rgba.data());
    glBindTexture(GL_TEXTURE_2D, 0);
}

void Viewer::startPrecompute() {
    if (!scene_) return;
    precompute_.start(*scene_->store);
    status_ = "precomputing every (receiver patch, light) pair in the background";
}

void Viewer::cancelPrecompute() { precompute_.cancel(); }

void Viewer::startAccuracyStudy() { accuracyJob_.start(scene_, orbit_.camera(), tasks_); }

void Viewer::openAccuracyStudy() {
    showAccuracy_ = true;
    startAccuracyStudy();
}

void Viewer::waitForBackground() {
    if (options_.preview && previewDirty_) restartPreview();  // --no-preview: none
    tasks_.wait();
    preview_.wait();
    pollBackground();
}

void Viewer::handleInput(int width, int height) {
    ImGuiIO& io = ImGui::GetIO();
    if (!scene_) return;
    const Viewport& vp = layout_.view;
    const bool overView = vp.contains(io.MousePos.x, io.MousePos.y) && !io.WantCaptureMouse;
    bool moved = false;
    // The columns' edges: a press on the view's first or last 5 pixels drags that column's edge.
    if (overView && ImGui::IsMouseClicked(ImGuiMouseButton_Left)) {
        if (io.MousePos.x < vp.x + 5) draggingColumn_ = -1;
        if (io.MousePos.x >= vp.x + vp.width - 5) draggingColumn_ = +1;
    }
    if (draggingColumn_ != 0) {
        if (ImGui::IsMouseDown(ImGuiMouseButton_Left)) {
            const int x = static_cast<int>(io.MousePos.x);
            if (draggingColumn_ < 0)
                options_.layout.leftWidth = std::clamp(x, 60, width);
            else
                options_.layout.rightWidth = std::clamp(width - x, 60, width);
            previewDirty_ = true;  // the view's size changed: a new preview once it rests
            lastCameraChange_ = std::chrono::steady_clock::now();
            return;
        }
        draggingColumn_ = 0;
        return;  // the release ends the drag, it picks nothing
    }
    // The split line of the rendered side-by-side view: a press within 6 pixels of it drags it.
    const bool split = options_.view == ViewMode::Rendered &&
                       options_.previewSettings.mode == PreviewMode::SideBySide;
    const double splitX = vp.x + options_.split * vp.width;
    if (split && overView && ImGui::IsMouseClicked(ImGuiMouseButton_Left) &&
        std::fabs(io.MousePos.x - splitX) <= 6)
        draggingSplit_ = true;
    if (draggingSplit_) {
        if (ImGui::IsMouseDown(ImGuiMouseButton_Left) && split) {
            options_.split = std::clamp(
                (static_cast<double>(io.MousePos.x) - vp.x) / std::max(1, vp.width), 0.0, 1.0);
            return;
        }
        draggingSplit_ = false;
        return;  // the release ends the drag, it picks nothing
    }
    if (overView || ImGui::IsMouseDragging(ImGuiMouseButton_Left) ||
        ImGui::IsMouseDragging(ImGuiMouseButton_Right)) {
        if (!io.WantCaptureMouse) {
            if (ImGui::IsMouseDragging(ImGuiMouseButton_Left, 2.0f)) {
                orbit_.orbit(io.MouseDelta.x, io.MouseDelta.y);
                moved = io.MouseDelta.x != 0 || io.MouseDelta.y != 0;
            } else if (ImGui::IsMouseDragging(ImGuiMouseButton_Right, 2.0f) ||
                       ImGui::IsMouseDragging(ImGuiMouseButton_Middle, 2.0f)) {
                orbit_.pan(io.MouseDelta.x, io.MouseDelta.y, vp.height);
                moved = io.MouseDelta.x != 0 || io.MouseDelta.y != 0;
            }
        }
    }
    if (overView && io.MouseWheel != 0) {
        orbit_.zoom(io.MouseWheel);
        moved = true;
    }
    // A click (release without a drag) picks.
    if (overView && ImGui::IsMouseReleased(ImGuiMouseButton_Left) &&
        io.MouseDragMaxDistanceSqr[ImGuiMouseButton_Left] < 9.0f)
        pickPixel(io.MousePos.x, io.MousePos.y, width, height);
    if (!io.WantCaptureKeyboard) {
        if (ImGui::IsKeyPressed('F')) fitCamera();
        if (ImGui::IsKeyPressed('H')) helpPanel_.toggle();
        if (ImGui::IsKeyPressed('T')) showTree_ = !showTree_;
        if (ImGui::IsKeyPressed('A')) showAccuracy_ = !showAccuracy_;
        if (ImGui::IsKeyPressed(ImGui::GetKeyIndex(ImGuiKey_Escape))) clearSelection();
        if (ImGui::IsKeyPressed('L') && selection_.selectedLight()) {
            selection_.nextLight();
            updateOverlay();
        }
        const PreviewMode modes[] = {PreviewMode::Exact, PreviewMode::Sampled,
                                     PreviewMode::SideBySide, PreviewMode::Difference,
                                     PreviewMode::Answers};
        for (int i = 0; i < 5; ++i)
            if (ImGui::IsKeyPressed('1' + i)) {
                options_.previewSettings.mode = modes[i];
                previewDirty_ = true;
            }
        if (ImGui::IsKeyPressed('R')) previewDirty_ = true;
        if (ImGui::IsKeyPressed('V')) {
            options_.view =
                options_.view == ViewMode::Raster ? ViewMode::Rendered : ViewMode::Raster;
            previewDirty_ = true;
        }
        if (ImGui::IsKeyPressed('P')) startPrecompute();
        if (ImGui::IsKeyPressed('C')) cancelPrecompute();
        if (ImGui::IsKeyPressed('Q') && io.KeyCtrl) quit_ = true;
    }
    if (moved) {
        previewDirty_ = true;
        lastCameraChange_ = std::chrono::steady_clock::now();
    }
}

void Viewer::frame(int width, int height, double deltaSeconds) {
    const auto start = std::chrono::steady_clock::now();
    layout_ = computeLayout(width, height, options_.layout);
    ImGuiIO& io = ImGui::GetIO();
    io.DisplaySize = ImVec2(static_cast<float>(width), static_cast<float>(height));
    io.DeltaTime = static_cast<float>(std::max(deltaSeconds, 1e-4));
    pollBackground();

    ImGui_ImplOpenGL3_NewFrame();
    ImGui::NewFrame();
    handleInput(width, height);
    drawPanels();
    ImGui::Render();

    glViewport(0, 0, width, height);
    glClearColor(0.1f, 0.1f, 0.12f, 1.0f);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    if (scene_) {
        double nearDistance = 0, farDistance = 1;
        orbit_.clipRange(scene_->bounds, nearDistance, farDistance);
        renderer_.draw(orbit_.camera(), nearDistance, farDistance, layout_.view, height,
                       viewImage());
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
    const auto record = [&](const char* name, const PanelRect& r) {
        panelRects_[name] = {r.x, r.y, r.width, r.height};
        panelText_.take(name);
    };
    const ScenePanel::Actions scene = scenePanel_.draw(l.scene, scene_.get());
    record("Scene", l.scene);
    switch (PrecomputePanel::draw(l.precompute, precompute_, preview_.effects(),
                                  scene_ ? &scene_->scene : nullptr)) {
        case PrecomputePanel::Action::Start:
            startPrecompute();
            break;
        case PrecomputePanel::Action::Cancel:
            cancelPrecompute();
            break;
        case PrecomputePanel::Action::None:
            break;
    }
    record("Precompute", l.precompute);
    if (showTree_) {
        placeNextWindow(l.tree);
        treePanel_.draw("History tree");
        record("History tree", l.tree);
    }
    switch (PreviewPanel::draw(l.preview, options_.previewSettings, options_.view, options_.exact,
                               saveStem_, previewImage_, preview_.running(), previewTexture_)) {
        case PreviewPanel::Action::Reopen:
            // The store's trees follow the build budget: a new store, the scene reopened.
            if (scene_) openAfterFrame_ = scene_->path;
            break;
        case PreviewPanel::Action::Restart:
            previewDirty_ = true;
            break;
        case PreviewPanel::Action::SaveView:
            saveView(saveStem_.data(), status_);
            break;
        case PreviewPanel::Action::None:
            break;
    }
    if (options_.view == ViewMode::Rendered &&
        options_.previewSettings.mode == PreviewMode::SideBySide) {
        // The split line over the view (under the windows), with the names of its two sides.
        const Viewport& vp = l.view;
        const float x = static_cast<float>(vp.x + options_.split * vp.width);
        const float midY = static_cast<float>(vp.y) + 0.5f * static_cast<float>(vp.height);
        ImDrawList* draw = ImGui::GetBackgroundDrawList();
        draw->AddLine(ImVec2(x, static_cast<float>(vp.y)),
                      ImVec2(x, static_cast<float>(vp.y + vp.height)), IM_COL32(255, 255, 255, 200),
                      2.0f);
        const auto label = [&](float left, const char* text) {
            const ImVec2 size = ImGui::CalcTextSize(text);
            draw->AddRectFilled(ImVec2(left - 4, midY - 2),
                                ImVec2(left + size.x + 4, midY + size.y + 2),
                                IM_COL32(0, 0, 0, 170));
            draw->AddText(ImVec2(left, midY), IM_COL32(255, 255, 255, 255), text);
        };
        label(x - 10 - ImGui::CalcTextSize("exact").x, "exact");
        label(x + 10, "sampled");
    }
    record("Preview", l.preview);
    if (PointPanel::draw(l.point, selection_)) updateOverlay();
    record("Point", l.point);
    LightPlanePanel::draw(l.lightPlane, selection_, scene_ ? &scene_->scene.mesh : nullptr);
    record("Light plane", l.lightPlane);
    PathPanel::draw(l.path, selection_);
    record("Path", l.path);
    // The overlays of the 3D view, recorded too (the tests check that they stay inside it).
    if (helpPanel_.visible()) record("Help", helpPanel_.draw(l.view));
    if (showAccuracy_) {
        drawAccuracy();
        panelText_.take("Accuracy");
    }
    record("Status", StatusBar::draw(l.view, status_, frameStats_));
    drawPixelInspector();
    if (hover_ != nullptr) panelText_.take("Pixel inspector");
    panelText_.end();
    // Actions that replace what the panels drew from, after every panel is drawn.
    if (scene.fit) fitCamera();
    if (scene.open) openScene(*scene.open);
    if (openAfterFrame_) {
        const std::filesystem::path path = *openAfterFrame_;
        openAfterFrame_.reset();
        const Camera camera = orbit_.camera();
        if (openScene(path)) setCamera(camera);  // the same view, with the new build budget
    }
}

bool Viewer::saveView(const std::filesystem::path& stem, std::string& message) {
    const PreviewImage& image = previewImage_;
    if (!scene_ || image.rgba.empty()) {
        message = "save view: no rendered image yet";
        return false;
    }
    const std::vector<float>& radiance =
        !image.exactRadiance.empty() ? image.exactRadiance : image.sampledRadiance;
    auto withExtension = [&](const char* ext) {
        std::filesystem::path p = stem;
        p += ext;
        return p;
    };
    try {
        std::error_code ec;
        if (stem.has_parent_path()) std::filesystem::create_directories(stem.parent_path(), ec);
        writeRgbaPng(withExtension(".png"), image.width, image.height, image.rgba);
        if (!radiance.empty()) {
            Film film;
            film.reset(image.imageWidth, image.height);
            film.passes = 1;
            for (size_t i = 0; i < film.sum.size(); ++i)
                film.sum[i] = Vec3{radiance[3 * i], radiance[3 * i + 1], radiance[3 * i + 2]};
            writePfm(film, withExtension(".pfm").string());
        }
        writeTextFile(withExtension(".json"),
                      jsonSceneWithCamera(
                          scene_->path, orbit_.camera(), withExtension(".json"),
                          scene_->scene.defaultLight ? &*scene_->scene.defaultLight : nullptr));
    } catch (const std::exception& e) {
        message = std::string("save view: ") + e.what();
        return false;
    }
    message = "saved " + withExtension(".png").string() + ", .pfm and .json (" +
              std::to_string(image.imageWidth) + "x" + std::to_string(image.height) + ", " +
              std::to_string(image.passes) + " passes)";
    return true;
}

void Viewer::drawPixelInspector() {
    hover_ = nullptr;
    const ImGuiIO& io = ImGui::GetIO();
    if (options_.view != ViewMode::Rendered || !scene_ || io.WantCaptureMouse || draggingSplit_ ||
        ImGui::IsMouseDragging(ImGuiMouseButton_Left) ||
        ImGui::IsMouseDragging(ImGuiMouseButton_Right))
        return;
    hover_ = pixelInspector_.inspect(*scene_, orbit_.camera(), layout_.view, previewImage_,
                                     io.MousePos.x, io.MousePos.y);
    if (hover_ == nullptr) return;
    const PixelReport& r = *hover_;
    ImGui::BeginTooltip();
    ImGui::Text("pixel (%d, %d)", r.x, r.y);
    auto radiance = [](const char* name, const std::optional<Vec3>& c) {
        if (c)
            ImGui::Text("%-8s L = (%.4g, %.4g, %.4g)", name, c->x, c->y, c->z);
        else
            ImGui::Text("%-8s not rendered (the preview's mode or size)", name);
    };
    radiance("exact", r.exact);
    radiance("sampled", r.sampled);
    if (r.answers) {
        std::string answered;
        for (size_t i = 0; i < kAnswers; ++i)
            if ((*r.answers)[i] > 0)
                answered += std::string(answered.empty() ? "" : ", ") +
                            toString(static_cast<Answer>(i)) + " " +
                            std::to_string((*r.answers)[i]);
        ImGui::Text("answered: %s", answered.empty() ? "no evaluation" : answered.c_str());
    }
    if (!r.hit) {
        ImGui::TextUnformatted("no surface");
    } else {
        ImGui::Text("face %u at (%.4g, %.4g, %.4g)", r.hit->face, r.hit->point.x, r.hit->point.y,
                    r.hit->point.z);
        for (const LightAtPoint& l : r.lights)
            ImGui::Text("light %u: %.2f%% visible, form factor %.4g%s", l.light, 100 * l.fraction,
                        l.formFactor, l.complete ? "" : " (over the hover budget: at least)");
        ImGui::TextUnformatted("click: inspect this point");
    }
    ImGui::EndTooltip();
}

void Viewer::drawAccuracy() {
    if (std::optional<AccuracyStudy> result = accuracyJob_.takeResult())
        accuracyPanel_.setResult(*result);
    // First shown over the 3D view: the controls at its top left, the plot beside them.
    const Viewport& vp = layout_.view;
    const float vx = static_cast<float>(vp.x), vy = static_cast<float>(vp.y);
    ImGui::SetNextWindowPos(ImVec2(vx + 8, vy + 64), ImGuiCond_FirstUseEver);
    if (ImGui::Begin("Accuracy controls", &showAccuracy_,
                     ImGuiWindowFlags_NoSavedSettings | ImGuiWindowFlags_AlwaysAutoResize)) {
        if (accuracyJob_.running()) {
            ImGui::ProgressBar(static_cast<float>(accuracyJob_.progress()), ImVec2(-1, 0),
                               "measuring exact vs 1..1024 shadow rays");
            if (ImGui::Button("Cancel")) accuracyJob_.cancel();
        } else if (ImGui::Button("Measure this view (64x64, 2 spp)")) {
            startAccuracyStudy();
        }
    }
    ImGui::End();
    if (!accuracyPanel_.hasResult()) return;
    ImGui::SetNextWindowPos(
        ImVec2(vx + std::max(8.0f, 0.5f * (static_cast<float>(vp.width) - 640)), vy + 110),
        ImGuiCond_FirstUseEver);
    accuracyPanel_.draw("Accuracy vs time");
    const std::array<float, 4>& r = accuracyPanel_.windowRect();
    panelRects_["Accuracy vs time"] = {r[0], r[1], r[2], r[3]};
}

}  // namespace penumbra::viewer
