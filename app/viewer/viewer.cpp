#include "app/viewer/viewer.h"

#include <imgui.h>
#include <imgui_impl_opengl3.h>

#include <algorithm>
#include <cstddef>
#include <system_error>

#include "app/viewer/default_camera.h"
#include "app/viewer/panels/tree_panel.h"
#include "app/viewer/picking.h"
#include "engine/io/scene_loader.h"
#include "engine/precompute/point_query.h"
#include "engine/precompute/precompute_scheduler.h"

namespace penumbra::viewer {

struct Viewer::PendingInspection {
    std::shared_ptr<LoadedScene> scene;
    uint32_t face = 0;
    Vec3 point;
    std::atomic<bool> done{false};
    std::mutex mutex;  // guards result and error once done is set
    std::optional<PointInspection> result;
    std::string error;
};

Layout computeLayout(int width, int height) {
    Layout l;
    l.width = width;
    l.height = height;
    l.leftWidth = std::clamp(width / 4, 0, 340);
    l.rightWidth = std::clamp(width / 3, 0, 440);
    l.view.x = l.leftWidth;
    l.view.y = 0;
    l.view.width = std::max(1, width - l.leftWidth - l.rightWidth);
    l.view.height = std::max(1, height);
    return l;
}

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

Viewer::Viewer(ViewerOptions options)
    : options_(std::move(options)),
      showHelp_(options_.showHelp),
      treePanel_(std::make_unique<TreePanel>()) {
    glGenTextures(1, &previewTexture_);
    glBindTexture(GL_TEXTURE_2D, previewTexture_);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    glBindTexture(GL_TEXTURE_2D, 0);
    sceneFiles_ = listSceneFiles(options_.assetsDirectory);
}

Viewer::~Viewer() {
    cancelAccuracyStudy();
    cancelPrecompute();
    preview_.stop();
    tasks_.wait();
    preview_.wait();
    precompute_.reset();
    glDeleteTextures(1, &previewTexture_);
}

bool Viewer::openScene(const std::filesystem::path& path) {
    std::shared_ptr<LoadedScene> loaded;
    try {
        loaded = loadScene(path);
    } catch (const std::exception& e) {
        error_ = e.what();
        status_ = "cannot open " + path.string() + ": " + error_;
        return false;
    }
    error_.clear();
    clearSelection();
    preview_.stop();
    // An accuracy study belongs to the scene it measured: a running one is dropped (its task
    // keeps the old scene alive until it stops), a finished one is no longer shown.
    cancelAccuracyStudy();
    accuracyJob_.reset();
    if (accuracyPanel_) accuracyPanel_->clear();
    if (precompute_) {
        // The old scheduler's destructor waits for its builds: let a task do that.
        cancelPrecompute();
        tasks_.run([old = std::move(precompute_)] {});
    }
    scene_ = std::move(loaded);
    renderer_.setScene(scene_->scene);
    orbit_.set(defaultCamera(*scene_));
    previewDirty_ = true;
    lastCameraChange_ = {};
    status_ = "opened " + path.string() + ": " + std::to_string(scene_->scene.faceCount()) +
              " faces, " + std::to_string(scene_->scene.lights.size()) + " area lights";
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
    layout_ = computeLayout(width, height);
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
    auto pending = std::make_shared<PendingInspection>();
    pending->scene = scene_;
    pending->face = *face;
    pending->point = x;
    pending_ = pending;
    selection_ = std::make_pair(*face, x);
    status_ = "inspecting the point on face " + std::to_string(*face) + "...";
    tasks_.run([pending] {
        std::optional<PointInspection> result;
        std::string error;
        try {
            result = inspectPoint(*pending->scene->store, pending->face, pending->point);
        } catch (const std::exception& e) {
            error = e.what();
        }
        {
            const std::lock_guard lock(pending->mutex);
            pending->result = std::move(result);
            pending->error = std::move(error);
        }
        pending->done = true;
    });
    return true;
}

void Viewer::clearSelection() {
    pending_.reset();
    inspection_.reset();
    selection_.reset();
    treePanel_->setTree(nullptr, {});
    renderer_.setOverlay({});
}

void Viewer::updateOverlay() {
    if (!inspection_ || !scene_) {
        renderer_.setOverlay({});
        treePanel_->setTree(nullptr, {});
        return;
    }
    selectedLight_ = std::min(
        selectedLight_, inspection_->lights.empty() ? size_t{0} : inspection_->lights.size() - 1);
    renderer_.setOverlay(buildOverlay(*inspection_, scene_->bounds.diagonal(), selectedLight_));
    if (inspection_->lights.empty()) {
        treePanel_->setTree(nullptr, {});
    } else {
        const LightInspection& li = inspection_->lights[selectedLight_];
        treePanel_->setTree(li.tree, li.result.path, &scene_->scene.mesh);
    }
}

void Viewer::pollBackground() {
    if (pending_ && pending_->done) {
        std::shared_ptr<PendingInspection> p = std::move(pending_);
        const std::lock_guard lock(p->mutex);
        if (p->result) {
            inspection_ = std::move(p->result);
            status_ = "point (" + std::to_string(inspection_->point.x) + ", " +
                      std::to_string(inspection_->point.y) + ", " +
                      std::to_string(inspection_->point.z) + ") on face " +
                      std::to_string(inspection_->face);
        } else {
            inspection_.reset();
            status_ = "the point query failed: " + p->error;
        }
        updateOverlay();
    }
    if (options_.preview && scene_ && previewDirty_ &&
        std::chrono::steady_clock::now() - lastCameraChange_ > std::chrono::milliseconds(200))
        restartPreview();
    if (std::optional<PreviewImage> image = preview_.takeUpdate()) uploadPreview(*image);
}

void Viewer::restartPreview() {
    previewDirty_ = false;
    if (!scene_) return;
    PreviewSettings s = options_.previewSettings;
    const Layout l = layout_.width > 0 ? layout_ : computeLayout(1280, 800);
    s.width = std::max(8, static_cast<int>(l.view.width * options_.previewScale));
    s.height = std::max(8, static_cast<int>(l.view.height * options_.previewScale));
    previewCamera_ = orbit_.camera();
    preview_.restart(scene_, previewCamera_, s);
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

bool Viewer::precomputeAvailable() const { return true; }

void Viewer::startPrecompute() {
    if (!scene_) return;
    if (!precompute_) precompute_ = std::make_shared<PrecomputeScheduler>(*scene_->store);
    precompute_->requestAll();
    precomputeStart_ = std::chrono::steady_clock::now();
    status_ = "precomputing every (receiver patch, light) pair in the background";
}

void Viewer::cancelPrecompute() {
    if (precompute_) precompute_->cancel();
}

bool Viewer::precomputeRunning() const {
    return precompute_ && precompute_->progress().state == PrecomputeProgress::State::Running;
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
        if (ImGui::IsKeyPressed('H')) showHelp_ = !showHelp_;
        if (ImGui::IsKeyPressed('T')) showTree_ = !showTree_;
        if (ImGui::IsKeyPressed('A')) showAccuracy_ = !showAccuracy_;
        if (ImGui::IsKeyPressed(ImGui::GetKeyIndex(ImGuiKey_Escape))) clearSelection();
        if (ImGui::IsKeyPressed('L') && inspection_ && !inspection_->lights.empty()) {
            selectedLight_ = (selectedLight_ + 1) % inspection_->lights.size();
            updateOverlay();
        }
        const PreviewMode modes[] = {PreviewMode::Exact, PreviewMode::Sampled,
                                     PreviewMode::SideBySide, PreviewMode::Difference};
        for (int i = 0; i < 4; ++i)
            if (ImGui::IsKeyPressed('1' + i)) {
                options_.previewSettings.mode = modes[i];
                previewDirty_ = true;
            }
        if (ImGui::IsKeyPressed('R')) previewDirty_ = true;
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
    layout_ = computeLayout(width, height);
    ImGuiIO& io = ImGui::GetIO();
    io.DisplaySize = ImVec2(static_cast<float>(width), static_cast<float>(height));
    io.DeltaTime = static_cast<float>(std::max(deltaSeconds, 1e-4));
    pollBackground();

    ImGui_ImplOpenGL3_NewFrame();
    ImGui::NewFrame();
    handleInput(width, height);
    drawScenePanel();
    drawPrecomputePanel();
    if (showTree_) drawTreePanel();
    drawPreviewPanel();
    drawPointPanel();
    drawLightPlanePanel();
    drawPathPanel();
    if (showHelp_) drawHelpPanel();
    if (showAccuracy_)
        drawAccuracyPanel();
    else
        panelRects_.erase("Accuracy vs time");
    drawStatusBar();
    ImGui::Render();

    glViewport(0, 0, width, height);
    glClearColor(0.1f, 0.1f, 0.12f, 1.0f);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    if (scene_) renderer_.draw(orbit_, scene_->bounds, layout_.view, height);
    glViewport(0, 0, width, height);
    ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());

    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    ++frameStats_.frames;
    frameStats_.lastSeconds = seconds;
    frameStats_.sumSeconds += seconds;
    frameStats_.maxSeconds = std::max(frameStats_.maxSeconds, seconds);
}

}  // namespace penumbra::viewer
