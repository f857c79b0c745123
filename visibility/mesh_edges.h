// MeshEdges: the undirected edges of a polygon mesh, each with the faces that use it and the
// direction of each use. Edges are identified by vertex ids (lo < hi), no arithmetic: exact.
// Built once per mesh in O(uses log uses) (the directed uses bucketed by their lower vertex, each
// bucket sorted), the buckets shared among `loops` (the same table whoever builds it).
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "visibility/parallel_loops.h"
#include "visibility/polygon_mesh.h"

namespace penumbra::vis {

class MeshEdges {
  public:
    // One use of an edge by a face: `forward` when the face's boundary runs lo -> hi.
    struct Use {
        uint32_t face = 0;
        bool forward = false;
    };
    struct Edge {
        uint32_t lo = 0, hi = 0;
    };

    MeshEdges() = default;
    explicit MeshEdges(const PolygonMesh& mesh, const ParallelLoops& loops = {});

    size_t size() const { return edges_.size(); }
    const Edge& edge(size_t e) const { return edges_[e]; }
    // The uses of edge e, in increasing face order.
    std::span<const Use> uses(size_t e) const {
        return {uses_.data() + begin_[e], uses_.data() + begin_[e + 1]};
    }
    // A manifold edge between consistently oriented faces: exactly two uses, one each way.
    bool manifold(size_t e) const {
        const auto u = uses(e);
        return u.size() == 2 && u[0].forward != u[1].forward;
    }

  private:
    std::vector<Edge> edges_;    // in (lo, hi) order
    std::vector<Use> uses_;      // grouped by edge
    std::vector<size_t> begin_;  // edge e's uses: uses_[begin_[e], begin_[e + 1])
};

}  // namespace penumbra::vis
