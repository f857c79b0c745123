#include "app/viewer/host/window_host.h"

#include <GLFW/glfw3.h>
#include <imgui.h>
#include <imgui_impl_glfw.h>

#include <chrono>
#include <cstdio>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "app/viewer/gl/offscreen_context.h"
#include "app/viewer/host/imgui_session.h"
#include "app/viewer/png_output.h"
#include "engine/io/finite_output.h"

namespace penumbra::viewer {
namespace {

// GLFW reports errors through a plain callback; the message is kept per thread until read.
thread_local std::string tGlfwError;

void onGlfwError(int code, const char* description) {
    tGlfwError = "GLFW error " + std::to_string(code) + ": " + (description ? description : "");
}

class GlfwLibrary {
  public:
    GlfwLibrary() {
        glfwSetErrorCallback(onGlfwError);
        ok_ = glfwInit() == GLFW_TRUE;
    }
    ~GlfwLibrary() {
        if (ok_) glfwTerminate();
    }
    GlfwLibrary(const GlfwLibrary&) = delete;
    GlfwLibrary& operator=(const GlfwLibrary&) = delete;
    bool ok() const { return ok_; }

  private:
    bool ok_ = false;
};

struct DropQueue {
    std::vector<std::filesystem::path> paths;
};

void onDrop(GLFWwindow* window, int count, const char** paths) {
    auto* queue = static_cast<DropQueue*>(glfwGetWindowUserPointer(window));
    for (int i = 0; i < count; ++i) queue->paths.emplace_back(paths[i]);
}

struct WindowDeleter {
    void operator()(GLFWwindow* w) const { glfwDestroyWindow(w); }
};

std::unique_ptr<GLFWwindow, WindowDeleter> createWindow(int width, int height,
                                                        const std::string& title) {
    glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 3);
    glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 3);
    glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
    glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GLFW_TRUE);
    // On a HiDPI monitor the window grows with the content scale (X11 and Windows; Wayland and
    // macOS scale the framebuffer themselves): --size is in screen units, and the panels laid out
    // for 1280x800 at scale 1 keep their proportions at 1.5 and 2.
    glfwWindowHint(GLFW_SCALE_TO_MONITOR, GLFW_TRUE);
    return std::unique_ptr<GLFWwindow, WindowDeleter>(
        glfwCreateWindow(width, height, title.c_str(), nullptr, nullptr));
}

}  // namespace

std::string windowUnavailableReason() {
    const GlfwLibrary glfw;
    if (!glfw.ok()) {
        std::string why = tGlfwError.empty() ? "glfwInit failed" : tGlfwError;
        const char* display = std::getenv("DISPLAY");
        if (display == nullptr || *display == 0) why = "no display ($DISPLAY is not set): " + why;
        return why;
    }
    glfwWindowHint(GLFW_VISIBLE, GLFW_FALSE);
    const auto probe = createWindow(64, 64, "penumbra probe");
    glfwDefaultWindowHints();
    if (!probe) return "no OpenGL 3.3 core window: " + tGlfwError;
    return {};
}

void runWindow(const WindowOptions& o) {
    gl::preferUiThreadSoftwareRasteriser();
    const GlfwLibrary glfw;
    if (!glfw.ok()) throw std::runtime_error("cannot start GLFW: " + tGlfwError);
    auto window = createWindow(o.width, o.height, "Penumbra - " + o.scene.filename().string());
    if (!window) throw std::runtime_error("cannot open an OpenGL 3.3 core window: " + tGlfwError);
    glfwMakeContextCurrent(window.get());
    glfwSwapInterval(1);
    const gl::GlApi api = gl::loadGlApi(
        [](const char* name) { return reinterpret_cast<void*>(glfwGetProcAddress(name)); });
    const gl::ScopedGlApi scope(api);
    DropQueue drops;
    glfwSetWindowUserPointer(window.get(), &drops);
    glfwSetDropCallback(window.get(), onDrop);
    {
        const ImGuiSession imgui;
        if (!ImGui_ImplGlfw_InitForOpenGL(window.get(), true))
            throw std::runtime_error("Dear ImGui's GLFW backend did not initialise");
        struct GlfwBackend {
            ~GlfwBackend() { ImGui_ImplGlfw_Shutdown(); }
        } backend;
        // HiDPI: the monitor's content scale sizes the panels, the widgets and the text.
        ViewerOptions options = o.viewer;
        float xScale = 1, yScale = 1;
        glfwGetWindowContentScale(window.get(), &xScale, &yScale);
        if (xScale > 0) options.layout.scale = xScale;
        Viewer viewer(options);
        if (!viewer.settingsWarning().empty())
            std::fprintf(stderr, "penumbra: warning: %s\n", viewer.settingsWarning().c_str());
        if (!o.scene.empty()) viewer.openScene(o.scene);
        if (o.camera) viewer.setCamera(*o.camera);
        if (o.precompute) viewer.startPrecompute();
        // The light move, once the precompute (if any) has ended: it then keeps the trees it
        // leaves true (moved_light_trees.h) and rebuilds the others.
        std::optional<std::pair<uint32_t, LightMove>> pendingMove = o.moveLight;
        const auto start = std::chrono::steady_clock::now();
        auto last = start;
        std::string lastState;
        constexpr auto kFrame = std::chrono::microseconds(1'000'000 / 60);
        while (!glfwWindowShouldClose(window.get()) && !viewer.quitRequested()) {
            const auto frameStart = std::chrono::steady_clock::now();
            glfwPollEvents();
            for (const auto& p : drops.paths) viewer.openScene(p);
            drops.paths.clear();
            if (pendingMove && !viewer.precomputeRunning()) {
                viewer.moveLight(pendingMove->first, pendingMove->second);  // refused: the status
                viewer.showLightWindow();
                pendingMove.reset();
            }
            ImGui_ImplGlfw_NewFrame();
            int fbWidth = 0, fbHeight = 0;
            glfwGetFramebufferSize(window.get(), &fbWidth, &fbHeight);
            if (fbWidth > 0 && fbHeight > 0) {
                viewer.frame(fbWidth, fbHeight,
                             std::chrono::duration<double>(frameStart - last).count());
                glfwSwapBuffers(window.get());
            }
            last = frameStart;
            if (!o.stateOut.empty() && viewer.frameStats().frames % 10 == 0) {
                nlohmann::json state = viewer.stateJson();
                // The frame times change every frame (the status bar shows them); the rest
                // changes on events.
                state.erase("frames");
                state["panelText"].erase("Status");
                requireFinite(state, "the viewer state");
                const std::string text = state.dump(2) + "\n";
                if (text != lastState) {
                    writeTextFile(o.stateOut, text);
                    lastState = text;
                }
            }
            if (o.quitAfterSeconds > 0 &&
                std::chrono::duration<double>(frameStart - start).count() > o.quitAfterSeconds)
                break;
            std::this_thread::sleep_until(frameStart + kFrame);
        }
        // The layout as the user left it, for the next run.
        if (const std::string why = viewer.saveSettings(); !why.empty())
            std::fprintf(stderr, "penumbra: warning: the layout was not saved: %s\n", why.c_str());
        const FrameStats& f = viewer.frameStats();
        std::fprintf(stderr,
                     "penumbra view: %zu frames, UI work per frame %.1f ms mean, %.1f ms max\n",
                     f.frames, f.frames ? 1e3 * f.sumSeconds / f.frames : 0.0, 1e3 * f.maxSeconds);
    }
}

}  // namespace penumbra::viewer
