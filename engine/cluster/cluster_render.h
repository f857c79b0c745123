// The render across the ranks of an MPI job (`penumbra render` under mpirun or srun): the image is
// bit-identical to a single process's with the same settings, and the effects summary the same
// numbers (timings apart), because a pixel's value depends only on its own random streams and the
// trees in the store (renderer.h), and every rank holds the same trees when it shades.
//
// Rank 0 runs the ProgressiveRenderer as a single process does, with a RenderCoordinator as its
// RenderCluster (renderer.h); the other ranks serve (serveRender):
//   1. HELLO as the precompute's (cluster_precompute.h): each worker loaded the scene, its scene
//      hash, or why not (refuseToServe); rank 0 refuses a bad scene once, alone.
//   2. The trees the image needs (prepare's, then each pass's refinement): rank 0 sends BUILD, and
//      the ranks run one round of the cluster precompute for that key list (coordinatePrecompute
//      with ClusterPrecomputeOptions::keys: one queue, each key handed out once, rank 0 building
//      too); rank 0 then sends every worker all of the round's trees (TREES, the visibility file's
//      record format; a worker keeps its own), and each answers how many it had built itself and
//      how many it had already (TREES_ACK): no tree is built twice (ClusterRenderStats). A
//      refinement first sends the pairs to refine (REFINE), so that every layout has the same
//      sub-patches before their trees are built and sent.
//   3. A pass: rank 0 sends PASS (its index and the film's over-limit cells: what a pixel's later
//      passes read), then hands tiles out in TILES batches, most expensive first (TileSchedule),
//      two batches in flight per worker, a batch about remaining / (4 x ranks) tiles (1 to 16);
//      rank 0's own threads take tiles from the same schedule. A worker shades a batch on its
//      threads and answers TILES_DONE: each tile's pixels (raw doubles), its cost, and what the
//      tiles found (PassFindings). Rank 0 adds the pass to the film, as a single process does.
//   4. DONE: the workers answer FINAL and return.
// Faults: a worker that sends nothing for silenceLimit (it sends HEARTBEAT every second) or
// reports a failure ends the render with an MpiError naming it; interrupted (Ctrl-C, the
// launcher's SIGTERM), rank 0 stops the workers and writes nothing (RenderCluster calls return
// false).
#pragma once

#include <chrono>
#include <cstddef>
#include <functional>
#include <string>
#include <vector>

#include "engine/cluster/cluster_precompute.h"
#include "engine/cluster/mpi_session.h"
#include "engine/precompute/visibility_store.h"
#include "engine/render/renderer.h"

