#include "visibility/region_decisions.h"

#include <stdexcept>

#include "visibility/edge_line.h"

namespace penumbra::vis {

void RegionDecisions::reset(const PolygonMesh& mesh, const HistoryTree& tree,
                            std::span<const Vec3> corners) {
    if (corners.empty() || corners.size() > 8)
        throw std::invalid_argument("RegionDecisions: a region needs 1 to 8 corners");
    mesh_ = &mesh;
    tree_ = &tree;
    corners_.assign(corners.begin(), corners.end());
    light_.clear();
    for (uint32_t v : mesh.faces[tree.light]) light_.push_back(mesh.vertices[v]);
    if (stamp_.size() < tree.nodes.size()) {
        stamp_.resize(tree.nodes.size(), 0);
        decision_.resize(tree.nodes.size(), Decision::Split);
    }
    if (++generation_ == 0) {  // wrapped: no stale stamp may match
        std::fill(stamp_.begin(), stamp_.end(), 0);
        generation_ = 1;
    }
    decided_ = splits_ = 0;
}

RegionDecisions::Decision RegionDecisions::compute(uint32_t node) {
    const HistoryNode& n = tree_->nodes[node];
    const EdgeLine edge = tree_->edgeLine(*mesh_, n);
    bool pos = false, neg = false;
    for (const Vec3& r : corners_) {
        // The side of line(r, l) against the edge is the side of l against the plane through r
        // and the edge's line (exact: edge_line.h).
        const EdgePlane plane(r, edge);
        for (const Vec3& l : light_) {
            const Sign s = plane.sign(l);
            pos |= s == Sign::Positive;
            neg |= s == Sign::Negative;
        }
        if (pos && neg) break;
    }
    const Decision d = !neg ? Decision::Positive : (!pos ? Decision::Negative : Decision::Split);
    stamp_[node] = generation_;
    decision_[node] = d;
    ++decided_;
    splits_ += d == Decision::Split;
    return d;
}

}  // namespace penumbra::vis
