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

#include "app/viewer/accuracy_job.h"
#include "app/viewer/gl/scene_renderer.h"
#include "app/viewer/layout.h"
#include "app/viewer/loaded_scene.h"
#include "app/viewer/orbit_camera.h"
#include "app/viewer/panels/accuracy_panel.h"
#include "app/viewer/panels/help_panel.h"
#include "app/viewer/panels/panel_text.h"
#include "app/viewer/panels/preview_panel.h"
#include "app/viewer/panels/scene_panel.h"
#include "app/viewer/panels/tree_graph_panel.h"
#include "app/viewer/pixel_inspector.h"
#include "app/viewer/precompute_job.h"
#include "app/viewer/preview_runner.h"
#include "app/viewer/selection.h"
#include "engine/precompute/point_inspection.h"
#include "engine/render/exact_options.h"

namespace penumbra::viewer {

struct ViewerOptions {
    std::filesystem::path assetsDirectory = "assets";  // the scene list of the Scene panel
    bool showHelp = true;
    bool preview = true;               // run the progressive preview (when the renderer exists)
    PreviewSettings previewSettings;   // width/height are overwritten from the viewport
    double previewScale = 0.25;        // preview pixels per viewport pixel (the panel's thumbnail)
    ViewMode view = ViewMode::Raster;  // the rendered view renders at the viewport's resolution
    double split = 0.5;  // side by side in the rendered view: exact left of this fraction
    ExactOptions exact;  // the build budget and the renderer's exact settings
    // How scenes load (engine/io/load_options.h): --strict (what the loaders repair is an error
    // instead) and --no-default-light (a scene without any light stays unlit).
    LoadOptions load = LoadOptions::forCommands();
    // The content scale (the window host sets GLFW's; screenshot --ui-scale) and the columns'
    // widths (dragged at the 3D view's edges).
    LayoutSettings layout;
};

class Viewer {
  public:
    // Needs the GL table current (builds shaders and buffers).
    explicit Viewer(ViewerOptions options);
    ~Viewer();
    Viewer(const Viewer&) = delete;
    Viewer& operator=(const Viewer&) = delete;

    // Opens a scene (synchronously: loading and the BVH). On failure the message goes to the
    // status line, the current scene stays, and false is returned.
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
    void startPrecompute();
    void cancelPrecompute();
    bool precomputeRunning() const { return precompute_.running(); }

    // The "Accuracy vs time" study of the current view (engine/studies/accuracy_study.h), in the
    // background: opens its panels and starts it (the A key and the panel's button do the same).
    void openAccuracyStudy();
    bool accuracyStudyRunning() const { return accuracyJob_.running(); }

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
    bool inspectionPending() const { return selection_.pending(); }

    // Keep what you see: the preview's image as STEM.png (as shown, 8-bit sRGB; side by side: both
    // halves), its linear exact radiance (the sampled one when the mode renders no exact image)
    // as STEM.pfm, and the scene with the current camera as STEM.json (engine/io/scene_file.h:
    // `penumbra view STEM.json` or `penumbra render STEM.json --size WxH` give this view again).
    // Every file atomically. False with the reason in `message` (no image yet, a write failed).
    bool saveView(const std::filesystem::path& stem, std::string& message);

    // What the UI shows, as JSON (for tests and --state-out).
    nlohmann::json stateJson() const;

  private:
    void handleInput(int width, int height);
    void pollBackground();
    // The preview for the current camera: at the thumbnail's scale, or at the view's resolution
    // in the rendered view; `coarse`: one pass at kCoarseScale (the rendered view while the camera
    // moves).
    void restartPreview(bool coarse = false);
    // The rendered view's image for this frame (nullptr: draw the rasterised scene).
    const ViewImage* viewImage();
    void uploadPreview(const PreviewImage& image);
    // The overlay and the tree browser follow the selection's inspection and light.
    void updateOverlay();
    void startAccuracyStudy();
    void drawPanels();
    // The rendered view's pixel inspector: a tooltip for the pixel under the mouse.
    void drawPixelInspector();
    void drawAccuracy();

    ViewerOptions options_;
    SceneRenderer renderer_;
    std::shared_ptr<LoadedScene> scene_;
    OrbitCamera orbit_;
    Layout layout_;
    std::string status_;
    bool quit_ = false;

    Selection selection_;

    // Preview.
    PreviewRunner preview_;
    PreviewImage previewImage_;
    GLuint previewTexture_ = 0;
    bool previewDirty_ = false;
    std::chrono::steady_clock::time_point lastCameraChange_, lastCoarseRestart_;
    ViewImage viewImage_;
    std::array<char, 256> saveStem_{};  // the Preview panel's "save view" path (STEM)
    std::optional<std::filesystem::path> openAfterFrame_;  // reopen (a new build budget)
    PixelInspector pixelInspector_;
    const PixelReport* hover_ = nullptr;  // this frame's pixel report (the inspector's)
    bool draggingSplit_ = false;
    int draggingColumn_ = 0;  // -1: the left column's edge, +1: the right one's

    PrecomputeJob precompute_;
    AccuracyJob accuracyJob_;

    // The panels that keep state of their own.
    ScenePanel scenePanel_;
    HelpPanel helpPanel_;
    ui::TreeGraphPanel treePanel_;
    bool showTree_ = true;
    ui::AccuracyPanel accuracyPanel_;
    bool showAccuracy_ = false;

    FrameStats frameStats_;
    std::map<std::string, std::array<float, 4>> panelRects_;  // x, y, width, height
    PanelText panelText_;    // what each panel said in the last frame
    tbb::task_group tasks_;  // inspections, and disposal of old schedulers; waited on in ~Viewer
};

}  // namespace penumbra::viewer
