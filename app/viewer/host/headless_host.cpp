#include "app/viewer/host/headless_host.h"

#include <imgui.h>

#include <cfloat>
#include <chrono>
#include <iostream>
#include <optional>
#include <stdexcept>

#include "app/viewer/host/host_error.h"
#include "app/viewer/host/imgui_session.h"
#include "app/viewer/png_output.h"
#include "engine/io/finite_output.h"
#include "engine/io/image_io.h"

namespace penumbra::viewer {

void runHeadless(const HeadlessOptions& o) {
    const std::unique_ptr<gl::OffscreenContext> context =
        gl::createOffscreenContext(o.backend, o.width, o.height);
    const gl::ScopedGlApi scope(context->api());
    const ImGuiSession imgui;
    ImGui::GetIO().BackendPlatformName = "penumbra-headless";
    // The mouse is nowhere: no hover effects in the screenshot.
    ImGui::GetIO().MousePos = ImVec2(-FLT_MAX, -FLT_MAX);

    Viewer viewer(o.viewer);
    if (!viewer.settingsWarning().empty())
        std::cerr << "penumbra: warning: " << viewer.settingsWarning() << '\n';
    if (o.resetLayout) viewer.resetLayout();
    for (const auto& [name, rect] : o.arrange) viewer.arrangement().arrange(name, rect);
    for (const std::string& name : o.collapse) viewer.arrangement().setCollapsed(name, true);
    if (!o.enlarge.empty() && viewer.arrangement().enlarged() != o.enlarge)
        viewer.arrangement().toggleEnlarged(o.enlarge);
    if (!viewer.openScene(o.scene))
        throw HostInputError(HostInputError::Input::Scene, viewer.status());
    if (o.printWarnings)
        for (const std::string& notice : viewer.scene()->scene.loadNotices())
            std::cerr << "penumbra: warning: " << notice << '\n';
    if (o.camera) viewer.setCamera(*o.camera);
    const double dt = 1.0 / 60;
    viewer.frame(o.width, o.height, dt);  // lays out the panels, builds the font atlas
    // The precompute of every pair, frames drawn until it ends (their times recorded).
    nlohmann::json precomputeFrames;
    const auto precomputeAll = [&] {
        viewer.frame(o.width, o.height, dt);
        viewer.resetFrameStats();
        const auto start = std::chrono::steady_clock::now();
        viewer.startPrecompute();
        while (viewer.precomputeRunning()) viewer.frame(o.width, o.height, dt);
        const double seconds =
            std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        const FrameStats stats = viewer.frameStats();
        precomputeFrames = {{"frames", stats.frames},
                            {"maxSeconds", stats.maxSeconds},
                            {"meanSeconds", stats.frames ? stats.sumSeconds / stats.frames : 0.0},
                            {"precomputeSeconds", seconds}};
    };
    if (o.moveLight) {
        // Precomputed first, the move keeps the trees it leaves true and rebuilds the others.
        if (o.precompute) precomputeAll();
        if (!viewer.moveLight(o.moveLight->first, o.moveLight->second))
            throw HostInputError(HostInputError::Input::MoveLight, viewer.status());
        viewer.waitForLightMove();
        if (viewer.scene()->version == 0)  // refused once built (the contract): the status says why
            throw HostInputError(HostInputError::Input::MoveLight, viewer.status());
        while (viewer.lightTreesRebuilding()) viewer.frame(o.width, o.height, dt);
        viewer.showLightWindow();
    }
    if (o.point && !viewer.selectPoint(*o.point))
        throw HostInputError(HostInputError::Input::Point, viewer.status());
    if (o.pixel && !viewer.pickPixel((*o.pixel)[0], (*o.pixel)[1], o.width, o.height))
        throw HostInputError(HostInputError::Input::Pixel, viewer.status());
    if (o.precompute && !o.moveLight) precomputeAll();
    if (o.accuracy) {
        // As in the window: the study runs on the viewer's tasks while frames are drawn.
        viewer.openAccuracyStudy();
        while (viewer.accuracy().running()) viewer.frame(o.width, o.height, dt);
    }
    viewer.waitForBackground();
    // The mouse over --hover (the pixel inspector's tooltip in the rendered view), or nowhere.
    if (o.hover)
        ImGui::GetIO().MousePos =
            ImVec2(static_cast<float>((*o.hover)[0]), static_cast<float>((*o.hover)[1]));
    // A few frames: auto-sized windows settle in two.
    for (int i = 0; i < 3; ++i) viewer.frame(o.width, o.height, dt);
    if (!o.saveView.empty()) {
        std::string message;
        if (!viewer.preview().save(o.saveView, viewer.scene(), viewer.camera(), message))
            throw std::runtime_error(message);
    }
    if (const std::string why = viewer.saveSettings(); !why.empty()) throw std::runtime_error(why);
    const std::vector<uint8_t> pixels = context->readRgba();
    if (!o.out.empty()) writeRgbaPng(o.out, o.width, o.height, pixels);
    const PreviewImage& preview = viewer.preview().image();
    if (!o.previewOut.empty() && preview.width > 0) {
        const std::optional<ImageFormat> format = imageFormatOf(o.previewOut);
        if (format == ImageFormat::Png) {
            writeRgbaPng(o.previewOut, preview.width, preview.height, preview.rgba);
        } else if (format) {
            const std::optional<Film> radiance = radianceFilm(preview);
            if (!radiance)
                throw std::runtime_error("cannot write '" + o.previewOut.string() +
                                         "': the preview has no linear image yet");
            writeImage(*radiance, o.previewOut.string(), *format);
        } else {
            throw std::runtime_error("cannot write '" + o.previewOut.string() +
                                     "': the preview image must be " + kImageExtensions);
        }
    }
    if (!o.stateOut.empty()) {
        nlohmann::json state = viewer.stateJson();
        state["backend"] = gl::toString(o.backend);
        state["renderer"] = context->description();
        if (!precomputeFrames.is_null()) state["precomputeFrames"] = precomputeFrames;
        requireFinite(state, o.stateOut);
        writeTextFile(o.stateOut, state.dump(2) + "\n");
    }
}

}  // namespace penumbra::viewer
