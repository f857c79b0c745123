// `penumbra view [SCENE] [--camera ...] [--size WxH] [--state-out FILE.json]
//  [--move-light N [--translate X,Y,Z] [--rotate AX,AY,AZ] [--scale S|SX,SY,SZ]] ...`
//
// The interactive viewer and visibility debugger in a window (app/viewer/host/window_host.h). With
// no display it says so and writes what the window would have shown instead: the headless
// screenshot (and the preview image, when the renderer is built in) into --out-dir (default out/).
#include <CLI/CLI.hpp>
#include <filesystem>
#include <iostream>
#include <memory>
#include <string>

#include "app/cli/arguments.h"
#include "app/cli/commands.h"
#include "app/viewer/host/headless_host.h"
#include "app/viewer/host/window_host.h"
#include "app/viewer/viewer_settings.h"

namespace penumbra::cli {
namespace {

struct ViewOptions {
    std::string scene = "assets/cornell_box.obj";
    std::string camera, size = "1280x800", stateOut, outDir = "out", view = "rendered", settings,
                        visibility;
    double quitAfter = 0;
    bool noPreview = false;
    bool precompute = false;
    SceneOptions sceneOptions;
    ExactOptions exact;
    LightMoveOptions move;
};

void runView(const CLI::App& sub, const ViewOptions& o) {
    const auto size = parseSize("--size", o.size, kWindowSize);
    std::optional<Camera> camera;
    if (sub.count("--camera") > 0) camera = parseCamera("--camera", o.camera);
    if (o.quitAfter < 0) throw usageError("--quit-after: must be >= 0 seconds");
    viewer::ViewMode view = viewer::ViewerOptions{}.view;
    viewer::PreviewMode mode = viewer::PreviewSettings{}.mode;
    if (!viewer::parseViewName(o.view, view, mode))
        throw usageError("--view: expected " + std::string(viewer::kViewNames) + ", got '" +
                         o.view + "'");
    const std::optional<std::pair<uint32_t, LightMove>> move = parseLightMove(sub, o.move, "view");
    // Scene problems are reported before any window opens.
    const Scene scene = loadSceneFile(o.scene, o.sceneOptions.load());
    if (move && move->first >= scene.lights.size())
        throw usageError("--move-light: no light " + std::to_string(move->first) + " (" + o.scene +
                         " has " + std::to_string(scene.lights.size()) + ")");
    const std::string why = viewer::windowUnavailableReason();
    if (why.empty()) {
        viewer::WindowOptions w;
        w.scene = o.scene;
        w.width = size[0];
        w.height = size[1];
        w.camera = camera;
        w.stateOut = o.stateOut;
        w.quitAfterSeconds = o.quitAfter;
        w.viewer.preview = !o.noPreview;
        w.viewer.exact = o.exact;
        w.viewer.visibilityFile = o.visibility;
        w.viewer.load = o.sceneOptions.load();
        w.viewer.view = view;
        w.viewer.previewSettings.mode = mode;
        w.precompute = o.precompute;
        w.moveLight = move;
        w.viewer.settingsFile = sub.count("--settings") > 0 ? std::filesystem::path(o.settings)
                                                            : viewer::defaultSettingsPath();
        try {
            viewer::runWindow(w);
        } catch (const std::runtime_error& e) {
            throw inputError(std::string("view: ") + e.what());
        }
        return;
    }
    std::cerr << "penumbra view: cannot open a window (" << why
              << "); writing the headless screenshot instead.\n";
    std::error_code ec;
    std::filesystem::create_directories(o.outDir, ec);
    if (ec) throw inputError("cannot create the output folder '" + o.outDir + "'");
    viewer::HeadlessOptions h;
    h.scene = o.scene;
    h.width = size[0];
    h.height = size[1];
    h.camera = camera;
    h.viewer.preview = !o.noPreview;
    h.viewer.exact = o.exact;
    h.viewer.visibilityFile = o.visibility;
    h.viewer.load = o.sceneOptions.load();
    h.viewer.view = view;
    h.viewer.previewSettings.mode = mode;
    h.moveLight = move;
    h.precompute = o.precompute;
    const std::filesystem::path dir(o.outDir);
    h.out = dir / "view.png";
    h.stateOut = o.stateOut.empty() ? dir / "view_state.json" : std::filesystem::path(o.stateOut);
    h.previewOut = dir / "preview.png";
    // Inspect the surface point at the centre of the 3D view, as a first click would.
    const viewer::Layout layout = viewer::computeLayout(h.width, h.height);
    h.pixel = std::array<double, 2>{layout.view.x + 0.5 * layout.view.width,
                                    layout.view.y + 0.5 * layout.view.height};
    try {
        try {
            viewer::runHeadless(h);
        } catch (const viewer::HostInputError& e) {
            // No surface under the centre: a screenshot without a selection is still useful.
            if (e.input != viewer::HostInputError::Input::Pixel) throw;
            h.pixel.reset();
            viewer::runHeadless(h);
        }
    } catch (const viewer::HostInputError& e) {  // (a std::runtime_error: caught first)
        throw inputError(e.what());
    } catch (const std::runtime_error& e) {
        throw inputError(std::string("view (headless): ") + e.what());
    }
    std::cout << "penumbra view: wrote " << h.out.string() << " and " << h.stateOut.string();
    if (std::filesystem::exists(h.previewOut)) std::cout << " and " << h.previewOut.string();
    std::cout << '\n';
}

}  // namespace

void registerViewCommand(CLI::App& app) {
    auto o = std::make_shared<ViewOptions>();
    CLI::App* sub = app.add_subcommand(
        "view",
        "The interactive viewer and visibility debugger (a window; with no display, writes the "
        "headless screenshot to --out-dir instead).");
    sub->add_option("scene", o->scene, "Scene file (default assets/cornell_box.obj)")
        ->type_name("SCENE");
    sub->add_option("--camera", o->camera, "Camera: eye, target, vertical field of view")
        ->type_name("EX,EY,EZ,TX,TY,TZ[,FOV]");
    sub->add_option("--size", o->size, "Window size (default 1280x800)")->type_name("WxH");
    sub->add_option("--state-out", o->stateOut, "Keep the UI state in this JSON file")
        ->type_name("FILE.json");
    sub->add_option("--out-dir", o->outDir, "Where the no-display fallback writes (default out/)")
        ->type_name("DIR");
    sub->add_option("--view", o->view,
                    "What the 3D view shows: the render at the view's size, rendered (exact, the "
                    "default), sampled, side (exact | sampled), diff, answers (how the exact "
                    "render answered each pixel); or raster (flat colours) (V toggles)")
        ->type_name("MODE");
    sub->add_option("--settings", o->settings,
                    "The viewer's settings file: the panels' layout, the columns, whether Help was "
                    "seen (default $XDG_CONFIG_HOME/penumbra/viewer.json, else "
                    "~/.config/penumbra/viewer.json)")
        ->type_name("FILE.json");
    sub->add_option("--quit-after", o->quitAfter, "Close the window after this many seconds")
        ->type_name("SECONDS");
    sub->add_flag("--no-preview", o->noPreview, "Do not run the progressive preview");
    addExactOptions(*sub, o->exact, ExactOptionSet::Render);
    sub->add_option("--visibility", o->visibility,
                    "Visibility file (.pvis, as precompute writes it): its trees are used when it "
                    "is current for the scene (else reported and rebuilt); the precompute and "
                    "the Precompute panel's Save write it back")
        ->type_name("FILE.pvis");
    sub->add_flag("--precompute", o->precompute,
                  "Start precomputing every pair in the background when the scene opens (with "
                  "--move-light, before the light moves)");
    addLightMoveOptions(*sub, o->move);
    addSceneOptions(*sub, o->sceneOptions);
    sub->callback([sub, o] { runView(*sub, *o); });
}

}  // namespace penumbra::cli
