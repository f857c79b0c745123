// LightSilhouetteEdges: S_L, the edges of a mesh that can bound a shadow of one area light L.
//
// Why only these: a shadow boundary seen from a receiver point x is a line from x to a point y of
// L that grazes an occluder edge e where e is a silhouette seen from x (one of its faces faces x,
// the other faces away). Every plane through e passes through the point where the segment x-y
// meets e, so x and y lie on opposite sides of both of e's face planes (or on them): e is a
// silhouette seen from y too. So an edge that is not a silhouette from any point of L bounds no
// shadow of L on any receiver; the set S_L of the others is the same for every receiver.
//
// Decided exactly, conservatively, on input coordinates only:
//   - an edge used by exactly two faces, once in each direction (a manifold edge between
//     consistently oriented faces), is left out of S_L only when every vertex of L lies strictly
//     in front of both face planes, or strictly behind both (exact orient3d signs: FacePlane).
//     The plane's value is affine and L convex, so then every point of L does: the edge is a
//     silhouette from none. Any zero sign keeps it (a line grazing a face plane);
//   - every other edge is kept: borders (one use), non-manifold edges (three or more uses) and
//     edges between inconsistently oriented faces (two uses in the same direction) can bound a
//     shadow whatever L is.
// The light's own face and faces coplanar with L have zero signs: their edges are kept.
// Edges are identified by vertex ids, as ClosedSurfaces does (a soup whose faces share no vertex
// ids has only borders: every edge kept, correct and useless). Cost: |L| orient3d per face,
// O(edges) after the edge table (MeshEdges); the faces and the edges shared among `loops` (the
// same set whoever decides which edge).
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "visibility/mesh_edges.h"
#include "visibility/parallel_loops.h"
#include "visibility/polygon_mesh.h"

namespace penumbra::vis {

class LightSilhouetteEdges {
  public:
    LightSilhouetteEdges(const PolygonMesh& mesh, const MeshEdges& edges, uint32_t lightFace,
                         const ParallelLoops& loops = {});

    uint32_t light() const { return light_; }
    // Whether edge `e` (an index in MeshEdges) is in S_L.
    bool contains(size_t e) const { return kept_[e] != 0; }
    // How many edges S_L holds, and of them those kept whatever L is (open: borders,
    // non-manifold, inconsistently oriented).
    size_t size() const { return size_; }
    size_t open() const { return open_; }
    // S_L's share of the mesh's edges (0 for a mesh without edges).
    double share() const { return kept_.empty() ? 0.0 : double(size_) / double(kept_.size()); }

  private:
    uint32_t light_;
    std::vector<uint8_t> kept_;  // (bytes: written concurrently)
    size_t size_ = 0, open_ = 0;
};

}  // namespace penumbra::vis
