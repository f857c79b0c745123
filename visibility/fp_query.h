// FPQuery (Mora & Aveneau 2005, Algorithm 2): the exactly visible fragments of the light L from a
// point x on the receiver B, by walking B's history tree with the 3D plane through x and each
// stored edge and clipping L.
//
// Two interfaces: FromPointQuery is a reusable workspace for hot loops (a renderer thread keeps
// one; after warm-up a query allocates nothing); fromPointQuery() is the one-shot convenience.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <utility>
#include <vector>

#include "visibility/answered_point.h"
#include "visibility/boundary_chain.h"
#include "visibility/clipped_occluder.h"
#include "visibility/edge_line.h"
#include "visibility/face_clusters.h"
#include "visibility/history_tree.h"
#include "visibility/polygon_clip.h"
#include "visibility/region_decisions.h"
#include "visibility/work_stage.h"

namespace penumbra::vis {

using Polygon3 = std::vector<Vec3>;

// Convex polygons stored back to back.
class FragmentList {
  public:
    size_t size() const { return begin_.size() - 1; }
    bool empty() const { return size() == 0; }
    std::span<const Vec3> operator[](size_t i) const {
        return {vertices_.data() + begin_[i], begin_[i + 1] - begin_[i]};
    }
    void clear() {
        vertices_.clear();
        begin_.assign(1, 0);
    }
    void add(std::span<const Vec3> polygon) {
        vertices_.insert(vertices_.end(), polygon.begin(), polygon.end());
        begin_.push_back(static_cast<uint32_t>(vertices_.size()));
    }
    // The polygons, each copied into its own vector (what outlives the query's next run).
    std::vector<Polygon3> polygons() const {
        std::vector<Polygon3> out;
        out.reserve(size());
        for (size_t i = 0; i < size(); ++i) out.emplace_back((*this)[i].begin(), (*this)[i].end());
        return out;
    }

  private:
    std::vector<Vec3> vertices_;
    std::vector<uint32_t> begin_{0};
};

// Where a visited node sent the light polygon: the positive side of the plane through x and the
// node's edge (child[0]), the negative side (child[1]), both (the plane split it in two), or none
// strictly (every vertex in the plane: x on the edge's line; it follows child[0] whole, a
// measure-zero set of points, documented rule).
enum class NodeSide : uint8_t { Positive, Negative, Both, OnPlane };
const char* toString(NodeSide side);

// One visited node of a walk (FromPointQuery::run's trace): the node, its depth in the tree (0 at
// the root) and where the polygon went. A node decided for a whole region (RegionDecisions)
// records the side it decided.
struct TraceStep {
    uint32_t node = 0;
    uint32_t depth = 0;
    NodeSide side = NodeSide::Positive;
};

// How FromPointQuery decides the side of each vertex (for measuring what exactness costs; the
// product always uses Filtered).
enum class PredicateMode : uint8_t {
    Filtered,     // exact for L's vertices, filtered for constructed ones (polygon_clip.h)
    AlwaysExact,  // every sign through the exact stage, no filter
    Naive,        // the plain double determinant's sign: approximate, can be wrong
};

// A reusable FPQuery. Not thread-safe: one per thread.
class FromPointQuery {
  public:
    explicit FromPointQuery(PredicateMode mode = PredicateMode::Filtered) : mode_(mode) {}

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
    const FragmentList& runDirect(const PolygonMesh& mesh, uint32_t receiver, uint32_t light,
                                  const AnsweredPoint& x, const BoxTree& faces,
                                  const FaceClusters* clusters = nullptr);
    const FragmentList& runDirect(const PolygonMesh& mesh, uint32_t receiver, uint32_t light,
                                  const Vec3& x, const BoxTree& faces,
                                  const FaceClusters* clusters = nullptr) {
        return runDirect(mesh, receiver, light, answeredAsGiven(x), faces, clusters);
    }
    uint32_t nodesVisited() const { return nodesVisited_; }
    // The last run() answered by the contact rule from the pair's occluders, not by the walk.
    bool answeredOnContact() const { return contactAnswer_; }

