// PassFindings: what the tiles of one pass found besides their pixels (the pairs and faces they
// used, their evaluations, the cells over the work limit), merged over the threads of a process
// and, for a render across the ranks of an MPI job (engine/cluster/cluster_render.h), over the
// processes: the renderer folds them into its effects summary and its next pass the same way
// wherever the tiles were shaded.
#pragma once

#include <cstdint>
#include <unordered_set>
#include <vector>

#include "engine/precompute/pair_key.h"
#include "engine/render/effects_summary.h"
#include "engine/render/shading.h"

namespace penumbra {

struct PassFindings {
    std::vector<PairKey> usedKeys;
    std::vector<uint32_t> facesSeen;
    ExactEvaluations evaluations;
    std::vector<PairKey> directKeys;
    std::vector<uint64_t> overLimitNow, edgeFailedNow, edgeDeclinedNow;
    std::vector<OverLimitPoint> overLimitTrees;
    // The lights whose light-edge index the shading process holds (DirectLighting::
    // lightEdgesBuilt): another process's, for the summary of the process that gathers.
    std::vector<uint32_t> lightEdgeIndices;

    void add(const PassFindings& o) {
        auto append = [](auto& to, const auto& from) {
            to.insert(to.end(), from.begin(), from.end());
        };
        append(usedKeys, o.usedKeys);
        append(facesSeen, o.facesSeen);
        evaluations += o.evaluations;
        append(directKeys, o.directKeys);
        append(overLimitNow, o.overLimitNow);
        append(edgeFailedNow, o.edgeFailedNow);
        append(edgeDeclinedNow, o.edgeDeclinedNow);
        append(overLimitTrees, o.overLimitTrees);
        append(lightEdgeIndices, o.lightEdgeIndices);
    }
};

// The (pixel, light) cells of the film's earlier passes that a pass's tiles read
// (ExactScratch::overLimitBefore, edgeFailedBefore, edgeDeclinedBefore).
struct PassCells {
    const std::unordered_set<uint64_t>* overLimit = nullptr;
    const std::unordered_set<uint64_t>* edgeFailed = nullptr;
    const std::unordered_set<uint64_t>* edgeDeclined = nullptr;
};

}  // namespace penumbra
