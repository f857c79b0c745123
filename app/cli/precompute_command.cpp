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
//
// Started by an MPI launcher with several ranks (a build with MPI), the pairs are built across the
// ranks (engine/cluster/cluster_precompute.h): rank 0 does all of the above, the others build
// quietly; the file is the same bytes (docs/cluster.md).
#include <tbb/global_control.h>
#include <tbb/info.h>
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <chrono>
#include <csignal>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <iostream>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include "app/cli/arguments.h"
#include "app/cli/commands.h"
#include "app/cli/interrupt_guard.h"
#include "engine/io/scene_loader.h"
#include "engine/io/visibility_file.h"
#include "engine/precompute/patch_layout.h"
#include "engine/precompute/precompute_scheduler.h"
#include "engine/raytrace/embree_scene.h"
#include "engine/scene/light_checks.h"

#ifdef PENUMBRA_HAVE_MPI
#include "engine/cluster/cluster_precompute.h"
#endif

namespace penumbra::cli {
namespace {

namespace fs = std::filesystem;
using State = PrecomputeProgress::State;

struct PrecomputeCommandOptions {
    std::string scene;
    std::string output;
    double memoryBudgetMB = 0;
    double patchFraction = 1.0 / 4;
    ExactOptions exact;
    int threads = 0;
    SceneOptions sceneOptions;
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

// What every rank sets up: the scene, its BVH and the store of its trees, with the command's
// settings. Rank 0 loads the scene as every command does (its warnings on stderr); the other
// ranks load it quietly, so that each warning and error is said once.
struct PrecomputeSetup {
    PrecomputeSetup(const PrecomputeCommandOptions& o, bool quiet)
        : scene(quiet ? loadScene(o.scene, o.sceneOptions.load())
                      : loadSceneFile(o.scene, o.sceneOptions.load())),
          bvh(scene.mesh),
          store(scene, &bvh, storeOptions(o)) {}
    static VisibilityStore::Options storeOptions(const PrecomputeCommandOptions& o) {
        VisibilityStore::Options options;
        options.patchFraction = o.patchFraction;
        o.exact.applyTo(options);
        return options;
    }
    const Scene scene;
    const EmbreeScene bvh;
    VisibilityStore store;
};

// The trees of an existing, current file (a rerun finishes the rest); a stale or corrupt one is
// reported and recomputed.
struct ExistingFile {
    bool loaded = false;
    size_t trees = 0;
};
ExistingFile readExisting(const fs::path& output, VisibilityStore& store) {
    ExistingFile existing;
    try {
        existing.trees = readVisibilityFile(output, store);
        existing.loaded = true;
    } catch (const VisibilityFileError& e) {
        if (e.status != VisibilityFileStatus::Missing)
            std::cerr << "penumbra: " << e.what() << " (" << toString(e.status)
                      << "); recomputing\n";
    }
    return existing;
}

int threadsOf(const PrecomputeCommandOptions& o) {
    return o.threads > 0 ? o.threads : std::max(1, tbb::info::default_concurrency());
}

size_t writeOrThrow(const fs::path& output, const VisibilityStore& store) {
    try {
        return writeVisibilityFile(output, store);
    } catch (const VisibilityFileError& e) {
        throw inputError(e.what());
    }
}

// After the builds, single process or cluster: the hidden lights' warning, the file (unless
// nothing new was built), the summary on stdout (`extra`: lines the cluster adds), and the error
// for a run that stopped early.
void finishPrecompute(const PrecomputeCommandOptions& o, const PrecomputeSetup& setup,
                      const PrecomputeProgress& p, const ExistingFile& existing, int threads,
                      const std::string& extra) {
    const Scene& scene = setup.scene;
    const VisibilityStore& store = setup.store;
    const fs::path output(o.output);
    if (p.state == State::Idle && store.treeCount() >= p.total) warnHiddenLights(scene, store);

    const bool nothingNew = existing.loaded && store.treeCount() == existing.trees;
    const size_t fileBytes = nothingNew ? fs::file_size(output) : writeOrThrow(output, store);

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
    std::printf("threads  %d\n", threads);
    std::fputs(extra.c_str(), stdout);
    if (nothingNew)
        std::printf("file     %s: valid and current, %zu trees loaded, nothing recomputed\n",
                    o.output.c_str(), existing.trees);
    else if (existing.loaded)
        std::printf("file     %s: %zu trees loaded, %zu built, written\n", o.output.c_str(),
                    existing.trees, store.treeCount() - existing.trees);
    else
        std::printf("file     %s: written\n", o.output.c_str());
    std::fflush(stdout);

    if (p.state == State::Failed) throw inputError(o.scene + ": " + p.error);
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

void runPrecompute(const PrecomputeCommandOptions& o) {
    PrecomputeSetup setup(o, false);
    VisibilityStore& store = setup.store;
    const ExistingFile existing = readExisting(o.output, store);

    const int threads = threadsOf(o);
    // TBB keeps one core for the thread that waits by default; this thread only polls, so let
    // `threads` workers run.
    tbb::global_control parallelism(tbb::global_control::max_allowed_parallelism, threads + 1);
    PrecomputeOptions schedulerOptions;
    schedulerOptions.threads = threads;
    schedulerOptions.memoryBudgetBytes = static_cast<size_t>(o.memoryBudgetMB * 1024.0 * 1024.0);
    PrecomputeScheduler scheduler(store, schedulerOptions);
    const InterruptGuard interruptGuard(SIGINT);
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
    finishPrecompute(o, setup, p, existing, scheduler.threads(), "");
}

#ifdef PENUMBRA_HAVE_MPI
// Under an MPI launcher with more than one rank (engine/cluster/cluster_precompute.h): rank 0
// reads the existing file, coordinates, builds, writes the one file and prints the summary; the
// other ranks build quietly. Ctrl-C and the launcher's SIGTERM stop every rank; rank 0 writes
// what was finished.
void runClusterPrecompute(cluster::MpiSession& session, const PrecomputeCommandOptions& o) {
    const int threads = threadsOf(o);
    tbb::global_control parallelism(tbb::global_control::max_allowed_parallelism, threads + 1);
    cluster::ClusterPrecomputeOptions options;
    options.threads = threads;
    options.memoryBudgetBytes = static_cast<size_t>(o.memoryBudgetMB * 1024.0 * 1024.0);
    const InterruptGuard interruptGuard(SIGINT), terminateGuard(SIGTERM);
    const auto interrupted = [] { return gInterrupted.load(std::memory_order_relaxed); };

    if (session.rank() != 0) {
        std::unique_ptr<PrecomputeSetup> setup;
        try {
            setup = std::make_unique<PrecomputeSetup>(o, true);
        } catch (const std::exception& e) {
            // Rank 0 reports it (once, naming this rank) unless it failed the same way.
            cluster::refuseToServe(session, e.what());
            return;
        }
        cluster::servePrecompute(session, setup->store, options, interrupted);
        return;
    }

    std::unique_ptr<PrecomputeSetup> setup;
    ExistingFile existing;
    try {
        setup = std::make_unique<PrecomputeSetup>(o, false);
        existing = readExisting(o.output, setup->store);
    } catch (...) {
        cluster::stopWorkers(session);  // then the usual error, from rank 0 alone
        throw;
    }
    const bool tty = ::isatty(STDERR_FILENO) != 0;
    bool printed = false;
    const auto onProgress = [&](const PrecomputeProgress& p) {
        printProgress(p, tty);
        printed = true;
    };
    // Said and written at once: the launcher may kill every rank a second after its SIGTERM.
    const auto checkpoint = [&] {
        if (printed && tty) std::fputc('\n', stderr);
        try {
            writeVisibilityFile(o.output, setup->store);
            std::fprintf(stderr,
                         "penumbra: stopping (%s): the %zu pairs finished so far are written to "
                         "%s; asking the other ranks for theirs\n",
                         gSignal.load() == SIGTERM ? "SIGTERM: Ctrl-C to the launcher, or a rank "
                                                     "ended and the launcher ends the job"
                                                   : "SIGINT",
                         setup->store.treeCount(), o.output.c_str());
        } catch (const VisibilityFileError& e) {
            std::cerr << "penumbra: warning: " << e.what() << '\n';
        }
        std::fflush(stderr);
    };
    const cluster::ClusterPrecomputeResult r = cluster::coordinatePrecompute(
        session, setup->store, options, interrupted, onProgress, checkpoint);
    PrecomputeProgress p = r.progress;
    if (printed) {
        printProgress(p, tty);
        if (tty) std::fputc('\n', stderr);
    }

    std::string extra = "ranks    " + std::to_string(session.size()) + ": trees built by rank";
    for (size_t k = 0; k < r.treesByRank.size(); ++k)
        extra += (k ? ", " : " ") + std::to_string(k) + " " + std::to_string(r.treesByRank[k]);
    char line[200];
    std::snprintf(line, sizeof line,
                  "\nsent     %zu trees to rank 0, %zu bytes (%.0f bytes per tree); rank 0 "
                  "decoded them in %.3f s\n",
                  r.treesReceived, r.bytesReceived,
                  r.treesReceived ? static_cast<double>(r.bytesReceived) / r.treesReceived : 0.0,
                  r.coordinatorSeconds);
    extra += line;

    if (!r.lostRank) {
        finishPrecompute(o, *setup, p, existing, r.threads, extra);
        return;
    }
    // A rank died or stopped answering: MPI_Finalize would wait for it. What was finished is
    // written, the error said, and the job ended.
    try {
        finishPrecompute(o, *setup, p, existing, r.threads, extra);
    } catch (const CommandError&) {
        // The error below says it all.
    }
    std::cerr << "penumbra: error: " << p.error << "; the " << setup->store.treeCount() << " of "
              << p.total << " pairs finished are in " << o.output << " (run again to finish)\n";
    std::cerr.flush();
    session.abort(kExitInputError);
}
#endif

void runPrecomputeCommand(const PrecomputeCommandOptions& o) {
#ifdef PENUMBRA_HAVE_MPI
    if (cluster::launchedByMpiLauncher()) {
        int exitCode = kExitOk;
        {
            cluster::MpiSession session;
            try {
                if (session.size() > 1)
                    runClusterPrecompute(session, o);
                else
                    runPrecompute(o);  // one rank: as without a launcher
            } catch (...) {
                // Said before MPI_Finalize: the launcher may kill this rank during it (a second
                // after its SIGTERM).
                exitCode = reportError(std::current_exception());
            }
            std::fflush(stdout);
            std::cerr.flush();
        }  // MPI_Finalize
        // A rank ends here, its builds stopped and its file written: oneTBB's wait for its
        // threads at exit (WorkerThreadsJoinedAtExit) was seen to never return on a worker rank
        // after MPI_Finalize (1 run in 5, Open MPI 4.1.4, oneTBB 2021.8).
        std::_Exit(exitCode);
    }
#endif
    runPrecompute(o);
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
    sub->callback([options] { runPrecomputeCommand(*options); });
}

}  // namespace penumbra::cli