namespace penumbra::cluster {

enum RenderTag : int {
    kTagBuild = 101,
    kTagTrees,
    kTagTreesAck,
    kTagRefine,
    kTagPass,
    kTagTiles,
    kTagTilesDone,
    kTagDone,
};

struct ClusterRenderOptions {
    int threads = 0;  // threads per rank (0: its cores)
    std::chrono::milliseconds silenceLimit{10000};
    std::chrono::milliseconds helloLimit{600000};
    std::chrono::milliseconds stopLimit{500};
};

// What the render sent, and who did what.
struct ClusterRenderStats {
    std::vector<size_t> treesByRank;  // trees each rank built
    size_t treesBuilt = 0;            // distinct trees the rounds added to rank 0's store
    size_t duplicateTrees = 0;      // built by more than one rank (sum of treesByRank - treesBuilt)
    size_t treeBytesToRank0 = 0;    // the workers' trees, encoded
    size_t treeBytesFromRank0 = 0;  // the rounds' trees sent to the workers (all of them)
    std::vector<size_t> tilesByRank;  // tiles each rank shaded, all passes
    size_t pixelBytes = 0;            // pixel values and tile costs received by rank 0
    size_t findingsBytes = 0;         // what the workers' tiles found, received by rank 0
    size_t passBytes = 0;             // the passes' starts (cells) sent to the workers
    size_t tileBytes = 0;             // the tile batches sent
    double coordinatorSeconds = 0;    // rank 0's main thread handling messages (decode, copy)
    double buildSeconds = 0;          // the build rounds, wall time
};

// Rank 0's side: the RenderCluster of its ProgressiveRenderer.
class RenderCoordinator : public RenderCluster {
  public:
    // `interrupted` is polled while rank 0 waits (Ctrl-C, SIGTERM).
    RenderCoordinator(MpiSession& session, VisibilityStore& store, ClusterRenderOptions options,
                      std::function<bool()> interrupted);
    // Waits for every worker's HELLO; throws MpiError naming a worker that could not load the
    // scene, has another one, or did not answer (the workers are stopped first).
    void start();
    // Sends the trees the store holds now (read from a visibility file) to every worker.
    void shareStore();
    bool buildTrees(const std::vector<PairKey>& keys) override;
    void refined(const std::vector<PairKey>& keys) override;
    bool shadePass(int pass, int width, int height, const PassCells& cells, TileSchedule& schedule,
                   std::vector<Vec3>& image, const std::function<void()>& shadeHere,
                   std::atomic<bool>& stopHere, PassFindings& found,
                   const std::atomic<bool>* cancel) override;
    // The render is over (or abandoned): every worker is told and answers. Returns the ranks
    // that did not answer within `limit` (dead), those known dead already included (the same
    // list again on a later call).
    std::vector<int> finish(std::chrono::milliseconds limit);
    const ClusterRenderStats& stats() const { return stats_; }
    // A worker was lost: MPI_Finalize would wait for it (the caller aborts the job instead),
    // and what was said of it (empty when only an MpiError said it).
    bool lostRank() const { return lostRank_; }
    const std::string& lostError() const { return lostError_; }
    // Interrupted: this rank's own signal, or a worker's note that the launcher's signal reached
    // it (serveRender sends kStoppedBySignal, cluster_precompute.h): Open MPI signals the ranks one
    // after another, and a worker's note is an interruption, not the failure to report (the ranks
    // that then do not answer the stop are the dead ones).
    bool interrupted() const { return peerStopped_ || interrupted_(); }

    RenderCoordinator(const RenderCoordinator&) = delete;
    RenderCoordinator& operator=(const RenderCoordinator&) = delete;

  private:
    // One round of the cluster precompute over `keys` (none: the HELLO round only), the workers
    // told first (BUILD); rank 0 builds too when `coordinatorBuilds`.
    ClusterPrecomputeResult buildRound(const std::vector<PairKey>& keys, bool coordinatorBuilds);
    // True (and noted) when `m` is a worker's kStoppedBySignal.
    bool stopNote(const MpiMessage& m);
    std::string name(int rank) const;
    void sendAll(int tag, const std::vector<unsigned char>& bytes);
    // One message to rank `to`, and the next message from any rank: a send or a receive that
    // failed (the rank died or stopped answering) loses that rank (lose).
    void send(int to, int tag, const std::vector<unsigned char>& bytes);
    std::optional<MpiMessage> receive();
    [[noreturn]] void lose(int rank, const std::string& why);

    MpiSession& session_;
    VisibilityStore& store_;
    ClusterRenderOptions options_;
    std::function<bool()> interrupted_;
    bool peerStopped_ = false;
    std::vector<std::string> hosts_;
    ClusterRenderStats stats_;
    bool lostRank_ = false;
    std::string lostError_;
    std::vector<bool> lost_;  // per rank: known dead (finish does not wait for it)
    bool finished_ = false;
    std::vector<int> silent_;  // finish's answer
};

// Every other rank: HELLO, then serves rank 0's BUILD, TREES, REFINE, PASS and TILES until DONE
// (or STOP, or `interrupted`). `renderer` renders from `camera` with `settings` over `store`.
void serveRender(MpiSession& session, VisibilityStore& store, ProgressiveRenderer& renderer,
                 const Camera& camera, const RenderSettings& settings,
                 const ClusterRenderOptions& options, const std::function<bool()>& interrupted);

}  // namespace penumbra::cluster
