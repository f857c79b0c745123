#include "visibility/region_decisions.h"

#include <stdexcept>

#include "visibility/predicates.h"

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
    candidatesReady_ = false;
}

const std::vector<uint32_t>& RegionDecisions::deferredCandidates() {
    if (candidatesReady_) return candidates_;
    candidatesReady_ = true;
    candidates_.clear();
    // Supporting planes of conv(R u L) through an edge of L and a corner of R, oriented with R and
    // L on their closed positive side (exact signs).
    std::vector<PlaneOrient> planes;
    for (size_t i = 0; i < light_.size(); ++i) {
        const Vec3& a = light_[i];
        const Vec3& b = light_[(i + 1) % light_.size()];
        for (const Vec3& r : corners_) {
            const PlaneOrient plane(a, b, r);
            bool pos = false, neg = false;
            for (const std::vector<Vec3>* points : {&light_, &corners_})
                for (const Vec3& p : *points) {
                    const Sign s = plane.sign(p);
                    pos |= s == Sign::Positive;
                    neg |= s == Sign::Negative;
                }
            if (pos == neg) continue;  // not supporting, or everything on it
            planes.push_back(neg ? PlaneOrient(b, a, r) : plane);
        }
    }
    std::vector<Vec3> points;
    for (uint32_t k = 0; k < tree_->deferred.size(); ++k) {
        const DeferredOccluder& d = tree_->deferred[k];
        bool boxOutside = false;
        if (!d.box.empty())
            for (const PlaneOrient& plane : planes)
                if (plane.boxNegative(d.box.lo, d.box.hi)) {
                    boxOutside = true;
                    break;
                }
        if (boxOutside) continue;
        points.clear();
        for (uint32_t id : d.vertexIds) points.push_back(tree_->vertex(*mesh_, id));
        bool outside = false;
        for (const PlaneOrient& plane : planes) {
            bool inside = false;
            for (const Vec3& p : points) inside |= plane.sign(p) == Sign::Positive;
            if (!inside) {
                outside = true;
                break;
            }
        }
        if (!outside) candidates_.push_back(k);
    }
    return candidates_;
}

RegionDecisions::Decision RegionDecisions::compute(uint32_t node) {
    const HistoryNode& n = tree_->nodes[node];
    const Vec3 v0 = tree_->vertex(*mesh_, n.v0), v1 = tree_->vertex(*mesh_, n.v1);
    bool pos = false, neg = false;
    for (const Vec3& r : corners_) {
        // orient3d(r, l, v0, v1) == orient3d(r, v0, v1, l): the plane through r and the edge.
        const PlaneOrient plane(r, v0, v1);
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
