// RegionDecisions: the nodes of a history tree that send every line from a small region of the
// receiver to the light the same way, so that the from-point queries of many points in that
// region (a tile of pixels, the 16 samples of a pixel) skip their plane tests there.
//
// R is given by points spanning it (the corners of a box holding the query points) and L is the
// light polygon. The side of line(r, l) against an edge line is affine in r and affine in l
// (orient3d(r, l, v0, v1) for an input edge, edge_line.h for a chord), so over every
// line from a point of conv(R) to a point of L its sign lies between the signs at the |R| x |L|
// corner-vertex pairs. At node n with edge (v0, v1):
//   Positive  no pair strictly negative: for every x in R, every point of L (so every fragment
//             FPQuery carries) is on the closed positive side of the plane (x, v0, v1): the query
//             follows child[0] with the whole fragment, as it does for a fragment on the plane.
//   Negative  no pair strictly positive, some strictly negative: child[1] with the whole
//             fragment. (A point query at x would send a fragment lying entirely in the plane to
//             child[0]; such a fragment has zero area, so no area moves.)
//   Split     otherwise: the query tests the plane through x as usual.
// Every sign is an exact predicate of the doubles given (filtered, exact fallback), so a decision
// is exact for every x inside the box; the decision is also right for the exact fragment where the
// point query's rounded fragment vertices (constructions) lie a hair outside L.
//
// Decisions are computed on demand, for the nodes the queries reach, and kept until reset();
// reset() costs O(1) (generation stamps), so a renderer thread keeps one per light and resets it
// per group of points. Not thread-safe: one per thread.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "visibility/edge_line.h"
#include "visibility/history_tree.h"

namespace penumbra::vis {

class RegionDecisions {
  public:
    enum class Decision : uint8_t { Positive, Negative, Split };

    // Starts over for `tree` (of `mesh`) and the region spanned by `corners` (at most 8 points; the
    // query points must lie in their convex hull).
    void reset(const PolygonMesh& mesh, const HistoryTree& tree, std::span<const Vec3> corners);
    const HistoryTree* tree() const { return tree_; }

    // The decision at an inner node of the tree (computed on first use).
    Decision at(uint32_t node) {
        if (stamp_[node] == generation_) return decision_[node];
        return compute(node);
    }

    // Nodes decided so far since reset() (each cost |R| x |L| signs), and how many were Split.
    uint32_t decided() const { return decided_; }
    uint32_t splits() const { return splits_; }

  private:
    Decision compute(uint32_t node);

    const PolygonMesh* mesh_ = nullptr;
    const HistoryTree* tree_ = nullptr;
    std::vector<Vec3> corners_, light_;
    PlaneOrient clip_[2];                  // B's and L's planes
    std::vector<BoundedValue> clipAt_[2];  // ... at each corner
    std::vector<uint32_t> stamp_;          // per node: generation_ when decision_ is current
    std::vector<Decision> decision_;
    uint32_t generation_ = 0;
    uint32_t decided_ = 0, splits_ = 0;
};

}  // namespace penumbra::vis
