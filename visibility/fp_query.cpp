#include "visibility/fp_query.h"

#include <stdexcept>

#include "visibility/pair_occluders.h"
#include "visibility/polygon_clip.h"

namespace penumbra::vis {

void FromPointQuery::visit(uint32_t node, std::span<const Vec3> poly, size_t depth) {
    // Down the tree while the plane leaves the polygon on one side (the common case: the same span
    // goes on, nothing is copied); recursion only where it is split in two.
    for (;;) {
        if (node == kVisibleLeaf) {
            fragments_.add(poly);
            return;
        }
        if (node == kHiddenLeaf) return;
        if (path_ != nullptr) path_->push_back(node);
        ++nodesVisited_;
        const HistoryNode& n = tree_->nodes[node];
        if (region_ != nullptr) {
            const RegionDecisions::Decision d = region_->at(node);
            if (d == RegionDecisions::Decision::Positive) {
                node = n.child[0];
                continue;
            }
            if (d == RegionDecisions::Decision::Negative) {
                node = n.child[1];
                continue;
            }
        }
        // The 5D test "which side of edge (v0,v1) does line(x, y) pass" is the 3D test
        // orient3d(x, y, v0, v1) = side of y against the plane through x, v0, v1: exact for the
        // vertices of L, filtered for constructed fragment vertices (an uncertain one counts as on
        // the plane: polygon_clip.h splitConstructed). When x, v0, v1 are collinear the plane is
        // undefined and every line through x meets the edge's line: all signs are zero and the
        // whole polygon follows child[0] (a measure-zero set of points x; documented rule).
        // orient3d(x, v0, v1, y) == orient3d(x, y, v0, v1) (a cyclic, hence even, permutation).
        const uint32_t c0 = n.child[0], c1 = n.child[1];
        if (c0 == kHiddenLeaf && c1 == kHiddenLeaf) return;  // (only without leaf merging)
        // A part bound for a hidden leaf is not written.
        const KeepParts keep = c0 == kHiddenLeaf   ? KeepParts::Negative
                               : c1 == kHiddenLeaf ? KeepParts::Positive
                                                   : KeepParts::Both;
        const PlaneOrient plane(x_, tree_->vertex(*mesh_, n.v0), tree_->vertex(*mesh_, n.v1));
        if (parts_.size() <= depth) parts_.resize(depth + 1);
        SplitParts& parts = parts_[depth];
        SplitOutcome outcome = SplitOutcome::OnPlane;
        switch (mode_) {
            case PredicateMode::Filtered:
                outcome = splitConstructed(poly, plane, light_, parts, keep);
                break;
            case PredicateMode::AlwaysExact:
                outcome = splitExact(poly, plane, parts);
                break;
            case PredicateMode::Naive:
                outcome = splitNaive(poly, plane, parts);
                break;
        }
        switch (outcome) {
            case SplitOutcome::OnPlane:  // measure zero: follows child[0] whole (see above)
            case SplitOutcome::Positive:
                node = c0;
                continue;
            case SplitOutcome::Negative:
                node = c1;
                continue;
            case SplitOutcome::Split: {
                // Spans into the parts' heap storage: they stay valid when deeper levels grow
                // parts_ (moving a vector keeps its buffer), and deeper levels use other entries.
                // One part left (the other is hidden): go on with it here, one level deeper.
                if (keep == KeepParts::Positive) {
                    poly = parts.positive();
                    node = c0;
                    ++depth;
                    continue;
                }
                if (keep == KeepParts::Negative) {
                    poly = parts.negative();
                    node = c1;
                    ++depth;
                    continue;
                }
                const std::span<const Vec3> positive = parts.positive();
                const std::span<const Vec3> negative = parts.negative();
                visit(c0, positive, depth + 1);
                visit(c1, negative, depth + 1);
                return;
            }
        }
    }
}

void FromPointQuery::preparePair(const PolygonMesh& mesh, const HistoryTree& tree) {
    // What depends on the pair and not on x: reused while consecutive runs ask for the same pair.
    // Checked by value (the faces' vertex coordinates), so a changed or reloaded mesh is noticed.
    const auto& lightFace = mesh.faces[tree.light];
    const auto& receiverFace = mesh.faces[tree.receiver];
    bool same = preparedMesh_ == &mesh && preparedReceiver_ == tree.receiver &&
                preparedLight_ == tree.light && light_.size() == lightFace.size();
    for (size_t i = 0; same && i < lightFace.size(); ++i)
        same = light_[i] == mesh.vertices[lightFace[i]];
    for (size_t i = 0; same && i < 3; ++i)
        same = receiverPlane_[i] == mesh.vertices[receiverFace[i]];
    if (same) return;
    preparedMesh_ = &mesh;
    preparedReceiver_ = tree.receiver;
    preparedLight_ = tree.light;
    light_.clear();
    for (uint32_t v : lightFace) light_.push_back(mesh.vertices[v]);
    for (size_t i = 0; i < 3; ++i) receiverPlane_[i] = mesh.vertices[receiverFace[i]];
    const FacePlane pl = facePlane(mesh, tree.light);
    lightPlane_ = PlaneOrient(pl.a, pl.b, pl.c);
    // The receiver sees only its front hemisphere (B's plane, exact on input points).
    clipConvexInto(light_, OrientedPlane{receiverPlane_[0], receiverPlane_[1], receiverPlane_[2]},
                   lightClipped_, discard_);
}

const FragmentList& FromPointQuery::run(const PolygonMesh& mesh, const HistoryTree& tree,
                                        const Vec3& x, std::vector<uint32_t>* path,
                                        RegionDecisions* region) {
    if (region != nullptr && region->tree() != &tree)
        throw std::invalid_argument("FromPointQuery::run: region decisions of another tree");
    fragments_.clear();
    nodesVisited_ = 0;
    // TooComplex: no tree, no answer here (the caller samples; fp_query.h).
    if (tree.kind == PairKind::BackFacing || tree.kind == PairKind::FullyHidden ||
        tree.kind == PairKind::TooComplex)
        return fragments_;
    preparePair(mesh, tree);
    // The light emits only to its front: x must be strictly in front of L's plane.
    if (lightPlane_.sign(x) != Sign::Positive) return fragments_;
    if (lightClipped_.size() < 3) return fragments_;
    if (tree.kind == PairKind::FullyVisible) {
        fragments_.add(lightClipped_);
        return fragments_;
    }
    mesh_ = &mesh;
    tree_ = &tree;
    x_ = x;
    path_ = path;
    region_ = region;
    visit(0, lightClipped_, 0);
    path_ = nullptr;
    region_ = nullptr;
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
