// Viewer: the viewer and visibility debugger, independent of where it draws. The window
// (window_host.cpp: GLFW) and the offscreen backends (headless_host.cpp: OSMesa, EGL) create a GL
// context, make its function table current (app/viewer/gl/gl_api.h), set up Dear ImGui's platform
// side, and call frame() once per frame: the same UI code runs in all three.
//
// Threads: the UI thread never waits on background work. Point inspections (which may build
// history trees), preview passes and the precompute run as oneTBB tasks; each frame polls atomics
// and swaps results under short mutexes.
//
// What it coordinates, each in its own file: the selection (selection.h) and the history-tree
// browser that follows it, the preview and the rendered view (preview.h), the mouse over the 3D
// view (view_mouse.h), the precompute (precompute_job.h), the accuracy study's windows
// (panels/accuracy_windows.h), the layout (layout.h) and the panels (panels/).
#pragma once

#include <tbb/task_group.h>

#include <array>
#include <filesystem>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <set>
#include <string>
#include <utility>

#include "app/viewer/gl/scene_renderer.h"
#include "app/viewer/layout.h"
#include "app/viewer/light_move_job.h"
#include "app/viewer/loaded_scene.h"
#include "app/viewer/orbit_camera.h"
#include "app/viewer/panel_arrangement.h"
#include "app/viewer/panels/accuracy_windows.h"
#include "app/viewer/panels/help_panel.h"
#include "app/viewer/panels/light_panel.h"
#include "app/viewer/panels/panel_text.h"
#include "app/viewer/panels/scene_panel.h"
#include "app/viewer/panels/tree_graph_panel.h"
#include "app/viewer/precompute_job.h"
#include "app/viewer/preview.h"
#include "app/viewer/selection.h"
#include "app/viewer/view_mouse.h"
#include "app/viewer/viewer_options.h"
#include "app/viewer/visibility_link.h"
#include "engine/precompute/point_inspection.h"

namespace penumbra::viewer {

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
    const LoadedScene* scene() const { return scene_.get(); }  // null before the first scene
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
    bool precomputeRunning() const { return precompute_.running(); }
    // The visibility file (--visibility, visibility_link.h): read its trees into the scene's
    // store again, or write the store's trees to it (atomically; a finished precompute does).
    // Each returns what it did, for the status line. The scene as opened only (not moved).
    std::string loadVisibility();
    std::string saveVisibility();
    const VisibilityLink& visibility() const { return visibility_; }

    // Moves area light `light` by `move` from where the file put it (engine/scene/light_move.h;
    // the Move light window, M, does this as its fields are dragged). The moved scene (a copy, its
    // BVH) is built in the background and replaces the current one at a later frame's poll: the
    // preview restarts on it tree-less (Preview::setTreeLess), an inspected point is inspected
    // again there (its tree-less answer at once), and the trees of the scene before, all stale, are
    // dropped with its store while their pairs are rebuilt in the background (the precompute job).
    // False with the reason in the status for a light that does not exist or a refused move (a
    // scale factor of 0 or below); a move the contract refuses once built says so at that poll.
    bool moveLight(uint32_t light, const LightMove& move);
    // A light move is being built, or the trees of the last one are being rebuilt.
    bool lightMoveBuilding() const { return lightJob_.busy(); }
    bool lightTreesRebuilding() const { return lightRebuild_; }
    void showLightWindow() { lightPanel_.show(); }

    // The "Accuracy vs time" study of the current view (engine/studies/accuracy_study.h), in the
    // background: opens its windows and starts it (the A key opens them, their button starts it).
    void openAccuracyStudy();
    const AccuracyWindows& accuracy() const { return accuracy_; }

    // One frame: ImGui frame (after the host's platform NewFrame), input, panels, the 3D view,
    // ImGui's draw data. The framebuffer must be bound and of this size.
    void frame(int width, int height, double deltaSeconds);

