// `penumbra render SCENE [--camera EX,EY,EZ,TX,TY,TZ[,FOV]] [--size WxH] [--spp N]
//                 [--method exact|sampled|reference] [--light-samples N] [--seed S] --out FILE`
//                 (and --up X,Y,Z, --reference-samples, --glossy-samples, --light-seed,
//                  --exposure, --threads, --out-pfm, --visibility; see --help)
//
// Renders the scene with the progressive CPU renderer (engine/render/renderer.h) and writes the
// image: FILE ending in .png (tone mapped, sRGB) or .pfm (linear float); --out may be given twice
// (one of each) and --out-pfm names a PFM file explicitly. The camera defaults to the scene's, else
// one fitted to the scene's bounds. Prints the time breakdown and what was simulated and why.
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
#include <vector>

#include "app/cli/commands.h"
#include "engine/io/visibility_file.h"
#include "engine/precompute/visibility_store.h"
#include "engine/render/embree_scene.h"
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
    uint64_t exactWorkLimit = RenderSettings{}.exactWorkLimit;
    uint64_t maxLpSolves = vis::BuildOptions{}.maxLpSolves;
    uint64_t minTreeSamples = RenderSettings{}.minTreeSamples;
    uint64_t seed = 1;
    uint64_t lightSeed = 1;
    double exposure = 1.0;
    int threads = 0;
    std::vector<std::string> out;
    std::string outPfm;
    std::string visibility;
};

std::vector<double> parseNumbers(const std::string& flag, const std::string& text) {
    std::vector<double> v;
    std::string_view rest = text;
    while (true) {
        const size_t comma = rest.find(',');
        const std::string_view item = rest.substr(0, comma);
        const std::optional<double> x = parseNumber(item);
        if (!x)
            throw usageError(flag + ": '" + std::string(item) + "' is not a finite number (in '" +
                             text + "')");
        v.push_back(*x);
        if (comma == std::string_view::npos) break;
        rest.remove_prefix(comma + 1);
    }
    return v;
}

Camera parseCamera(const std::string& text) {
    const std::vector<double> v = parseNumbers("--camera", text);
    if (v.size() != 6 && v.size() != 7)
        throw usageError("--camera: expected EX,EY,EZ,TX,TY,TZ[,FOV] (6 or 7 numbers), got " +
                         std::to_string(v.size()) + " in '" + text + "'");
    Camera c;
    c.eye = {v[0], v[1], v[2]};
    c.target = {v[3], v[4], v[5]};
    if (v.size() == 7) c.fovYDegrees = v[6];
    if (c.eye == c.target) throw usageError("--camera: the eye and the target are the same point");
    if (!(c.fovYDegrees > 0 && c.fovYDegrees < 180))
        throw usageError("--camera: the field of view must be in (0, 180) degrees");
    for (const Vec3* p : {&c.eye, &c.target})
        if (const auto problem = coordinateProblem(*p)) throw usageError("--camera: " + *problem);
    return c;
}

void parseSize(const std::string& text, int& w, int& h) {
    const size_t x = text.find_first_of("xX");
    auto parseInt = [&](std::string_view s, int& out) {
        const auto r = std::from_chars(s.data(), s.data() + s.size(), out);
        return !s.empty() && r.ec == std::errc{} && r.ptr == s.data() + s.size() && out >= 1 &&
               out <= 16384;
    };
    const std::string_view s = text;
    if (x == std::string::npos || !parseInt(s.substr(0, x), w) || !parseInt(s.substr(x + 1), h))
        throw usageError("--size: expected WxH with 1 <= W, H <= 16384, got '" + text + "'");
}

