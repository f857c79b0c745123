#include "visibility/fp_query/active_occluders.h"

#include "visibility/face_plane.h"
#include "visibility/fp_query/query_parts.h"

namespace penumbra::vis {

void ActiveOccluders::clear(bool run) {
    list_.clear();
    planes_.clear();
    pencils_.clear();
    pencilOnB_.clear();
    planeEdges_.clear();
    if (run) {
        lightChord_ = false;
        boxesBuilt_ = false;
    }
}

void ActiveOccluders::activate(uint32_t face) {
    QueryRun& r = q_.run;
    r.budget.enter(WorkStage::ActivateOccluders);
    const PolygonMesh& mesh = r.mesh();
    // x on the occluder's plane: every segment from x meets that plane at x only, so the
    // occluder blocks none (the contact rule: a segment that touches an occluder only at its end
    // point x is not blocked).
    const auto& ids = mesh.faces[face];
    const PlaneOrient plane = facePlane(mesh, face).orient();
    const Sign side = r.occluderSide(plane);
    if (side == Sign::Zero) return;
    // Seen from behind on a closed surface taken as a solid: the faces seen from the front block
    // every segment that this one would (solid_filter.h).
    if (side == Sign::Negative && q_.solids.leavesOut(face)) return;
    // Outside the pyramid from x over L as a whole face: its clipped part is too (a subset). The
    // cheap rejection, before any clip: most candidates of the box hierarchy end here.
    for (const PlaneOrient& h : r.pyramid) {
        bool inside = false;
        for (uint32_t v : ids) {
            BoundedValue b;
            inside =
                h.filtered(mesh.vertices[v], b) ? b.value > 0 : h.value(mesh.vertices[v]).value > 0;
            if (inside) break;
        }
        if (!inside) return;
    }
    // Clipped to the region in front of B's and L's planes, as the builder clips its occluders,
    // exactly (clipped_occluder.h): a line from x to L meets the clipped part between them (and
    // the line beyond x or beyond L, which the sign test would also see, lies outside that
    // region).
    const OrientedPlane& frontB = r.pair.frontB();
    const OrientedPlane& frontL = r.pair.frontL();
    clipped_.clip(mesh, face, frontB.orient, frontL.orient);
    if (clipped_.empty()) return;
    // Outside the pyramid from x over L (exact on the clipped polygon's symbolic vertices).
    for (const PlaneOrient& h : r.pyramid)
        if (clipped_.outside(h)) return;
    // Seen from x in front of its plane, the occluder is counter-clockwise, and the lines from x
    // through it lie on the negative side of every plane through x and an edge line a -> b:
    // orient3d(x, p, a, b) = -orient3d(p, a, b, x) for p inside it.
    Occluder a;
    a.face = face;
    a.firstPlane = static_cast<uint32_t>(planes_.size());
    a.firstPencil = static_cast<uint32_t>(pencils_.size());
    a.blocked = side == Sign::Positive ? Sign::Negative : Sign::Positive;
    for (const auto& [v0, v1] : clipped_.edges()) {
        if (!isClipEdge(v0)) {
            planes_.emplace_back(r.x, mesh.vertices[v0], mesh.vertices[v1]);
            planeEdges_.emplace_back(v0, v1);
        } else {
            const bool onB = v1 == kReceiverPlaneEdge;
            lightChord_ = lightChord_ || !onB;
            pencilOnB_.push_back(onB ? 1 : 0);
            pencils_.emplace_back(r.x, onB ? frontB.orient : frontL.orient,
                                  r.clipPlaneAt(onB ? 0 : 1), plane);
        }
    }
    a.planeCount = static_cast<uint32_t>(planes_.size()) - a.firstPlane;
    a.pencilCount = static_cast<uint32_t>(pencils_.size()) - a.firstPencil;
    list_.push_back(a);
}

uint32_t ActiveOccluders::addEdgePlane(uint32_t lo, uint32_t hi) {
    const uint32_t ref = static_cast<uint32_t>(planes_.size());
    planes_.emplace_back(q_.run.x, q_.run.mesh().vertices[lo], q_.run.mesh().vertices[hi]);
    planeEdges_.emplace_back(lo, hi);
    return ref;
}

void ActiveOccluders::reorder(std::span<const uint32_t> order) {
    scratch_.clear();
    for (uint32_t j : order) scratch_.push_back(list_[j]);
    list_.swap(scratch_);
    boxesBuilt_ = false;  // (its items are indices into the list)
}

const BoxTree& ActiveOccluders::boxes() {
    // (Rebuilt when occluders were activated since: the silhouette path adds some late.)
    if (boxesBuilt_ && boxList_.size() == list_.size()) return boxes_;
    boxesBuilt_ = true;
    boxList_.clear();
    for (const Occluder& o : list_) boxList_.push_back(q_.run.mesh().faceBounds(o.face));
    boxes_ = BoxTree(boxList_);
    return boxes_;
}

}  // namespace penumbra::vis
