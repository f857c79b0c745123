// FPQuery (Mora & Aveneau 2005, Algorithm 2): the exactly visible fragments of the light L from a
// point x on the receiver B, by walking B's history tree with the 3D plane through x and each
// stored edge and clipping L.
//
// Two interfaces: FromPointQuery is a reusable workspace for hot loops (a renderer thread keeps
// one; after warm-up a query allocates nothing); fromPointQuery() is the one-shot convenience.
//
// The query is a set of strategies, each a small class with its own state in this folder, sharing
// one per-run context (query_run.h: x, the pair, the pyramid and cone, the work budget, the
// answer) and chosen here (query_parts.h):
//   tree_walk        the history tree's walk (Algorithm 2)
//   contact_rule     points on an occluder's contact with B, answered from the pair's occluders
//   active_occluders the per-point occluders: a partial tree's deferred ones or the direct path's
//   occluder_clip    Algorithm 1: L clipped occluder by occluder
//   chain_build      the boundary chain: the occluder edges that do not cancel
//   chain_cells      L cut into the chain's cells, each labelled by one certified line
//   line_tests       a cell's line against the occluders
//   silhouette_path  a partial tree's silhouettes (deferred_silhouettes.h)
//   cluster_path     face groups taken whole by the direct path (face_clusters.h)
//   solid_filter     closed surfaces taken as solids (closed_surfaces.h)
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <vector>

#include "visibility/answered_point.h"
#include "visibility/face_clusters.h"
#include "visibility/fp_query/edge_decline.h"
#include "visibility/fp_query/fragment_list.h"
#include "visibility/fp_query/work_budget.h"
#include "visibility/history_tree.h"
#include "visibility/light_edge_index.h"
#include "visibility/region_decisions.h"

namespace penumbra::vis {

// How FromPointQuery decides the side of each vertex (for measuring what exactness costs; the
// product always uses Filtered).
enum class PredicateMode : uint8_t {
    Filtered,     // exact for L's vertices, filtered for constructed ones (polygon_clip.h)
    AlwaysExact,  // every sign through the exact stage, no filter
    Naive,        // the plain double determinant's sign: approximate, can be wrong
};

// The per-point occluders (a partial tree's deferred ones, or the direct path's) are clipped
// by their boundary chain (boundary_chain.h) instead of one by one (Mora-Aveneau Algorithm
// 1, whose cost follows the number of fragments) when there are at least minOccluders of
// them and at most 1 / gain of their edges remain after cancellation. minOccluders 0 =
// never; gain 0 = whatever remains. Both give the same answer (they cut L into different
// fragments).
// Its cells are labelled by crossings (the count of the cell before and the chain edges
// between them) when the chain has at least crossingsMinEdges edges in L's cone; on a
// shorter one each cell's line is tested, which costs less there (the same answer).
// Closed surfaces are tried as solids (runDirect with groups) where the walk left at least
// solidMinFaces candidates, counting a face of a group seen from behind as a quarter (the
// checks cost about as much as activating that many faces; 0 = always).
struct ChainOptions {
    uint32_t minOccluders = 24;
    uint32_t gain = 3;
    uint32_t crossingsMinEdges = 8;
    uint32_t solidMinFaces = 64;
};

// Of a run: the edges of the occluders it clipped against (counted once per face that uses
// them), the edges left after cancellation (the boundary chain), the cells the chain cut L into,
// and those cells whose sample point could not be certified (answered by Algorithm 1). Of the
// cells, those labelled from the previous cell's count and the chain edges between the two
// (crossingLabels) instead of a line tested against the occluders.
struct ChainCounts {
    uint32_t occluderEdges = 0, boundaryEdges = 0, cells = 0, fallbacks = 0;
    uint32_t crossingLabels = 0;
    // Cells decided whole before the chain's edges left in them were cut
    // (ChainCells::decideWhole), hidden or seen.
    uint32_t hiddenWhole = 0, seenWhole = 0;
    // Cells labelled from the ref point of a cell holding them, found inside them on the way
    // down by exact signs: no point of their own, no count (ChainCells::classify).
    uint32_t refLabels = 0;
    // On the light-edge path: the S_L edges the hierarchy found near the cone, less those in
    // subtrees skipped as seen wholly from one side (silhouette_cull.h), each one's weight taken
    // (occluderEdges: with the skipped ones), against boundaryEdges (those of nonzero weight) and
    // the chain's edges in the cone (chainInCone, also on the other paths).
    uint32_t lightEdgesExamined = 0, chainInCone = 0;
};

struct QueryParts;

// A reusable FPQuery. Not thread-safe: one per thread.
class FromPointQuery {
  public:
    using ChainOptions = vis::ChainOptions;
    using ChainCounts = vis::ChainCounts;

