// `penumbra precompute SCENE -o FILE [--memory-budget MB] [--patch-fraction F] [--threads N]`
//
// Builds the history tree of every (receiver patch, light) pair of the scene on the
// PrecomputeScheduler and writes them to FILE (engine/io/visibility_file.h). Progress goes to
// stderr about every 0.5 s; the summary (pairs by kind, nodes, bytes, seconds, threads) to stdout.
//
// An existing FILE is read first: if it is valid and made for this scene and these settings, its
// trees are used and only missing pairs are built (none, for a complete file: nothing is
// recomputed and the file is left as it is). A stale or corrupt FILE is reported on stderr and
// recomputed from scratch, then overwritten.
//
// Once every pair is built, a light no receiver gets any light from (each of its pairs back-facing
// or fully hidden) is reported on stderr (engine/scene/light_checks.h).
//
// Ctrl-C cancels: the running builds stop, the pairs built so far are written (so a second run
// resumes) and the exit status is 130. Reaching the memory budget also writes the pairs built so
// far, then fails with exit status 1.
#include <tbb/global_control.h>
#include <tbb/info.h>
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <chrono>
#include <csignal>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include "app/cli/arguments.h"
#include "app/cli/commands.h"
#include "engine/io/visibility_file.h"
#include "engine/precompute/patch_layout.h"
#include "engine/precompute/precompute_scheduler.h"
#include "engine/raytrace/embree_scene.h"
#include "engine/scene/light_checks.h"

namespace penumbra::cli {
namespace {

namespace fs = std::filesystem;
using State = PrecomputeProgress::State;

constexpr int kExitInterrupted = 130;  // the shell's convention for a SIGINT

struct PrecomputeCommandOptions {
    std::string scene;
    std::string output;
    double memoryBudgetMB = 0;
    double patchFraction = 1.0 / 4;
    ExactOptions exact;
    int threads = 0;
    SceneOptions sceneOptions;
};

// The one piece of global state here: a signal handler can only reach a global, and only a
// lock-free atomic (or sig_atomic_t) may be written from it.
std::atomic<bool> gInterrupted{false};
static_assert(std::atomic<bool>::is_always_lock_free);

extern "C" void onInterrupt(int) { gInterrupted.store(true, std::memory_order_relaxed); }

// Installs the SIGINT handler for the command's lifetime and restores the previous one.
class InterruptGuard {
  public:
    InterruptGuard() {
        gInterrupted.store(false);
        struct sigaction action {};
        action.sa_handler = &onInterrupt;
        sigemptyset(&action.sa_mask);
        installed_ = ::sigaction(SIGINT, &action, &previous_) == 0;
    }
    ~InterruptGuard() {
        if (installed_) ::sigaction(SIGINT, &previous_, nullptr);
    }
    InterruptGuard(const InterruptGuard&) = delete;
    InterruptGuard& operator=(const InterruptGuard&) = delete;

