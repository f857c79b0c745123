// HeadlessHost: runs the Viewer in an offscreen GL context (OSMesa or EGL surfaceless) and writes
// the complete UI as a PNG: `penumbra screenshot`, and `penumbra view` when there is no display.
#pragma once

#include <array>
#include <filesystem>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "app/viewer/gl/offscreen_context.h"
#include "app/viewer/host/host_error.h"
#include "app/viewer/viewer.h"

namespace penumbra::viewer {

struct HeadlessOptions {
    std::filesystem::path scene;
    gl::OffscreenBackend backend = gl::OffscreenBackend::OsMesa;
    int width = 1280, height = 800;
    std::optional<Vec3> point;                   // inspect this point (on the face containing it)
    std::optional<std::array<double, 2>> pixel;  // or the point under this pixel
    std::optional<Camera> camera;                // else the scene's, else fitted
    std::optional<std::array<double, 2>> hover;  // the mouse over this pixel for the last frames
    // Move this area light (Viewer::moveLight) before anything else is done (after the precompute
    // when `precompute` is set: the move then keeps the trees it leaves true), then draw frames
    // until the trees it made stale are rebuilt; the Move light window is shown.
    std::optional<std::pair<uint32_t, LightMove>> moveLight;
    std::filesystem::path out;       // the screenshot (PNG)
    std::filesystem::path stateOut;  // optional: the UI state (JSON)
    // Optional: the preview image alone, by the extension: .png as shown, .pfm or .exr its linear
    // radiance (radianceFilm, preview_runner.h).
    std::filesystem::path previewOut;
    std::filesystem::path saveView;  // optional: Preview::save to this stem (.png .pfm .exr .json)
    // Start the precompute of every pair and draw frames until it ends, recording the frame
    // times (state JSON "precomputeFrames"); with moveLight, of the scene before the move.
    bool precompute = false;
    // Run the "Accuracy vs time" study of the view and draw frames until it ends: the panel is
    // in the screenshot and the study in the state JSON ("accuracy").
    bool accuracy = false;
    // Print the scene's loader warnings to stderr ("penumbra: warning: ..."), as the commands that
    // load a scene do (screenshot; view has printed them already).
    bool printWarnings = false;
    // The panels arranged as the user would (after the settings file, if any, is read): the
    // layout reset first, then panels moved and sized (x, y, width, height), collapsed, one
    // enlarged (names: panel_arrangement.h). The settings file (viewer.settingsFile) is written
    // at the end, as the window does when it closes.
    bool resetLayout = false;
    std::vector<std::pair<std::string, PanelRect>> arrange;
    std::vector<std::string> collapse;
    std::string enlarge;
    ViewerOptions viewer;
};

// Throws HostInputError (host_error.h) for bad input (scene, point, pixel) and
// std::runtime_error when the GL backend cannot start (its message says why).
void runHeadless(const HeadlessOptions& options);

}  // namespace penumbra::viewer