    explicit FromPointQuery(PredicateMode mode = PredicateMode::Filtered);
    ~FromPointQuery();
    FromPointQuery(FromPointQuery&&) noexcept;
    FromPointQuery& operator=(FromPointQuery&&) noexcept;

    // The visible fragments of tree.light from x (x should lie on the receiver face; it is not
    // projected): disjoint convex parts of L, counter-clockwise as L. Applies the receiver's front
    // hemisphere and the light's one-sided emission: a point behind the light gets no fragment.
    // When `trace` is given, the visited nodes are appended in depth-first order, each with its
    // depth and the side the polygon went to (the walk's own decisions: nothing is re-walked). The
    // result is valid until the next run. A partial tree (HistoryTree::deferred) gives the same
    // answer: what reaches a visible leaf is clipped against the deferred occluders from x (those
    // whose box can meet the pyramid from x over L), with the same signs as the walk. `region`,
    // when given, must have been reset for this tree and a region holding x: nodes it decides for
    // the whole region are followed without a plane test (region_decisions.h). Contact rule: a
    // segment from x that touches an occluder only at x is not blocked by it. The tree's cells are
    // closed sets of lines, so where x lies exactly on an occluder's contact with B they hold the
    // limit of the neighbouring points instead; such an x (exactly in the plane of an occluder that
    // reaches B's plane: HistoryTree::contactPlanes) is answered from the pair's occluders
    // directly, as runDirect() does (answeredOnContact() says so, and no trace is recorded). So
    // is an x a rounding in front of B's plane next to such an occluder (nearContact): the
    // tree's lines run on to B's plane behind x, and may meet the occluder there.
    // x.at is the point answered; every occluder whose plane holds x.input exactly is taken as
    // touching x (it blocks nothing; answered_point.h), at x.at as at x.input.
    const FragmentList& run(const PolygonMesh& mesh, const HistoryTree& tree,
                            const AnsweredPoint& x, std::vector<TraceStep>* trace = nullptr,
                            RegionDecisions* region = nullptr);
    // A point answered as given (answeredAsGiven).
    const FragmentList& run(const PolygonMesh& mesh, const HistoryTree& tree, const Vec3& x,
                            std::vector<TraceStep>* trace = nullptr,
                            RegionDecisions* region = nullptr) {
        return run(mesh, tree, answeredAsGiven(x), trace, region);
    }
    // The same answer without a tree: the visible fragments of `light` from x on `receiver`, with
    // every face of `faces` (a hierarchy over the mesh's face boxes) that may meet the pyramid from
    // x over the light clipped from x directly (as a partial tree's deferred occluders are). Exact
    // like run(); costs O(log faces + the faces in that pyramid) per point and no precompute: for
    // pairs seen by a few points only (the renderer's choice). Honours the work limit.
    // `clusters`, when given, must have been built over `faces` (face_clusters.h): with the
    // boundary chain on, a group of faces that x certainly sees all one way, whose box lies
    // strictly in front of B's and L's planes, enters the chain as its boundary instead of face by
    // face (the same answer; the cells' lines are tested against its faces through `faces`).
    // With `clusters`, a mesh component that x may take as a solid (closed_surfaces.h: none of
    // its open edges in the pyramid, nothing of it reaching L's plane or through x) has its faces
    // and groups seen from behind left out, or blocks the whole light where x lies inside it (the
    // same answer; solidGroupsLeftOut, hiddenBySolid).
    // `lightEdges`, when given, must have been built for this mesh and `light`
    // (light_edge_index.h; else it is not used): the boundary chain is then built from L's
    // silhouette edges near x's cone and each cell's line tested against the faces through
    // `faces` (fp_query/edge_path.h), without activating the faces in the pyramid; where that
    // path cannot be taken (a face cut by L's plane near the cone) the faces are (the same
    // answer; usedLightEdges()).
    const FragmentList& runDirect(const PolygonMesh& mesh, uint32_t receiver, uint32_t light,
                                  const AnsweredPoint& x, const BoxTree& faces,
                                  const FaceClusters* clusters = nullptr,
                                  const LightEdgeIndex* lightEdges = nullptr);
    const FragmentList& runDirect(const PolygonMesh& mesh, uint32_t receiver, uint32_t light,
                                  const Vec3& x, const BoxTree& faces,
                                  const FaceClusters* clusters = nullptr,
                                  const LightEdgeIndex* lightEdges = nullptr) {
        return runDirect(mesh, receiver, light, answeredAsGiven(x), faces, clusters, lightEdges);
    }
    // The light-edge path alone (fp_query/edge_path.h): the same answer as runDirect, from S_L's
    // edges near x's cone, or null where that path cannot be taken (a face cut by L's plane may
    // meet the cone, x behind B's plane, `lightEdges` not built for this mesh and `light`, or
    // the boundary chain off: ChainOptions::minOccluders 0) or would not pay (more than one in
    // ChainOptions::gain of the S_L edges found near the cone keep a nonzero weight: separate
    // faces, whose edges hardly cancel); then nothing is answered and only the check's work is
    // counted. Honours the work limit like runDirect (limitReached). For
    // the renderer's points that the default path gave up on at the work limit: tried before
    // they are sampled, so that easy points never pay for the index lookups.
    const FragmentList* runLightEdges(const PolygonMesh& mesh, uint32_t receiver, uint32_t light,
                                      const AnsweredPoint& x, const BoxTree& faces,
                                      const LightEdgeIndex& lightEdges);
    uint32_t nodesVisited() const;
    // The last run() answered by the contact rule from the pair's occluders, not by the walk.
    bool answeredOnContact() const;

