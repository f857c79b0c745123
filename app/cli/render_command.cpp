// `penumbra render SCENE [--camera EX,EY,EZ,TX,TY,TZ[,FOV]] [--size WxH] [--spp N]
//                 [--method exact|sampled|reference] [--light-samples N] [--seed S] --out FILE`
//                 (and --up X,Y,Z, --reference-samples, --glossy-samples, --light-seed,
//                  --exposure, --threads, --out-pfm, --out-answers, --visibility; see --help)
//
// Renders the scene with the progressive CPU renderer (engine/render/renderer.h) and writes the
// image: FILE ending in .png (tone mapped, sRGB), .pfm or .exr (linear float); --out may be given
// several times (one file per format, say) and --out-pfm names a PFM file explicitly. The camera
// defaults to the scene's, else the viewer's (engine/render/default_camera.h). Prints the time
// breakdown and what was simulated and why. --out-answers FILE.png (exact): how each pixel was
// answered (engine/render/answers.h), with the shares of each answer printed as its legend.
// --visibility FILE.pvis: the history trees are read from FILE when it is current for this scene
// (as `penumbra precompute` writes it; a stale or corrupt file is reported and recomputed), and
// FILE is written back atomically with every tree the render added, so the next render of the
// scene, from any camera, reuses them.
#include <tbb/global_control.h>

#include <CLI/CLI.hpp>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "app/cli/arguments.h"
#include "app/cli/commands.h"
#include "engine/io/image_io.h"
#include "engine/io/text_input.h"
#include "engine/io/visibility_file.h"
#include "engine/precompute/visibility_store.h"
#include "engine/raytrace/embree_scene.h"
#include "engine/render/default_camera.h"
#include "engine/render/renderer.h"
#include "engine/scene/scene_validation.h"

