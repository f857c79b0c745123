// The strategies of one FromPointQuery (from_point_query.h), their shared per-run context, and the
// choice between them: the tree walk, or the direct path's candidates; then, for what reaches a
// visible leaf, the boundary chain or Algorithm 1. Each strategy reaches the others through this
// struct; FromPointQuery holds one.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>

#include "visibility/fp_query/active_occluders.h"
#include "visibility/fp_query/chain_build.h"
#include "visibility/fp_query/chain_cells.h"
#include "visibility/fp_query/cluster_path.h"
#include "visibility/fp_query/contact_rule.h"
#include "visibility/fp_query/edge_path.h"
#include "visibility/fp_query/line_tests.h"
#include "visibility/fp_query/occluder_clip.h"
#include "visibility/fp_query/query_run.h"
#include "visibility/fp_query/silhouette_path.h"
#include "visibility/fp_query/solid_filter.h"
#include "visibility/fp_query/tree_walk.h"

namespace penumbra::vis {

struct QueryParts {
    explicit QueryParts(PredicateMode mode)
        : run(mode),
          active(*this),
          contact(*this),
          walk(*this),
          clip(*this),
          chain(*this),
          cells(*this),
          lines(*this),
          silhouettes(*this),
          clusters(*this),
          solids(*this),
          edges(*this) {}
    QueryParts(const QueryParts&) = delete;
    QueryParts& operator=(const QueryParts&) = delete;

    QueryRun run;
    ActiveOccluders active;
    ContactRule contact;
    TreeWalk walk;
    OccluderClip clip;
    ChainBuild chain;
    ChainCells cells;
    LineTests lines;
    SilhouettePath silhouettes;
    ClusterPath clusters;
    SolidFilter solids;
    EdgePath edges;
    // The last run was answered by the contact rule from the pair's occluders.
    bool contactAnswer = false;
    // The per-point occluders are ready for this run (a partial tree prepares them at its first
    // visible leaf: a point in full shadow pays nothing).
    bool deferredPrepared = true;

    // Resets every strategy's per-run state.
    void startRun();
    // Prepares the pair, then whether x sees any of the light at all (in front of L's plane, and
    // some of L in front of B's).
    bool startPair(const PolygonMesh& mesh, uint32_t receiver, uint32_t light, const Vec3& x);
    // What reaches a visible leaf: kept, or with the per-point occluders clipped against it (by
    // the boundary chain when it pays, else by Algorithm 1).
    void reachVisible(std::span<const Vec3> poly, size_t depth);
    // A partial tree's deferred occluders that may block a line from x to L, activated (or the
    // silhouette path taken).
    void prepareDeferred(const HistoryTree& tree);
    // QueryRun::candidates: the items of `index` whose box may meet the pyramid, in increasing
    // order, each node visited counted as work; false when the work limit stopped the search.
    bool findCandidates(const BoxTree& index);
    // The answer from the faces in QueryRun::candidates alone (no tree): each activated (solids
    // tried first where they pay), then L clipped.
    void clipCandidates();
    // The light-edge path (edge_path.h), after preparePyramid: true when it was taken (the
    // answer is in run.fragments, or the work limit was reached), false when it cannot be (the
    // boundary chain off, or EdgePath::prepare declined: nothing answered).
    bool takeLightEdges(const BoxTree& faces, const LightEdgeIndex& index);
};

}  // namespace penumbra::vis