    // Work budget of one run, in plane tests (a node's test, or a deferred occluder's edge
    // against a fragment): 0 = none. A run that reaches it stops, answers an incomplete fragment
    // list and reports limitReached(); the caller must then answer the point otherwise (the
    // renderer samples it and says so). Counts, not seconds: deterministic (work_budget.h).
    void setWorkLimit(uint64_t planeTests);
    uint64_t workLimit() const;
    uint64_t work() const;
    bool limitReached() const;
    // The stage the last run was in when it reached the work limit (when limitReached()).
    WorkStage limitStage() const;
    // The last run's work by the stage it was spent in (indexed by WorkStage; the sum is work()).
    const std::array<uint64_t, kWorkStages>& stageWork() const;
    // Of a partial tree's deferred occluders, those the last run clipped against (their cone from
    // x may meet L; on the silhouette path only those that cross B's or L's plane, and the others
    // where a cell needed Algorithm 1), and the clips that changed a fragment (split or removed
    // it).
    uint32_t deferredActive() const;
    uint32_t deferredClips() const;

    void setChainOptions(const ChainOptions& o);
    const ChainCounts& chainCounts() const;
    // The last run took a partial tree's silhouettes (deferred_silhouettes.h) for its deferred
    // occluders.
    bool usedSilhouettes() const;
    // The last direct run took the light-edge path (fp_query/edge_path.h).
    bool usedLightEdges() const;
    // Why the last runLightEdges did not take that path (EdgeDecline::None where it did).
    EdgeDecline lightEdgeDecline() const;
    // The face groups the last direct run took whole (face_clusters.h).
    uint32_t clustersUsed() const;
    // Of them, those decided by every face's exact side (exactFacing), not the cone test.
    uint32_t clustersUsedByExactSides() const;
    // Closed surfaces taken as solids by the last direct run (closed_surfaces.h): the face groups
    // and the faces it left out as seen from behind, and whether such a surface blocked every
    // segment from x to L (x inside it, the light outside, or the other way round).
    uint32_t solidGroupsLeftOut() const;
    uint32_t solidFacesLeftOut() const;
    bool hiddenBySolid() const;

  private:
    std::unique_ptr<QueryParts> q_;
};

struct FromPointResult {
    std::vector<Polygon3> fragments;  // disjoint convex parts of L visible from x (CCW as L)
    std::vector<TraceStep> trace;     // the nodes visited, in depth-first order, with their sides
    bool answeredOnContact = false;   // FromPointQuery::answeredOnContact (no trace then)
    uint32_t nodesVisited = 0;
    uint32_t deferredActive = 0, deferredClips = 0;  // FromPointQuery's counters
};

// One-shot FromPointQuery::run with the trace recorded.
FromPointResult fromPointQuery(const PolygonMesh& mesh, const HistoryTree& tree,
                               const AnsweredPoint& x);
inline FromPointResult fromPointQuery(const PolygonMesh& mesh, const HistoryTree& tree,
                                      const Vec3& x) {
    return fromPointQuery(mesh, tree, answeredAsGiven(x));
}

}  // namespace penumbra::vis
