// LightEdgeIndex: what the per-point edge finder (fp_query/edge_path.h) needs of one area light L,
// built once per light: S_L's edges (light_silhouette_edges.h) with their faces, a box hierarchy
// over those edges, each face's side of L's plane, and a box hierarchy over the faces that L's
// plane cuts.
//
// Exact: S_L and the faces' sides are exact orient3d signs of input points; the hierarchies'
// boxes are unions of input coordinates (no rounding) and are only ever used to cull
// conservatively (BoxTree: a box is skipped only when certainly outside a plane).
//
// Why each part:
//   - Per node of the edge hierarchy, bounds on its edges' Front faces' planes
//     (silhouette_cull.h): a point skips the subtrees it certainly sees from one side, where no
//     edge is a silhouette (most of those near a hard point's cone). A triangle stored again
//     (the same three vertex ids, either way round) counts there as its first copy, its uses
//     turned where it is turned (twinUses): a two-sided sheet stored as two opposite faces
//     (the motorbike's 67,326) is then one-sided to the cull, as it is to the weights.
//   - S_L holds every edge that can bound a shadow of L (light_silhouette_edges.h), so a point
//     needs only those of its edges that may meet its cone over L: the edge hierarchy finds them
//     in O(log |S_L| + found), whatever the number of faces in that cone.
//   - A face with no vertex strictly in front of L's plane (Behind) is cut away whole by the
//     query's clip to L's front (clipped_occluder.h): it blocks nothing and its edges' uses are
//     left out of every weight. A face with vertices strictly on both sides (Across) is cut by
//     L's plane: its clipped part has a chord on that plane, which no input edge describes, so a
//     point whose cone over L may meet such a face takes the face-by-face path (edge_path.h).
//   - Every other face (Front: no vertex strictly behind, one strictly in front) is kept whole
//     by that clip.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include "visibility/box_tree.h"
#include "visibility/mesh_edges.h"
#include "visibility/parallel_loops.h"
#include "visibility/polygon_mesh.h"
#include "visibility/silhouette_cull.h"

namespace penumbra::vis {

class LightEdgeIndex {
  public:
    // A face's vertices against L's plane (exact signs): none strictly behind and one strictly
    // in front (Front), none strictly in front (Behind, also a face of fewer than 3 vertices),
    // or some strictly on each side (Across).
    enum class Side : uint8_t { Front, Behind, Across };

    LightEdgeIndex() = default;
    // `edges` must be mesh's edge table (MeshEdges(mesh)); the index copies what it keeps.
    // Its parts are built concurrently where `loops` are given (the same index either way).
    LightEdgeIndex(const PolygonMesh& mesh, const MeshEdges& edges, uint32_t lightFace,
                   const ParallelLoops& loops = {});

