// FaceClusters: groups of mesh faces that a point may see all from the front or all from the
// back, each with the edges that do not cancel between its own faces. The from-point query's
// direct path (FromPointQuery::runDirect) puts a group that a point certainly sees one way into
// its boundary chain (boundary_chain.h) as that boundary, weighted by the side, instead of
// activating each of its faces: on a closed or smooth mesh the pyramid from x holds thousands
// of faces, while the chain only needs the edges where the side changes (silhouettes).
//
// The groups are the nodes of the mesh's face hierarchy (BoxTree over the face boxes) with
// kMinFaces to kMaxFaces faces. Per group, built once per mesh:
// - a cone holding its faces' exact normals N_f = (v1 - v0) x (v2 - v0): a unit axis u and a
//   lower bound on cos(angle(N_f, u)) for every face, from the rounded cross product and its
//   error bound (PlaneOrient's n and perm), so also for faces whose rounded normal is off;
// - its boundary: the sum of its faces' directed edge uses (mesh vertex ids), each face with
//   weight +1; edges whose uses sum to zero are left out (boundary_chain.h).
// A group is kept only if its cone is narrower than a half space and at most half of its edge
// uses remain (separate faces, such as leaves, share no edges: then nothing is gained).
//
// facing(cluster, x): +1 when x lies strictly in front of every face's plane, -1 strictly behind
// every one, 0 when that is not certain. Sound: for any point p of the group's box and
// w = x - p, u.w > sin(theta) |w| (theta the cone's half angle) puts w within 90 deg - theta of
// u, so within 90 deg of every N_f: N_f.(x - v0_f) > 0, since v0_f lies in the box. The test is
// made in doubles with a margin of 1e-12 of the magnitudes involved, far above their rounding
// error (some 1e-15): a filter without an exact stage, whose "not certain" the caller answers
// face by face, exactly.
//
// With the groups, the mesh's closed surfaces (closed_surfaces.h) and per group the component
// all its faces belong to: where a point may take a closed component as a solid, a group of it
// that the point sees from behind is left out whole.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "visibility/bounds3.h"
#include "visibility/box_tree.h"
#include "visibility/closed_surfaces.h"
#include "visibility/polygon_mesh.h"

namespace penumbra::vis {

class FaceClusters {
  public:
    static constexpr uint32_t kNone = UINT32_MAX;
    static constexpr uint32_t kMinFaces = 16, kMaxFaces = 4096;

    FaceClusters() = default;
    // The groups of `faces`, a hierarchy over mesh's face boxes (item i = face i).
    FaceClusters(const PolygonMesh& mesh, const BoxTree& faces);

    // The group at hierarchy node `node`, or kNone.
    uint32_t clusterAt(uint32_t node) const {
        return node < clusterOfNode_.size() ? clusterOfNode_[node] : kNone;
    }
    int facing(uint32_t cluster, const Vec3& x) const;
    // An edge of a group's boundary: from vertex lo to hi (lo < hi), and the sum of its faces'
    // uses in that direction (nonzero).
    struct Use {
        uint32_t lo = 0, hi = 0;
        int32_t weight = 0;
    };
    std::span<const Use> boundary(uint32_t cluster) const {
        const Cluster& c = clusters_[cluster];
        return {uses_.data() + c.firstUse, c.useCount};
    }
    size_t size() const { return clusters_.size(); }
    // The component (closed_surfaces.h) of every face of the group, or kNone when they lie in
    // several.
    uint32_t componentOf(uint32_t cluster) const { return clusters_[cluster].component; }
    const ClosedSurfaces& surfaces() const { return surfaces_; }
    // Whether mesh face `face` lies in some group (a point may take it whole with its group).
    bool grouped(uint32_t face) const { return face < groupedFace_.size() && groupedFace_[face]; }
    size_t bytes() const {
        return clusterOfNode_.size() * sizeof(uint32_t) + clusters_.size() * sizeof(Cluster) +
               uses_.size() * sizeof(Use) + groupedFace_.size() + surfaces_.bytes();
    }

  private:
    struct Cluster {
        Bounds3 box;
        Vec3 axis;
        double sinBound = 1;  // an upper bound on sin of the cone's half angle
        uint32_t firstUse = 0, useCount = 0;
        uint32_t component = kNone;
    };
    ClosedSurfaces surfaces_;
    std::vector<uint32_t> clusterOfNode_;
    std::vector<Cluster> clusters_;
    std::vector<Use> uses_;
    std::vector<uint8_t> groupedFace_;
};

}  // namespace penumbra::vis
