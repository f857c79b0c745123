// WindowHost: the interactive viewer in a GLFW window (OpenGL 3.3 core through libGL/GLX, which
// GLFW opens at run time). The loop caps itself at 60 frames per second (glfwSwapInterval has no
// effect under Xvfb and some compositors).
#pragma once

#include <filesystem>
#include <optional>

#include "app/viewer/viewer.h"

namespace penumbra::viewer {

struct WindowOptions {
    std::filesystem::path scene;
    int width = 1280, height = 800;
    std::optional<Camera> camera;
    std::filesystem::path stateOut;  // optional: the UI state (JSON), rewritten when it changes
    double quitAfterSeconds = 0;     // > 0: close by itself (tests)
    bool precompute = false;         // start precomputing every pair once the scene is open
    // Move this area light once the scene is open (after the precompute, when `precompute` is
    // set), and show the Move light window.
    std::optional<std::pair<uint32_t, LightMove>> moveLight;
    ViewerOptions viewer;
};

// Why the window cannot open (no display, no GLX 3.3 context); empty when it can. Calls glfwInit
// and terminates GLFW again.
std::string windowUnavailableReason();

// Runs until the window closes, then prints the frame times (count, mean, max) to stderr.
// Throws std::runtime_error when no window can be opened.
void runWindow(const WindowOptions& options);

}  // namespace penumbra::viewer
