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
//
// With --shards, each rank writes the trees it built to its own shard, FILE.rank-RRRRR-of-NNNNN
// (engine/io/visibility_file.h), and FILE itself is not written: `penumbra merge FILE
// FILE.rank-*` joins them (app/cli/merge_command.cpp), so that no tree travels to rank 0. A rank
// first reads its own shard of an earlier run (same name) and rank 0 lists the pairs that FILE and
// every other shard present hold (any rank count), so a rerun builds only what is missing. A
// single process with --shards is rank 0 of 1: it writes FILE.rank-00000-of-00001.
#include <tbb/global_control.h>
#include <tbb/info.h>
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <chrono>
#include <csignal>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <iostream>
#include <memory>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "app/cli/arguments.h"
#include "app/cli/commands.h"
#include "app/cli/interrupt_guard.h"
#include "app/cli/mpi_launch.h"
#include "engine/io/scene_loader.h"
#include "engine/io/visibility_file.h"
#include "engine/precompute/patch_layout.h"
#include "engine/precompute/precompute_scheduler.h"
#include "engine/precompute/scene_hash.h"
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
    bool shards = false;
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

// --shards: this rank's shard and the pairs built already elsewhere.
struct ShardPlan {
    fs::path path;                   // this rank's shard
    VisibilityShard shard;           // index, count, the scene's pair total
    ExistingFile own;                // its trees of an earlier run (read into the store)
    std::vector<PairKey> elsewhere;  // in FILE and the other shards present (rank 0 only)
    size_t otherFiles = 0;           // those files
};
ShardPlan planShard(const PrecomputeCommandOptions& o, VisibilityStore& store, int rank, int ranks,
                    bool listOthers) {
    ShardPlan plan;
    plan.shard.index = static_cast<uint32_t>(rank);
    plan.shard.count = static_cast<uint32_t>(ranks);
    plan.shard.pairTotal = everyPairKey(store).size();
    plan.path = shardPath(o.output, plan.shard.index, plan.shard.count);
    plan.own = readExisting(plan.path, store);
    if (!listOthers) return plan;
    std::vector<fs::path> others = shardPaths(o.output);
    std::erase(others, plan.path);
    others.insert(others.begin(), fs::path(o.output));
    const uint64_t hash = sceneHash(store.scene(), store.options());
    for (const fs::path& other : others) {
        try {
            const std::vector<PairKey> keys = visibilityFileKeys(other, hash);
            plan.elsewhere.insert(plan.elsewhere.end(), keys.begin(), keys.end());
            ++plan.otherFiles;
        } catch (const VisibilityFileError& e) {
            if (e.status != VisibilityFileStatus::Missing)
                std::cerr << "penumbra: warning: " << e.what() << " (" << toString(e.status)
                          << "); its pairs are built again\n";
        }
    }
    std::sort(plan.elsewhere.begin(), plan.elsewhere.end());
    plan.elsewhere.erase(std::unique(plan.elsewhere.begin(), plan.elsewhere.end()),
                         plan.elsewhere.end());
    return plan;
}

size_t writeShard(const ShardPlan& plan, const VisibilityStore& store) {
    VisibilityFileWriteOptions options;
    options.shard = plan.shard;
    try {
        return writeVisibilityFile(plan.path, store, options);
    } catch (const VisibilityFileError& e) {
        throw inputError(e.what());
    }
}

