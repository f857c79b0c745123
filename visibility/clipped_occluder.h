// ClippedOccluder: a face clipped to the region in front of B's and L's planes, exactly and
// without constructing a point.
//
// Why that region: a segment from a point of B to a point of L lies in front of both planes, so
// a stabbing line meets an occluder between B and L iff it meets the occluder's part there
// (pair_occluders.h). The clipped part is a convex polygon whose edges lie on input edges of the
// face (a shortened edge keeps its line) or on the chords where the face's plane meets B's or L's
// plane (EdgeLine::Planes). Its vertices are never formed: each is kept symbolically (an input
// vertex, the crossing of an input edge with a plane, or the corner where the two chords meet),
// and every side test on one is an exact function of the input it was built from:
//   a crossing c of the input edge p -> q with plane X satisfies, for any plane h,
//   sign h(c) = sign(piX(p) h(q) - piX(q) h(p)) * sign piX(p)        (edge_line.h pencilValue)
// because c = (piX(p) q - piX(q) p) / (piX(p) - piX(q)) and h is affine. A corner's side is not
// decided (side() says so): callers treat it as "may be on either side".
//
// The edges are listed in the face's order (counter-clockwise seen from its front) in the history
// tree's encoding (history_tree.h: input edges by mesh vertex ids, chords by face and plane). A
// chord meeting B's plane is directed n_B x n_face, which is the face's counter-clockwise order
// along the clipped boundary (the part kept lies on B's positive side). Every listed edge's closed
// inner side contains the clipped polygon and together they cut it out exactly; an edge of zero
// length (a vertex exactly on a plane) may be listed, which changes no answer.
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <utility>
#include <vector>

#include "visibility/edge_line.h"
#include "visibility/polygon_mesh.h"
#include "visibility/predicates.h"

namespace penumbra::vis {

class ClippedOccluder {
  public:
    struct Vertex {
        enum class Kind : uint8_t { Input, Crossing, Corner };
        Kind kind = Kind::Input;
        uint8_t plane = 0;   // Crossing: 0 = B's plane, 1 = L's plane
        uint32_t index = 0;  // Input: the face's vertex i; Crossing: its edge i -> i + 1
    };
    using Edge = std::pair<uint32_t, uint32_t>;  // HistoryNode (v0, v1) encoding

    // Clips face `face` of `mesh` by the planes of B and L (PlaneOrient of their first three
    // vertices). Reuses its storage: hot loops keep one.
    void clip(const PolygonMesh& mesh, uint32_t face, const PlaneOrient& receiverPlane,
              const PlaneOrient& lightPlane);

    bool empty() const { return empty_; }      // zero area (exact)
    bool clipped() const { return clipped_; }  // some vertex was behind B's or L's plane
    std::span<const Edge> edges() const { return edges_; }
    std::span<const Vertex> vertices() const { return vertices_; }
    std::span<const Vec3> facePoints() const { return points_; }

    // The exact side of a vertex against plane h; nullopt for a corner.
    std::optional<Sign> side(const Vertex& v, const PlaneOrient& h) const;
    // True only if no point of the clipped polygon is strictly on h's positive side (certain: an
    // input vertex's sign is exact; a crossing whose sign the filter cannot certify, and a
    // corner, count as possibly positive).
    bool outside(const PlaneOrient& h) const;
    // The sign of the side of line(p, v) (fromP) or line(v, p) against e, for a vertex v of the
    // clipped polygon: exact for an input vertex; for a crossing c of q0 -> q1 with plane X,
    // from side(c) = (piX(q0) side(q1) - piX(q1) side(q0)) / (piX(q0) - piX(q1)) (the side is
    // affine in c) with the filter of differenceOfProducts; nullopt where that filter cannot
    // certify it, and for a corner. For culling, where "unknown" only costs work.
    std::optional<Sign> lineSide(const Vertex& v, const Vec3& p, bool fromP,
                                 const EdgeLine& e) const;

  private:
    struct Entry {
        Vertex vertex;
        Edge edge;                       // the edge leaving this vertex
        uint32_t faceEdge = UINT32_MAX;  // that edge's index in the face (none for a chord)
    };
    Sign crossingSide(uint32_t edge, const PlaneOrient& x, Sign fromSide,
                      const PlaneOrient& h) const;
    void clipBy(uint8_t which);

    const PolygonMesh* mesh_ = nullptr;
    uint32_t face_ = 0;
    PlaneOrient planes_[2];  // B's and L's
    std::vector<Vec3> points_;
    std::vector<Sign> signs_[2];  // per face vertex, against B's and L's planes
    std::vector<Entry> poly_, next_;
    std::vector<Sign> polySigns_;
    std::vector<Vertex> vertices_;
    std::vector<Edge> edges_;
    bool empty_ = true, clipped_ = false;
};

}  // namespace penumbra::vis