bool endsWith(std::string s, std::string_view suffix) {
    for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    return s.size() >= suffix.size() &&
           s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

void runRender(const RenderOptions& o) {
    RenderSettings settings;
    parseSize(o.size, settings.width, settings.height);
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
    settings.exactWorkLimit = o.exactWorkLimit;
    settings.minTreeSamples = o.minTreeSamples;
    settings.seed = o.seed;
    settings.lightSeed = o.lightSeed;

    std::vector<std::string> png, pfm;
    for (const std::string& f : o.out) {
        if (endsWith(f, ".png"))
            png.push_back(f);
        else if (endsWith(f, ".pfm"))
            pfm.push_back(f);
        else
            throw usageError("--out '" + f + "': the file must end in .png or .pfm");
    }
    if (!o.outPfm.empty()) pfm.push_back(o.outPfm);
    if (png.empty() && pfm.empty()) throw usageError("nothing to write: give --out FILE");

    std::optional<Camera> camera;
    if (!o.camera.empty()) camera = parseCamera(o.camera);
    const Scene scene = loadSceneFile(o.scene);
    if (!o.up.empty()) {
        const std::vector<double> u = parseNumbers("--up", o.up);
        if (u.size() != 3 || (u[0] == 0 && u[1] == 0 && u[2] == 0))
            throw usageError("--up: expected a nonzero vector X,Y,Z, got '" + o.up + "'");
        const Vec3 up{u[0], u[1], u[2]};
        if (camera)
            camera->up = up;
        else if (!scene.camera)
            camera = Camera::fitting(scene.mesh.bounds(), {0.3, 0.4, 1.0}, 45, up);
    }
    if (!camera) camera = scene.camera ? *scene.camera : Camera::fitting(scene.mesh.bounds());

    std::optional<tbb::global_control> threads;
    if (o.threads > 0) threads.emplace(tbb::global_control::max_allowed_parallelism, o.threads);

    const EmbreeScene bvh(scene.mesh);
    VisibilityStore::Options storeOptions;
    storeOptions.build.maxLpSolves = o.maxLpSolves;
    VisibilityStore store(scene, &bvh, storeOptions);
    size_t loadedTrees = 0;
    const bool exact = settings.method == DirectMethod::Exact;
    // A file that is there but could not be used (corrupt, stale) is rewritten after the render
    // even when the render added no tree: leaving it would report it again on every run.
    bool repair = false;
    if (!o.visibility.empty() && exact) {
        try {
            loadedTrees = readVisibilityFile(o.visibility, store);
        } catch (const VisibilityFileError& e) {
            if (e.status != VisibilityFileStatus::Missing) {
                std::cerr << "penumbra: " << e.what() << " (" << toString(e.status)
                          << "); recomputing\n";
                repair = e.status != VisibilityFileStatus::Unreadable;
            }
        }
    }
    ProgressiveRenderer renderer(scene, bvh, store);
    RenderTimes times;
    const Film film = renderer.render(*camera, settings, &times);

    std::printf("%s: %u faces, %zu area lights, %zu point lights; %dx%d, %d spp, %s",
                o.scene.c_str(), scene.faceCount(), scene.lights.size(), scene.pointLights.size(),
                settings.width, settings.height, settings.spp, toString(settings.method));
    if (settings.method == DirectMethod::Sampled)
        std::printf(" (%d shadow rays per light)", settings.lightSamples);
    if (settings.method == DirectMethod::Reference)
        std::printf(" (%d shadow rays per light)", settings.referenceSamples);
    std::printf(
        "\ntime: precompute %.3f s (%zu trees), primary rays %.3f s, shading %.3f s, "
        "total %.3f s\n",
        times.precompute, store.treeCount(), times.primary, times.shading, times.total);
    std::printf("cpu time (all threads): precompute %.3f s, rendering %.3f s, total %.3f s\n",
                times.precomputeCpu, times.totalCpu - times.precomputeCpu, times.totalCpu);
    if (!o.visibility.empty()) {
        if (!exact) {
            std::printf("visibility: %s not used (the %s method needs no history trees)\n",
                        o.visibility.c_str(), toString(settings.method));
        } else if (store.treeCount() == loadedTrees && !repair) {
            std::printf("visibility: %zu trees read from %s, none added\n", loadedTrees,
                        o.visibility.c_str());
        } else {
            try {
                const size_t bytes = writeVisibilityFile(o.visibility, store);
                std::printf("visibility: %zu trees read, %zu added, wrote %s (%zu bytes)\n",
                            loadedTrees, store.treeCount() - loadedTrees, o.visibility.c_str(),
                            bytes);
            } catch (const VisibilityFileError& e) {
                throw inputError(e.what());
            }
        }
    }
    std::printf("effects:\n");
    const std::string text = renderer.effects().text();
    size_t start = 0;
    while (start < text.size()) {
        const size_t end = text.find('\n', start);
        std::printf("  %s\n", text.substr(start, end - start).c_str());
        if (end == std::string::npos) break;
        start = end + 1;
    }
    try {
        for (const std::string& f : png) {
            writePng(film, f, o.exposure);
            std::printf("wrote %s\n", f.c_str());
        }
        for (const std::string& f : pfm) {
            writePfm(film, f);
            std::printf("wrote %s\n", f.c_str());
        }
    } catch (const std::runtime_error& e) {
        throw inputError(e.what());
    }
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
    sub->add_option("--max-lp-solves", o->maxLpSolves,
                    "Exact: build budget of one history tree in linear programs; a tree that "
                    "reaches it is partial, its remaining occluders clipped per point (0 = no "
                    "limit)")
        ->capture_default_str();
    sub->add_option("--min-tree-samples", o->minTreeSamples,
                    "Exact: a pair the image samples fewer times gets no history tree, its points "
                    "are evaluated directly (0 = a tree for every pair)")
        ->capture_default_str();
    sub->add_option("--exact-work-limit", o->exactWorkLimit,
                    "Exact: plane tests one point's query may make; a point that needs more is "
                    "sampled with --light-samples rays and counted (0 = every point exact)")
        ->capture_default_str();
    sub->add_option("--seed", o->seed, "Seed of the pixel sampling pattern")->capture_default_str();
    sub->add_option("--light-seed", o->lightSeed, "Seed of the light sampling")
        ->capture_default_str();
    sub->add_option("--exposure", o->exposure, "PNG: radiance scale before tone mapping")
        ->check(CLI::PositiveNumber)
        ->capture_default_str();
    sub->add_option("--threads", o->threads, "Worker threads (0: all cores)")
        ->check(CLI::Range(0, 4096))
        ->capture_default_str();
    sub->add_option("--out", o->out, "Output image, .png or .pfm (may be given twice)")->take_all();
    sub->add_option("--out-pfm", o->outPfm, "Also write the linear radiance as PFM to this file");
    sub->add_option("--visibility", o->visibility,
                    "Visibility file (.pvis): read the history trees from it when current, write "
                    "it back with the trees this render added (exact method)");
    sub->callback([o] { runRender(*o); });
}

}  // namespace penumbra::cli
