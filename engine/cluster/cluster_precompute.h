// The precompute across the ranks of an MPI job: rank 0 coordinates (and builds), the other ranks
// build, and every tree ends up in rank 0's store, which the caller writes as one visibility file,
// byte-identical to a single process's (the file is sorted by key and holds no time).
//
// The protocol (tags of ClusterTag, every message a byte string, mpi_session.h):
//   1. Every rank loads the scene. A worker says HELLO to rank 0: its scene hash
//      (scene_hash.h: the scene and the settings that shape the trees), or why it could not load
//      it (refuseToServe). Rank 0 checks every hash against its own (a node with another file
//      would build other trees), or, when it cannot load the scene itself, sends STOP at once
//      and reports the error alone.
//   2. Rank 0 holds the pairs still missing (everyPairKey less those its store already has, from
//      an existing file: a rerun finishes the rest) in face order and hands them out in WORK
//      batches, two per worker in flight so that a worker never waits for its next batch. A batch
//      is about remaining / (4 x ranks) pairs, between 1 and 64 (guided: large while much is
//      left, small at the end so that the last trees, whose costs differ by orders of magnitude,
//      spread). Rank 0 takes batches for its own PrecomputeScheduler too.
//   3. A worker builds a batch on its own PrecomputeScheduler (its oneTBB arena) and sends its
//      trees back as RESULT, encoded by the visibility file's own record format
//      (encodeTreeRecords); rank 0 decodes them into its store (validated as a file's trees) and
//      sends the next batch. A worker sends HEARTBEAT every second while it builds.
//   4. STOP (all built, Ctrl-C, the memory budget, a failure): each worker cancels its builds and
//      answers FINAL with the trees of its unfinished batches that are complete, then returns.
//      Rank 0 waits for every FINAL, so the file holds every pair finished anywhere.
//
// Shards (ClusterPrecomputeOptions::shards, `precompute --shards`): the same protocol, but no tree
// travels. Each rank keeps the trees it built and writes them to its own shard file at the end (or
// when stopped); RESULT and FINAL then carry a u64 count of trees (FINAL also the shard's write
// error, if any), so rank 0's messages are keys and counts only and its store holds only its own
// trees. The memory budget then counts each rank's own store: a worker over it cancels its builds
// and says OVERBUDGET, and rank 0 stops every rank as for its own. `penumbra merge` joins the
// shards (engine/io/visibility_merge.h).
//
// Faults: a worker that cannot load the scene or whose build fails sends its error (FAILURE); one
// that sends nothing for silenceLimit (killed, hung, its node gone) is named as such. Either way
// rank 0 stops the others, keeps what was finished and reports "rank N (host): cause". Open MPI's
// launcher itself ends the whole job when a rank dies (docs/cluster.md): the silence limit is for
// launchers and networks that do not.
#pragma once

#include <chrono>
#include <cstddef>
#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "engine/cluster/mpi_session.h"
#include "engine/precompute/precompute_scheduler.h"
#include "engine/precompute/visibility_store.h"

namespace penumbra::cluster {

enum ClusterTag : int {
    kTagHello = 1,
    kTagWork,
    kTagResult,
    kTagHeartbeat,
    kTagFailure,
    kTagStop,
    kTagFinal,
    kTagOverBudget,  // with shards: a worker's own trees passed the memory budget
};

// What a render worker (cluster_render.h) that the launcher's SIGTERM, or a SIGINT, reached sends
// rank 0 as kTagFailure: an interruption, not a failure. A build round takes it as its own
// interrupt (and that worker as answered: it ends on the stop), so that the ranks that then do
// not answer are named as the cause, not the one that said it was stopped.
inline constexpr std::string_view kStoppedBySignal = "stopped by a signal (SIGTERM or SIGINT)";

struct ClusterPrecomputeOptions {
    int threads = 0;  // concurrent builds per rank (0: its cores)
    // Of rank 0's store, which gathers every tree (with shards: of each rank's own); 0: no limit.
    size_t memoryBudgetBytes = 0;
    // A worker that sends nothing for this long is reported as lost.
    std::chrono::milliseconds silenceLimit{10000};
    // How long rank 0 waits for the workers' HELLO (each loads the scene first).
    std::chrono::milliseconds helloLimit{600000};
    // Interrupted (Ctrl-C, SIGTERM), how long rank 0 waits for the workers' FINAL: Open MPI's
    // mpirun kills every rank about a second after its SIGTERM.
    std::chrono::milliseconds stopLimit{500};
    bool coordinatorBuilds = true;  // rank 0 builds batches too
    // The pairs to build, in the order they are handed out (the trees an image needs: the
    // cluster's render, cluster_render.h); unset: every pair of the scene. Those the store holds
    // already are skipped either way.
    std::optional<std::vector<PairKey>> keys;
    // Each rank keeps its trees for its own shard (above); only counts reach rank 0.
    bool shards = false;
    // Pairs built already but not in rank 0's store (the other shards of earlier runs, the
    // output file): not handed out, counted as done.
    std::vector<PairKey> builtElsewhere;
};

struct ClusterPrecomputeResult {
    // done/total over every pair of the scene; state Idle when all are built, Cancelled,
    // OverBudget or Failed (error: "rank N (host): ...").
    PrecomputeProgress progress;
    bool lostRank = false;            // a rank died or stopped answering: MPI_Finalize would hang
    std::vector<int> silentRanks;     // those ranks
    size_t treesReceived = 0;         // trees decoded from the workers
    size_t bytesReceived = 0;         // their encoded size
    std::vector<size_t> treesByRank;  // trees built by each rank (rank 0's own builds first)
    double coordinatorSeconds = 0;    // rank 0's main thread decoding and inserting trees
    int threads = 0;                  // builds per rank
    std::vector<std::string> shardErrors;  // with shards: "rank N (host): why" per failed write
};

// Rank 0. The store holds the scene's trees read from a file (if any); the missing ones are built
// across the ranks and added to it. `interrupted` is polled every few milliseconds (Ctrl-C,
// SIGTERM); once it says so, `checkpoint` is called at once (to write what the store holds)
// before the workers are stopped. `onProgress` gets the progress about every 0.5 s.
ClusterPrecomputeResult coordinatePrecompute(
    MpiSession& session, VisibilityStore& store, const ClusterPrecomputeOptions& options,
    const std::function<bool()>& interrupted,
    const std::function<void(const PrecomputeProgress&)>& onProgress,
    const std::function<void()>& checkpoint);

// Rank 0 could not load the scene (or set up the precompute): tells every worker to stop, without
// waiting for their HELLO. The caller then reports its error, alone.
void stopWorkers(MpiSession& session);

// Every other rank: says HELLO with the store's scene hash, then builds the batches rank 0 sends
// until it says STOP, or until `interrupted` (the launcher's SIGTERM reached this rank too): then
// it sends what it finished at once and waits for rank 0's STOP. Throws MpiError when rank 0
// cannot be reached. With shards, `writeShard` is called once the builds stopped, before FINAL
// (which carries its error: "" when written).
void servePrecompute(MpiSession& session, VisibilityStore& store,
                     const ClusterPrecomputeOptions& options,
                     const std::function<bool()>& interrupted,
                     const std::function<std::string()>& writeShard = {});

// A worker that could not load the scene: says HELLO with `error` and waits for rank 0's STOP (so
// that rank 0 reports it before the launcher sees a rank end).
void refuseToServe(MpiSession& session, const std::string& error);

}  // namespace penumbra::cluster
