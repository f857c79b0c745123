// Precompute time and size against the triangle count (the bench runs it on the dragon's
// resolutions): a fixed set of receiver patches, every patch of the floor (the largest face) and
// those of 32 faces of the model drawn with a fixed seed, against every light, built on the
// PrecomputeScheduler under a time limit. Counts are exact; times are measurements of one run.
#pragma once

#include <cstdint>
#include <string>

#include "engine/scene/scene.h"
#include "engine/studies/precompute_run.h"
#include "engine/studies/study_harness.h"

namespace penumbra {

struct ScalingRow {
    std::string scene;  // the scene file
    uint32_t faces = 0;
    double loadSeconds = 0;  // the scene's load and its BVH's build
    PrecomputeRun precompute;
};

// Measures `scene` (loaded from `path` in `loadSeconds`). `limit`: seconds for the precompute.
ScalingRow runScalingStudy(const std::string& path, const Scene& scene, double loadSeconds,
                           double limit, const StudyLog& log);

}  // namespace penumbra