    // Work budget of one run, in plane tests (a node's test, or a deferred occluder's edge
    // against a fragment): 0 = none. A run that reaches it stops, answers an incomplete fragment
    // list and reports limitReached(); the caller must then answer the point otherwise (the
    // renderer samples it and says so). Counts, not seconds: deterministic.
    void setWorkLimit(uint64_t planeTests) { workLimit_ = planeTests; }
    uint64_t work() const { return work_; }
    bool limitReached() const { return limitReached_; }
    // The stage the last run was in when it reached the work limit (when limitReached()).
    WorkStage limitStage() const { return limitStage_; }
    // The last run's work by the stage it was spent in (indexed by WorkStage; the sum is work()).
    const std::array<uint64_t, kWorkStages>& stageWork() const { return stageWork_; }
    // Of a partial tree's deferred occluders, those the last run clipped against (their cone from
    // x may meet L; on the silhouette path only those that cross B's or L's plane, and the others
    // where a cell needed Algorithm 1), and the clips that changed a fragment (split or removed
    // it).
    uint32_t deferredActive() const { return static_cast<uint32_t>(active_.size()); }
    uint32_t deferredClips() const { return deferredClips_; }

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
    void setChainOptions(const ChainOptions& o) { chainOptions_ = o; }
    // Of the last run: the edges of the occluders it clipped against (counted once per face that
    // uses them), the edges left after cancellation (the boundary chain), the cells the chain cut
    // L into, and those cells whose sample point could not be certified (answered by Algorithm 1).
    // Of the cells, those labelled from the previous cell's count and the chain edges between
    // the two (crossingLabels) instead of a line tested against the occluders.
    struct ChainCounts {
        uint32_t occluderEdges = 0, boundaryEdges = 0, cells = 0, fallbacks = 0;
        uint32_t crossingLabels = 0;
        // Cells decided whole before the chain's edges left in them were cut
        // (decideCellWhole), hidden or seen.
        uint32_t hiddenWhole = 0, seenWhole = 0;
    };
    const ChainCounts& chainCounts() const { return chainCounts_; }
    // The last run took a partial tree's silhouettes (deferred_silhouettes.h) for its deferred
    // occluders.
    bool usedSilhouettes() const { return surface_ != nullptr; }
    // The face groups the last direct run took whole (face_clusters.h).
    uint32_t clustersUsed() const { return static_cast<uint32_t>(usedClusters_.size()); }
    // Of them, those decided by every face's exact side (exactFacing), not the cone test.
    uint32_t clustersUsedByExactSides() const { return clustersByExactSides_; }
    // Closed surfaces taken as solids by the last direct run (closed_surfaces.h): the face groups
    // and the faces it left out as seen from behind, and whether such a surface blocked every
    // segment from x to L (x inside it, the light outside, or the other way round).
    uint32_t solidGroupsLeftOut() const { return solidGroupsLeft_; }
    uint32_t solidFacesLeftOut() const { return solidFacesLeft_; }
    bool hiddenBySolid() const { return solidHidden_; }

