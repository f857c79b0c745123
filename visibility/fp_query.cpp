#include "visibility/fp_query.h"

#include <deque>

#include "visibility/pair_occluders.h"
#include "visibility/polygon_clip.h"

namespace penumbra::vis {
namespace {

struct Walker {
    const PolygonMesh& mesh;
    const HistoryTree& tree;
    const Vec3& x;
    FromPointResult& out;
    // Two polygon buffers per depth, reused along the walk (no allocation per node).
    // A deque: growing it keeps the references held by shallower levels valid.
    std::deque<std::pair<std::vector<Vec3>, std::vector<Vec3>>> buffers;

    void visit(uint32_t node, const std::vector<Vec3>& poly, size_t depth) {
        if (node == kVisibleLeaf) {
            out.fragments.push_back(poly);
            return;
        }
        if (node == kHiddenLeaf) return;
        out.path.push_back(node);
        ++out.nodesVisited;
        const HistoryNode& n = tree.nodes[node];
        // The 5D test "which side of edge (v0,v1) does line(x, y) pass" is the 3D test
        // orient3d(x, y, v0, v1) = side of y against the plane through x, v0, v1: exact per
        // vertex. When x, v0, v1 are collinear the plane is undefined and every line through x
        // meets the edge's line: all signs are zero and the whole polygon follows child[0]
        // (a measure-zero set of points x; documented rule).
        // orient3d(x, v0, v1, y) == orient3d(x, y, v0, v1) (a cyclic, hence even, permutation).
        const OrientedPlane plane{x, tree.vertex(mesh, n.v0), tree.vertex(mesh, n.v1)};
        if (buffers.size() <= depth) buffers.resize(depth + 1);
        auto& [pos, neg] = buffers[depth];
        clipConvexInto(poly, plane, pos, neg);
        if (pos.empty() && neg.empty()) {
            visit(n.child[0], poly, depth + 1);
            return;
        }
        if (!pos.empty()) visit(n.child[0], pos, depth + 1);
        if (!neg.empty()) visit(n.child[1], neg, depth + 1);
    }
};

}  // namespace

FromPointResult fromPointQuery(const PolygonMesh& mesh, const HistoryTree& tree, const Vec3& x) {
    FromPointResult out;
    if (tree.kind == PairKind::BackFacing || tree.kind == PairKind::FullyHidden) return out;
    // The light emits only to its front: x must be strictly in front of L's plane.
    if (facePlane(mesh, tree.light).side(x) != Sign::Positive) return out;
    std::vector<Vec3> light;
    for (uint32_t v : mesh.faces[tree.light]) light.push_back(mesh.vertices[v]);
    // The receiver sees only its front hemisphere (B's plane, exact on input points).
    const FacePlane pb = facePlane(mesh, tree.receiver);
    light = clipConvexPositive(light, OrientedPlane{pb.a, pb.b, pb.c});
    if (light.size() < 3) return out;
    if (tree.kind == PairKind::FullyVisible) {
        out.fragments.push_back(std::move(light));
        return out;
    }
    Walker{mesh, tree, x, out, {}}.visit(0, light, 0);
    return out;
}

}  // namespace penumbra::vis
