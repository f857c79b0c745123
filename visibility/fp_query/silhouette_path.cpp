#include "visibility/fp_query/silhouette_path.h"

#include <algorithm>

#include "visibility/face_plane.h"
#include "visibility/fp_query/query_parts.h"

namespace penumbra::vis {

bool SilhouettePath::prepare(const HistoryTree& tree) {
    QueryRun& r = q_.run;
    const DeferredSilhouettes& s = tree.silhouettes;
    if (!s.usable() || r.chainOptions.minOccluders == 0 ||
        tree.deferred.size() < r.chainOptions.minOccluders)
        return false;
    const Bounds3& q = s.region;
    const Vec3& x = r.x;
    if (!(x.x >= q.lo.x && x.x <= q.hi.x && x.y >= q.lo.y && x.y <= q.hi.y && x.z >= q.lo.z &&
          x.z <= q.hi.z))
        return false;  // the sides decided for Q are not certainly x's
    surface_ = &s;
    restActivated_ = false;
    if (slotStamp_.size() < s.slots.size()) {
        slotStamp_.resize(s.slots.size(), 0);
        slotSide_.resize(s.slots.size(), 0);
    }
    if (++runStamp_ == 0) {  // wrapped: no stale stamp may match
        std::fill(slotStamp_.begin(), slotStamp_.end(), 0);
        runStamp_ = 1;
    }
    r.prepareCone();
    r.budget.enter(WorkStage::ActivateOccluders);
    for (uint32_t slot : s.clipped) {
        if (!r.budget.spend()) return true;
        q_.active.activate(tree.deferred[slot].face);
    }
    clipped_ = q_.active.size();
    r.budget.enter(WorkStage::FindOccluders);
    // The kept edges whose segment may meet the cone over L (which holds the clipped pyramid):
    // the others cannot cut a cell.
    groups_.clear();
    r.budget.spend(s.groups.notOutside(r.cone(), groups_, r.budget.left()));
    std::sort(groups_.begin(), groups_.end());  // deterministic order
    return true;
}

void SilhouettePath::activateRest() {
    if (restActivated_) return;
    restActivated_ = true;
    QueryRun& r = q_.run;
    r.budget.enter(WorkStage::FindOccluders);
    lineSlots_.clear();
    if (!r.budget.spend(r.tree->deferredIndex.notOutside(r.pyramid, lineSlots_, r.budget.left())))
        return;
    std::sort(lineSlots_.begin(), lineSlots_.end());
    r.budget.enter(WorkStage::ActivateOccluders);
    for (uint32_t slot : lineSlots_) {
        if (!isSurface(slot)) continue;
        if (!r.budget.spend()) return;
        q_.active.activate(r.tree->deferred[slot].face);
    }
}

int SilhouettePath::sideAt(uint32_t slot) {
    const int8_t decided = surface_->sides[slot];
    QueryRun& r = q_.run;
    // x in Q (decided for x, not for a moved point's input: its contacts are tested below).
    if (decided != 0 && !r.moved) return decided;
    if (slotStamp_[slot] == runStamp_) return slotSide_[slot];
    if (!r.budget.spend()) return 0;
    const PlaneOrient plane = facePlane(r.mesh(), r.tree->deferred[slot].face).orient();
    const Sign s =
        r.moved && plane.sign(r.input) == Sign::Zero ? Sign::Zero : exactSign(plane, r.x);
    slotStamp_[slot] = runStamp_;
    slotSide_[slot] = static_cast<int8_t>(toInt(s));
    return slotSide_[slot];
}

LineHit SilhouettePath::hitKind(uint32_t slot, const Vec3& y) {
    const int s = sideAt(slot);
    if (s == 0) return LineHit::Miss;  // x on its plane: it blocks nothing (the contact rule)
    const LineHit hit = q_.lines.faceHitKind(q_.run.tree->deferred[slot].face, s, y);
    if (hit == LineHit::Miss) return hit;
    if (std::find(recentHits_.begin(), recentHits_.end(), slot) == recentHits_.end()) {
        recentHits_[recentNext_] = slot;
        recentNext_ = (recentNext_ + 1) % kRecentHits;
    }
    return hit;
}

bool SilhouettePath::lineBlocked(const Vec3& y) {
    QueryRun& r = q_.run;
    LineTests& lines = q_.lines;
    // The activated faces that cross B's or L's plane, then the Surface faces (not activated:
    // tested from their input edges), the last few that hid a cell first.
    for (size_t j = 0; j < clipped_; ++j) {
        if (lines.hits(j, y)) return true;
        if (r.budget.reached()) return false;
    }
    for (uint32_t k = 0; k < kRecentHits; ++k) {
        const uint32_t slot = recentHits_[(recentNext_ + kRecentHits - 1 - k) % kRecentHits];
        if (slot < surface_->slots.size() && isSurface(slot) && hits(slot, y)) return true;
    }
    // Each face as the hierarchy finds it: the first hit ends the search.
    lines.setLinePlanes(y);
    uint32_t visited = 0;
    const bool hit = r.tree->deferredIndex.anyNotOutside(
        lines.linePlanes(),
        [&](uint32_t slot) {
            if (r.budget.reached()) return true;
            return isSurface(slot) && hits(slot, y);
        },
        visited);
    r.budget.spend(visited);
    return hit && !r.budget.reached();
}

std::optional<int> SilhouettePath::countLine(const Vec3& y) {
    QueryRun& r = q_.run;
    LineTests& lines = q_.lines;
    HitCount c;
    auto add = [&](LineHit h) { return c.add(h, r.budget); };
    for (size_t j = 0; j < clipped_; ++j)
        if (add(lines.hitKind(j, y))) return std::nullopt;
    lines.setLinePlanes(y);
    uint32_t visited = 0;
    r.tree->deferredIndex.anyNotOutside(
        lines.linePlanes(),
        [&](uint32_t slot) {
            if (r.budget.reached()) return true;
            return isSurface(slot) && add(hitKind(slot, y));
        },
        visited);
    r.budget.spend(visited);
    if (c.touch || r.budget.reached()) return std::nullopt;
    return c.count;
}

}  // namespace penumbra::vis
