// `penumbra screenshot SCENE [--point X,Y,Z | --pixel X,Y] [--camera ...] [--size WxH]
//  --out FILE.png [--state-out FILE.json] [--preview-out FILE.png|.pfm|.exr] [--backend osmesa|egl]
//  [--precompute] [--accuracy] [--move-light N [--translate X,Y,Z] [--rotate AX,AY,AZ]
//  [--scale S|SX,SY,SZ]] ...`
//
// Renders the complete viewer UI offscreen (app/viewer/host/headless_host.h): the same Viewer code
// as the window, with the inspected point's fragments, path and tree panels open.
#include <CLI/CLI.hpp>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "app/cli/arguments.h"
#include "app/cli/commands.h"
#include "app/viewer/host/headless_host.h"
#include "app/viewer/panel_arrangement.h"
#include "engine/io/image_io.h"

namespace penumbra::cli {
namespace {

struct ScreenshotOptions {
    std::string scene, point, pixel, hover, camera, size = "1280x800", out, stateOut, previewOut,
                                                    saveView, settings, enlarge, visibility;
    LightMoveOptions move;
    std::vector<std::string> panels, collapse;
    bool resetLayout = false;
    std::string backend = "osmesa", previewMode = "exact", view = "rendered";
    int lightSamples = 16, passes = 8;
    double uiScale = 1;
    bool noPreview = false, precompute = false, accuracy = false;
    SceneOptions sceneOptions;
    ExactOptions exact;
};

// A panel's name as the Panels menu and the state JSON say it (panel_arrangement.h).
std::string panelName(const char* flag, const std::string& name) {
    std::string names;
    for (const viewer::PanelName& p : viewer::arrangeablePanels()) {
        if (name == p.name) return name;
        names += std::string(names.empty() ? "" : ", ") + "'" + p.name + "'";
    }
    throw usageError(std::string(flag) + ": no panel named '" + name + "' (the panels: " + names +
                     ")");
}

viewer::PreviewMode parsePreviewMode(const std::string& s) {
    if (s == "exact") return viewer::PreviewMode::Exact;
    if (s == "sampled") return viewer::PreviewMode::Sampled;
    if (s == "side") return viewer::PreviewMode::SideBySide;
    if (s == "diff") return viewer::PreviewMode::Difference;
    if (s == "answers") return viewer::PreviewMode::Answers;
    throw usageError("--preview-mode: expected exact, sampled, side, diff or answers, got '" + s +
                     "'");
}

void runScreenshot(const CLI::App& sub, const ScreenshotOptions& o) {
    viewer::HeadlessOptions h;
    h.scene = o.scene;
    if (sub.count("--point") > 0 && sub.count("--pixel") > 0)
        throw usageError("screenshot: give at most one of --point and --pixel");
    if (sub.count("--point") > 0) {
        const auto v = parseNumberList("--point", o.point, 3);
        h.point = Vec3{v[0], v[1], v[2]};
    }
    if (sub.count("--pixel") > 0) {
        const auto v = parseNumberList("--pixel", o.pixel, 2);
        h.pixel = std::array<double, 2>{v[0], v[1]};
    }
    if (sub.count("--camera") > 0) h.camera = parseCamera("--camera", o.camera);
    h.moveLight = parseLightMove(sub, o.move, "screenshot");
    if (sub.count("--hover") > 0) {
        const auto v = parseNumberList("--hover", o.hover, 2);
        h.hover = std::array<double, 2>{v[0], v[1]};
    }
    const auto size = parseSize("--size", o.size, kWindowSize);
    h.width = size[0];
    h.height = size[1];
    if (h.hover && ((*h.hover)[0] < 0 || (*h.hover)[1] < 0 || (*h.hover)[0] >= h.width ||
                    (*h.hover)[1] >= h.height))
        throw usageError("--hover: outside the " + o.size + " image");
    if (h.pixel && ((*h.pixel)[0] < 0 || (*h.pixel)[1] < 0 || (*h.pixel)[0] >= h.width ||
                    (*h.pixel)[1] >= h.height))
        throw usageError("--pixel: outside the " + o.size + " image");
    if (o.backend == "osmesa")
        h.backend = gl::OffscreenBackend::OsMesa;
    else if (o.backend == "egl")
        h.backend = gl::OffscreenBackend::Egl;
    else
        throw usageError("--backend: expected osmesa or egl, got '" + o.backend + "'");
    if (o.lightSamples < 1 || o.lightSamples > 65536)
        throw usageError("--light-samples: " + std::to_string(o.lightSamples) +
                         " out of range (1..65536)");
    if (o.passes < 1 || o.passes > 4096)
        throw usageError("--passes: " + std::to_string(o.passes) + " out of range (1..4096)");
    h.viewer.previewSettings.mode = parsePreviewMode(o.previewMode);
    if (sub.count("--view") > 0) {
        if (sub.count("--preview-mode") > 0 && o.view != "raster")
            throw usageError("screenshot: --view " + o.view +
                             " names the preview's mode already; drop --preview-mode");
        if (!viewer::parseViewName(o.view, h.viewer.view, h.viewer.previewSettings.mode))
            throw usageError("--view: expected " + std::string(viewer::kViewNames) + ", got '" +
                             o.view + "'");
    }
    if (!(o.uiScale >= 0.5 && o.uiScale <= 4))
        throw usageError("--ui-scale: " + std::to_string(o.uiScale) + " out of range (0.5..4)");
    h.viewer.layout.scale = static_cast<float>(o.uiScale);
    h.viewer.previewSettings.lightSamples = o.lightSamples;
    h.viewer.previewSettings.passes = o.passes;
    h.viewer.preview = !o.noPreview;
    h.viewer.exact = o.exact;
    h.viewer.visibilityFile = o.visibility;
    h.viewer.load = o.sceneOptions.load();
    h.printWarnings = true;
    h.viewer.showHelp = true;
    h.out = o.out;
    h.stateOut = o.stateOut;
    if (!o.previewOut.empty() && !imageFormatOf(o.previewOut))
        throw usageError("--preview-out '" + o.previewOut + "': the file must end in " +
                         kImageExtensions);
    h.previewOut = o.previewOut;
    h.saveView = o.saveView;
    h.precompute = o.precompute;
    h.accuracy = o.accuracy;
    if (sub.count("--settings") > 0) h.viewer.settingsFile = o.settings;
    h.resetLayout = o.resetLayout;
    for (const std::string& p : o.panels) {
        const size_t eq = p.rfind('=');
        if (eq == std::string::npos)
            throw usageError("--panel: expected NAME=X,Y,WIDTH,HEIGHT, got '" + p + "'");
        const std::string name = panelName("--panel", p.substr(0, eq));
        const auto v = parseNumberList("--panel", p.substr(eq + 1), 4);
        if (!(v[2] > 0 && v[3] > 0))
            throw usageError("--panel: " + name + "'s width and height must be > 0");
        h.arrange.emplace_back(
            name, viewer::PanelRect{static_cast<float>(v[0]), static_cast<float>(v[1]),
                                    static_cast<float>(v[2]), static_cast<float>(v[3])});
    }
    for (const std::string& c : o.collapse) h.collapse.push_back(panelName("--collapse", c));
    if (sub.count("--enlarge") > 0) h.enlarge = panelName("--enlarge", o.enlarge);
    try {
        viewer::runHeadless(h);
    } catch (const viewer::HostInputError& e) {  // (a std::runtime_error: caught first)
        using Input = viewer::HostInputError::Input;
        const char* option = e.input == Input::Point       ? "--point: "
                             : e.input == Input::Pixel     ? "--pixel: "
                             : e.input == Input::MoveLight ? "--move-light: "
                                                           : "";
        throw inputError(option + std::string(e.what()));
    } catch (const std::runtime_error& e) {
        throw inputError(std::string("screenshot: ") + e.what());
    }
}

}  // namespace

void registerScreenshotCommand(CLI::App& app) {
    auto o = std::make_shared<ScreenshotOptions>();
    CLI::App* sub = app.add_subcommand(
        "screenshot",
        "Render the viewer's complete UI offscreen (OSMesa, or EGL surfaceless) into a PNG, with "
        "the inspected point's fragments, path and history-tree panels open.");
    sub->add_option("scene", o->scene, "Scene file (.obj with its .mtl)")
        ->required()
        ->type_name("SCENE");
    sub->add_option("--point", o->point, "Inspect this point (on a face of the scene)")
        ->type_name("X,Y,Z");
    sub->add_option("--pixel", o->pixel, "Inspect the surface point under this pixel")
        ->type_name("X,Y");
    sub->add_option("--hover", o->hover,
                    "The mouse over this pixel (the rendered view's pixel inspector)")
        ->type_name("X,Y");
    sub->add_option("--camera", o->camera, "Camera: eye, target, vertical field of view")
        ->type_name("EX,EY,EZ,TX,TY,TZ[,FOV]");
    sub->add_option("--size", o->size, "Image size (default 1280x800)")->type_name("WxH");
    addLightMoveOptions(*sub, o->move);
    sub->add_option("--out", o->out, "The screenshot (PNG)")->required()->type_name("FILE.png");
    sub->add_option("--state-out", o->stateOut, "The UI state as JSON")->type_name("FILE.json");
    sub->add_option("--preview-out", o->previewOut,
                    "The preview image alone: .png as shown, .pfm or .exr its linear radiance "
                    "(the exact image's, else the sampled one's)")
        ->type_name("FILE");
    sub->add_option("--ui-scale", o->uiScale,
                    "The UI's content scale, as a HiDPI monitor's (the window takes GLFW's)")
        ->type_name("S");
    sub->add_option(
           "--save-view", o->saveView,
           "Save the view as the UI's button does: STEM.png, STEM.pfm, STEM.exr and STEM.json "
           "(the scene with this camera)")
        ->type_name("STEM");
    sub->add_option("--backend", o->backend, "osmesa (default) or egl")->type_name("NAME");
    sub->add_option("--preview-mode", o->previewMode,
                    "exact (default), sampled, side, diff or answers")
        ->type_name("MODE");
    sub->add_option("--view", o->view,
                    "What the 3D view shows: the render at the view's size, rendered (exact, the "
                    "default; in the --preview-mode), sampled, side (exact | sampled), diff, "
                    "answers (how the exact render answered each pixel); or raster (flat colours)")
        ->type_name("MODE");
    sub->add_option("--light-samples", o->lightSamples, "Shadow rays per light (sampled)")
        ->type_name("N");
    sub->add_option("--passes", o->passes, "Preview passes (default 8)")->type_name("N");
    sub->add_flag("--no-preview", o->noPreview, "Do not run the progressive preview");
    sub->add_option("--settings", o->settings,
                    "Read the viewer's settings (the panels' layout, the columns, whether Help was "
                    "seen) from this file if it exists, and write them back at the end, as the "
                    "window does when it closes (default: none read or written)")
        ->type_name("FILE.json");
    sub->add_flag("--reset-layout", o->resetLayout,
                  "Reset the layout (as Ctrl+L does), before --panel, --collapse, --enlarge");
    sub->add_option("--panel", o->panels,
                    "Move and size a panel as a mouse drag would (repeatable); names: Scene, "
                    "Precompute, 'History tree', Preview, Point, 'Light plane', Path, Help")
        ->type_name("NAME=X,Y,W,H");
    sub->add_option("--collapse", o->collapse, "Collapse a panel (repeatable)")->type_name("NAME");
    sub->add_option("--enlarge", o->enlarge, "Enlarge a panel to most of the window (as E does)")
        ->type_name("NAME");
    addExactOptions(*sub, o->exact, ExactOptionSet::Render);
    sub->add_option("--visibility", o->visibility,
                    "Visibility file (.pvis): its trees are used when it is current for the scene "
                    "(else reported and rebuilt); --precompute writes it back")
        ->type_name("FILE.pvis");
    sub->add_flag("--precompute", o->precompute,
                  "Precompute every pair in the background while drawing frames (with "
                  "--move-light, before the light moves); the state JSON records the frame "
                  "times");
    sub->add_flag("--accuracy", o->accuracy,
                  "Run the view's accuracy-vs-time study (64x64, 2 spp: exact against 1..1024 "
                  "shadow rays) in the background while drawing frames, and show its panel");
    addSceneOptions(*sub, o->sceneOptions);
    sub->callback([sub, o] { runScreenshot(*sub, *o); });
}

}  // namespace penumbra::cli