// The end of a run with --shards (this rank's shard written): the summary, the next step, and the
// error for a run that stopped early. `done` counts the pairs built anywhere, `extra` what the
// cluster adds.
void finishShard(const PrecomputeCommandOptions& o, const PrecomputeSetup& setup,
                 const PrecomputeProgress& p, const ShardPlan& plan, size_t shardBytes, int threads,
                 const std::string& extra) {
    const VisibilityStore& store = setup.store;
    const size_t total = plan.shard.pairTotal;
    std::printf("scene    %s: %u faces, %zu lights\n", o.scene.c_str(), setup.scene.faceCount(),
                setup.scene.lights.size());
    std::printf("pairs    %zu of %zu built (%zu held by %zu other files before this run)\n", p.done,
                total, plan.elsewhere.size(), plan.otherFiles);
    std::printf("seconds  %.3f\n", p.seconds);
    std::printf("threads  %d\n", threads);
    std::fputs(extra.c_str(), stdout);
    std::printf("shard    %s: %zu trees (%zu of an earlier run), %zu bytes, written\n",
                plan.path.string().c_str(), store.treeCount(), plan.own.trees, shardBytes);
    if (p.state == State::Idle && p.done >= total)
        std::printf("next     every pair is built: penumbra merge -o %s %s.rank-*\n",
                    o.output.c_str(), o.output.c_str());
    std::fflush(stdout);
    if (p.state == State::Failed) throw inputError(o.scene + ": " + p.error);
    if (p.state == State::Cancelled)
        throw CommandError(kExitInterrupted, "interrupted after " + std::to_string(p.done) +
                                                 " of " + std::to_string(total) +
                                                 " pairs; the shards hold them (run again to "
                                                 "finish)");
    if (p.state == State::OverBudget)
        throw inputError("memory budget of " + std::to_string(o.memoryBudgetMB) +
                         " MB reached after " + std::to_string(p.done) + " of " +
                         std::to_string(total) +
                         " pairs; the shards hold them (run again with a larger --memory-budget "
                         "to finish)");
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
    std::optional<ShardPlan> plan;
    ExistingFile existing;
    if (o.shards)
        plan = planShard(o, store, 0, 1, true);
    else
        existing = readExisting(o.output, store);

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

    size_t builtBefore = 0;  // with shards: the pairs this run does not build
    if (plan) {
        std::vector<PairKey> missing;
        for (const PairKey& k : everyPairKey(store)) {
            if (store.find(k) ||
                std::binary_search(plan->elsewhere.begin(), plan->elsewhere.end(), k))
                ++builtBefore;
            else
                missing.push_back(k);
        }
        scheduler.request(std::move(missing));
    } else {
        scheduler.requestAll();
    }
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
    if (plan) {
        const size_t bytes = writeShard(*plan, store);
        p.done += builtBefore;
        finishShard(o, setup, p, *plan, bytes, scheduler.threads(), "");
        return;
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
    options.shards = o.shards;
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
        if (!o.shards) {
            cluster::servePrecompute(session, setup->store, options, interrupted);
            return;
        }
        const ShardPlan plan = planShard(o, setup->store, session.rank(), session.size(), false);
        const auto write = [&]() -> std::string {
            writeShard(plan, setup->store);
            return {};
        };
        cluster::servePrecompute(session, setup->store, options, interrupted, write);
        return;
    }

    std::unique_ptr<PrecomputeSetup> setup;
    ExistingFile existing;
    std::optional<ShardPlan> plan;
    try {
        setup = std::make_unique<PrecomputeSetup>(o, false);
        if (o.shards) {
            plan = planShard(o, setup->store, 0, session.size(), true);
            options.builtElsewhere = plan->elsewhere;
        } else {
            existing = readExisting(o.output, setup->store);
        }
    } catch (...) {
        cluster::stopWorkers(session);  // then the usual error, from rank 0 alone
        throw;
    }
    // A message still arriving when interrupted is given up on at once (mpi_session.h): a rank
    // that died mid-message must not keep rank 0 from writing and naming it before the SIGKILL.
    session.setInterrupted(interrupted);
    const bool tty = ::isatty(STDERR_FILENO) != 0;
    bool printed = false;
    const auto onProgress = [&](const PrecomputeProgress& p) {
        printProgress(p, tty);
        printed = true;
    };
    // Said and written at once: the launcher may kill every rank a second after its SIGTERM.
    const auto checkpoint = [&] {
        if (printed && tty) std::fputc('\n', stderr);
        const fs::path written = plan ? plan->path : fs::path(o.output);
        try {
            VisibilityFileWriteOptions writeOptions;
            if (plan) writeOptions.shard = plan->shard;
            writeVisibilityFile(written, setup->store, writeOptions);
            std::fprintf(
                stderr,
                "penumbra: stopping (%s): the %zu pairs finished so far are written to "
                "%s; %s\n",
                gSignal.load() == SIGTERM ? "SIGTERM: Ctrl-C to the launcher, or a rank "
                                            "ended and the launcher ends the job"
                                          : "SIGINT",
                setup->store.treeCount(), written.string().c_str(),
                plan ? "every rank writes its own shard" : "asking the other ranks for theirs");
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
    if (plan)  // no tree travels: the workers' messages are counts (and WORK's keys)
        std::snprintf(line, sizeof line,
                      "\nsent     no trees: %zu built by the other ranks into their shards, "
                      "reported in %zu bytes\n",
                      r.treesReceived, r.bytesReceived);
    extra += line;

    if (plan) {
        for (const std::string& e : r.shardErrors) std::cerr << "penumbra: error: " << e << '\n';
        if (!r.shardErrors.empty() && p.state == State::Idle) {
            p.state = State::Failed;
            p.error = std::to_string(r.shardErrors.size()) + " shard(s) could not be written";
        }
        const auto finish = [&] {
            finishShard(o, *setup, p, *plan, writeShard(*plan, setup->store), r.threads, extra);
        };
        if (!r.lostRank) {
            finish();
            return;
        }
        try {
            finish();
        } catch (const CommandError&) {
        }
        std::cerr << "penumbra: error: " << p.error << "; the shards hold the " << p.done << " of "
                  << p.total << " pairs finished (run again to finish)\n";
        std::cerr.flush();
        session.abort(kExitInputError);
    }
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
    if (cluster::launchedByMpiLauncher())
        runLaunched([&](cluster::MpiSession& session) { runClusterPrecompute(session, o); },
                    [&] { runPrecompute(o); });
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
    sub->add_flag("--shards", options->shards,
                  "Write this rank's trees to its own shard FILE.rank-RRRRR-of-NNNNN instead of "
                  "FILE (under MPI: no tree travels to rank 0); join them with penumbra merge");
    sub->add_option("--threads", options->threads,
                    "Concurrent builds (default: the number of cores)")
        ->check(CLI::PositiveNumber);
    addSceneOptions(*sub, options->sceneOptions);
    sub->callback([options] { runPrecomputeCommand(*options); });
}

}  // namespace penumbra::cli