  private:
    void preparePair(const PolygonMesh& mesh, uint32_t receiver, uint32_t light);
    // preparePair, then whether x sees any of the light at all (in front of L's plane, and some
    // of L in front of B's).
    bool startPair(const PolygonMesh& mesh, uint32_t receiver, uint32_t light, const Vec3& x);
    void preparePyramid();  // pyramid_: the planes through x_ and the edges of lightClipped_
    // Adds mesh face `face`, clipped exactly to the region in front of B's and L's planes
    // (clipped_occluder.h), to active_ unless it certainly blocks nothing from x_ (outside the
    // pyramid, or x_ on its plane: the contact rule).
    void activateFace(const PolygonMesh& mesh, uint32_t face);
    // The answer from the faces in candidates_ alone (no tree): each activated, then L clipped.
    void clipCandidates(const PolygonMesh& mesh);
    // Whether x lies exactly in one of tree.contactPlanes.
    bool onContact(const HistoryTree& tree, const Vec3& x) const;
    // The side of x_ against an occluder's plane under the contact rule: Zero where the run's
    // input point lies exactly in it (a moved point touches what its input touches:
    // answered_point.h), else x_'s exact side. Every strategy decides "x on the occluder's plane"
    // through it.
    Sign occluderSide(const PlaneOrient& plane) const {
        if (moved_ && plane.sign(input_) == Sign::Zero) return Sign::Zero;
        return plane.sign(x_);
    }
    // Whether x may lie strictly in front of B's plane with an inserted occluder that may meet
    // the sliver between x and B's plane that the lines from x to L cross behind x
    // (conservative: a box test against a rigorous bound of that sliver;
    // HistoryTree::contactBoxes). B's plane and L's vertices come from preparePair, their
    // values at L's vertices from contactLightLow_.
    bool nearContact(const PolygonMesh& mesh, const HistoryTree& tree, const Vec3& x);
    // Its tests for a point x with b(x) at most bx.value + bx.error (B's orient3d value): false
    // only where no inserted occluder can meet the sliver; monotone in that bound.
    bool mayMeetSliver(const HistoryTree& tree, const Vec3& x, const BoundedValue& bx);
    // Per vertex of light_, a lower bound of B's plane's orient3d value there (nearContact's;
    // valid until preparePair prepares another pair).
    std::vector<double> contactLightLow_;
    bool contactLightLowValid_ = false;
    // B's (0) or L's (1) plane evaluated at x_, once per run (the pencil planes of chords).
    const BoundedValue& clipPlaneAt(int which);
    // A node's split with the predicates of mode_ (input edges) or the filtered ones (chords).
    template <class Plane>
    SplitOutcome splitBy(std::span<const Vec3> poly, const Plane& plane, SplitParts& parts,
                         KeepParts keep) const;
    // `depth` indexes the split scratch (parts_), `treeDepth` is the node's depth (for the trace).
    void visit(uint32_t node, std::span<const Vec3> poly, size_t depth, uint32_t treeDepth);
    // Records the side the current node sent the polygon to (the trace's entry `index`).
    void traceSide(size_t index, NodeSide side) {
        if (trace_ != nullptr) (*trace_)[index].side = side;
    }
    // What reaches a visible leaf: kept, or with the deferred occluders clipped against it (by the
    // boundary chain when there are many, else clipByOccluders).
    void reachVisible(std::span<const Vec3> poly, size_t depth);
    // Algorithm 1 in 3D from x: `poly` clipped against active_[from] on (those that may meet it).
    void clipByOccluders(std::span<const Vec3> poly, size_t from, size_t depth);
    // The same against `count` occluders: clipList_[listBase..] when `culled`, else
    // active_[from..].
    void clipListed(std::span<const Vec3> poly, size_t listBase, size_t count, bool culled,
                    size_t from, size_t depth);
    // Appends to clipList_ the indices from `from` on of the active occluders whose box is not
    // certainly outside the pyramid from x over `poly`'s hull, in increasing order; false when
    // the work limit stopped it.
    bool cullFor(std::span<const Vec3> poly, size_t from);
    // Puts active_ in the order Algorithm 1 clips it: largest solid angle from x first.
    void orderActive();
    // Below kCullMin occluders a polygon is clipped against each in turn; from it on, against
    // those its pyramid's box query returns. A piece split off inherits the rest of its
    // polygon's list, queried again for it only when that is kRecullMin long or more (each query
    // costs a hierarchy walk; 64 measured fastest on the table scene, 16 to 128 tried).
    static constexpr size_t kCullMin = 16, kRecullMin = 64;
    // The boundary-chain evaluation: `poly` cut by the chain's edges (those in chainLists_[level])
    // into cells no chain edge crosses, each kept or dropped whole by one certified line. A chain
    // of kLongestFirstMin edges or more cuts along its longest edges first (buildChain).
    static constexpr size_t kLongestFirstMin = 32;
    bool useChain();
    void buildChain();
    void chainCells(std::span<const Vec3> poly, size_t depth, size_t level);
    void classifyCell(std::span<const Vec3> poly, size_t depth);
    // A cell of the chain's cutting, before it is cut further: labelled by its point y as a leaf
    // is, and decided whole where the edges left to cut it cannot change the answer (c(y) above
    // what crossing them all could take away: hidden; c(y) = 0 and none can add: seen). True:
    // decided (or the work limit reached), nothing more to cut.
    bool decideCellWhole(std::span<const Vec3> poly, size_t level);
    // Where chainCells tries that: a list of kWholeMax edges or fewer, half or less of the one
    // the last try on its path had (a try costs about as much as one more cut of the cell).
    static constexpr size_t kWholeMax = 64;
    std::vector<size_t> wholeTriedAt_;  // per level: the list size of the last try on its path
    // A cell's point y, the rounded centroid of `poly` (a cell the chain cut), and whether it is
    // certified strictly inside the cone and every bound of the cell (exact signs), so that c(y)
    // is the cell's value; with crossings_, the sides of y taken on the way are kept in sideY_
    // (a new yStamp_). False also when the work limit is reached (limitReached_).
    bool certifiedPoint(std::span<const Vec3> poly, Vec3& y);
    // Advances yStamp_ (every cached side of the previous y becomes stale).
    void nextYStamp();
    // y, counted c(y) = count, becomes the point later cells are counted from (countByCrossings);
    // `level`: the chain level whose list (from its first edge) holds every edge that may lie
    // between y and the next cell point, or kNoLevel when the next split sets it.
    void takeRef(const Vec3& y, int count, size_t level);
    // The plane through x and the active occluder edge `ref` (an index in activePlanes_, or with
    // kPencilRef in activePencils_): its exact sign at an input point, and a split by it.
    Sign refSign(uint32_t ref, const Vec3& y) const;
    SplitOutcome splitByRef(uint32_t ref, std::span<const Vec3> poly, SplitParts& parts) const;
    static constexpr uint32_t kPencilRef = 0x80000000u;
    void prepareDeferred(const PolygonMesh& mesh, const HistoryTree& tree);
    // The silhouette path of a partial tree (deferred_silhouettes.h), when its silhouettes pay
    // and x lies in their region: only the deferred faces that cross B's or L's plane are
    // activated, the chain is built from the pair's kept edges in the cone, and a cell's line is
    // tested against the deferred faces through the tree's hierarchy. False: not taken.
    bool prepareSurface(const HistoryTree& tree);
    // How a line from x meets an occluder: not, through its interior, or touching its boundary
    // (a closed hit with a zero sign).
    enum class LineHit { Miss, Through, Touch };
    // The line from x through y crosses Surface slot `slot`'s face (closed; exact signs at y),
    // as lineHits() for an activated face.
    bool surfaceHits(uint32_t slot, const Vec3& y) {
        return surfaceHitKind(slot, y) != LineHit::Miss;
    }
    // The side Surface slot `slot`'s face faces x: +1 (x in front of its plane), -1, 0 (x on
    // it); decided for Q, else the exact sign, taken once per run.
    int sideAt(uint32_t slot);
    // Whether the line through y crosses one of the occluders (a cell's label).
    bool lineBlocked(const Vec3& y);
    // c(y), the number of occluders the line from x through y crosses (boundary_chain.h), for a
    // certified cell point y: from the last counted cell's by the chain edges whose segments
    // cross the triangle (x, that cell's point, y) (countByCrossings), else counted on the line
    // (countLine). Empty where a sign is zero (the triangle or the line touches an edge): the
    // caller then tests the line (lineBlocked).
    std::optional<int> countByCrossings(const Vec3& y);
    std::optional<int> countLine(const Vec3& y);
    LineHit surfaceHitKind(uint32_t slot, const Vec3& y);
    // Surface path: activates the deferred Surface faces in the pyramid too (a cell that needs
    // Algorithm 1), once per run.
    void activateSurface();
    // cone() for this run (lightWhole_, lightCone_).
    void prepareCone();
    // Resets the per-run state (the answer, counters, active occluders, path and region).
    void startRun();
    // candidates_: the items of `index` whose box may meet pyramid_, in increasing order, each
    // node visited counted as work; false when the work limit stopped the search.
    bool findCandidates(const BoxTree& index);
    // The same with the face groups (runDirect): a node of `faces` whose group x certainly sees
    // one way, lying strictly in front of B's and L's planes, goes to usedClusters_ whole
    // (stamped, with the nodes above it, for the line walks); the faces of the other nodes go to
    // candidates_.
    struct ClusterWalk;
    bool findClustered(const BoxTree& faces, const FaceClusters& clusters);
    bool walkClusters(uint32_t node, const ClusterWalk& walk);
    // A group whose cone test is not certain (near x, the test's usual answer) and that holds
    // kExactFacingMax faces or fewer: +1 or -1 when x lies strictly on that side of every one of
    // `faces` (exact signs), else 0. Such a group enters the chain by its boundary, as a group
    // the cone test decides, instead of activating its faces one by one.
    static constexpr size_t kExactFacingMax = 64;
    int exactFacing(std::span<const uint32_t> faces);
    uint32_t clustersByExactSides_ = 0;
    // Closed surfaces as solids (runDirect with groups). For a component S of the mesh whose
    // open edges lie outside the pyramid, the count of S's faces a segment from x to L crosses
    // seen from the front, minus those seen from behind, is the winding number of S's faces'
    // boundaries seen from x, the same for every segment in the open cone when nothing else of
    // that sum lies in it (closed_surfaces.h): the chords where B's or L's plane cuts S's faces
    // and the edges of B and L themselves, left out as occluders. With x on or in front of B's
    // plane, what lies in B's plane is seen outside the open cone; what lies in L's plane is
    // not, so a component with a face reaching L's plane in the pyramid is no solid for x, nor
    // L's own; with x behind B's plane by a rounding, neither is B's (or one with a face that
    // B's plane cuts) unless each of B's edges (that face) is shown to miss the open cone
    // (missesCone); nor is one with a face through x (x on its surface: the winding changes
    // across that face's plane, unless it is B's plane with x on it). Each
    // remaining component's winding is counted once along the segment from x to a vertex of L
    // (exact signs; a segment through an edge of S makes S no solid): 0 and a segment that
    // crosses S's faces crosses one seen from the front, so those seen from behind are left
    // out; not 0 and every segment is blocked. Decided once per run (prepareSolids), after the
    // walk, where enough is to be left out (worthSolids).
    enum class SolidState : uint8_t { Unknown, Ready, Off };
    SolidState solidState_ = SolidState::Unknown;
    bool solidHidden_ = false;
    uint32_t solidGroupsLeft_ = 0, solidFacesLeft_ = 0;
    bool worthSolids() const;
    // False: no component is a solid for x (or the work limit was reached).
    bool prepareSolids();
    // Whether x may take `component` (FaceClusters::kNone: none) as a solid (prepareSolids).
    bool solidComponent(uint32_t component) const {
        return solidState_ == SolidState::Ready && component != FaceClusters::kNone &&
               componentStamp_[component] != solidRun_;
    }
    // The used groups x sees from behind, of components taken as solids, left out (unstamped).
    void leaveOutSolidBacks();
    // Whether the segment from x to v crosses `face`'s interior: +1 seen from the front, -1 from
    // behind, 0 not; nullopt where a sign is zero on its boundary (the segment touches an edge).
    std::optional<int> segmentCrossing(uint32_t face, const Vec3& v);
    // The side of the plane through x, a and b that every vertex of L lies strictly on, or Zero
    // when they do not (exact signs).
    Sign lightSideOf(const Vec3& a, const Vec3& b) const;
    // Whether the convex face on vertex ids `ids` certainly misses the open cone from x over L:
    // strictly outside one of the pyramid's planes, or on the closed side of a plane through x
    // and one of its edges that L lies strictly off (exact signs).
    bool missesCone(const std::vector<uint32_t>& ids);
    std::vector<uint32_t> componentStamp_;  // per component: solidRun_ when it is no solid
    std::vector<int32_t> componentWinding_;
    std::vector<uint32_t> windingStamp_;  // per component: solidRun_ when its winding is set
    std::vector<uint32_t> windingComponents_;
    std::vector<uint32_t> solidFound_;
    uint32_t solidRun_ = 0;
    bool clustersActive() const { return !usedClusters_.empty() && !clustersDissolved_; }
    // The line from x through y against mesh face `face`, unclipped (closed; exact signs at y),
    // x strictly in front of its plane (side +1) or behind it (-1): a surface slot's face, or a
    // used group's.
    LineHit faceHitKind(uint32_t face, int side, const Vec3& y);
    // Each face of the used groups whose box is not certainly off the line through y
    // (linePlanes_, set by the caller) passed to visit(face, side) until it returns true (then
    // true; also when the work limit stops the walk).
    template <class Visit>
    bool clusterFacesOnLine(Visit&& visit);
    bool clusterLineBlocked(const Vec3& y);
    // A cell that needs Algorithm 1: every face of the used groups activated, once per run.
    void dissolveClusters();
    SplitParts& partsAt(size_t depth) {
        if (parts_.size() <= depth) parts_.resize(depth + 1);
        return parts_[depth];
    }

