// Building the history tree of one (receiver, light) pair: P2PQuery, Algorithm 1 of Mora & Aveneau
// 2005, with the conservative classification of line_polytope.h.
#pragma once

#include <atomic>
#include <cstdint>
#include <span>
#include <stdexcept>

#include "visibility/history_tree.h"

namespace penumbra::vis {

struct BuildOptions {
    bool mergeLeaves = true;     // merge sibling leaves with the same label (paper 3.2)
    bool quadricPruning = true;  // drop splits whose one side holds no real line
    // When set and it becomes true, the build stops at the next leaf it processes (within one
    // classification: well under a millisecond) by throwing BuildCancelled.
    const std::atomic<bool>* cancel = nullptr;
    // Build budget: when the construction has solved this many linear programs, it stops and the
    // occluders not yet inserted are deferred to the query (HistoryTree::deferred): a partial
    // tree, exact like a complete one, whose queries clip the deferred occluders from each point.
    // The shadow of a 70k-triangle bunny on a floor patch is an arrangement of thousands of
    // silhouette edges in line space: a complete tree would take minutes. 0 = no limit.
    // Deterministic (counts, not seconds), so a visibility file does not depend on the machine.
    // The default stops a pair after about 0.05 s on one core (measured on table: a lower budget
    // moves more work to the queries, a higher one more to the precompute; 10k was the fastest
    // in total, see the bench report).
    uint64_t maxLpSolves = 10000;
};

// Thrown by buildHistoryTree when BuildOptions::cancel is raised. No partial tree is returned.
struct BuildCancelled : std::runtime_error {
    BuildCancelled() : std::runtime_error("history tree build cancelled") {}
};

struct BuildStats {
    uint32_t occludersInShaft = 0;  // faces that may block a line between B and L
    uint32_t occludersInserted = 0;
    uint64_t classifications = 0;    // leaf-against-hyperplane decisions
    uint64_t lpSolves = 0;           // linear programs solved for them
    uint64_t uncertain = 0;          // decisions that could not be certified (took the split)
    uint64_t exactCertificates = 0;  // decisions certified by the exact rational fallback
    uint64_t prunedSplits = 0;       // splits dropped by the real-line (quadric) test
    uint64_t realLineTests = 0;      // real-line tests run (each side of a Mixed split)
    uint64_t realLineWitness = 0;    // ... settled by finding a real line (no proof needed)
    uint64_t realLineLpSolves = 0;   // linear programs of the real-line tests (in lpSolves too)
    double realLineSeconds = 0;      // time in the real-line tests (in seconds too)
    uint64_t mergedLeaves = 0;
    uint32_t occludersDeferred = 0;  // left to the query (HistoryTree::deferred)
    bool budgetExceeded = false;     // the build stopped at maxLpSolves (a partial tree)
    double seconds = 0;
};

// candidates: the faces that may occlude (e.g. from a BVH shaft query); empty = all faces.
// receiverPatch: a convex part of the receiver face (receiver_patches.h) the tree is built for;
// empty = the whole face. The tree is exact for the lines through that region.
HistoryTree buildHistoryTree(const PolygonMesh& mesh, uint32_t receiver, uint32_t light,
                             const BuildOptions& options = {},
                             std::span<const uint32_t> candidates = {}, BuildStats* stats = nullptr,
                             std::span<const Vec3> receiverPatch = {});

}  // namespace penumbra::vis