  private:
    struct sigaction previous_ {};
    bool installed_ = false;
};

std::string duration(double s) {
    char buf[32];
    if (s < 60)
        std::snprintf(buf, sizeof buf, "%.1f s", s);
    else if (s < 3600)
        std::snprintf(buf, sizeof buf, "%d min %02d s", static_cast<int>(s) / 60,
                      static_cast<int>(s) % 60);
    else
        std::snprintf(buf, sizeof buf, "%d h %02d min", static_cast<int>(s) / 3600,
                      static_cast<int>(s) / 60 % 60);
    return buf;
}

void printProgress(const PrecomputeProgress& p, bool tty) {
    const double percent = p.total ? 100.0 * static_cast<double>(p.done) / p.total : 100.0;
    std::string line = "precompute: " + std::to_string(p.done) + "/" + std::to_string(p.total) +
                       " pairs (" + std::to_string(static_cast<int>(percent)) + "%), " +
                       duration(p.seconds);
    if (p.secondsLeft > 0) line += ", about " + duration(p.secondsLeft) + " left";
    if (tty)
        std::fprintf(stderr, "\r%-78s", line.c_str());
    else
        std::fprintf(stderr, "%s\n", line.c_str());
    std::fflush(stderr);
}

// Every light whose pairs are all back-facing or hidden (some hidden: a light that faces away
// from everything is reported on load already), from a store holding every pair. A penumbra tree
// none of whose leaves is visible hides the whole light too (occluders that each block part of
// it, together all of it).
void warnHiddenLights(const Scene& scene, const VisibilityStore& store) {
    std::vector<size_t> lightOfFace(scene.faceCount(), SIZE_MAX);
    for (size_t k = 0; k < scene.lights.size(); ++k) lightOfFace[scene.lights[k]] = k;
    struct Counts {
        size_t backFacing = 0, hidden = 0, lit = 0;
    };
    std::vector<Counts> counts(scene.lights.size());
    store.forEach([&](const PairKey& key, const PairRecord& r) {
        if (PatchLayout::refineLevel(key) > 0) return;
        const size_t k = lightOfFace[key.lightFace];
        if (k == SIZE_MAX) return;
        switch (r.tree.kind) {
            case vis::PairKind::BackFacing:
                ++counts[k].backFacing;
                break;
            case vis::PairKind::FullyHidden:
                ++counts[k].hidden;
                break;
            case vis::PairKind::FullyVisible:
                ++counts[k].lit;
                break;
            case vis::PairKind::Penumbra:
                ++(r.tree.leafCount(true) > 0 ? counts[k].lit : counts[k].hidden);
                break;
        }
    });
    for (size_t k = 0; k < counts.size(); ++k)
        if (counts[k].lit == 0 && counts[k].hidden > 0)
            std::cerr << "penumbra: warning: "
                      << hiddenLightWarning(scene, k, counts[k].backFacing, counts[k].hidden)
                      << '\n';
}

void runPrecompute(const PrecomputeCommandOptions& o) {
    const Scene scene = loadSceneFile(o.scene, o.sceneOptions.load());
    const EmbreeScene bvh(scene.mesh);
    VisibilityStore::Options storeOptions;
    storeOptions.patchFraction = o.patchFraction;
    o.exact.applyTo(storeOptions);
    VisibilityStore store(scene, &bvh, storeOptions);
    const fs::path output(o.output);

    size_t loadedTrees = 0;
    bool loaded = false;
    try {
        loadedTrees = readVisibilityFile(output, store);
        loaded = true;
    } catch (const VisibilityFileError& e) {
        if (e.status != VisibilityFileStatus::Missing)
            std::cerr << "penumbra: " << e.what() << " (" << toString(e.status)
                      << "); recomputing\n";
    }

    const int threads = o.threads > 0 ? o.threads : std::max(1, tbb::info::default_concurrency());
    // TBB keeps one core for the thread that waits by default; this thread only polls, so let
    // `threads` workers run.
    tbb::global_control parallelism(tbb::global_control::max_allowed_parallelism, threads + 1);
    PrecomputeOptions schedulerOptions;
    schedulerOptions.threads = threads;
    schedulerOptions.memoryBudgetBytes = static_cast<size_t>(o.memoryBudgetMB * 1024.0 * 1024.0);
    PrecomputeScheduler scheduler(store, schedulerOptions);
    const InterruptGuard interruptGuard;
    const bool tty = ::isatty(STDERR_FILENO) != 0;

    scheduler.requestAll();
    auto lastPrint = std::chrono::steady_clock::now();
    bool printed = false;
    PrecomputeProgress p = scheduler.progress();
    while (p.state == State::Running) {
        if (gInterrupted.load(std::memory_order_relaxed)) scheduler.cancel();
        std::this_thread::sleep_for(std::chrono::milliseconds(50));
        p = scheduler.progress();
        const auto now = std::chrono::steady_clock::now();
        if (p.state == State::Running && now - lastPrint >= std::chrono::milliseconds(500)) {
            printProgress(p, tty);
            printed = true;
            lastPrint = now;
        }
    }
    scheduler.wait();
    p = scheduler.progress();
    if (printed) {
        printProgress(p, tty);
        if (tty) std::fputc('\n', stderr);
    }
    if (p.state == State::Failed) throw inputError(o.scene + ": " + p.error);
    if (p.state == State::Idle && store.treeCount() >= p.total) warnHiddenLights(scene, store);

    const bool nothingNew = loaded && store.treeCount() == loadedTrees;
    size_t fileBytes = 0;
    if (nothingNew) {
        fileBytes = fs::file_size(output);
    } else {
        try {
            fileBytes = writeVisibilityFile(output, store);
        } catch (const VisibilityFileError& e) {
            throw inputError(e.what());
        }
    }

    const auto kinds = store.kindCounts();
    size_t nodes = 0, deferred = 0;
    store.forEach([&](const PairKey&, const PairRecord& r) {
        nodes += r.tree.nodes.size();
        deferred += r.tree.deferred.size();
    });
    std::printf("scene    %s: %u faces, %zu lights%s\n", o.scene.c_str(), scene.faceCount(),
                scene.lights.size(),
                scene.defaultLight ? (" (" + std::string(kDefaultLightNote) + ")").c_str() : "");
    std::printf(
        "pairs    %zu of %zu: %zu back-facing, %zu fully visible, %zu fully hidden, "
        "%zu penumbra (%zu partial: the build budget stopped them, %zu occluders left to the "
        "query)\n",
        store.treeCount(), p.total, kinds[0], kinds[1], kinds[2], kinds[3], store.partialCount(),
        deferred);
    std::printf("nodes    %zu\n", nodes);
    std::printf("bytes    %zu in memory, file %zu\n", store.bytes(), fileBytes);
    std::printf("seconds  %.3f\n", p.seconds);
    std::printf("threads  %d\n", scheduler.threads());
    if (nothingNew)
        std::printf("file     %s: valid and current, %zu trees loaded, nothing recomputed\n",
                    o.output.c_str(), loadedTrees);
    else if (loaded)
        std::printf("file     %s: %zu trees loaded, %zu built, written\n", o.output.c_str(),
                    loadedTrees, store.treeCount() - loadedTrees);
    else
        std::printf("file     %s: written\n", o.output.c_str());
    std::fflush(stdout);

    if (p.state == State::Cancelled)
        throw CommandError(kExitInterrupted, "interrupted after " + std::to_string(p.done) +
                                                 " of " + std::to_string(p.total) + " pairs; " +
                                                 o.output + " holds them (run again to finish)");
    if (p.state == State::OverBudget)
        throw inputError("memory budget of " + std::to_string(o.memoryBudgetMB) +
                         " MB reached after " + std::to_string(p.done) + " of " +
                         std::to_string(p.total) + " pairs; " + o.output +
                         " holds them (run again with a larger --memory-budget to finish)");
}

}  // namespace

void registerPrecomputeCommand(CLI::App& app) {
    auto options = std::make_shared<PrecomputeCommandOptions>();
    CLI::App* sub = app.add_subcommand(
        "precompute",
        "Build the history trees of every (receiver patch, light) pair and save them to a file");
    sub->add_option("scene", options->scene,
                    "Scene file (.obj, .ply, .off, .stl, .gltf, .glb or a .json scene)")
        ->required();
    sub->add_option("-o,--output", options->output, "Visibility file to write (.pvis)")->required();
    sub->add_option("--memory-budget", options->memoryBudgetMB,
                    "Stop once the trees take more than this many MB (0: no limit)")
        ->check(CLI::NonNegativeNumber);
    addExactOptions(*sub, options->exact, ExactOptionSet::BuildOnly);
    sub->add_option("--patch-fraction", options->patchFraction,
                    "Receiver patch size as a fraction of the scene diagonal (0: whole faces)")
        ->check(CLI::Range(0.0, 1.0));
    sub->add_option("--threads", options->threads,
                    "Concurrent builds (default: the number of cores)")
        ->check(CLI::PositiveNumber);
    addSceneOptions(*sub, options->sceneOptions);
    sub->callback([options] { runPrecompute(*options); });
}

}  // namespace penumbra::cli
