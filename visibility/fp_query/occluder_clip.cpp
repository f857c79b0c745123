#include "visibility/fp_query/occluder_clip.h"

#include <algorithm>
#include <cmath>

#include "visibility/fp_query/query_parts.h"

namespace penumbra::vis {

void OccluderClip::clipOrdered(std::span<const Vec3> poly, size_t depth) {
    if (!ordered_) order();
    clipByOccluders(poly, 0, depth);
}

void OccluderClip::order() {
    QueryRun& r = q_.run;
    ActiveOccluders& active = q_.active;
    const PolygonMesh& mesh = r.mesh();
    // Largest first: an occluder that hides much of L removes it before the smaller ones cut it
    // into pieces (Algorithm 1's cost follows the pieces). The key is the solid angle of the
    // whole face from x (Van Oosterom and Strackee's formula per triangle of a fan), in doubles:
    // it orders the occluders and decides nothing else, and every order gives the same answer.
    ordered_ = true;
    orderKeys_.clear();
    for (uint32_t j = 0; j < active.size(); ++j) {
        const auto& ids = mesh.faces[active[j].face];
        const Vec3 a = mesh.vertices[ids[0]] - r.x;
        const double la = length(a);
        double omega = 0;
        for (size_t i = 1; i + 1 < ids.size(); ++i) {
            const Vec3 b = mesh.vertices[ids[i]] - r.x, c = mesh.vertices[ids[i + 1]] - r.x;
            const double lb = length(b), lc = length(c);
            const double den = la * lb * lc + dot(a, b) * lc + dot(a, c) * lb + dot(b, c) * la;
            omega += 2 * std::atan2(std::abs(dot(a, cross(b, c))), den);
        }
        orderKeys_.emplace_back(-omega, j);
    }
    std::sort(orderKeys_.begin(), orderKeys_.end());  // ties in the activation order
    order_.clear();
    for (const auto& [key, j] : orderKeys_) order_.push_back(j);
    active.reorder(order_);
}

const std::vector<PlaneOrient>& OccluderClip::hullCone(std::span<const Vec3> poly) {
    QueryRun& r = q_.run;
    const std::vector<Vec3>& light = r.light();
    if (lightTurn_ == Sign::Zero)  // x strictly in front of L (startPair): not zero
        lightTurn_ = PlaneOrient(r.x, light[0], light[1]).sign(light[2]);
    hullCone_.clear();
    const size_t n = poly.size();
    for (size_t i = 0; i < n; ++i) {
        const PlaneOrient h = lightTurn_ == Sign::Positive
                                  ? PlaneOrient(r.x, poly[i], poly[(i + 1) % n])
                                  : PlaneOrient(r.x, poly[(i + 1) % n], poly[i]);
        bool holds = true, strict = false;
        for (size_t k = 0; holds && k < n; ++k) {
            if (k == i || k == (i + 1) % n) continue;
            const Sign s = h.sign(poly[k]);
            holds = s != Sign::Negative;
            strict = strict || s == Sign::Positive;
        }
        if (holds && strict) hullCone_.push_back(h);
    }
    r.budget.spend(n);
    return hullCone_;
}

bool OccluderClip::cullFor(std::span<const Vec3> poly, size_t from) {
    QueryRun& r = q_.run;
    r.budget.enter(WorkStage::ClipOccluders);
    // The occluders that may meet the polygon's hull (hullCone).
    hullCone(poly);
    if (r.budget.reached()) return false;
    const BoxTree& boxes = q_.active.boxes();
    cullOut_.clear();
    if (!r.budget.spend(boxes.notOutside(hullCone_, cullOut_, r.budget.left()))) return false;
    std::sort(cullOut_.begin(), cullOut_.end());
    for (uint32_t j : cullOut_)
        if (j >= from) clipList_.push_back(j);
    return true;
}

void OccluderClip::clipByOccluders(std::span<const Vec3> poly, size_t from, size_t depth) {
    const size_t n = q_.active.size();
    // The occluders to clip against: those from `from` on in order, or, where there are many, those
    // of them whose box is not certainly outside the polygon's pyramid from x (cullFor), kept in
    // clipList_ above the callers' lists.
    const size_t listBase = clipList_.size();
    const bool culled = n - std::min(from, n) >= kCullMin;
    if (culled && !cullFor(poly, from)) {
        clipList_.resize(listBase);
        return;
    }
    const size_t count = culled ? clipList_.size() - listBase : n - from;
    clipListed(poly, listBase, count, culled, from, depth);
    clipList_.resize(listBase);
}

void OccluderClip::clipListed(std::span<const Vec3> poly, size_t listBase, size_t count,
                              bool culled, size_t from, size_t depth) {
    QueryRun& r = q_.run;
    const ActiveOccluders& active = q_.active;
    const std::vector<Vec3>& light = r.light();
    r.budget.enter(WorkStage::ClipOccluders);
    // Algorithm 1 in 3D, from x: a deferred occluder blocks the lines from x that lie on its
    // blocked side of every plane through x and one of its edges. Each part split off on the
    // unblocked side of an edge goes on to the next occluder; what is left after the last edge is
    // hidden. The signs are those of the walk (splitConstructed).
    for (size_t k = 0; k < count; ++k) {
        if (r.budget.reached()) return;
        const size_t j = culled ? clipList_[listBase + k] : from + k;
        const ActiveOccluders::Occluder& o = active[j];
        const SplitOutcome unblocked =
            o.blocked == Sign::Positive ? SplitOutcome::Negative : SplitOutcome::Positive;
        // Entirely outside one of its edge planes: it blocks none of this polygon. Checked for
        // every edge before any split, so that an occluder beside the polygon cuts nothing (a
        // split by the first edge would leave two visible pieces where one was).
        // Its input edges' planes, then its chords' (the order of the edges changes no answer).
        auto forEachPlane = [&](auto&& f) {
            for (uint32_t e = 0; e < o.planeCount; ++e)
                if (!f(active.plane(o.firstPlane + e))) return;
            for (uint32_t e = 0; e < o.pencilCount; ++e)
                if (!f(active.pencil(o.firstPencil + e))) return;
        };
        bool outside = false;
        forEachPlane([&](const auto& plane) {
            if (!r.budget.spend()) return false;
            SplitOutcome side = sideOfConstructed(poly, plane, light);
            if (side == SplitOutcome::OnPlane) side = SplitOutcome::Positive;  // as visit()
            outside = side == unblocked;
            return !outside;
        });
        if (r.budget.reached()) return;
        if (outside) continue;
        // Split by each edge plane in turn: the part on its unblocked side is free of this
        // occluder, the rest goes on to the next plane. The free parts are kept aside (in
        // parts_ above `depth`) until the end: if the rest turns out wholly unblocked too, the
        // occluder blocks none of `poly`, and `poly` goes on whole instead of in pieces (an
        // occluder beside a corner of it would otherwise cut it for nothing: the pieces' union
        // is `poly`, so the answer is the same, with fewer fragments for the next occluders).
        std::span<const Vec3> current = poly;
        size_t d = depth;
        const size_t freeBase = freeParts_.size();
        bool untouched = false;
        forEachPlane([&](const auto& plane) {
            if (!r.budget.spend()) return false;
            SplitParts& parts = r.partsAt(d);
            SplitOutcome outcome = splitConstructed(current, plane, light, parts, KeepParts::Both);
            if (outcome == SplitOutcome::OnPlane) outcome = SplitOutcome::Positive;  // as visit()
            if (outcome == unblocked) {
                untouched = true;
                return false;
            }
            if (outcome != SplitOutcome::Split) return true;  // wholly on the blocked side of it
            freeParts_.push_back(o.blocked == Sign::Positive ? parts.negative() : parts.positive());
            current = o.blocked == Sign::Positive ? parts.positive() : parts.negative();
            ++d;  // `current` lives in parts_[d - 1] now
            return true;
        });
        if (r.budget.reached() || untouched) {
            freeParts_.resize(freeBase);
            if (r.budget.reached()) return;
            continue;  // this occluder blocks none of it
        }
        // The rest is blocked: the free parts go on to the next occluders, each from the first
        // level none of them is stored in (deeper levels do not touch them).
        ++clips_;
        // (A part's list is the rest of this one, or culled again for it where that is long.)
        for (size_t f = freeBase; f < freeParts_.size(); ++f) {
            if (count - k - 1 >= kRecullMin)
                clipByOccluders(freeParts_[f], j + 1, d);
            else
                clipListed(freeParts_[f], culled ? listBase + k + 1 : listBase, count - k - 1,
                           culled, j + 1, d);
            if (r.budget.reached()) break;
        }
        freeParts_.resize(freeBase);
        return;
    }
    if (r.budget.reached()) return;
    r.fragments.add(poly);
}

}  // namespace penumbra::vis
