// PointInspection: everything the viewer's debugger shows about one surface point: per light the
// exact answer of the from-point query (engine/precompute/point_query.h: fragments, fraction, form
// factors), the time it took, and the history-tree path it walked with, per visited node, the
// occluder edge, the occluder face and which side(s) of the node's plane the light polygon went to.
// In the engine because the bench measures a click too (engine/studies/per_point_study.h).
#pragma once

#include <cstddef>
#include <cstdint>
#include <limits>
#include <optional>
#include <span>
#include <vector>

#include "engine/precompute/point_query.h"
#include "engine/precompute/visibility_store.h"

namespace penumbra {

// Plane tests the tree-less answer of a click may take on the UI thread (all lights together):
// about 10 ms at most (some 35 ns a test on the bench's 2-core VM), far above what most points
// need (`penumbra bench` reports the click latency and the clicks over budget: 0 of 200 on table,
// 2 of 200 on the bunny). A point that needs more is answered by the full inspection alone.
inline constexpr uint64_t kClickWork = uint64_t{1} << 18;

// kClickWork divided evenly among `lights` lights: inspectPointDirect's work limit for a click.
constexpr uint64_t clickWorkPerLight(size_t lights) {
    return kClickWork / (lights > 0 ? lights : 1);
}

// One visited node of the query's walk (vis::TraceStep) with what the debugger shows of it.
struct PathStep {
    uint32_t node = 0;
    uint32_t depth = 0;                   // 0 at the root
    uint32_t v0 = 0, v1 = 0;              // the node's oriented edge (history_tree.h encoding)
    Vec3 a, b;                            // a segment of it, for display (vis::edgeSegment)
    uint32_t occluderFace = kNoOccluder;  // HistoryTree::nodeOccluder, when recorded
    vis::NodeSide side = vis::NodeSide::Positive;  // where the walk sent the light polygon
    static constexpr uint32_t kNoOccluder = std::numeric_limits<uint32_t>::max();
};

struct LightInspection {
    LightAtPoint result;        // queryPoint's answer for this light
    double seconds = 0;         // wall time of the query, including a tree build when needed
    bool treeWasBuilt = false;  // the tree was not in the store before this query
    PairKey key;                // the tree that served the query
    // The tree (owned by the store, valid for its lifetime); nullptr for the light's own face.
    const vis::HistoryTree* tree = nullptr;
    std::vector<PathStep> steps;  // one per step of result.trace, same order
};

struct PointInspection {
    uint32_t face = 0;
    Vec3 point;
    Vec3 normal;  // unit normal of the face
    std::vector<LightInspection> lights;
    // The fragments came from the tree-less query (inspectPointDirect): no tree, path or kind
    // yet; the full inspection (inspectPoint) is on its way.
    bool treesPending = false;
};

// Queries every light at x on `face` (builds missing trees on the calling thread: run it off the
// UI thread). Throws what queryPoint throws.
PointInspection inspectPoint(VisibilityStore& store, uint32_t face, const Vec3& x);

// The fragments and numbers of every light at x without history trees (queryPointDirect over
// `faces`, with its face `groups` when given, as the renderer): cheap enough for the UI thread,
// so that a click answers in the frame it happens. treesPending is set, no light has a tree or
// a path. nullopt when a light's query reached `workLimit` plane tests (0 = none): then only the
// full inspection can answer.
std::optional<PointInspection> inspectPointDirect(const Scene& scene, const vis::BoxTree& faces,
                                                  uint32_t face, const Vec3& x, uint64_t workLimit,
                                                  const vis::FaceClusters* groups = nullptr);

// The debugger's rows for a query's trace on `tree`: each step with its node's edge, a segment of
// it and its occluder face.
std::vector<PathStep> pathSteps(const vis::PolygonMesh& mesh, const vis::HistoryTree& tree,
                                std::span<const vis::TraceStep> trace);

}  // namespace penumbra
