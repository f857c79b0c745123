#include "visibility/fp_query/cluster_path.h"

#include <algorithm>

#include "visibility/face_plane.h"
#include "visibility/fp_query/query_parts.h"

namespace penumbra::vis {

struct ClusterPath::Walk {
    const BoxTree& faces;
    const FaceClusters& clusters;
    std::span<const PlaneBoxCull> pyramid;
    // B's and L's planes turned around: a box strictly on their negative side lies strictly in
    // front of B and of L (PlaneBoxCull over the hierarchy's root box, rigorous), so no face in
    // it is clipped.
    PlaneBoxCull behindB, behindL;
};

bool ClusterPath::find(const BoxTree& faces, const FaceClusters& clusters) {
    QueryRun& r = q_.run;
    clusters_ = &clusters;
    faces_ = &faces;
    r.budget.enter(WorkStage::FindOccluders);
    r.candidates.clear();
    used_.clear();
    exactSides_ = 0;
    if (faces.empty()) return true;
    if (nodeStamp_.size() < faces.nodeCount()) {
        nodeStamp_.resize(faces.nodeCount(), 0);
        nodeSide_.resize(faces.nodeCount(), 0);
    }
    if (++nodeRun_ == 0) {  // wrapped: no stale stamp may match
        std::fill(nodeStamp_.begin(), nodeStamp_.end(), 0);
        nodeRun_ = 1;
    }
    std::array<PlaneBoxCull, BoxTree::kMaxCullPlanes> cull;
    const Bounds3& region = faces.nodeBox(0);
    const OrientedPlane& frontB = r.pair.frontB();
    const OrientedPlane& frontL = r.pair.frontL();
    const Walk w{faces, clusters, faces.cullPlanes(r.pyramid, cull),
                 PlaneBoxCull(PlaneOrient(frontB.a, frontB.c, frontB.b), region.lo, region.hi),
                 PlaneBoxCull(PlaneOrient(frontL.a, frontL.c, frontL.b), region.lo, region.hi)};
    walk(0, w);
    if (r.budget.reached()) return false;
    return true;
}

int ClusterPath::exactFacing(std::span<const uint32_t> faces) {
    QueryRun& r = q_.run;
    // Exact: each face's plane (through its first three vertices, as activateFace takes it) at
    // x; the first face that disagrees, or has x on its plane, ends the test.
    int side = 0;
    for (uint32_t face : faces) {
        if (!r.budget.spend()) return 0;
        const Sign s = r.occluderSide(facePlane(r.mesh(), face).orient());
        const int f = toInt(s);
        if (f == 0 || (side != 0 && f != side)) return 0;
        side = f;
    }
    return side;
}

bool ClusterPath::walk(uint32_t node, const Walk& w) {
    QueryRun& r = q_.run;
    if (!r.budget.spend()) return false;
    const Bounds3& box = w.faces.nodeBox(node);
    if (BoxTree::outsideOne(w.pyramid, box)) return false;
    const uint32_t cluster = w.clusters.clusterAt(node);
    if (cluster != FaceClusters::kNone && w.behindB.negative(box.lo, box.hi) &&
        w.behindL.negative(box.lo, box.hi)) {
        // (The cone test certifies x's side with some slack, not the input's contacts: a moved
        // point takes the exact sides.)
        int side = r.moved ? 0 : w.clusters.facing(cluster, r.x);
        if (side == 0 && w.faces.nodeItems(node).size() <= kExactFacingMax) {
            side = exactFacing(w.faces.nodeItems(node));
            exactSides_ += side != 0 ? 1 : 0;
        }
        if (r.budget.reached()) return false;
        if (side != 0) {
            used_.push_back({node, cluster, side});
            nodeStamp_[node] = nodeRun_;
            nodeSide_[node] = static_cast<int8_t>(side);
            return true;
        }
    }
    if (w.faces.isLeaf(node)) {
        for (uint32_t face : w.faces.nodeItems(node))
            if (!BoxTree::outsideOne(w.pyramid, w.faces.itemBox(face)))
                r.candidates.push_back(face);
        return false;
    }
    const bool left = walk(node + 1, w);
    if (r.budget.reached()) return false;
    const bool right = walk(w.faces.rightChild(node), w);
    if (left || right) {
        nodeStamp_[node] = nodeRun_;
        nodeSide_[node] = 0;
    }
    return left || right;
}

bool ClusterPath::lineBlocked(const Vec3& y) {
    QueryRun& r = q_.run;
    LineTests& lines = q_.lines;
    // The group faces that hid the last cells first (a hidden cell's neighbour is mostly hidden
    // by the same few), then each face as the walk finds it: the first hit ends it.
    for (uint32_t k = 0; k < kRecentHits; ++k) {
        const auto [face, side] = recentHits_[(recentNext_ + kRecentHits - 1 - k) % kRecentHits];
        if (side != 0 && lines.faceHitKind(face, side, y) != LineHit::Miss) return true;
        if (r.budget.reached()) return false;
    }
    lines.setLinePlanes(y);
    const bool hit = facesOnLine(lines.linePlanes(), r.budget, [&](uint32_t face, int side) {
        if (lines.faceHitKind(face, side, y) == LineHit::Miss) return r.budget.reached();
        recentHits_[recentNext_] = {face, side};
        recentNext_ = (recentNext_ + 1) % kRecentHits;
        return true;
    });
    return hit && !r.budget.reached();
}

void ClusterPath::dissolve() {
    QueryRun& r = q_.run;
    r.budget.enter(WorkStage::ActivateOccluders);
    for (const Used& c : used_) {
        for (uint32_t face : faces_->nodeItems(c.node)) {
            if (!r.budget.spend()) return;
            q_.active.activate(face);
        }
    }
    dissolved_ = true;
}

}  // namespace penumbra::vis
