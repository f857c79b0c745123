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
//
// Started by an MPI launcher with several ranks (a build with MPI), the trees and the tiles are
// spread over the ranks (engine/cluster/cluster_render.h): rank 0 does all of the above and
// writes the same image, bit for bit; the other ranks serve quietly (docs/cluster.md).
#include <tbb/global_control.h>
#include <tbb/info.h>

#include <CLI/CLI.hpp>
#include <charconv>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstdlib>
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
#include "app/cli/interrupt_guard.h"
#include "app/cli/mpi_launch.h"
#include "engine/io/image_io.h"
#include "engine/io/scene_loader.h"
#include "engine/io/text_input.h"
#include "engine/io/visibility_file.h"
#include "engine/precompute/visibility_store.h"
#include "engine/raytrace/embree_scene.h"
#include "engine/render/default_camera.h"
#include "engine/render/renderer.h"
#include "engine/scene/scene_validation.h"

#ifdef PENUMBRA_HAVE_MPI
#include "engine/cluster/cluster_precompute.h"
#include "engine/cluster/cluster_render.h"
#endif

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

// What a finished render writes, in one process or on rank 0 of a cluster: the visibility file
// back (exact method), the hidden-light warnings, the effects summary and the images.
void writeResults(const RenderOptions& o, const RenderSettings& settings,
                  const VisibilityStore& store, const VisibilityInput& visibility,
                  const ProgressiveRenderer& renderer, const Film& film, const Outputs& out,
                  const std::string& answers) {
    if (!o.visibility.empty()) {
        if (settings.method != DirectMethod::Exact)
            std::printf("visibility: %s not used (the %s method needs no history trees)\n",
                        o.visibility.c_str(), toString(settings.method));
        else
            writeVisibility(o.visibility, store, visibility);
    }
    const EffectsSummary effects = renderer.effects();
    for (const std::string& w : effects.hiddenLights)
        std::cerr << "penumbra: warning: " << w << '\n';
    printEffects(effects.text());
    writeImages(film, out, o.exposure, answers);
}

void runRender(const RenderOptions& o);

#ifdef PENUMBRA_HAVE_MPI
// What every rank of a render under MPI sets up, as a single process does: rank 0 loads the scene
// as every command does (its warnings on stderr), the other ranks quietly.
struct RenderSetup {
    RenderSetup(const RenderOptions& o, bool quiet)
        : settings(renderSettings(o)),
          scene(quiet ? loadScene(o.scene, o.sceneOptions.load())
                      : loadSceneFile(o.scene, o.sceneOptions.load())),
          bvh(scene.mesh),
          store(scene, &bvh, storeOptions(o)),
          camera(cameraOf(o, scene, bvh)) {
        outputs(o);  // refused here, by every rank alike
        if (!o.outAnswers.empty())
            throw usageError(
                "--out-answers: not across the ranks of an MPI job (each pixel's answers stay "
                "on the rank that shaded it); render it in one process");
    }
    static VisibilityStore::Options storeOptions(const RenderOptions& o) {
        VisibilityStore::Options options;
        o.exact.applyTo(options);
        return options;
    }
    static Camera cameraOf(const RenderOptions& o, const Scene& scene, const EmbreeScene& bvh) {
        std::optional<Vec3> up;
        if (!o.up.empty()) up = parseDirection("--up", o.up);
        if (o.camera.empty()) return defaultCamera(scene, bvh, up);
        Camera c = parseCamera("--camera", o.camera);
        if (up) c.up = *up;
        return c;
    }
    const RenderSettings settings;
    const Scene scene;
    const EmbreeScene bvh;
    VisibilityStore store;
    const Camera camera;
};

std::string clusterLines(const cluster::ClusterRenderStats& s, size_t tilesInAll) {
    const size_t ranks = s.tilesByRank.size();
    size_t workerTiles = 0, workerTrees = 0;
    for (size_t r = 1; r < ranks; ++r) {
        workerTiles += s.tilesByRank[r];
        workerTrees += s.treesByRank[r];
    }
    std::string out = "ranks    " + std::to_string(ranks) + ": trees built by rank";
    for (size_t r = 0; r < ranks; ++r)
        out += (r ? ", " : " ") + std::to_string(r) + " " + std::to_string(s.treesByRank[r]);
    out += " (" + std::to_string(s.duplicateTrees) + " built twice); tiles shaded by rank";
    for (size_t r = 0; r < ranks; ++r) {
        const size_t tiles =
            r == 0 ? tilesInAll - std::min(tilesInAll, workerTiles) : s.tilesByRank[r];
        out += (r ? ", " : " ") + std::to_string(r) + " " + std::to_string(tiles);
    }
    char line[400];
    std::snprintf(line, sizeof line,
                  "\nsent     trees: %zu bytes to rank 0 (%.0f per tree), %zu from rank 0 to the "
                  "workers; image: %zu bytes of pixels and tile costs, %zu of findings, %zu of "
                  "pass starts, %zu of tile batches; rank 0 handled them in %.3f s, its build "
                  "rounds took %.3f s\n",
                  s.treeBytesToRank0,
                  workerTrees ? static_cast<double>(s.treeBytesToRank0) / workerTrees : 0.0,
                  s.treeBytesFromRank0, s.pixelBytes, s.findingsBytes, s.passBytes, s.tileBytes,
                  s.coordinatorSeconds, s.buildSeconds);
    return out + line;
}

