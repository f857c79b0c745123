// The light-edge path of the direct query (FromPointQuery::runDirect with a LightEdgeIndex): the
// boundary chain built from S_L's edges that may meet x's cone over L (light_edge_index.h), each
// weighted by the sides x sees its faces from, instead of from every face in x's pyramid
// activated one by one; a cell's line is tested against the faces through the face hierarchy,
// unclipped. Its work follows the S_L edges near the cone and the faces near the cells' lines,
// not the faces in the cone.
//
// What it computes, exactly. Let G be the faces other than B and L that are Front of L's plane
// (light_edge_index.h) and whose plane does not hold x (the contact rule, QueryRun::occluderSide),
// each weighted s_f = +1 or -1 by the side x lies on. For a ray from x, c'(ray) is the number of
// faces of G it meets (closed, t > 0: LineTests::faceHitKind is a ray test). c' changes only
// across the rays through an edge e whose weight w(e) = sum over its uses by G of s_f (+1 for a
// use lo -> hi, -1 for hi -> lo) is not zero (boundary_chain.h), by w(e): so the chain is these
// edges, input segments whole, with no chord. Every such edge that meets the closed cone over L
// is in S_L (the proof is in edge_path.cpp), so the finder loses none. c' is the query's c on the
// rays that matter: a ray from x (on or in front of B's plane) to a point of L strictly in front of
// B meets a face of G only strictly in front of B and, G's faces lying on L's closed front side,
// not beyond L: where the face's part clipped to the region between B and L (clipped_occluder.h,
// the direct path's occluders) is the face itself; faces Behind L meet no such ray. So each cell,
// labelled by c' at one certified line, gets the same label as the face-by-face path gives it.
//
// Not taken (the face-by-face path answers; the same answer) where an Across face (cut by L's
// plane: its chord on L's plane bounds shadows and is no input edge) may meet the cone, or where
// x lies strictly behind B's plane. A cell whose point cannot be certified activates the faces
// in the pyramid and is clipped by Algorithm 1, as on the other paths.
//
// Approximate, never deciding: the boxes of the hierarchies (conservative culls); the order the
// chain is cut in.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include "visibility/box_tree.h"
#include "visibility/face_plane.h"
#include "visibility/fp_query/edge_decline.h"
#include "visibility/fp_query/line_tests.h"
#include "visibility/light_edge_index.h"

namespace penumbra::vis {

struct QueryParts;

class EdgePath {
  public:
    // A chain edge: S_L's edge (lo < hi) and its weight w(e) (from lo to hi).
    struct Remaining {
        uint32_t lo = 0, hi = 0;
        int weight = 0;
    };

    explicit EdgePath(QueryParts& q) : q_(q) {}

    void reset() {
        index_ = nullptr;
        faces_ = nullptr;
        restActivated_ = false;
        examined_ = 0;
        nearCone_ = 0;
        recentHits_.fill(UINT32_MAX);
        recentNext_ = 0;
        decline_ = EdgeDecline::None;
    }
    // Takes the path for this run (after QueryRun::preparePyramid): `index` built for this
    // pair's light and mesh, no Across face near the cone, x on or in front of B's plane. Finds
    // the S_L edges that may meet the cone and keeps those of nonzero weight (remaining()).
    // False: not taken (the face-by-face path answers; the check's work is counted).
    bool prepare(const BoxTree& faces, const LightEdgeIndex& index);
    bool active() const { return index_ != nullptr; }
    // Why the last run did not take it (None: taken, or not tried).
    EdgeDecline decline() const { return decline_; }
    void declined(EdgeDecline why) { decline_ = why; }
    // The edges of nonzero weight among those found (in the order the hierarchy found them).
    const std::vector<Remaining>& remaining() const { return remaining_; }
    // The S_L edges the hierarchy found near the cone, each one's weight taken.
    uint32_t examined() const { return examined_; }
    // Those and the edges of the subtrees skipped whole as holding no silhouette from x (their
    // node's box not outside the cone): the edges near the cone, as a face-by-face path would
    // meet them.
    uint32_t nearCone() const { return nearCone_; }
    // A cell that needs Algorithm 1: the faces that may meet its hull activated (those not yet
    // activated this run), or every face in the pyramid once per run (activateRest) where no
    // plane through x and an edge of the cell holds it.
    void activateNear(std::span<const Vec3> poly);
    void activateRest();
    // The line tests of this path: the faces of G on the ray from x through y.
    bool lineBlocked(const Vec3& y);
    std::optional<int> countLine(const Vec3& y);

  private:
    // s_f for a face of G, 0 for any other face; taken once per run.
    int faceSide(uint32_t face);
    // x's side of `plane`, the plane of `face` (Front), under the contact rule: s_f, or 0 for B
    // and L (and once the work limit is reached: the run then gives up); one plane test.
    int sideOf(uint32_t face, const FacePlane& plane);
    // The same for the Front face numbered `local` in the index (LightEdgeIndex::localFace), from
    // the index's copy of its corners (the weights' loop: nearby edges' faces in nearby memory).
    int localSide(uint32_t local);
    // Activates those of `faces` (other than B and L) not activated yet this run.
    void activate(std::span<const uint32_t> faces);
    // rayPlanes_: the culling planes of the ray from x through y (a certified cell point).
    void setRayPlanes(const Vec3& y);

    QueryParts& q_;
    const LightEdgeIndex* index_ = nullptr;
    const BoxTree* faces_ = nullptr;
    bool restActivated_ = false;
    uint32_t examined_ = 0, nearCone_ = 0;
    std::vector<uint32_t> found_;
    std::vector<uint32_t> receiverEdges_;  // B's edges in S_L (their index ids)
    std::vector<Remaining> remaining_;
    std::vector<PlaneOrient> rayPlanes_;
    // Per face: the run whose s_f it holds (above two bits) and s_f + 1 (faceSide).
    std::vector<uint32_t> faceMemo_;
    // Per local face of the index: the same as faceMemo_ (localSide).
    std::vector<uint32_t> localMemo_;
    // Per face: the run that activated it (activate).
    std::vector<uint32_t> activeMemo_;
    std::vector<PlaneOrient> nearPlanes_;
    std::vector<uint32_t> nearFaces_;
    static constexpr uint32_t kStampEnd = 1u << 30;
    uint32_t runStamp_ = 0;
    // The last faces that hid a cell (a hidden cell's neighbour is mostly hidden by the same
    // few): tried before the hierarchy.
    static constexpr uint32_t kRecentHits = 8;
    std::array<uint32_t, kRecentHits> recentHits_{};
    uint32_t recentNext_ = 0;
    EdgeDecline decline_ = EdgeDecline::None;
};

}  // namespace penumbra::vis