    PredicateMode mode_;
    const PolygonMesh* mesh_ = nullptr;
    const HistoryTree* tree_ = nullptr;
    Vec3 x_;
    // The run's input point (AnsweredPoint::input) and whether x_ was moved off it: the contact
    // rule is decided there (occluderSide).
    Vec3 input_;
    bool moved_ = false;
    std::vector<TraceStep>* trace_ = nullptr;
    RegionDecisions* region_ = nullptr;
    uint32_t nodesVisited_ = 0;
    uint64_t workLimit_ = 0, work_ = 0;
    bool limitReached_ = false;
    WorkStage stage_ = WorkStage::Walk, limitStage_ = WorkStage::Walk;  // (set on entering one)
    std::array<uint64_t, kWorkStages> stageWork_{};
    // What is left of the work limit (0 = no limit: unbounded).
    uint64_t workBudgetLeft() const {
        return workLimit_ == 0 ? 0 : (work_ < workLimit_ ? workLimit_ - work_ : 1);
    }
    // Counts `tests` plane tests (or hierarchy nodes visited); false once the work limit is
    // reached (the run then unwinds).
    bool spend(uint64_t tests = 1) {
        work_ += tests;
        stageWork_[static_cast<size_t>(stage_)] += tests;
        if (workLimit_ != 0 && work_ > workLimit_) {
            if (!limitReached_) limitStage_ = stage_;
            limitReached_ = true;
        }
        return !limitReached_;
    }
    FragmentList fragments_;
    // The pair's part that does not depend on x (preparePair): L's vertices, its plane, L clipped
    // to B's front half-space, and what identifies them.
    const PolygonMesh* preparedMesh_ = nullptr;
    uint32_t preparedReceiver_ = 0, preparedLight_ = 0;
    Vec3 receiverPlane_[3];
    PlaneOrient lightPlane_;
    OrientedPlane frontB_{{}, {}, {}}, frontL_{{}, {}, {}};  // B's and L's planes (preparePair)
    std::vector<Vec3> light_, lightClipped_, discard_;
    // The split parts per recursion depth, reused along the walk and across runs.
    std::vector<SplitParts> parts_;
    // clipByOccluders' free parts of the occluder being clipped, per active call (a stack).
    std::vector<std::span<const Vec3>> freeParts_;
    // Per run of a partial tree: the deferred occluders that may block a line from x to L, each
    // with the planes through x and its edges and the side of them its blocked lines are on.
    struct ActiveOccluder {
        uint32_t firstPlane = 0, planeCount = 0;    // of its input edges, in activePlanes_
        uint32_t firstPencil = 0, pencilCount = 0;  // of its chords, in activePencils_
        Sign blocked = Sign::Zero;
        uint32_t face = 0;
    };
    std::vector<ActiveOccluder> active_;
    std::vector<PlaneOrient> activePlanes_;
    std::vector<PencilPlane> activePencils_;
    std::vector<uint8_t> activePencilOnB_;  // per pencil: its chord lies on B's plane (else L's)
    // The input edge (mesh vertex ids) of each of activePlanes_.
    std::vector<std::pair<uint32_t, uint32_t>> activePlaneEdges_;
    // The boundary chain of a run (built at its first use): per edge, its plane (a ref) and, for
    // an input edge, the whole input segment (which contains the clipped one).
    struct ChainEdge {
        uint32_t ref = 0;
        bool segment = false;
        // An input edge with an end point strictly behind B's plane (exact): its face is cut by
        // B's plane and c(y) changes only across its part in front (countByCrossings).
        bool behindB = false;
        Vec3 a, b;
        // How c(y) changes when y passes from the positive to the negative side of the ref's
        // plane across the segment (the edge's weight, boundary_chain.h; 0 for a chord, whose
        // jump is not known: a path may cross its plane only where that is shown not to matter).
        int jump = 0;
    };
    std::vector<ChainEdge> chain_;
    BoundaryChain chainBuilder_;
    // The surface path of this run (prepareSurface), or null: the tree's silhouettes, the
    // number of activated faces that cross B's or L's plane (the first of active_), whether the
    // Surface faces were activated too, and the kept groups in the cone.
    const DeferredSilhouettes* surface_ = nullptr;
    size_t surfaceClipped_ = 0;
    bool surfaceActivated_ = false;
    std::vector<uint32_t> surfaceGroups_, lineSlots_, surfaceRemaining_;
    std::vector<uint32_t> slotStamp_;  // per slot: the run whose sign slotSide_ holds
    std::vector<int8_t> slotSide_;
    uint32_t runStamp_ = 0;
    // The last Surface slots that hid a cell (a hidden cell's neighbour is mostly hidden by the
    // same few faces): tried before the hierarchy.
    static constexpr uint32_t kRecentHits = 8;
    std::array<uint32_t, kRecentHits> recentHits_{};
    uint32_t recentNext_ = 0;
    static constexpr uint32_t kSurfaceRef = 0x40000000u;
    std::vector<uint32_t> chainRefs_;
    std::vector<int> chainWeights_;  // per chain ref, its weight from the lower vertex id
    std::vector<int> surfaceSums_;   // per surfaceRemaining_, its weight
    // Cell labels by crossings (classifyCell): allowed for the run (no occluder cut by L's plane:
    // then c(y) changes only across the occluders' input edges and their chords on B's plane), the
    // last counted cell's point and count, and the shallowest chain level (with the index of
    // the edge that split it) passed since then: the path between the two points lies in that
    // level's cell, which only its list's edges from that index on may cross.
    bool lightChord_ = false;
    bool crossings_ = false;
    bool chainChords_ = false;  // a chord in the chain (cut first)
    // x on or in front of B's plane and some chord on B's plane left out of the chain: a cell is
    // labelled only from a point strictly in front of B's plane (buildChain).
    bool chordsOnBLeftOut_ = false;
    bool haveRef_ = false;
    Vec3 refY_;
    int refCount_ = 0;
    static constexpr size_t kNoLevel = SIZE_MAX;
    size_t crossLevel_ = kNoLevel, crossIndex_ = 0;
    // Per chain edge, the side of its plane the ref point lies on and the one the cell point
    // being counted lies on, each valid where its stamp is refStamp_ (yStamp_): a cell's sides
    // become the ref's when it is counted.
    std::vector<int8_t> sideRef_, sideY_;
    std::vector<uint32_t> stampRef_, stampY_;
    uint32_t refStamp_ = 0, yStamp_ = 0;
    // Per recursion level, the chain edges that may cross the cell.
    std::vector<std::vector<uint32_t>> chainLists_;
    std::vector<std::vector<uint8_t>> chainSides_;  // per level, chainCells' scratch
    // The cell's bounding planes so far (a chain edge's plane with the side the cell is on, and
    // the edge's index in chain_).
    struct CellBound {
        uint32_t ref;
        Sign side;
        uint32_t edge;
    };
    std::vector<CellBound> bounds_;
    ChainOptions chainOptions_;
    bool chainBuilt_ = false;
    // Per run: active_ was put in Algorithm 1's order (orderActive); the side of the plane
    // through x, L[0] and L[1] that L[2] is on (the turn of every polygon that is part of L,
    // seen from x; cullFor).
    bool activeOrdered_ = false;
    Sign lightTurn_ = Sign::Zero;
    // Sort keys with indices: orderActive's, and buildChain's longest-first order.
    std::vector<std::pair<double, uint32_t>> orderKeys_;
    std::vector<ActiveOccluder> orderScratch_;
    std::vector<PlaneOrient> hullCone_;
    std::vector<uint32_t> cullOut_;
    // clipByOccluders' candidate lists, one above the other per active call (a stack).
    std::vector<uint32_t> clipList_;
    bool chainPays_ = false;  // enough occluder edges cancel (buildChain)
    // L lies wholly in front of B, lightClipped_ is L itself (buildChain: only the chain asks).
    bool lightWhole_ = false;
    // The planes through x and L's input edges: pyramid_ itself when lightWhole_, else
    // lightCone_ (buildChain).
    std::vector<PlaneOrient> lightCone_;
    const std::vector<PlaneOrient>& cone() const { return lightWhole_ ? pyramid_ : lightCone_; }
    uint32_t lastHit_ = 0;  // the occluder that hid the last hidden cell (tried first)
    // The direct path's face groups (runDirect), per run: the groups taken whole (the node of
    // `faces`, the group, the side x sees it from), whether they were activated face by face
    // since (a cell that needed Algorithm 1), and per node of `faces` the run that stamped it
    // (a used group or a node above one) with the group's side (0 above one). Per used group's
    // boundary edge in the chain builder (kClusterRef), its vertices.
    const FaceClusters* clusters_ = nullptr;
    const BoxTree* clusterTree_ = nullptr;
    struct UsedCluster {
        uint32_t node = 0, cluster = 0;
        int side = 0;
    };
    std::vector<UsedCluster> usedClusters_;
    bool clustersDissolved_ = false;
    std::vector<uint32_t> nodeStamp_;
    std::vector<int8_t> nodeSide_;
    uint32_t nodeRun_ = 0;
    std::vector<std::pair<uint32_t, uint32_t>> clusterEdges_;
    static constexpr uint32_t kClusterRef = 0x20000000u;
    // The last group faces that hid a cell (face, side): tried before the walk.
    std::array<std::pair<uint32_t, int>, kRecentHits> recentClusterHits_{};
    uint32_t recentClusterNext_ = 0;
    // The cells' lines against the occluders: all of them in turn, until a run has tested
    // kScanBeforeBoxes times their number; then through a hierarchy of their faces' boxes, built
    // for the run, which returns every occluder whose box is not certainly off the line.
    static constexpr uint64_t kScanBeforeBoxes = 4;
    uint64_t scanned_ = 0;
    bool activeBoxesBuilt_ = false;
    BoxTree activeBoxes_;
    std::vector<Bounds3> activeBoxList_;
    std::vector<PlaneOrient> linePlanes_;
    std::vector<uint32_t> onLine_;
    // Whether the line through y crosses active occluder j (closed; exact signs at y).
    bool lineHits(size_t j, const Vec3& y) { return lineHitKind(j, y) != LineHit::Miss; }
    LineHit lineHitKind(size_t j, const Vec3& y);
    // The hierarchy of active_'s boxes (built once per run; lineBlocked builds it lazily).
    void buildActiveBoxes();
    // linePlanes_: four planes holding the line through x_ and y, at right angles.
    void setLinePlanes(const Vec3& y);
    ChainCounts chainCounts_;
    std::vector<PlaneOrient> pyramid_;  // the planes through x and L's edges, interior positive
    ClippedOccluder clipped_;           // activateFace's scratch
    std::vector<uint32_t> candidates_;
    uint32_t deferredClips_ = 0;
    bool deferredPrepared_ = true;  // active_ is ready for this run
    bool contactAnswer_ = false;
    BoundedValue clipValue_[2];
    bool clipValueKnown_[2] = {false, false};
};

struct FromPointResult {
    std::vector<Polygon3> fragments;  // disjoint convex parts of L visible from x (CCW as L)
    std::vector<TraceStep> trace;     // the nodes visited, in depth-first order, with their sides
    bool answeredOnContact = false;   // FromPointQuery::answeredOnContact (no trace then)
    uint32_t nodesVisited = 0;
    uint32_t deferredActive = 0, deferredClips = 0;  // FromPointQuery's counters
};

// The node ids of a trace, in its order (e.g. the path to highlight in a tree browser).
std::vector<uint32_t> traceNodes(std::span<const TraceStep> trace);

// One-shot FromPointQuery::run with the trace recorded.
FromPointResult fromPointQuery(const PolygonMesh& mesh, const HistoryTree& tree,
                               const AnsweredPoint& x);
inline FromPointResult fromPointQuery(const PolygonMesh& mesh, const HistoryTree& tree,
                                      const Vec3& x) {
    return fromPointQuery(mesh, tree, answeredAsGiven(x));
}

}  // namespace penumbra::vis
