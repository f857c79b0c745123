// Quadric pruning and leaf merging (vis::BuildOptions) on and off: every pair of one scene
// precomputed four times, with the trees' size and the query time they give. Counts are exact;
// times are measurements of one run.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "engine/scene/scene.h"
#include "engine/studies/precompute_run.h"
#include "engine/studies/study_harness.h"

namespace penumbra {

struct BuildOptionsRow {
    std::string scene;  // the scene file
    bool mergeLeaves = true, quadricPruning = true;
    PrecomputeRun precompute;  // every pair, within the limit
    // The mean query (light 0, one thread) at up to `points` area-weighted random points whose
    // pair has a tree (engine/scene/surface_samples.h, seed 1); 0 when none has.
    double queryUs = 0;
};

// The four combinations, both on first. `limit`: seconds per precompute.
std::vector<BuildOptionsRow> runBuildOptionsStudy(const std::string& path, const Scene& scene,
                                                  double limit, size_t points, const StudyLog& log);

}  // namespace penumbra