namespace penumbra::cli {
namespace {

struct RenderOptions {
    std::string scene;
    std::string camera;
    std::string up;
    std::string size = "512x512";
    int spp = 16;
    std::string method = "exact";
    int lightSamples = 128;
    int referenceSamples = 1024;
    int glossySamples = 16;
    ExactOptions exact;
    uint64_t seed = 1;
    uint64_t lightSeed = 1;
    double exposure = 1.0;
    int threads = 0;
    std::vector<std::string> out;
    std::string outPfm;
    std::string outAnswers;
    std::string visibility;
    SceneOptions sceneOptions;
};

RenderSettings renderSettings(const RenderOptions& o) {
    RenderSettings settings;
    const auto [width, height] = parseSize("--size", o.size, kImageSize);
    settings.width = width;
    settings.height = height;
    settings.spp = o.spp;
    if (o.method == "exact")
        settings.method = DirectMethod::Exact;
    else if (o.method == "sampled")
        settings.method = DirectMethod::Sampled;
    else if (o.method == "reference")
        settings.method = DirectMethod::Reference;
    else
        throw usageError("--method: expected exact, sampled or reference, got '" + o.method + "'");
    settings.lightSamples = o.lightSamples;
    settings.referenceSamples = o.referenceSamples;
    settings.glossySamples = o.glossySamples;
    o.exact.applyTo(settings);
    settings.seed = o.seed;
    settings.recordAnswers = !o.outAnswers.empty();
    settings.lightSeed = o.lightSeed;
    return settings;
}

// The images to write, each with its format (--out FILE.png|.pfm|.exr, --out-pfm FILE).
struct Outputs {
    std::vector<std::pair<std::string, ImageFormat>> images;
};

Outputs outputs(const RenderOptions& o) {
    Outputs out;
    for (const std::string& f : o.out) {
        const std::optional<ImageFormat> format = imageFormatOf(f);
        if (!format)
            throw usageError("--out '" + f + "': the file must end in " + kImageExtensions);
        out.images.emplace_back(f, *format);
    }
    if (!o.outPfm.empty()) out.images.emplace_back(o.outPfm, ImageFormat::Pfm);
    if (out.images.empty()) throw usageError("nothing to write: give --out FILE");
    if (!o.outAnswers.empty()) {
        if (lowerExtension(o.outAnswers) != ".png")
            throw usageError("--out-answers '" + o.outAnswers + "': the file must end in .png");
        if (o.method != "exact")
            throw usageError("--out-answers: only the exact method has answers (got --method " +
                             o.method + ")");
    }
    return out;
}

// --visibility FILE: the trees read into the store before the render (when the file is current).
struct VisibilityInput {
    size_t loadedTrees = 0;
    // A file that is there but could not be used (corrupt, stale) is rewritten after the render
    // even when the render added no tree: leaving it would report it again on every run.
    bool repair = false;
};

VisibilityInput readVisibility(const std::string& file, VisibilityStore& store) {
    VisibilityInput in;
    try {
        in.loadedTrees = readVisibilityFile(file, store);
    } catch (const VisibilityFileError& e) {
        if (e.status != VisibilityFileStatus::Missing) {
            std::cerr << "penumbra: " << e.what() << " (" << toString(e.status)
                      << "); recomputing\n";
            in.repair = e.status != VisibilityFileStatus::Unreadable;
        }
    }
    return in;
}

// Writes FILE back when the render added trees or the file needs repair, and says so.
void writeVisibility(const std::string& file, const VisibilityStore& store,
                     const VisibilityInput& in) {
    if (store.treeCount() == in.loadedTrees && !in.repair) {
        std::printf("visibility: %zu trees read from %s, none added\n", in.loadedTrees,
                    file.c_str());
        return;
    }
    try {
        const size_t bytes = writeVisibilityFile(file, store);
        std::printf("visibility: %zu trees read, %zu added, wrote %s (%zu bytes)\n", in.loadedTrees,
                    store.treeCount() - in.loadedTrees, file.c_str(), bytes);
    } catch (const VisibilityFileError& e) {
        throw inputError(e.what());
    }
}

void printTimes(const RenderOptions& o, const Scene& scene, const RenderSettings& settings,
                const RenderTimes& times, const VisibilityStore& store) {
    std::printf("%s: %u faces, %zu area lights, %zu point lights; %dx%d, %d spp, %s",
                o.scene.c_str(), scene.faceCount(), scene.lights.size(), scene.pointLights.size(),
                settings.width, settings.height, settings.spp, toString(settings.method));
    if (settings.method == DirectMethod::Sampled)
        std::printf(" (%d shadow rays per light)", settings.lightSamples);
    if (settings.method == DirectMethod::Reference)
        std::printf(" (%d shadow rays per light)", settings.referenceSamples);
    std::printf("\ntime: precompute %.3f s (%zu trees", times.precompute, store.treeCount());
    if (store.layout().refinedCount() > 0)
        std::printf("; %.3f s of it refining between passes", times.refine);
    std::printf("), primary rays %.3f s, shading %.3f s, total %.3f s\n", times.primary,
                times.shading, times.total);
    std::printf("cpu time (all threads): precompute %.3f s, rendering %.3f s, total %.3f s\n",
                times.precomputeCpu, times.totalCpu - times.precomputeCpu, times.totalCpu);
}

void printEffects(const std::string& text) {
    std::printf("effects:\n");
    size_t start = 0;
    while (start < text.size()) {
        const size_t end = text.find('\n', start);
        std::printf("  %s\n", text.substr(start, end - start).c_str());
        if (end == std::string::npos) break;
        start = end + 1;
    }
}

void writeImages(const Film& film, const Outputs& out, double exposure,
                 const std::string& answers) {
    try {
        if (!answers.empty()) {
            writeAnswersPng(film, answers);
            std::printf("wrote %s: how each pixel was answered, %s\n", answers.c_str(),
                        describeAnswers(film.answers).c_str());
        }
        for (const auto& [f, format] : out.images) {
            writeImage(film, f, format, exposure);
            std::printf("wrote %s\n", f.c_str());
        }
    } catch (const std::runtime_error& e) {
        throw inputError(e.what());
    }
}

void runRender(const RenderOptions& o) {
    const RenderSettings settings = renderSettings(o);
    const Outputs out = outputs(o);
    std::optional<Camera> camera;
    if (!o.camera.empty()) camera = parseCamera("--camera", o.camera);
    std::optional<Vec3> up;
    if (!o.up.empty()) up = parseDirection("--up", o.up);
    const Scene scene = loadSceneFile(o.scene, o.sceneOptions.load());

    std::optional<tbb::global_control> threads;
    if (o.threads > 0) threads.emplace(tbb::global_control::max_allowed_parallelism, o.threads);

    const EmbreeScene bvh(scene.mesh);
    if (!camera)
        camera = defaultCamera(scene, bvh, up);
    else if (up)
        camera->up = *up;
    VisibilityStore::Options storeOptions;
    o.exact.applyTo(storeOptions);
    VisibilityStore store(scene, &bvh, storeOptions);
    const bool exact = settings.method == DirectMethod::Exact;
    VisibilityInput visibility;
    if (!o.visibility.empty() && exact) visibility = readVisibility(o.visibility, store);
    ProgressiveRenderer renderer(scene, bvh, store);
    RenderTimes times;
    const Film film = renderer.render(*camera, settings, &times);

    printTimes(o, scene, settings, times, store);
    if (!o.visibility.empty()) {
        if (!exact)
            std::printf("visibility: %s not used (the %s method needs no history trees)\n",
                        o.visibility.c_str(), toString(settings.method));
        else
            writeVisibility(o.visibility, store, visibility);
    }
    const EffectsSummary effects = renderer.effects();
    for (const std::string& w : effects.hiddenLights)
        std::cerr << "penumbra: warning: " << w << '\n';
    printEffects(effects.text());
    writeImages(film, out, o.exposure, o.outAnswers);
    std::fflush(stdout);
}

}  // namespace

void registerRenderCommand(CLI::App& app) {
    auto o = std::make_shared<RenderOptions>();
    CLI::App* sub = app.add_subcommand(
        "render", "Render an image with exact soft shadows (or shadow-ray sampling to compare)");
    sub->add_option("scene", o->scene,
                    "Scene file (.obj, .ply, .off, .stl, .gltf, .glb or a .json scene)")
        ->required();
    sub->add_option("--camera", o->camera,
                    "Eye and target, and optionally the vertical field of view in degrees: "
                    "EX,EY,EZ,TX,TY,TZ[,FOV] (default: the scene's camera, else one fitted to it)");
    sub->add_option("--up", o->up, "The camera's up direction X,Y,Z (default 0,1,0)");
    sub->add_option("--size", o->size, "Image size WxH")->capture_default_str();
    sub->add_option("--spp", o->spp, "Primary samples per pixel (passes)")
        ->check(CLI::Range(1, 1 << 20))
        ->capture_default_str();
    sub->add_option("--method", o->method, "exact | sampled | reference")->capture_default_str();
    sub->add_option("--light-samples", o->lightSamples,
                    "Shadow rays per area light per shading point (sampled)")
        ->check(CLI::Range(1, 1 << 20))
        ->capture_default_str();
    sub->add_option("--reference-samples", o->referenceSamples,
                    "Shadow rays per area light per shading point (reference)")
        ->check(CLI::Range(1, 1 << 24))
        ->capture_default_str();
    sub->add_option("--glossy-samples", o->glossySamples,
                    "Samples per light inside the visible fragments for glossy materials (exact)")
        ->check(CLI::Range(1, 1 << 20))
        ->capture_default_str();
    addExactOptions(*sub, o->exact, ExactOptionSet::Render);
    sub->add_option("--seed", o->seed, "Seed of the pixel sampling pattern")->capture_default_str();
    sub->add_option("--light-seed", o->lightSeed, "Seed of the light sampling")
        ->capture_default_str();
    sub->add_option("--exposure", o->exposure, "PNG: radiance scale before tone mapping")
        ->check(CLI::PositiveNumber)
        ->capture_default_str();
    sub->add_option("--threads", o->threads, "Worker threads (0: all cores)")
        ->check(CLI::Range(0, 4096))
        ->capture_default_str();
    sub->add_option(
           "--out", o->out,
           "Output image: .png (tone mapped), .pfm or .exr (linear radiance, 32-bit float); "
           "may be given several times")
        ->take_all();
    sub->add_option("--out-pfm", o->outPfm, "Also write the linear radiance as PFM to this file");
    sub->add_option("--out-answers", o->outAnswers,
                    "Exact: also write how each pixel was answered, as a PNG: fully visible "
                    "(yellow), no light (dark grey), tree walk (green), direct (blue), boundary "
                    "chain (purple), sampled over the work limit (red); a pixel is the mean of its "
                    "evaluations' colours");
    sub->add_option("--visibility", o->visibility,
                    "Visibility file (.pvis): read the history trees from it when current, write "
                    "it back with the trees this render added (exact method)");
    addSceneOptions(*sub, o->sceneOptions);
    sub->callback([o] { runRender(*o); });
}

}  // namespace penumbra::cli
