// FPQuery (Mora & Aveneau 2005, Algorithm 2): the exactly visible fragments of the light L from a
// point x on the receiver B, by walking B's history tree with the 3D plane through x and each
// stored edge and clipping L.
#pragma once

#include <cstdint>
#include <vector>

#include "visibility/history_tree.h"

namespace penumbra::vis {

using Polygon3 = std::vector<Vec3>;

struct FromPointResult {
    std::vector<Polygon3> fragments;  // disjoint convex parts of L visible from x (CCW as L)
    std::vector<uint32_t> path;       // node ids visited, in depth-first order
    uint32_t nodesVisited = 0;
};

// x should lie on the receiver face (it is not projected). Applies the receiver's front hemisphere
// and the light's one-sided emission: a point behind the light gets no fragment.
FromPointResult fromPointQuery(const PolygonMesh& mesh, const HistoryTree& tree, const Vec3& x);

}  // namespace penumbra::vis