// Ends a job that lost a rank: MPI_Finalize would wait for it.
[[noreturn]] void abortJob(cluster::MpiSession& session, const std::string& error) {
    std::fflush(stdout);
    std::cerr << "penumbra: error: " << error << "; nothing written\n";
    std::cerr.flush();
    session.abort(kExitInputError);
}

// Under an MPI launcher with more than one rank (engine/cluster/cluster_render.h): rank 0 renders
// as a single process does, the trees and the tiles spread over the ranks, and writes the image
// and the summary; the other ranks serve quietly. Ctrl-C (the launcher's SIGTERM) stops every
// rank, and rank 0 writes nothing.
void runClusterRender(cluster::MpiSession& session, const RenderOptions& o) {
    const int threads = o.threads > 0 ? o.threads : std::max(1, tbb::info::default_concurrency());
    // This thread coordinates: `threads` others shade and build.
    tbb::global_control parallelism(tbb::global_control::max_allowed_parallelism, threads + 1);
    cluster::ClusterRenderOptions options;
    options.threads = threads;
    const InterruptGuard interruptGuard(SIGINT), terminateGuard(SIGTERM);
    const auto interrupted = [] { return gInterrupted.load(std::memory_order_relaxed); };

    if (session.rank() != 0) {
        std::unique_ptr<RenderSetup> setup;
        try {
            setup = std::make_unique<RenderSetup>(o, true);
        } catch (const std::exception& e) {
            cluster::refuseToServe(session, e.what());  // rank 0 says it, once
            return;
        }
        ProgressiveRenderer renderer(setup->scene, setup->bvh, setup->store);
        cluster::serveRender(session, setup->store, renderer, setup->camera, setup->settings,
                             options, interrupted);
        return;
    }

    std::unique_ptr<RenderSetup> setup;
    try {
        setup = std::make_unique<RenderSetup>(o, false);
    } catch (...) {
        cluster::stopWorkers(session);  // then the usual error, from rank 0 alone
        throw;
    }
    const RenderSettings& settings = setup->settings;
    VisibilityStore& store = setup->store;
    const bool exact = settings.method == DirectMethod::Exact;
    VisibilityInput visibility;
    // Interrupted, rank 0 writes nothing: a message still arriving is given up on at once, so
    // that a rank that died mid-message (the launcher's SIGTERM follows) is named before the
    // launcher's SIGKILL a second later (mpi_session.h).
    session.setInterrupted(interrupted);
    cluster::RenderCoordinator coordinator(session, store, options, interrupted);
    try {
        coordinator.start();
        if (!o.visibility.empty() && exact) {
            visibility = readVisibility(o.visibility, store);
            coordinator.shareStore();
        }
    } catch (const cluster::MpiError& e) {
        if (coordinator.lostRank()) abortJob(session, e.what());
        throw inputError(e.what());
    }
    ProgressiveRenderer renderer(setup->scene, setup->bvh, store);
    renderer.setCluster(&coordinator);
    RenderTimes times;
    Film film;
    std::optional<std::string> failure;
    try {
        film = renderer.render(setup->camera, settings, &times, &gInterrupted);
    } catch (const cluster::MpiError& e) {
        failure = e.what();
    }
    if (coordinator.interrupted()) {
        // Ctrl-C reaches every rank (the launcher's SIGTERM), and so does a rank's death under
        // Open MPI: the ranks that do not answer the stop are the dead ones. Said at once when
        // a build round found them already: the launcher kills every rank a second after its
        // SIGTERM.
        if (coordinator.lostRank() && !coordinator.lostError().empty())
            abortJob(session, coordinator.lostError());
        const std::vector<int> silent = coordinator.finish(options.stopLimit);
        if (!silent.empty()) {
            std::string ranks;
            for (int r : silent) ranks += (ranks.empty() ? "rank " : ", ") + std::to_string(r);
            abortJob(session, ranks +
                                  " did not answer the stop (it had ended: killed or crashed; "
                                  "the launcher then stops the job)");
        }
        throw CommandError(kExitInterrupted, "interrupted after " + std::to_string(film.passes) +
                                                 " of " + std::to_string(settings.spp) +
                                                 " passes; nothing written");
    }
    if (failure) {
        coordinator.finish(options.stopLimit);
        abortJob(session, *failure);
    }
    const std::vector<int> silent = coordinator.finish(options.silenceLimit);
    if (!silent.empty())
        abortJob(session, "rank " + std::to_string(silent.front()) +
                              " did not answer the end of the render (killed or crashed)");

    printTimes(o, setup->scene, settings, times, store);
    std::fputs(clusterLines(coordinator.stats(), static_cast<size_t>(TileSchedule::tileCount(
                                                     settings.width, settings.height)) *
                                                     static_cast<size_t>(film.passes))
                   .c_str(),
               stdout);
    writeResults(o, settings, store, visibility, renderer, film, outputs(o), "");
    std::fflush(stdout);
}
#endif

void runRenderCommand(const RenderOptions& o) {
#ifdef PENUMBRA_HAVE_MPI
    if (cluster::launchedByMpiLauncher())
        runLaunched([&](cluster::MpiSession& session) { runClusterRender(session, o); },
                    [&] { runRender(o); });
#endif
    runRender(o);
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
    writeResults(o, settings, store, visibility, renderer, film, out, o.outAnswers);
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
    sub->callback([o] { runRenderCommand(*o); });
}

}  // namespace penumbra::cli
