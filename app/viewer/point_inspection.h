// PointInspection: everything the debugger shows about one surface point: per light the exact
// answer of the from-point query (engine/precompute/point_query.h: fragments, fraction, form
// factors), the time it took, and the history-tree path it walked with, per visited node, the
// occluder edge, the occluder face and which side(s) of the node's plane the light polygon went to.
#pragma once

#include <cstdint>
#include <limits>
#include <vector>

#include "engine/precompute/point_query.h"
#include "engine/precompute/visibility_store.h"

namespace penumbra::viewer {

// Which children of a node the query descended into: the light polygon (as clipped so far) lay on
// the positive side of the plane through x and the node's edge, the negative side, both (the
// plane split it into two fragments), or in the plane (x on the edge's line: the documented rule
// sends it to the positive child).
enum class PathSide { Positive, Negative, Both, InPlane };
const char* toString(PathSide side);

struct PathStep {
    uint32_t node = 0;
    uint32_t depth = 0;                   // 0 at the root
    uint32_t v0 = 0, v1 = 0;              // the node's oriented edge (history_tree.h encoding)
    Vec3 a, b;                            // a segment of it, for display (vis::edgeSegment)
    uint32_t occluderFace = kNoOccluder;  // HistoryTree::nodeOccluder, when recorded
    PathSide side = PathSide::Positive;
    static constexpr uint32_t kNoOccluder = std::numeric_limits<uint32_t>::max();
};

struct LightInspection {
    LightAtPoint result;        // queryPoint's answer for this light
    double seconds = 0;         // wall time of the query, including a tree build when needed
    bool treeWasBuilt = false;  // the tree was not in the store before this query
    PairKey key;                // the tree that served the query
    // The tree (owned by the store, valid for its lifetime); nullptr for the light's own face.
    const vis::HistoryTree* tree = nullptr;
    std::vector<PathStep> steps;  // one per node of result.path, same order
};

struct PointInspection {
    uint32_t face = 0;
    Vec3 point;
    Vec3 normal;  // unit normal of the face
    std::vector<LightInspection> lights;
};

// Queries every light at x on `face` (builds missing trees on the calling thread: run it off the
// UI thread). Throws what queryPoint throws.
PointInspection inspectPoint(VisibilityStore& store, uint32_t face, const Vec3& x);

// The path of fromPointQuery(mesh, tree, x) with the side taken at each node, from a re-walk that
// applies the same exact clipping rules (visibility/fp_query.cpp); its node sequence equals
// FromPointResult::path (a test checks this).
std::vector<PathStep> pathSteps(const vis::PolygonMesh& mesh, const vis::HistoryTree& tree,
                                const Vec3& x);

}  // namespace penumbra::viewer
