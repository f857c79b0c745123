// A precompute as the studies measure it: some (receiver patch, light) pairs, or all of them,
// built on the PrecomputeScheduler (every core) under a time limit, and what the store holds
// after it. Counts are exact; times are wall and process CPU seconds of this run.
#pragma once

#include <cstddef>
#include <vector>

#include "engine/precompute/visibility_store.h"

namespace penumbra {

// The store's pairs by what they call for (vis::PairKind), and its partial trees (the build
// budget stopped them: their deferred occluders are clipped by each point's query).
struct PairKinds {
    size_t backFacing = 0, fullyVisible = 0, fullyHidden = 0, penumbra = 0, partial = 0;
};
PairKinds pairKinds(const VisibilityStore& store);

// The history-tree nodes of every tree in the store.
size_t treeNodes(const VisibilityStore& store);

struct PrecomputeRun {
    double seconds = 0, cpu = 0;             // wall, and process CPU (all threads)
    size_t pairs = 0;                        // pairs requested
    size_t done = 0;                         // of them, built (or found built) before the limit
    bool complete = false;                   // all of them, within the limit
    size_t trees = 0, nodes = 0, bytes = 0;  // the store's after the run
    PairKinds kinds;
};

// Builds `keys` (every pair of the store's scene when null); cancels the scheduler once `limit`
// seconds have passed. Throws StudyError when a build fails.
PrecomputeRun precomputePairs(VisibilityStore& store, const std::vector<PairKey>* keys,
                              double limit);

}  // namespace penumbra
