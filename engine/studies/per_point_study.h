// The from-point query at random points of one scene (light 0, one thread): its time against 16
// and 128 shadow rays, the boundary chain's counts, the visible region's outline, and what a
// click in the viewer costs (the tree-less answer within the click's budget, and the former
// answer through freshly built history trees).
//
// Exact and measured: the counts (nodes, fragments, edges, cells, loops) are exact for these
// points (engine/scene/surface_samples.h, seed 1); the times are wall microseconds or
// milliseconds of one run, each loop over all points after an untimed warm-up pass.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>

#include "engine/scene/scene.h"
#include "engine/studies/study_harness.h"

namespace penumbra {

// A click in the viewer (engine/precompute/point_inspection.h): every light's fragments from the
// tree-less query within the click's work budget, on up to 200 points; and the former click, the
// history trees built and walked (a fresh store), on up to 20.
struct ClickLatency {
    size_t points = 0;
    double fragmentsMedianMs = 0, fragmentsP99Ms = 0, fragmentsMaxMs = 0;
    size_t overBudget = 0;  // clicks whose tree-less query reached the budget
    size_t treePoints = 0;
    double withTreesMedianMs = 0, withTreesMaxMs = 0;
};

// The boundary chain (vis::FromPointQuery::ChainOptions) at the points, and the partial trees'
// silhouettes (vis::DeferredSilhouettes) once per tree the points use.
struct ChainStats {
    // The points clipped against enough occluders for the chain to be considered, their
    // occluder edges and the boundary edges left once shared edges cancel.
    size_t manyOccluderPoints = 0, occluderEdges = 0, boundaryEdges = 0;
    // The points the chain evaluated, the cells it cut the light into (those labelled by
    // crossings, without a line test) and the fragments kept.
    size_t points = 0, cells = 0, crossingLabels = 0, fragments = 0;
    double oneByOneUs = 0;  // the mean query with every occluder clipped one by one (Algorithm 1)
    // The partial trees the points use, those whose silhouettes pay, their deferred faces' edge
    // uses and those kept for the patch, and the points answered from them.
    size_t partialTrees = 0, silhouetteTrees = 0;
    uint64_t silhouetteUses = 0, silhouetteKept = 0;
    size_t silhouettePoints = 0;
};

// The visible region's boundary (vis::visibleOutline) at the points, summed over them; and per
// point the fragments' form factor against the outline built and integrated (the same value).
struct OutlineStats {
    size_t fragmentEdges = 0, loops = 0, edges = 0;
    double integrationUs = 0, outlineUs = 0;
};

struct PerPointRow {
    std::string scene;  // the scene file
    size_t points = 0;
    // The exact query and the form factor of its fragments: the mean over all points, then with
    // each point timed alone (the clock's own cost, some 20-40 ns, included).
    double exactUs = 0, exactMedianUs = 0, exactP99Us = 0, exactMaxUs = 0;
    ClickLatency click;
    double rays16Us = 0, rays128Us = 0;  // Embree's shadow rays, per point
    double nodesPerQuery = 0;
    ChainStats chain;
    double fragmentsPerQuery = 0;
    OutlineStats outline;
};

// Measures `points` points of `scene` (loaded from `path`; it must have a light).
PerPointRow runPerPointStudy(const std::string& path, const Scene& scene, size_t points,
                             const StudyLog& log);

}  // namespace penumbra
