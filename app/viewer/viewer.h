// Viewer: the viewer and visibility debugger, independent of where it draws. The window
// (window_host.cpp: GLFW) and the offscreen backends (headless_host.cpp: OSMesa, EGL) create a GL
// context, make its function table current (app/viewer/gl/gl_api.h), set up Dear ImGui's platform
// side, and call frame() once per frame: the same UI code runs in all three.
//
// Threads: the UI thread never waits on background work. Point inspections (which may build
// history trees), preview passes and the precompute run as oneTBB tasks; each frame polls atomics
// and swaps results under short mutexes.
#pragma once

#include <tbb/task_group.h>

#include <array>
#include <atomic>
#include <chrono>
#include <deque>
#include <filesystem>
#include <map>
#include <memory>
#include <mutex>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "app/viewer/gl/scene_renderer.h"
#include "app/viewer/loaded_scene.h"
#include "app/viewer/orbit_camera.h"
#include "app/viewer/panels/accuracy_panel.h"
#include "app/viewer/point_inspection.h"
#include "app/viewer/preview_runner.h"

namespace penumbra {
class PrecomputeScheduler;
}

namespace penumbra::viewer {

class TreePanel;

struct ViewerOptions {
    std::filesystem::path assetsDirectory = "assets";  // the scene list of the Scene panel
    bool showHelp = true;
    bool preview = true;              // run the progressive preview (when the renderer exists)
    PreviewSettings previewSettings;  // width/height are overwritten from the viewport
    double previewScale = 0.25;       // preview pixels per viewport pixel
};

// Where the panels and the 3D view go in a framebuffer of the given size.
struct Layout {
    Viewport view;       // the 3D view
    int leftWidth = 0;   // left column: scene, precompute, history tree, preview
    int rightWidth = 0;  // right column: point, light plane, path
    int width = 0, height = 0;
};
Layout computeLayout(int width, int height);

// The scene list of the Scene panel: every file loadScene reads (engine/io/scene_loader.h, any case
// of the extension) directly in `assets`, then in `assets`/scenes (the JSON scenes), each
// directory's files sorted. Missing directories list nothing.
std::vector<std::filesystem::path> listSceneFiles(const std::filesystem::path& assets);

struct FrameStats {
    size_t frames = 0;
    double maxSeconds = 0, sumSeconds = 0, lastSeconds = 0;
};

class Viewer {
  public:
    // Needs the GL table current (builds shaders and buffers).
    explicit Viewer(ViewerOptions options);
    ~Viewer();
    Viewer(const Viewer&) = delete;
    Viewer& operator=(const Viewer&) = delete;

    // Opens a scene (synchronously: loading and the BVH). On failure the message goes to the
    // status line, the current scene stays, and false is returned (error() holds it).
    bool openScene(const std::filesystem::path& path);
    bool hasScene() const { return scene_ != nullptr; }
    const LoadedScene* scene() const { return scene_.get(); }
    void setCamera(const Camera& camera);
    const Camera& camera() const { return orbit_.camera(); }
    void fitCamera();

    // Selects the surface point under framebuffer pixel (px, py) for the layout of a framebuffer
    // of size (width, height). False (with a status message) when nothing is hit.
    bool pickPixel(double px, double py, int width, int height);
    // Selects point x (on `face`, or on the face findFaceContaining finds). False with a status
    // message when x lies on no face or on several.
    bool selectPoint(const Vec3& x, std::optional<uint32_t> face = std::nullopt);
    void clearSelection();

    // Precompute (engine/precompute/precompute_scheduler.h): every pair of the scene, in the
    // background.
    bool precomputeAvailable() const;
    void startPrecompute();
    void cancelPrecompute();
    bool precomputeRunning() const;

    // The "Accuracy vs time" study of the current view (engine/studies/accuracy_study.h), in the
    // background: opens its panels and starts it (the A key and the panel's button do the same).
    void openAccuracyStudy();
    bool accuracyStudyRunning() const;

    // One frame: ImGui frame (after the host's platform NewFrame), input, panels, the 3D view,
    // ImGui's draw data. The framebuffer must be bound and of this size.
    void frame(int width, int height, double deltaSeconds);

    bool quitRequested() const { return quit_; }
    const std::string& status() const { return status_; }
    const FrameStats& frameStats() const { return frameStats_; }
    const Layout& layout() const { return layout_; }
    const PreviewImage& previewImage() const { return previewImage_; }
    void resetFrameStats() { frameStats_ = {}; }

    // Headless only (blocks): until the pending inspection has arrived and the preview finished.
    void waitForBackground();
    bool inspectionPending() const { return pending_ != nullptr; }

    // What the UI shows, as JSON (for tests and --state-out).
    nlohmann::json stateJson() const;

  private:
    struct PendingInspection;
    void handleInput(int width, int height);
    void pollBackground();
    void restartPreview();
    void uploadPreview(const PreviewImage& image);
    void updateOverlay();

    // Positions the next panel window and records its rectangle (panelRects_).
    void place(const char* panel, float x, float y, float w, float h);
    void drawScenePanel();
    void drawHelpPanel();
    void drawPointPanel();
    void drawLightPlanePanel();
    void drawPathPanel();
    void drawTreePanel();
    void drawPreviewPanel();
    void drawPrecomputePanel();
    void drawStatusBar();
    void drawAccuracyPanel();
    void startAccuracyStudy();
    void cancelAccuracyStudy();

    ViewerOptions options_;
    SceneRenderer renderer_;
    std::shared_ptr<LoadedScene> scene_;
    OrbitCamera orbit_;
    Layout layout_;
    std::string status_;
    std::string error_;
    bool quit_ = false;
    bool showHelp_ = true, showTree_ = true;

    // The selection and its inspection (arrives from a background task).
    std::optional<PointInspection> inspection_;
    std::shared_ptr<PendingInspection> pending_;
    size_t selectedLight_ = 0;
    std::optional<std::pair<uint32_t, Vec3>> selection_;

    // Preview.
    PreviewRunner preview_;
    PreviewImage previewImage_;
    GLuint previewTexture_ = 0;
    Camera previewCamera_;
    bool previewDirty_ = false;
    std::chrono::steady_clock::time_point lastCameraChange_;

    // Precompute (null when the scheduler is not built in).
    std::shared_ptr<PrecomputeScheduler> precompute_;
    std::chrono::steady_clock::time_point precomputeStart_;

    // "Accuracy vs time" (A): the study of engine/studies/accuracy_study.h for the current scene
    // and view, measured on a background task; the window shows its progress, then the curves.
    struct AccuracyJob;
    std::shared_ptr<AccuracyJob> accuracyJob_;
    std::unique_ptr<ui::AccuracyPanel> accuracyPanel_;
    bool showAccuracy_ = false;

    std::unique_ptr<TreePanel> treePanel_;
    std::vector<std::filesystem::path> sceneFiles_;
    FrameStats frameStats_;
    std::map<std::string, std::array<float, 4>> panelRects_;  // x, y, width, height
    tbb::task_group tasks_;  // inspections, and disposal of old schedulers; waited on in ~Viewer
};

}  // namespace penumbra::viewer
