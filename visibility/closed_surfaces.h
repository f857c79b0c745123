// ClosedSurfaces: a mesh's faces split into components (faces joined by shared edges, identified
// by their vertex ids), and the edges where a component is open: those whose directed uses do
// not sum to zero (borders of holes, edges of open sheets, non-manifold edges used an unequal
// number of times each way, edges between faces oriented inconsistently). A component with no
// open edge is a closed, consistently oriented surface (self-intersecting or with non-manifold
// edges allowed: only the uses' sum matters), the boundary of a solid.
//
// Why the from-point query wants this (FromPointQuery::runDirect): for such a surface S and a
// segment from x to a light point p that touches none of its edges, the faces it crosses from
// their front (x in front of their plane) minus those it crosses from their back is the winding
// number of S's projection from x, the same for every p of the light when nothing of S's
// boundary lies in the cone from x over the light. So where that number is 0, a segment that
// crosses a face of S crosses one seen from the front, and the faces x sees from behind can be
// left out of the query; where it is not, every segment is blocked. A component is used so for
// one point only where its open edges (this class's BoxTree over them) lie outside the cone.
//
// Exact: components and open edges are decided on vertex ids, no arithmetic. Built in O(edges).
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "visibility/box_tree.h"
#include "visibility/polygon_mesh.h"

namespace penumbra::vis {

class ClosedSurfaces {
  public:
    ClosedSurfaces() = default;
    explicit ClosedSurfaces(const PolygonMesh& mesh);

    uint32_t componentCount() const { return componentCount_; }
    uint32_t componentOf(uint32_t face) const { return faceComponent_[face]; }
    // An open edge: its vertices (lo < hi) and its component.
    struct OpenEdge {
        uint32_t lo = 0, hi = 0, component = 0;
    };
    std::span<const OpenEdge> openEdges() const { return openEdges_; }
    // Over the open edges' boxes (item i = openEdges()[i]).
    const BoxTree& openEdgeTree() const { return openEdgeTree_; }
    // Of the components, those with no open edge (closed everywhere), and their faces.
    uint32_t closedCount() const { return closedCount_; }
    size_t closedFaces() const { return closedFaces_; }
    size_t bytes() const {
        return faceComponent_.size() * sizeof(uint32_t) + openEdges_.size() * sizeof(OpenEdge) +
               openEdges_.size() * (2 * sizeof(Bounds3) + sizeof(uint32_t));
    }

  private:
    uint32_t componentCount_ = 0, closedCount_ = 0;
    size_t closedFaces_ = 0;
    std::vector<uint32_t> faceComponent_;
    std::vector<OpenEdge> openEdges_;
    BoxTree openEdgeTree_;
};

}  // namespace penumbra::vis