    uint32_t light() const { return light_; }
    // The mesh it was built for: its face and vertex counts (a query checks them).
    size_t faceCount() const { return sides_.size(); }
    size_t vertexCount() const { return vertexCount_; }
    // S_L's edges (mesh vertex ids, lo < hi), each with its uses (face and direction), numbered
    // in the order of edgeBoxes()'s leaves.
    size_t size() const { return edges_.size(); }
    const MeshEdges::Edge& edge(uint32_t i) const { return edges_[i]; }
    std::span<const MeshEdges::Use> uses(uint32_t i) const {
        return {uses_.data() + begin_[i], uses_.data() + begin_[i + 1]};
    }
    // S_L's share of the mesh's edges, and how many of them are open (border, non-manifold,
    // inconsistently oriented).
    double share() const { return share_; }
    size_t open() const { return open_; }
    // A hierarchy over S_L's edges' boxes (items: indices in edge()).
    const BoxTree& edgeBoxes() const { return edgeBoxes_; }
    // Per node of edgeBoxes(): whether a point certainly sees no edge below as a silhouette
    // (silhouette_cull.h; the counting uses are those by Front faces).
    const SilhouetteCull& silhouettes() const { return silhouettes_; }
    // The index in edge() of the S_L edge between mesh vertices lo < hi, if it is in S_L.
    std::optional<uint32_t> find(uint32_t lo, uint32_t hi) const;
    Side side(uint32_t face) const { return sides_[face]; }
    // The Front faces that S_L's edges use, numbered in the order the edges (in leaf order) first
    // use them, each with its first three vertices (those its plane is taken from, face_plane.h)
    // as indices into a copy of those vertices numbered the same way: a point's weights read the
    // faces of nearby edges from nearby memory, not from the mesh's face and vertex lists,
    // scattered over the whole model. The copies are the input coordinates: the planes taken
    // from them are the same.
    static constexpr uint32_t kNotFront = SilhouetteCull::kNotCounted;
    // Per use of edge i (as uses(i)), its face's local number, or kNotFront where the face is not
    // Front.
    std::span<const uint32_t> useLocalFaces(uint32_t i) const {
        return {useLocal_.data() + begin_[i], useLocal_.data() + begin_[i + 1]};
    }
    size_t localFaceCount() const { return localFaces_.size(); }
    // The face numbered `local`, and its first three vertices as indices into localVertices().
    uint32_t localFace(uint32_t local) const { return localFaces_[local]; }
    const std::array<uint32_t, 3>& localCorners(uint32_t local) const {
        return localCorners_[local];
    }
    std::span<const Vec3> localVertices() const { return localVertices_; }
    // A hierarchy over the Across faces' boxes (items: indices for acrossFace()); empty when
    // there are none.
    const BoxTree& acrossFaces() const { return acrossFaces_; }
    uint32_t acrossFace(uint32_t item) const { return acrossIds_[item]; }
    size_t acrossCount() const { return acrossCount_; }
    // The memory it holds, in bytes (the edges, their uses, the faces' sides, both hierarchies).
    size_t bytes() const {
        return edges_.capacity() * sizeof(MeshEdges::Edge) +
               uses_.capacity() * sizeof(MeshEdges::Use) + begin_.capacity() * sizeof(uint32_t) +
               sides_.capacity() * sizeof(Side) + edgeBoxes_.bytes() +
               acrossFaces_.bytes() + acrossIds_.capacity() * sizeof(uint32_t) +
               silhouettes_.bytes() + sortedKeys_.capacity() * sizeof(uint64_t) +
               sortedIds_.capacity() * sizeof(uint32_t) + useLocal_.capacity() * sizeof(uint32_t) +
               localFaces_.capacity() * sizeof(uint32_t) +
               localCorners_.capacity() * sizeof(std::array<uint32_t, 3>) +
               localVertices_.capacity() * sizeof(Vec3);
    }

  private:
    // The uses as the silhouette cull counts them: a Front triangle stored more than once (the
    // same three vertex ids) counts as its first copy, each use turned where its copy runs the
    // other way round.
    void twinUses(const PolygonMesh& mesh, std::vector<MeshEdges::Use>& uses,
                  std::vector<uint32_t>& local) const;

    uint32_t light_ = 0;
    size_t vertexCount_ = 0;
    std::vector<MeshEdges::Edge> edges_;
    std::vector<MeshEdges::Use> uses_;
    std::vector<uint32_t> begin_;
    double share_ = 0;
    size_t open_ = 0, acrossCount_ = 0;
    BoxTree edgeBoxes_;
    SilhouetteCull silhouettes_;
    // S_L's edges by (lo << 32 | hi), increasing, with their indices in edge() (find).
    std::vector<uint64_t> sortedKeys_;
    std::vector<uint32_t> sortedIds_;
    std::vector<Side> sides_;
    std::vector<uint32_t> useLocal_;                     // per use: its face in localFaces_
    std::vector<uint32_t> localFaces_;                   // per local face: its face
    std::vector<std::array<uint32_t, 3>> localCorners_;  // per local face: in localVertices_
    std::vector<Vec3> localVertices_;
    std::vector<uint32_t> acrossIds_;  // per item of acrossFaces_: its face
    BoxTree acrossFaces_;
};

}  // namespace penumbra::vis
