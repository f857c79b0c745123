#include "visibility/fp_query.h"

#include "visibility/pair_occluders.h"
#include "visibility/polygon_clip.h"

namespace penumbra::vis {

void FromPointQuery::visit(uint32_t node, std::span<const Vec3> poly, size_t depth) {
    if (node == kVisibleLeaf) {
        fragments_.add(poly);
        return;
    }
    if (node == kHiddenLeaf) return;
    if (path_ != nullptr) path_->push_back(node);
    ++nodesVisited_;
    const HistoryNode& n = tree_->nodes[node];
    // The 5D test "which side of edge (v0,v1) does line(x, y) pass" is the 3D test
    // orient3d(x, y, v0, v1) = side of y against the plane through x, v0, v1: exact for the
    // vertices of L, filtered for constructed fragment vertices (an uncertain one counts as on
    // the plane: polygon_clip.h clipConstructedInto). When x, v0, v1 are collinear
    // the plane is undefined and every line through x meets the edge's line: all signs are zero
    // and the whole polygon follows child[0] (a measure-zero set of points x; documented rule).
    // orient3d(x, v0, v1, y) == orient3d(x, y, v0, v1) (a cyclic, hence even, permutation).
    const OrientedPlane plane{x_, tree_->vertex(*mesh_, n.v0), tree_->vertex(*mesh_, n.v1)};
    if (buffers_.size() <= depth) buffers_.resize(depth + 1);
    auto& [pos, neg] = buffers_[depth];
    switch (mode_) {
        case PredicateMode::Filtered: clipConstructedInto(poly, plane, light_, pos, neg); break;
        case PredicateMode::AlwaysExact: clipExactInto(poly, plane, pos, neg); break;
        case PredicateMode::Naive: clipNaiveInto(poly, plane, pos, neg); break;
    }
    if (pos.empty() && neg.empty()) {
        visit(n.child[0], poly, depth + 1);
        return;
    }
    if (!pos.empty()) visit(n.child[0], pos, depth + 1);
    if (!neg.empty()) visit(n.child[1], neg, depth + 1);
}

const FragmentList& FromPointQuery::run(const PolygonMesh& mesh, const HistoryTree& tree,
                                        const Vec3& x, std::vector<uint32_t>* path) {
    fragments_.clear();
    nodesVisited_ = 0;
    // TooComplex: no tree, no answer here (the caller samples; fp_query.h).
    if (tree.kind == PairKind::BackFacing || tree.kind == PairKind::FullyHidden ||
        tree.kind == PairKind::TooComplex)
        return fragments_;
    // The light emits only to its front: x must be strictly in front of L's plane.
    if (facePlane(mesh, tree.light).side(x) != Sign::Positive) return fragments_;
    light_.clear();
    for (uint32_t v : mesh.faces[tree.light]) light_.push_back(mesh.vertices[v]);
    // The receiver sees only its front hemisphere (B's plane, exact on input points).
    const FacePlane pb = facePlane(mesh, tree.receiver);
    clipConvexInto(light_, OrientedPlane{pb.a, pb.b, pb.c}, lightClipped_, discard_);
    if (lightClipped_.size() < 3) return fragments_;
    if (tree.kind == PairKind::FullyVisible) {
        fragments_.add(lightClipped_);
        return fragments_;
    }
    mesh_ = &mesh;
    tree_ = &tree;
    x_ = x;
    path_ = path;
    visit(0, lightClipped_, 0);
    path_ = nullptr;
    return fragments_;
}

FromPointResult fromPointQuery(const PolygonMesh& mesh, const HistoryTree& tree, const Vec3& x) {
    FromPointQuery query;
    FromPointResult out;
    const FragmentList& fragments = query.run(mesh, tree, x, &out.path);
    out.fragments.reserve(fragments.size());
    for (size_t i = 0; i < fragments.size(); ++i)
        out.fragments.emplace_back(fragments[i].begin(), fragments[i].end());
    out.nodesVisited = query.nodesVisited();
    return out;
}

}  // namespace penumbra::vis