    // The panels' arrangement (panel_arrangement.h): the user's moves, resizes, collapses and
    // enlargements; "reset layout" (Ctrl+L, the Panels menu) puts every panel and column back.
    PanelArrangement& arrangement() { return arrangement_; }
    void resetLayout();
    // The settings file (ViewerOptions::settingsFile): why it could not be read at the start
    // ("" when it was read, or is missing: a first run), and saving it (the arrangement, the
    // columns, Help seen; not over a file that could not be read). Returns "" or why not.
    const std::string& settingsWarning() const { return settingsWarning_; }
    std::string saveSettings() const;

    bool quitRequested() const { return quit_; }
    const std::string& status() const { return status_; }
    const FrameStats& frameStats() const { return frameStats_; }
    void resetFrameStats() { frameStats_ = {}; }
    // The preview, its image and the rendered view (Preview::save keeps what you see).
    const Preview& preview() const { return preview_; }

    // Headless only (blocks): until a requested light move has arrived (moveLight) and replaced
    // the scene.
    void waitForLightMove();
    // Headless only (blocks): until the pending inspection has arrived and the preview finished.
    void waitForBackground();

    // What the UI shows, as JSON (for tests and --state-out).
    nlohmann::json stateJson() const;

  private:
    void handleInput(int width, int height);
    void pollBackground();
    // The overlay and the tree browser follow the selection's inspection and light.
    void updateOverlay();
    // The menu bar (Panels: enlarge, show, reset layout); returns its height.
    int drawMenuBar();
    void drawPanels();
    // A moved version of the scene arrived (LightMoveJob): it replaces the current one (above).
    void lightMoveArrived(std::shared_ptr<LoadedScene> moved);
    // Enlarges the panel under the mouse, else restores the enlarged one, else enlarges the
    // history tree (the E key).
    void enlargeHovered();

    ViewerOptions options_;
    SceneRenderer renderer_;
    std::shared_ptr<LoadedScene> scene_;
    OrbitCamera orbit_;
    Layout layout_;
    std::string status_;
    bool quit_ = false;

    Selection selection_;

    Preview preview_;
    std::array<char, 256> saveStem_{};  // the Preview panel's "save view" path (STEM)
    std::optional<std::filesystem::path> openAfterFrame_;  // reopen (a new build budget)
    ViewMouse mouse_;

    PrecomputeJob precompute_;
    VisibilityLink visibility_;  // the visibility file of the scene (--visibility)
    // The status line tells of a running precompute: it says how it ended at the next poll after.
    bool precomputeWatched_ = false;
    std::optional<PrecomputeProgress> precomputeNow_;  // this frame's reading (none: not started)

    // Light moves: the job that builds the moved scenes, the pairs whose trees were dropped by
    // moves (rebuilt in the background while lightRebuild_), and what the Move light window says.
    LightMoveJob lightJob_;
    std::set<std::pair<uint32_t, uint32_t>> rebuildPairs_;  // (receiver face, light face)
    bool lightRebuild_ = false;
    LightMoveStatus lightStatus_;

    // The panels that keep state of their own.
    ScenePanel scenePanel_;
    HelpPanel helpPanel_;
    LightPanel lightPanel_;
    ui::TreeGraphPanel treePanel_;
    bool showTree_ = true;
    AccuracyWindows accuracy_;

    PanelArrangement arrangement_;
    std::string settingsWarning_;
    bool settingsReadable_ = true;
    bool settingsWarned_ = false;  // the status line said it once  // not a file that could not be
                                   // read: saveSettings() may write

    FrameStats frameStats_;
    std::map<std::string, std::array<float, 4>> panelRects_;  // x, y, width, height
    std::map<std::string, float> panelOverflow_;              // panels/panel_fit.h
    PanelText panelText_;    // what each panel said in the last frame
    tbb::task_group tasks_;  // inspections, and disposal of old schedulers; waited on in ~Viewer
};

}  // namespace penumbra::viewer
