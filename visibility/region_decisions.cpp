#include "visibility/region_decisions.h"

#include <stdexcept>

#include "visibility/edge_line.h"
#include "visibility/face_plane.h"

namespace penumbra::vis {

void RegionDecisions::reset(const PolygonMesh& mesh, const HistoryTree& tree,
                            std::span<const Vec3> corners) {
    if (corners.empty() || corners.size() > 8)
        throw std::invalid_argument("RegionDecisions: a region needs 1 to 8 corners");
    mesh_ = &mesh;
    tree_ = &tree;
    corners_.assign(corners.begin(), corners.end());
    // B's and L's planes at the corners, for the chords' pencil planes (once per region, not once
    // per node: corners on B's plane make the filter fail and take the exact stage).
    for (int k = 0; k < 2; ++k) {
        clip_[k] = facePlane(mesh, k == 0 ? tree.receiver : tree.light).orient();
        clipAt_[k].clear();
        for (const Vec3& r : corners_) clipAt_[k].push_back(clip_[k].value(r));
    }
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
    bool pos = false, neg = false;
    // The side of line(r, l) against the edge is the side of l against the plane through r and
    // the edge's line (exact: edge_line.h).
    auto sides = [&](const auto& plane) {
        for (const Vec3& l : light_) {
            const Sign s = plane.sign(l);
            pos |= s == Sign::Positive;
            neg |= s == Sign::Negative;
        }
    };
    if (!isClipEdge(n.v0)) {
        const Vec3 v0 = mesh_->vertices[n.v0], v1 = mesh_->vertices[n.v1];
        for (size_t k = 0; k < corners_.size() && !(pos && neg); ++k)
            sides(PlaneOrient(corners_[k], v0, v1));
    } else {
        const int which = n.v1 == kReceiverPlaneEdge ? 0 : 1;
        const auto& f = mesh_->faces[n.v0 & ~kClipEdge];
        const PlaneOrient occluder(mesh_->vertices[f[0]], mesh_->vertices[f[1]],
                                   mesh_->vertices[f[2]]);
        for (size_t k = 0; k < corners_.size() && !(pos && neg); ++k)
            sides(PencilPlane(corners_[k], clip_[which], clipAt_[which][k], occluder));
    }
    const Decision d = !neg ? Decision::Positive : (!pos ? Decision::Negative : Decision::Split);
    stamp_[node] = generation_;
    decision_[node] = d;
    ++decided_;
    splits_ += d == Decision::Split;
    return d;
}

}  // namespace penumbra::vis
