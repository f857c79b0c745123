#include "visibility/fp_query.h"

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <stdexcept>
#include <type_traits>

#include "visibility/pair_occluders.h"
#include "visibility/polygon_clip.h"

namespace penumbra::vis {

const char* toString(NodeSide side) {
    switch (side) {
        case NodeSide::Positive:
            return "+";
        case NodeSide::Negative:
            return "-";
        case NodeSide::Both:
            return "both";
        case NodeSide::OnPlane:
            return "in plane (+)";
    }
    return "?";
}

void FromPointQuery::visit(uint32_t node, std::span<const Vec3> poly, size_t depth,
                           uint32_t treeDepth) {
    // Down the tree while the plane leaves the polygon on one side (the common case: the same span
    // goes on, nothing is copied); recursion only where it is split in two.
    for (;;) {
        if (node == kVisibleLeaf) {
            reachVisible(poly, depth);
            return;
        }
        if (node == kHiddenLeaf) return;
        if (limitReached_) return;
        stage_ = WorkStage::Walk;
        const size_t step = trace_ != nullptr ? trace_->size() : 0;
        if (trace_ != nullptr) trace_->push_back({node, treeDepth, NodeSide::Positive});
        ++nodesVisited_;
        const HistoryNode& n = tree_->nodes[node];
        ++treeDepth;  // of the children
        if (region_ != nullptr) {
            const RegionDecisions::Decision d = region_->at(node);
            if (d == RegionDecisions::Decision::Positive) {
                node = n.child[0];
                continue;
            }
            if (d == RegionDecisions::Decision::Negative) {
                traceSide(step, NodeSide::Negative);
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
        if (!spend()) return;
        SplitParts& parts = partsAt(depth);
        SplitOutcome outcome;
        if (!isClipEdge(n.v0)) {
            outcome = splitBy(poly, PlaneOrient(x_, mesh_->vertices[n.v0], mesh_->vertices[n.v1]),
                              parts, keep);
        } else {
            // A chord of a clip: the plane through x and the meet of B's (or L's) plane with the
            // occluder's, as the pencil of the two (edge_line.h); exact for L's vertices too.
            const uint32_t face = n.v0 & ~kClipEdge;
            const auto& f = mesh_->faces[face];
            const PlaneOrient occluderPlane(mesh_->vertices[f[0]], mesh_->vertices[f[1]],
                                            mesh_->vertices[f[2]]);
            const bool onB = n.v1 == kReceiverPlaneEdge;
            const PlaneOrient& clip = onB ? frontB_.orient : frontL_.orient;
            outcome = splitBy(poly, PencilPlane(x_, clip, clipPlaneAt(onB ? 0 : 1), occluderPlane),
                              parts, keep);
        }
        switch (outcome) {
            case SplitOutcome::OnPlane:  // measure zero: follows child[0] whole (see above)
                traceSide(step, NodeSide::OnPlane);
                node = c0;
                continue;
            case SplitOutcome::Positive:
                node = c0;
                continue;
            case SplitOutcome::Negative:
                traceSide(step, NodeSide::Negative);
                node = c1;
                continue;
            case SplitOutcome::Split: {
                traceSide(step, NodeSide::Both);
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
                visit(c0, positive, depth + 1, treeDepth);
                visit(c1, negative, depth + 1, treeDepth);
                return;
            }
        }
    }
}

template <class Plane>
SplitOutcome FromPointQuery::splitBy(std::span<const Vec3> poly, const Plane& plane,
                                     SplitParts& parts, KeepParts keep) const {
    if constexpr (std::is_same_v<Plane, PlaneOrient>) {
        switch (mode_) {
            case PredicateMode::Filtered:
                break;
            case PredicateMode::AlwaysExact:
                return splitExact(poly, plane, parts);
            case PredicateMode::Naive:
                return splitNaive(poly, plane, parts);
        }
    }
    // (The chords' pencil planes have no naive or always-exact variant: the predicate study
    // measures input edges.)
    return splitConstructed(poly, plane, light_, parts, keep);
}

void FromPointQuery::reachVisible(std::span<const Vec3> poly, size_t depth) {
    if (!deferredPrepared_) {  // on the first visible leaf: a point in full shadow pays nothing
        deferredPrepared_ = true;
        prepareDeferred(*mesh_, *tree_);
    }
    if (useChain()) {
        if (limitReached_) return;  // (the chain may be half built)
        chainCells(poly, depth, 0);
        return;
    }
    if (!activeOrdered_) orderActive();
    clipByOccluders(poly, 0, depth);
}

void FromPointQuery::orderActive() {
    // Largest first: an occluder that hides much of L removes it before the smaller ones cut it
    // into pieces (Algorithm 1's cost follows the pieces). The key is the solid angle of the
    // whole face from x (Van Oosterom and Strackee's formula per triangle of a fan), in doubles:
    // it orders the occluders and decides nothing else, and every order gives the same answer.
    activeOrdered_ = true;
    orderKeys_.clear();
    for (uint32_t j = 0; j < active_.size(); ++j) {
        const auto& ids = mesh_->faces[active_[j].face];
        const Vec3 a = mesh_->vertices[ids[0]] - x_;
        const double la = length(a);
        double omega = 0;
        for (size_t i = 1; i + 1 < ids.size(); ++i) {
            const Vec3 b = mesh_->vertices[ids[i]] - x_, c = mesh_->vertices[ids[i + 1]] - x_;
            const double lb = length(b), lc = length(c);
            const double den = la * lb * lc + dot(a, b) * lc + dot(a, c) * lb + dot(b, c) * la;
            omega += 2 * std::atan2(std::abs(dot(a, cross(b, c))), den);
        }
        orderKeys_.emplace_back(-omega, j);
    }
    std::sort(orderKeys_.begin(), orderKeys_.end());  // ties in the activation order
    orderScratch_.clear();
    for (const auto& [key, j] : orderKeys_) orderScratch_.push_back(active_[j]);
    active_.swap(orderScratch_);
    activeBoxesBuilt_ = false;  // (its items are indices into active_)
}

bool FromPointQuery::cullFor(std::span<const Vec3> poly, size_t from) {
    stage_ = WorkStage::ClipOccluders;
    // The planes through x and the polygon's edges that have no vertex of it strictly on their
    // negative side (exact signs of its vertices, doubles: a rounded polygon that is not quite
    // convex loses only the planes that would cut it), oriented as L is seen from x: each holds
    // the polygon's hull, so an occluder whose box lies strictly outside one blocks none of it.
    if (lightTurn_ == Sign::Zero)  // x strictly in front of L (startPair): not zero
        lightTurn_ = PlaneOrient(x_, light_[0], light_[1]).sign(light_[2]);
    hullCone_.clear();
    const size_t n = poly.size();
    for (size_t i = 0; i < n; ++i) {
        const PlaneOrient h = lightTurn_ == Sign::Positive
                                  ? PlaneOrient(x_, poly[i], poly[(i + 1) % n])
                                  : PlaneOrient(x_, poly[(i + 1) % n], poly[i]);
        bool holds = true, strict = false;
        for (size_t k = 0; holds && k < n; ++k) {
            if (k == i || k == (i + 1) % n) continue;
            const Sign s = h.sign(poly[k]);
            holds = s != Sign::Negative;
            strict = strict || s == Sign::Positive;
        }
        if (holds && strict) hullCone_.push_back(h);
    }
    if (!spend(n)) return false;
    buildActiveBoxes();
    cullOut_.clear();
    if (!spend(activeBoxes_.notOutside(hullCone_, cullOut_, workBudgetLeft()))) return false;
    std::sort(cullOut_.begin(), cullOut_.end());
    for (uint32_t j : cullOut_)
        if (j >= from) clipList_.push_back(j);
    return true;
}

void FromPointQuery::clipByOccluders(std::span<const Vec3> poly, size_t from, size_t depth) {
    // The occluders to clip against: active_[from..] in order, or, where there are many, those
    // of them whose box is not certainly outside the polygon's pyramid from x (cullFor), kept in
    // clipList_ above the callers' lists.
    const size_t listBase = clipList_.size();
    const bool culled = active_.size() - std::min(from, active_.size()) >= kCullMin;
    if (culled && !cullFor(poly, from)) {
        clipList_.resize(listBase);
        return;
    }
    const size_t count = culled ? clipList_.size() - listBase : active_.size() - from;
    clipListed(poly, listBase, count, culled, from, depth);
    clipList_.resize(listBase);
}

void FromPointQuery::clipListed(std::span<const Vec3> poly, size_t listBase, size_t count,
                                bool culled, size_t from, size_t depth) {
    stage_ = WorkStage::ClipOccluders;
    // Algorithm 1 in 3D, from x: a deferred occluder blocks the lines from x that lie on its
    // blocked side of every plane through x and one of its edges. Each part split off on the
    // unblocked side of an edge goes on to the next occluder; what is left after the last edge is
    // hidden. The signs are those of the walk (splitConstructed).
    for (size_t k = 0; k < count; ++k) {
        if (limitReached_) return;
        const size_t j = culled ? clipList_[listBase + k] : from + k;
        const ActiveOccluder& o = active_[j];
        const SplitOutcome unblocked =
            o.blocked == Sign::Positive ? SplitOutcome::Negative : SplitOutcome::Positive;
        // Entirely outside one of its edge planes: it blocks none of this polygon. Checked for
        // every edge before any split, so that an occluder beside the polygon cuts nothing (a
        // split by the first edge would leave two visible pieces where one was).
        // Its input edges' planes, then its chords' (the order of the edges changes no answer).
        auto forEachPlane = [&](auto&& f) {
            for (uint32_t e = 0; e < o.planeCount; ++e)
                if (!f(activePlanes_[o.firstPlane + e])) return;
            for (uint32_t e = 0; e < o.pencilCount; ++e)
                if (!f(activePencils_[o.firstPencil + e])) return;
        };
        bool outside = false;
        forEachPlane([&](const auto& plane) {
            if (!spend()) return false;
            SplitOutcome side = sideOfConstructed(poly, plane, light_);
            if (side == SplitOutcome::OnPlane) side = SplitOutcome::Positive;  // as visit()
            outside = side == unblocked;
            return !outside;
        });
        if (limitReached_) return;
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
            if (!spend()) return false;
            SplitParts& parts = partsAt(d);
            SplitOutcome outcome = splitConstructed(current, plane, light_, parts, KeepParts::Both);
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
        if (limitReached_ || untouched) {
            freeParts_.resize(freeBase);
            if (limitReached_) return;
            continue;  // this occluder blocks none of it
        }
        // The rest is blocked: the free parts go on to the next occluders, each from the first
        // level none of them is stored in (deeper levels do not touch them).
        ++deferredClips_;
        // (A part's list is the rest of this one, or culled again for it where that is long.)
        for (size_t f = freeBase; f < freeParts_.size(); ++f) {
            if (count - k - 1 >= kRecullMin)
                clipByOccluders(freeParts_[f], j + 1, d);
            else
                clipListed(freeParts_[f], culled ? listBase + k + 1 : listBase, count - k - 1,
                           culled, j + 1, d);
            if (limitReached_) break;
        }
        freeParts_.resize(freeBase);
        return;
    }
    if (limitReached_) return;
    fragments_.add(poly);
}

// ---- The boundary chain --------------------------------------------------------------------
//
// What is exact here. c(y), the number of active occluders the line from x through y crosses, is
// constant on any open convex set of lines from x that no boundary-chain edge meets
// (boundary_chain.h). L is cut by the planes through x and the chain's edges, each only where its
// segment may meet the cell, into cells; every decision that drops an edge for a cell (the cell
// on one side of its plane, or the segment outside one of the cell's bounding planes) is recorded
// as a bounding plane of the cell or made by exact signs of input points. A cell is then decided
// by one line: a point y (the rounded centroid of its vertices, a double) is certified strictly
// inside every bounding plane of the cell by exact orient3d signs, so c(y) is the cell's value,
// and the line through y is tested exactly against each occluder (closed: a line along an edge
// that cancels still sees c >= 1 on both sides of it). Where y cannot be certified (a cell
// thinner than the rounding of its centroid), the cell is clipped by Algorithm 1 instead. The
// cells' vertices are rounded constructions, as the fragments of Algorithm 1 are (polygon_clip.h
// splitConstructed); no label depends on them.

namespace {

// plane.sign(y) (exact for an input point y) with the filter's path inlined, for both plane
// kinds (PlaneOrient::sign does this itself; PencilPlane's calls the out-of-line value()): these
// tests are the chain's innermost loop.
template <class Plane>
Sign exactSign(const Plane& plane, const Vec3& y) {
    BoundedValue b;
    if (plane.filtered(y, b)) return b.sign();
    return plane.value(y).sign();
}

}  // namespace

Sign FromPointQuery::refSign(uint32_t ref, const Vec3& y) const {
    return (ref & kPencilRef) != 0 ? exactSign(activePencils_[ref & ~kPencilRef], y)
                                   : exactSign(activePlanes_[ref], y);
}

SplitOutcome FromPointQuery::splitByRef(uint32_t ref, std::span<const Vec3> poly,
                                        SplitParts& parts) const {
    return (ref & kPencilRef) != 0
               ? splitConstructed(poly, activePencils_[ref & ~kPencilRef], light_, parts)
               : splitConstructed(poly, activePlanes_[ref], light_, parts);
}

bool FromPointQuery::useChain() {
    if (surface_ != nullptr || clustersActive()) {
        if (!chainBuilt_) buildChain();
        return true;
    }
    if (chainOptions_.minOccluders == 0 || active_.size() < chainOptions_.minOccluders)
        return false;
    if (!chainBuilt_) buildChain();
    return chainPays_;
}

void FromPointQuery::prepareCone() {
    // The cone from x over L itself, of exact planes (the pyramid over L clipped to B's front
    // has rounded vertices where B's plane cuts L): cells and their sample lines are bounded by
    // it. The occluders were gathered for the clipped pyramid, so c counts only them; in the
    // part of the cone beyond B's plane it is still a function constant on each cell, and on the
    // cells' part in front of B it is the answer.
    // Exact: every vertex of L strictly in front of B's plane (then the clip kept L as it is).
    lightWhole_ = true;
    for (const Vec3& v : light_) lightWhole_ = lightWhole_ && frontB_.side(v) == Sign::Positive;
    if (!lightWhole_) pyramidPlanes(x_, light_, lightCone_);
}

bool FromPointQuery::prepareSurface(const HistoryTree& tree) {
    const DeferredSilhouettes& s = tree.silhouettes;
    if (!s.usable() || chainOptions_.minOccluders == 0 ||
        tree.deferred.size() < chainOptions_.minOccluders)
        return false;
    const Bounds3& q = s.region;
    if (!(x_.x >= q.lo.x && x_.x <= q.hi.x && x_.y >= q.lo.y && x_.y <= q.hi.y && x_.z >= q.lo.z &&
          x_.z <= q.hi.z))
        return false;  // the sides decided for Q are not certainly x's
    surface_ = &s;
    surfaceActivated_ = false;
    if (slotStamp_.size() < s.slots.size()) {
        slotStamp_.resize(s.slots.size(), 0);
        slotSide_.resize(s.slots.size(), 0);
    }
    if (++runStamp_ == 0) {  // wrapped: no stale stamp may match
        std::fill(slotStamp_.begin(), slotStamp_.end(), 0);
        runStamp_ = 1;
    }
    prepareCone();
    stage_ = WorkStage::ActivateOccluders;
    for (uint32_t slot : s.clipped) {
        if (!spend()) return true;
        activateFace(*mesh_, tree.deferred[slot].face);
    }
    surfaceClipped_ = active_.size();
    stage_ = WorkStage::FindOccluders;
    // The kept edges whose segment may meet the cone over L (which holds the clipped pyramid):
    // the others cannot cut a cell.
    surfaceGroups_.clear();
    spend(s.groups.notOutside(cone(), surfaceGroups_, workBudgetLeft()));
    std::sort(surfaceGroups_.begin(), surfaceGroups_.end());  // deterministic order
    return true;
}

void FromPointQuery::activateSurface() {
    if (surfaceActivated_) return;
    surfaceActivated_ = true;
    stage_ = WorkStage::FindOccluders;
    lineSlots_.clear();
    if (!spend(tree_->deferredIndex.notOutside(pyramid_, lineSlots_, workBudgetLeft()))) return;
    std::sort(lineSlots_.begin(), lineSlots_.end());
    stage_ = WorkStage::ActivateOccluders;
    for (uint32_t slot : lineSlots_) {
        if (surface_->slots[slot] != DeferredSilhouettes::Slot::Surface) continue;
        if (!spend()) return;
        activateFace(*mesh_, tree_->deferred[slot].face);
    }
}

int FromPointQuery::sideAt(uint32_t slot) {
    const int8_t decided = surface_->sides[slot];
    // x in Q (decided for x_, not for a moved point's input: its contacts are tested below).
    if (decided != 0 && !moved_) return decided;
    if (slotStamp_[slot] == runStamp_) return slotSide_[slot];
    if (!spend()) return 0;
    const PlaneOrient plane = facePlane(*mesh_, tree_->deferred[slot].face).orient();
    const Sign s = moved_ && plane.sign(input_) == Sign::Zero ? Sign::Zero : exactSign(plane, x_);
    slotStamp_[slot] = runStamp_;
    slotSide_[slot] = static_cast<int8_t>(s == Sign::Positive ? 1 : s == Sign::Negative ? -1 : 0);
    return slotSide_[slot];
}

FromPointQuery::LineHit FromPointQuery::surfaceHitKind(uint32_t slot, const Vec3& y) {
    const int s = sideAt(slot);
    if (s == 0) return LineHit::Miss;  // x on its plane: it blocks nothing (activateFace)
    const LineHit hit = faceHitKind(tree_->deferred[slot].face, s, y);
    if (hit == LineHit::Miss) return hit;
    if (std::find(recentHits_.begin(), recentHits_.end(), slot) == recentHits_.end()) {
        recentHits_[recentNext_] = slot;
        recentNext_ = (recentNext_ + 1) % kRecentHits;
    }
    return hit;
}

FromPointQuery::LineHit FromPointQuery::faceHitKind(uint32_t face, int side, const Vec3& y) {
    // x in front of the face (side +1): the lines through it are on the negative side of the
    // planes through x and its edges (activateFace), so a positive sign misses.
    const auto& ids = mesh_->faces[face];
    const std::vector<Vec3>& v = mesh_->vertices;
    const Sign unblocked = side > 0 ? Sign::Positive : Sign::Negative;
    bool touch = false;
    for (size_t i = 0; i < ids.size(); ++i) {
        if (!spend()) return LineHit::Miss;
        const PlaneOrient plane(x_, v[ids[i]], v[ids[(i + 1) % ids.size()]]);
        const Sign sign = exactSign(plane, y);
        if (sign == unblocked) return LineHit::Miss;
        touch = touch || sign == Sign::Zero;
    }
    return touch ? LineHit::Touch : LineHit::Through;
}

void FromPointQuery::buildChain() {
    stage_ = WorkStage::BuildChain;
    chainBuilt_ = true;
    chainBuilder_.clear();
    for (const ActiveOccluder& o : active_) {
        const int weight = o.blocked == Sign::Negative ? 1 : -1;  // x in front of the face: +1
        for (uint32_t e = 0; e < o.planeCount; ++e) {
            const auto& [v0, v1] = activePlaneEdges_[o.firstPlane + e];
            chainBuilder_.add(v0, v1, weight, o.firstPlane + e);
        }
        // A chord is the face's own (no other face has it): it never cancels.
        for (uint32_t e = 0; e < o.pencilCount; ++e)
            chainBuilder_.add(kClipEdge | (o.firstPencil + e), 0, weight,
                              kPencilRef | (o.firstPencil + e));
    }
    uint32_t surfaceUses = 0;
    surfaceRemaining_.clear();
    surfaceSums_.clear();
    if (surface_ != nullptr) {
        // The kept edges in the cone, each use weighted by the side its face faces x (a face
        // whose plane holds x blocks nothing and adds none). An edge only surface faces use
        // remains where its weighted directions do not sum to zero; one a clipped face uses too
        // goes through the chain builder with that face's uses. A ref marks the use until its
        // edge is known to remain.
        for (uint32_t g : surfaceGroups_) {
            const uint32_t begin = surface_->groupBegin[g], end = surface_->groupBegin[g + 1];
            surfaceUses += end - begin;
            if (surface_->groupWithClipped[g]) {
                for (uint32_t u = begin; u < end; ++u) {
                    const DeferredSilhouettes::Use& use = surface_->uses[u];
                    const int weight = sideAt(use.slot);
                    if (weight != 0) chainBuilder_.add(use.v0, use.v1, weight, kSurfaceRef | u);
                }
                continue;
            }
            int sum = 0;
            for (uint32_t u = begin; u < end; ++u) {
                const DeferredSilhouettes::Use& use = surface_->uses[u];
                sum += sideAt(use.slot) * (use.v0 < use.v1 ? 1 : -1);
            }
            if (limitReached_) return;
            if (sum != 0) {
                surfaceRemaining_.push_back(kSurfaceRef | begin);
                surfaceSums_.push_back(sum);
            }
        }
    }
    // The used face groups' boundaries, each edge weighted by the side x sees its group from (the
    // group's inner edges cancel as its faces' would; its boundary edges are summed with the
    // other uses of the same edges).
    clusterEdges_.clear();
    if (clustersActive()) {
        for (const UsedCluster& c : usedClusters_) {
            for (const FaceClusters::Use& use : clusters_->boundary(c.cluster)) {
                chainBuilder_.add(use.lo, use.hi, c.side * use.weight,
                                  kClusterRef | static_cast<uint32_t>(clusterEdges_.size()));
                clusterEdges_.emplace_back(use.lo, use.hi);
            }
        }
    }
    chainBuilder_.remaining(chainRefs_, chainWeights_);
    // The remaining group edges get their planes through x now (the others never do).
    for (uint32_t& ref : chainRefs_) {
        if ((ref & kPencilRef) != 0 || (ref & kClusterRef) == 0) continue;
        const auto [lo, hi] = clusterEdges_[ref & ~kClusterRef];
        ref = static_cast<uint32_t>(activePlanes_.size());
        activePlanes_.emplace_back(x_, mesh_->vertices[lo], mesh_->vertices[hi]);
        activePlaneEdges_.emplace_back(lo, hi);
    }
    if (surface_ != nullptr) {
        chainRefs_.insert(chainRefs_.end(), surfaceRemaining_.begin(), surfaceRemaining_.end());
        chainWeights_.insert(chainWeights_.end(), surfaceSums_.begin(), surfaceSums_.end());
        // The remaining kept edges get their planes through x now (the others never do).
        for (uint32_t& ref : chainRefs_) {
            if ((ref & kPencilRef) != 0 || (ref & kSurfaceRef) == 0) continue;
            const DeferredSilhouettes::Use& use = surface_->uses[ref & ~kSurfaceRef];
            ref = static_cast<uint32_t>(activePlanes_.size());
            activePlanes_.emplace_back(x_, mesh_->vertices[use.v0], mesh_->vertices[use.v1]);
            activePlaneEdges_.emplace_back(use.v0, use.v1);
        }
    } else {
        prepareCone();
    }
    chainCounts_.occluderEdges = static_cast<uint32_t>(chainBuilder_.uses()) + surfaceUses;
    chainCounts_.boundaryEdges = static_cast<uint32_t>(chainRefs_.size());
    // The cells are decided one line each but are never dropped before the chain has cut them,
    // while Algorithm 1 drops a hidden part at once: the chain pays where most edges cancel
    // (closed and smooth surfaces), not among separate faces (leaves), where it only adds work.
    // (The surface path was chosen for the pair: its silhouettes pay.)
    chainPays_ = surface_ != nullptr || clustersActive() ||
                 chainRefs_.size() * chainOptions_.gain <= chainBuilder_.uses();
    chain_.clear();
    chainChords_ = false;
    chordsOnBLeftOut_ = false;
    if (!chainPays_) return;
    // x on or in front of B's plane (exact): seen from x, a chord on B's plane lies on or behind
    // that plane (the ray from x through a point of it goes on behind B), so it meets no line
    // from x to a point strictly in front of B, and no triangle of x and two such points: it
    // changes c nowhere in L's part in front of B, the answer's part. Such chords are left out
    // of the chain, and each cell is labelled from a point strictly in front of B's plane
    // (certifiedPoint), which holds its part in front of B. (With x behind B's plane by a
    // rounding they project into L within some ulps of the line where B's plane meets L's, and
    // are cut first.)
    const bool leaveOutChordsOnB = frontB_.orient.sign(x_) != Sign::Negative;
    if (chainLists_.empty()) chainLists_.resize(1);
    std::vector<uint32_t>& root = chainLists_[0];
    root.clear();
    for (size_t k = 0; k < chainRefs_.size(); ++k) {
        const uint32_t ref = chainRefs_[k];
        ChainEdge e;
        e.ref = ref;
        if ((ref & kPencilRef) != 0 && leaveOutChordsOnB && activePencilOnB_[ref & ~kPencilRef]) {
            chordsOnBLeftOut_ = true;
            continue;
        }
        if ((ref & kPencilRef) == 0) {
            const auto [v0, v1] = activePlaneEdges_[ref];
            e.segment = true;
            e.a = mesh_->vertices[v0];
            e.b = mesh_->vertices[v1];
            e.behindB = frontB_.orient.sign(e.a) == Sign::Negative ||
                        frontB_.orient.sign(e.b) == Sign::Negative;
            // The ref's plane is through x, v0, v1; the weight is the edge's from its lower id.
            e.jump = v0 < v1 ? chainWeights_[k] : -chainWeights_[k];
        }
        // Every vertex of L on one closed side of its plane: its line misses L's open cone.
        bool positive = false, negative = false;
        for (const Vec3& v : light_) {
            const Sign s = refSign(ref, v);
            positive = positive || s == Sign::Positive;
            negative = negative || s == Sign::Negative;
        }
        if (!positive || !negative) continue;
        // Its segment outside one side plane of the pyramid over L (closed): it misses the cone.
        bool outside = false;
        for (size_t k = 0; e.segment && !outside && k < cone().size(); ++k)
            outside = exactSign(cone()[k], e.a) != Sign::Positive &&
                      exactSign(cone()[k], e.b) != Sign::Positive;
        if (outside) continue;
        chainChords_ = chainChords_ || !e.segment;
        root.push_back(static_cast<uint32_t>(chain_.size()));
        chain_.push_back(e);
    }
    if (root.size() >= kLongestFirstMin) {
        // The cuts in order of the angle each segment spans from x (|a x b| / |a| |b|, rounded:
        // only an order, no decision), chords first (they bound the part of L in front of B):
        // an autopartition that cuts along long edges first makes fewer cells. Measured every
        // point exact at 128x128, 4 spp: dragon plane tests 604M -> 461M, CPU 12.0 -> 10.8 s;
        // motorbike (64x64, 2 spp) 590M -> 429M, 13.4 -> 11.9 s; the same images. Chords last
        // instead: 512M on the dragon.
        orderKeys_.clear();
        for (uint32_t i : root) {
            const ChainEdge& e = chain_[i];
            double span = 2;  // (above any segment's: a sine)
            if (e.segment) {
                const Vec3 a = e.a - x_, b = e.b - x_;
                span = length(cross(a, b)) / (length(a) * length(b));
            }
            orderKeys_.emplace_back(-span, i);
        }
        std::sort(orderKeys_.begin(), orderKeys_.end());
        for (size_t k = 0; k < root.size(); ++k) root[k] = orderKeys_[k].second;
    } else {
        // Chords first here too: the cells below them lie on one side of every chord's plane,
        // where the crossings need no chord (countByCrossings, decideCellWhole).
        std::stable_partition(root.begin(), root.end(),
                              [&](uint32_t i) { return !chain_[i].segment; });
    }
    // Cells may be labelled by crossings when c(y) changes only across the chain's edges: no
    // occluder cut by L's plane (c would also change where y passes through such an occluder,
    // near its chord in L's plane). An occluder cut by B's plane has its chord on B's plane; seen
    // from x on B's plane that chord lies on the line where B's plane meets L's, outside L's
    // part in front of B, but with x off B's plane by a rounding (a rendered point, or one
    // rounded from a wall's contact line) the plane through x and the chord turns through L
    // within some ulps of that line, and c jumps there by an amount the chain does not hold.
    // Such chords are cut first (above): a path between two points strictly on one side of
    // every chord's plane crosses no chord, and one that may cross a chord's plane is counted on
    // its line instead (countByCrossings; decideCellWhole decides no cell a chord may still
    // cut). (Before, any such chord in L's cone left every cell of the point to its line test,
    // and none was decided whole: on the motorbike, whose faces' planes often cut the light, its
    // points over the work limit took 7.3 ms each with every point exact, 5.5 ms since.) And only
    // for a long chain: on a short one a cell's line test, which stops at the first face that
    // hides it, costs less than the count that starts the crossings.
    crossings_ = !lightChord_ && chain_.size() >= chainOptions_.crossingsMinEdges;
    if (crossings_ && sideRef_.size() < chain_.size()) {
        sideRef_.resize(chain_.size());
        sideY_.resize(chain_.size());
        stampRef_.resize(chain_.size(), 0);
        stampY_.resize(chain_.size(), 0);
    }
    bounds_.clear();
}

void FromPointQuery::chainCells(std::span<const Vec3> poly, size_t depth, size_t level) {
    stage_ = WorkStage::CutCells;
    const size_t boundsAtEntry = bounds_.size();
    if (level == 0) {  // a part of L the walk kept: any chain edge may lie between it and the last
        crossLevel_ = 0;
        crossIndex_ = 0;
    }
    if (wholeTriedAt_.size() <= level) wholeTriedAt_.resize(level + 1);
    const size_t listSize = chainLists_[level].size();
    wholeTriedAt_[level] = level == 0 ? SIZE_MAX : wholeTriedAt_[level - 1];
    if (crossings_ && level > 0 && listSize <= kWholeMax && listSize > 1 &&
        2 * listSize <= wholeTriedAt_[level]) {
        wholeTriedAt_[level] = listSize;
        if (decideCellWhole(poly, level)) return;
    }
    for (size_t i = 0; i < chainLists_[level].size(); ++i) {
        if (!spend()) return;
        const ChainEdge& e = chain_[chainLists_[level][i]];
        SplitOutcome outcome = splitByRef(e.ref, poly, partsAt(depth));
        if (outcome == SplitOutcome::OnPlane) {  // a cell of zero area
            bounds_.resize(boundsAtEntry);
            return;
        }
        if (outcome != SplitOutcome::Split) {
            bounds_.push_back({e.ref,
                               outcome == SplitOutcome::Positive ? Sign::Positive : Sign::Negative,
                               chainLists_[level][i]});
            continue;
        }
        // Two cells: each takes the rest of the list but the edges whose segment lies on the
        // other side of this plane (closed; exact signs of the segment's input end points).
        const SplitParts& parts = parts_[depth];
        const std::span<const Vec3> sides[2] = {parts.positive(), parts.negative()};
        if (chainLists_.size() <= level + 1) chainLists_.resize(level + 2);
        if (chainSides_.size() <= level) chainSides_.resize(level + 1);
        // Per remaining edge, the sides its segment reaches (bit 0: positive, bit 1: negative),
        // taken once for both cells.
        std::vector<uint8_t>& reach = chainSides_[level];
        reach.clear();
        for (size_t j = i + 1; j < chainLists_[level].size(); ++j) {
            const ChainEdge& f = chain_[chainLists_[level][j]];
            uint8_t r = 3;
            if (f.segment) {
                if (!spend(2)) return;
                const Sign sa = refSign(e.ref, f.a), sb = refSign(e.ref, f.b);
                r = static_cast<uint8_t>((sa == Sign::Positive || sb == Sign::Positive ? 1 : 0) |
                                         (sa == Sign::Negative || sb == Sign::Negative ? 2 : 0));
            }
            reach.push_back(r);
        }
        for (int k = 0; k < 2; ++k) {
            const Sign side = k == 0 ? Sign::Positive : Sign::Negative;
            std::vector<uint32_t>& next = chainLists_[level + 1];
            next.clear();
            for (size_t j = i + 1; j < chainLists_[level].size(); ++j)
                if ((chainSides_[level][j - i - 1] & (1 << k)) != 0)
                    next.push_back(chainLists_[level][j]);
            if (k == 1 && (crossLevel_ == kNoLevel || level < crossLevel_)) {
                // The next cell is on the other side of this split from the last counted one.
                crossLevel_ = level;
                crossIndex_ = i;
            }
            bounds_.push_back({e.ref, side, chainLists_[level][i]});
            chainCells(sides[k], depth + 1, level + 1);
            bounds_.pop_back();
            if (limitReached_) return;
        }
        bounds_.resize(boundsAtEntry);
        return;
    }
    classifyCell(poly, depth);
    bounds_.resize(boundsAtEntry);
}

void FromPointQuery::classifyCell(std::span<const Vec3> poly, size_t depth) {
    stage_ = WorkStage::LabelCells;
    ++chainCounts_.cells;
    if (poly.size() < 3) return;
    Vec3 y;
    const bool certified = certifiedPoint(poly, y);
    if (limitReached_) return;
    if (!certified) {
        ++chainCounts_.fallbacks;
        if (surface_ != nullptr) activateSurface();
        if (clustersActive()) dissolveClusters();
        if (limitReached_) return;
        clipByOccluders(poly, 0, depth);
        return;
    }
    if (crossings_) {
        // c(y) from the last counted cell's, else from the line; the cell is seen where it is 0.
        std::optional<int> c;
        if (haveRef_) {
            c = countByCrossings(y);
            if (c) ++chainCounts_.crossingLabels;
        }
        if (!c && !limitReached_) c = countLine(y);
        if (limitReached_) return;
        if (c && *c >= 0) {
            takeRef(y, *c, kNoLevel);
            if (*c == 0) fragments_.add(poly);
            return;
        }
        haveRef_ = false;  // (a negative count cannot be: tested on the line instead)
    }
    if (lineBlocked(y) || limitReached_) return;
    fragments_.add(poly);
}

bool FromPointQuery::certifiedPoint(std::span<const Vec3> poly, Vec3& y) {
    y = Vec3{};
    for (const Vec3& v : poly) y += v;
    y = y / static_cast<double>(poly.size());
    bool certified = true;
    for (const PlaneOrient& h : cone()) {
        if (!spend()) return false;
        if (exactSign(h, y) != Sign::Positive) certified = false;
    }
    if (certified && chordsOnBLeftOut_) {
        if (!spend()) return false;
        certified = frontB_.orient.sign(y) == Sign::Positive;
    }
    if (crossings_) nextYStamp();
    for (size_t k = 0; certified && k < bounds_.size(); ++k) {
        if (!spend()) return false;
        const Sign s = refSign(bounds_[k].ref, y);
        certified = s == bounds_[k].side;
        if (crossings_) {  // the side of y the crossings count needs too (countByCrossings)
            sideY_[bounds_[k].edge] = static_cast<int8_t>(s);
            stampY_[bounds_[k].edge] = yStamp_;
        }
    }
    return certified;
}

void FromPointQuery::takeRef(const Vec3& y, int count, size_t level) {
    haveRef_ = true;
    refY_ = y;
    refCount_ = count;
    // The chain edges' sides taken at y are now the ref's.
    std::swap(sideRef_, sideY_);
    std::swap(stampRef_, stampY_);
    refStamp_ = yStamp_;
    crossLevel_ = level;
    crossIndex_ = 0;
}

void FromPointQuery::nextYStamp() {
    if (++yStamp_ == 0) {  // wrapped: no stale stamp may match
        std::fill(stampRef_.begin(), stampRef_.end(), 0);
        std::fill(stampY_.begin(), stampY_.end(), 0);
        yStamp_ = 1;
    }
}

bool FromPointQuery::decideCellWhole(std::span<const Vec3> poly, size_t level) {
    // Exact, with crossings_ (c changes only across the chain's segments, by their weights):
    // every point z of the open cell is reached from y along the segment y -> z inside the
    // (convex) cell, which crosses each chain segment at most once, and only those left in this
    // level's list can meet the cell (the others were put on one side of a plane bounding it).
    // Leaving y's side of an edge's plane changes c by +jump from its positive side and -jump
    // from its negative side; so c(z) lies between c(y) - down and c(y) + up, the sums of the
    // decreases and increases the list's edges could bring (an edge whose plane holds y counts
    // both ways). c >= 1 on the whole cell when c(y) > down; c = 0 on it when c(y) = 0 and
    // up = 0 (c is never negative). y is certified as a leaf's point is; the sides are exact.
    stage_ = WorkStage::LabelCells;
    if (poly.size() < 3) return false;
    if (chainChords_) {  // a chord left in the list may cut the cell: its jump is not known
        for (uint32_t idx : chainLists_[level])
            if (!chain_[idx].segment) return false;
    }
    Vec3 y;
    const bool certified = certifiedPoint(poly, y);
    if (limitReached_) return true;
    if (!certified) return false;
    std::optional<int> c;
    if (haveRef_) c = countByCrossings(y);
    if (!c && !limitReached_) c = countLine(y);
    if (limitReached_) return true;
    if (!c || *c < 0) return false;
    int down = 0, up = 0;
    for (uint32_t idx : chainLists_[level]) {
        const ChainEdge& e = chain_[idx];
        Sign s;
        if (stampY_[idx] == yStamp_) {
            s = static_cast<Sign>(sideY_[idx]);
        } else {
            if (!spend()) return true;
            s = refSign(e.ref, y);
            sideY_[idx] = static_cast<int8_t>(s);
            stampY_[idx] = yStamp_;
        }
        const int toNegative = e.jump, toPositive = -e.jump;
        if (s != Sign::Negative) {  // may leave the positive side (or the plane)
            down += std::max(0, -toNegative);
            up += std::max(0, toNegative);
        }
        if (s != Sign::Positive) {
            down += std::max(0, -toPositive);
            up += std::max(0, toPositive);
        }
    }
    // y is the ref from now on; the path from it to any later cell point inside this cell lies
    // in this cell, which only this level's list may cross.
    takeRef(y, *c, level);
    if (*c > down) {
        ++chainCounts_.cells;
        ++chainCounts_.hiddenWhole;
        return true;
    }
    if (*c == 0 && up == 0) {
        ++chainCounts_.cells;
        ++chainCounts_.seenWhole;
        fragments_.add(poly);
        return true;
    }
    return false;
}

std::optional<int> FromPointQuery::countByCrossings(const Vec3& y) {
    // As y moves to y' along the segment between them (inside L), the line from x sweeps the
    // triangle (x, y, y'), and c changes by an edge's weight exactly where the triangle's
    // interior meets the edge's segment (an edge of weight 0 changes nothing; the chain holds
    // every edge of nonzero weight that may meet the cone over L). Exact: orient3d signs at the
    // input end points, x, and the two sample points; any zero where it could matter (the
    // triangle touches an edge, or an end point lies in its plane) gives up.
    if (crossLevel_ == kNoLevel) return std::nullopt;
    int c = refCount_;
    const std::vector<uint32_t>& list = chainLists_[crossLevel_];
    // Whether the triangle (x, ref, y) lies in the closed half-space in front of B's plane
    // (exact signs; asked only when an edge cut by that plane crosses it: 0 = not yet known).
    int triangleInFront = 0;
    for (size_t j = crossIndex_; j < list.size(); ++j) {
        const ChainEdge& e = chain_[list[j]];
        const uint32_t idx = list[j];
        Sign s0;
        if (stampRef_[idx] == refStamp_) {
            s0 = static_cast<Sign>(sideRef_[idx]);
        } else {
            if (!spend()) return std::nullopt;
            s0 = refSign(e.ref, refY_);
        }
        Sign s1;
        if (stampY_[idx] == yStamp_) {  // a bound of y's cell: taken when it was certified
            s1 = static_cast<Sign>(sideY_[idx]);
        } else {
            if (!spend()) return std::nullopt;
            s1 = refSign(e.ref, y);
            sideY_[idx] = static_cast<int8_t>(s1);  // the ref's own side if y becomes the ref
            stampY_[idx] = yStamp_;
        }
        if (s0 == s1 && s0 != Sign::Zero) continue;  // both strictly on one side of its plane
        // A chord's plane between them: the path may cross the chord, by an unknown jump.
        if (!e.segment) return std::nullopt;
        if (!spend(5)) return std::nullopt;
        const Sign qa = orientSign(x_, refY_, y, e.a), qb = orientSign(x_, refY_, y, e.b);
        if (qa == qb && qa != Sign::Zero) continue;  // the segment misses the triangle's plane
        if (qa == Sign::Zero || qb == Sign::Zero) return std::nullopt;
        // The segment's line against the triangle's three sides.
        const Sign t0 = orientSign(e.a, e.b, x_, refY_), t1 = orientSign(e.a, e.b, refY_, y),
                   t2 = orientSign(e.a, e.b, y, x_);
        if ((t0 == -t1 && t0 != Sign::Zero) || (t1 == -t2 && t1 != Sign::Zero) ||
            (t2 == -t0 && t2 != Sign::Zero))
            continue;  // it passes beside the triangle
        if (t0 == Sign::Zero || t1 == Sign::Zero || t2 == Sign::Zero) return std::nullopt;
        // Through the interior: then y and y' are strictly on either side of the edge's plane.
        if (s0 == Sign::Zero || s1 == Sign::Zero || s0 == s1) return std::nullopt;
        // An edge cut by B's plane bounds its occluder only in front of that plane: the crossing
        // counts where the triangle lies there (x, the ref and y on its closed front side: a
        // rendered x is often a rounding behind it), else the line decides.
        if (e.behindB) {
            if (triangleInFront == 0) {
                if (!spend(3)) return std::nullopt;
                const bool front = frontB_.orient.sign(x_) != Sign::Negative &&
                                   frontB_.orient.sign(refY_) != Sign::Negative &&
                                   frontB_.orient.sign(y) != Sign::Negative;
                triangleInFront = front ? 1 : -1;
            }
            if (triangleInFront < 0) return std::nullopt;
        }
        c += s0 == Sign::Positive ? e.jump : -e.jump;
    }
    return c;
}

std::optional<int> FromPointQuery::countLine(const Vec3& y) {
    // Every occluder the line crosses, through its interior (a line that touches one's boundary
    // is where c jumps: no count).
    int c = 0;
    bool touch = false;
    auto add = [&](LineHit h) {
        if (h == LineHit::Touch) touch = true;
        if (h == LineHit::Through) ++c;
        return touch || limitReached_;
    };
    if (surface_ != nullptr) {
        for (size_t j = 0; j < surfaceClipped_; ++j)
            if (add(lineHitKind(j, y))) return std::nullopt;
        setLinePlanes(y);
        uint32_t visited = 0;
        tree_->deferredIndex.anyNotOutside(
            linePlanes_,
            [&](uint32_t slot) {
                if (limitReached_) return true;
                return surface_->slots[slot] == DeferredSilhouettes::Slot::Surface &&
                       add(surfaceHitKind(slot, y));
            },
            visited);
        spend(visited);
        if (touch || limitReached_) return std::nullopt;
        return c;
    }
    if (!activeBoxesBuilt_) {  // (as lineBlocked: a scan first, the hierarchy once it pays)
        scanned_ += active_.size();
        for (size_t j = 0; j < active_.size(); ++j)
            if (add(lineHitKind(j, y))) return std::nullopt;
    } else {
        setLinePlanes(y);
        onLine_.clear();
        if (!spend(activeBoxes_.notOutside(linePlanes_, onLine_))) return std::nullopt;
        for (uint32_t j : onLine_)
            if (add(lineHitKind(j, y))) return std::nullopt;
    }
    if (clustersActive()) {  // and the used groups' faces
        setLinePlanes(y);
        clusterFacesOnLine(
            [&](uint32_t face, int side) { return add(faceHitKind(face, side, y)); });
        if (touch || limitReached_) return std::nullopt;
    }
    return c;
}

void FromPointQuery::buildActiveBoxes() {
    // (Rebuilt when occluders were activated since: activateSurface adds some late.)
    if (activeBoxesBuilt_ && activeBoxList_.size() == active_.size()) return;
    activeBoxesBuilt_ = true;
    activeBoxList_.clear();
    for (const ActiveOccluder& o : active_) activeBoxList_.push_back(mesh_->faceBounds(o.face));
    activeBoxes_ = BoxTree(activeBoxList_);
}

void FromPointQuery::setLinePlanes(const Vec3& y) {
    // A point of an occluder on the line lies in every plane through x and y: its box is on no
    // such plane's strictly negative side, whichever way it is turned. Two planes at right angles
    // about the line keep only boxes near it (two of nearly one plane would keep a whole slab):
    // through a third point p off the line, any double (the cull is rigorous for the plane
    // through x, y and p, which holds the line; planes made degenerate by rounding cull nothing:
    // still sound).
    const Vec3 d = y - x_;
    const double ax = std::abs(d.x), ay = std::abs(d.y), az = std::abs(d.z);
    const Vec3 axis = ax <= ay && ax <= az ? Vec3{1, 0, 0}
                      : ay <= az           ? Vec3{0, 1, 0}
                                           : Vec3{0, 0, 1};
    const Vec3 u = cross(d, axis), v = cross(d, u);
    const double lu = length(u), lv = length(v), ld = length(d);
    const Vec3 p1 = lu > 0 ? y + u * (ld / lu) : light_[0];
    const Vec3 p2 = lv > 0 ? y + v * (ld / lv) : light_[1];
    linePlanes_.clear();
    linePlanes_.emplace_back(x_, y, p1);
    linePlanes_.emplace_back(x_, p1, y);
    linePlanes_.emplace_back(x_, y, p2);
    linePlanes_.emplace_back(x_, p2, y);
}

bool FromPointQuery::lineBlocked(const Vec3& y) {
    if (surface_ != nullptr) {
        // The activated faces that cross B's or L's plane, then the Surface faces (not
        // activated: tested from their input edges), the last few that hid a cell first.
        for (size_t j = 0; j < surfaceClipped_; ++j) {
            if (lineHits(j, y)) return true;
            if (limitReached_) return false;
        }
        for (uint32_t k = 0; k < kRecentHits; ++k) {
            const uint32_t slot = recentHits_[(recentNext_ + kRecentHits - 1 - k) % kRecentHits];
            if (slot < surface_->slots.size() &&
                surface_->slots[slot] == DeferredSilhouettes::Slot::Surface && surfaceHits(slot, y))
                return true;
        }
        // Each face as the hierarchy finds it: the first hit ends the search.
        setLinePlanes(y);
        uint32_t visited = 0;
        const bool hit = tree_->deferredIndex.anyNotOutside(
            linePlanes_,
            [&](uint32_t slot) {
                if (limitReached_) return true;
                return surface_->slots[slot] == DeferredSilhouettes::Slot::Surface &&
                       surfaceHits(slot, y);
            },
            visited);
        spend(visited);
        return hit && !limitReached_;
    }
    // The line through y against the occluders (closed), the last one that hid a cell first.
    const size_t n = active_.size();
    if (n == 0) return clustersActive() && clusterLineBlocked(y);
    if (lineHits(lastHit_ % n, y)) return true;
    if (!activeBoxesBuilt_ && scanned_ >= kScanBeforeBoxes * n) buildActiveBoxes();
    if (activeBoxesBuilt_) {
        setLinePlanes(y);
        onLine_.clear();
        if (!spend(activeBoxes_.notOutside(linePlanes_, onLine_))) return false;
        for (uint32_t j : onLine_) {
            if (lineHits(j, y)) return true;
            if (limitReached_) return false;
        }
    } else {
        for (size_t t = 1; t < n; ++t) {
            if (lineHits((lastHit_ + t) % n, y)) return true;
            if (limitReached_) return false;
        }
        scanned_ += n;
    }
    return clustersActive() && clusterLineBlocked(y);
}

bool FromPointQuery::clusterLineBlocked(const Vec3& y) {
    // The group faces that hid the last cells first (a hidden cell's neighbour is mostly hidden
    // by the same few), then each face as the walk finds it: the first hit ends it.
    for (uint32_t k = 0; k < kRecentHits; ++k) {
        const auto [face, side] =
            recentClusterHits_[(recentClusterNext_ + kRecentHits - 1 - k) % kRecentHits];
        if (side != 0 && faceHitKind(face, side, y) != LineHit::Miss) return true;
        if (limitReached_) return false;
    }
    setLinePlanes(y);
    const bool hit = clusterFacesOnLine([&](uint32_t face, int side) {
        if (faceHitKind(face, side, y) == LineHit::Miss) return limitReached_;
        recentClusterHits_[recentClusterNext_] = {face, side};
        recentClusterNext_ = (recentClusterNext_ + 1) % kRecentHits;
        return true;
    });
    return hit && !limitReached_;
}

template <class Visit>
bool FromPointQuery::clusterFacesOnLine(Visit&& visit) {
    // Down the stamped nodes to the used groups, and through each group's nodes, with the line's
    // planes (a face on the line is on no plane's strictly negative side).
    const BoxTree& t = *clusterTree_;
    std::array<PlaneBoxCull, 4> planes;
    const std::span<const PlaneBoxCull> cull = t.cullPlanes(linePlanes_, planes);
    auto off = [&](const Bounds3& b) { return BoxTree::outsideOne(cull, b); };
    // Each entry: a node and the side of the group it lies in (0: above the used groups).
    std::pair<uint32_t, int> stack[160];
    int top = 0;
    if (nodeStamp_[0] == nodeRun_) stack[top++] = {0, 0};
    while (top > 0) {
        auto [node, side] = stack[--top];
        if (side == 0) {
            if (nodeStamp_[node] != nodeRun_) continue;
            side = nodeSide_[node];
        }
        if (!spend()) return true;
        if (off(t.nodeBox(node))) continue;
        if (t.isLeaf(node)) {
            if (side == 0) continue;  // (a leaf above a group: cannot be)
            for (uint32_t face : t.nodeItems(node))
                if (!off(t.itemBox(face)) && visit(face, side)) return true;
            continue;
        }
        stack[top++] = {t.rightChild(node), side};
        stack[top++] = {node + 1, side};
    }
    return false;
}

void FromPointQuery::dissolveClusters() {
    stage_ = WorkStage::ActivateOccluders;
    for (const UsedCluster& c : usedClusters_) {
        for (uint32_t face : clusterTree_->nodeItems(c.node)) {
            if (!spend()) return;
            activateFace(*mesh_, face);
        }
    }
    clustersDissolved_ = true;
}

FromPointQuery::LineHit FromPointQuery::lineHitKind(size_t j, const Vec3& y) {
    const ActiveOccluder& o = active_[j];
    const Sign unblocked = o.blocked == Sign::Positive ? Sign::Negative : Sign::Positive;
    bool touch = false;
    for (uint32_t e = 0; e < o.planeCount; ++e) {
        if (!spend()) return LineHit::Miss;
        const Sign s = exactSign(activePlanes_[o.firstPlane + e], y);
        if (s == unblocked) return LineHit::Miss;
        touch = touch || s == Sign::Zero;
    }
    for (uint32_t e = 0; e < o.pencilCount; ++e) {
        if (!spend()) return LineHit::Miss;
        const Sign s = exactSign(activePencils_[o.firstPencil + e], y);
        if (s == unblocked) return LineHit::Miss;
        touch = touch || s == Sign::Zero;
    }
    lastHit_ = static_cast<uint32_t>(j);
    return touch ? LineHit::Touch : LineHit::Through;
}

void FromPointQuery::preparePyramid() {
    // The pyramid from x over L (clipped to B's front): a line from x to L lies inside it, so an
    // occluder with no vertex strictly inside one of its side planes blocks none of them.
    pyramidPlanes(x_, lightClipped_, pyramid_);
}

void FromPointQuery::activateFace(const PolygonMesh& mesh, uint32_t face) {
    stage_ = WorkStage::ActivateOccluders;
    // x on the occluder's plane: every segment from x meets that plane at x only, so the
    // occluder blocks none (the contact rule: a segment that touches an occluder only at its end
    // point x is not blocked).
    const auto& ids = mesh.faces[face];
    const PlaneOrient plane = facePlane(mesh, face).orient();
    const Sign side = occluderSide(plane);
    if (side == Sign::Zero) return;
    // Seen from behind on a closed surface taken as a solid: the faces seen from the front block
    // every segment that this one would (prepareSolids).
    if (side == Sign::Negative && solidState_ == SolidState::Ready &&
        solidComponent(clusters_->surfaces().componentOf(face))) {
        ++solidFacesLeft_;
        return;
    }
    // Outside the pyramid from x over L as a whole face: its clipped part is too (a subset). The
    // cheap rejection, before any clip: most candidates of the box hierarchy end here.
    for (const PlaneOrient& h : pyramid_) {
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
    clipped_.clip(mesh, face, frontB_.orient, frontL_.orient);
    if (clipped_.empty()) return;
    // Outside the pyramid from x over L (exact on the clipped polygon's symbolic vertices).
    for (const PlaneOrient& h : pyramid_)
        if (clipped_.outside(h)) return;
    // Seen from x in front of its plane, the occluder is counter-clockwise, and the lines from x
    // through it lie on the negative side of every plane through x and an edge line a -> b:
    // orient3d(x, p, a, b) = -orient3d(p, a, b, x) for p inside it.
    ActiveOccluder a;
    a.face = face;
    a.firstPlane = static_cast<uint32_t>(activePlanes_.size());
    a.firstPencil = static_cast<uint32_t>(activePencils_.size());
    a.blocked = side == Sign::Positive ? Sign::Negative : Sign::Positive;
    for (const auto& [v0, v1] : clipped_.edges()) {
        if (!isClipEdge(v0)) {
            activePlanes_.emplace_back(x_, mesh.vertices[v0], mesh.vertices[v1]);
            activePlaneEdges_.emplace_back(v0, v1);
        } else {
            const bool onB = v1 == kReceiverPlaneEdge;
            lightChord_ = lightChord_ || !onB;
            activePencilOnB_.push_back(onB ? 1 : 0);
            activePencils_.emplace_back(x_, onB ? frontB_.orient : frontL_.orient,
                                        clipPlaneAt(onB ? 0 : 1), plane);
        }
    }
    a.planeCount = static_cast<uint32_t>(activePlanes_.size()) - a.firstPlane;
    a.pencilCount = static_cast<uint32_t>(activePencils_.size()) - a.firstPencil;
    active_.push_back(a);
}

void FromPointQuery::prepareDeferred(const PolygonMesh& mesh, const HistoryTree& tree) {
    active_.clear();
    activePlanes_.clear();
    activePencils_.clear();
    activePencilOnB_.clear();
    activePlaneEdges_.clear();
    deferredClips_ = 0;
    if (!tree.partial()) return;
    preparePyramid();
    if (prepareSurface(tree)) return;
    // The occluders whose box may meet the pyramid, in the order the hierarchy finds them.
    if (!tree.deferredIndex.empty()) {
        if (!findCandidates(tree.deferredIndex)) return;
    } else {
        candidates_.clear();
        for (uint32_t k = 0; k < tree.deferred.size(); ++k) candidates_.push_back(k);
    }
    stage_ = WorkStage::ActivateOccluders;
    for (uint32_t k : candidates_) {
        if (!spend()) return;
        activateFace(mesh, tree.deferred[k].face);
    }
}

bool FromPointQuery::findCandidates(const BoxTree& index) {
    stage_ = WorkStage::FindOccluders;
    candidates_.clear();
    if (!spend(index.notOutside(pyramid_, candidates_, workBudgetLeft()))) return false;
    return true;
}

struct FromPointQuery::ClusterWalk {
    const BoxTree& faces;
    const FaceClusters& clusters;
    std::span<const PlaneBoxCull> pyramid;
    // B's and L's planes turned around: a box strictly on their negative side lies strictly in
    // front of B and of L (PlaneBoxCull over the hierarchy's root box, rigorous), so no face in
    // it is clipped.
    PlaneBoxCull behindB, behindL;
};

bool FromPointQuery::findClustered(const BoxTree& faces, const FaceClusters& clusters) {
    stage_ = WorkStage::FindOccluders;
    candidates_.clear();
    usedClusters_.clear();
    clustersByExactSides_ = 0;
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
    const ClusterWalk walk{
        faces, clusters, faces.cullPlanes(pyramid_, cull),
        PlaneBoxCull(PlaneOrient(frontB_.a, frontB_.c, frontB_.b), region.lo, region.hi),
        PlaneBoxCull(PlaneOrient(frontL_.a, frontL_.c, frontL_.b), region.lo, region.hi)};
    walkClusters(0, walk);
    if (limitReached_) return false;
    return true;
}

int FromPointQuery::exactFacing(std::span<const uint32_t> faces) {
    // Exact: each face's plane (through its first three vertices, as activateFace takes it) at
    // x; the first face that disagrees, or has x on its plane, ends the test.
    int side = 0;
    for (uint32_t face : faces) {
        if (!spend()) return 0;
        const Sign s = occluderSide(facePlane(*preparedMesh_, face).orient());
        const int f = s == Sign::Positive ? 1 : s == Sign::Negative ? -1 : 0;
        if (f == 0 || (side != 0 && f != side)) return 0;
        side = f;
    }
    return side;
}

bool FromPointQuery::walkClusters(uint32_t node, const ClusterWalk& w) {
    if (!spend()) return false;
    const Bounds3& box = w.faces.nodeBox(node);
    if (BoxTree::outsideOne(w.pyramid, box)) return false;
    const uint32_t cluster = w.clusters.clusterAt(node);
    if (cluster != FaceClusters::kNone && w.behindB.negative(box.lo, box.hi) &&
        w.behindL.negative(box.lo, box.hi)) {
        // (The cone test certifies x_'s side with some slack, not the input's contacts: a moved
        // point takes the exact sides.)
        int side = moved_ ? 0 : w.clusters.facing(cluster, x_);
        if (side == 0 && w.faces.nodeItems(node).size() <= kExactFacingMax) {
            side = exactFacing(w.faces.nodeItems(node));
            clustersByExactSides_ += side != 0 ? 1 : 0;
        }
        if (limitReached_) return false;
        if (side != 0) {
            usedClusters_.push_back({node, cluster, side});
            nodeStamp_[node] = nodeRun_;
            nodeSide_[node] = static_cast<int8_t>(side);
            return true;
        }
    }
    if (w.faces.isLeaf(node)) {
        for (uint32_t face : w.faces.nodeItems(node))
            if (!BoxTree::outsideOne(w.pyramid, w.faces.itemBox(face))) candidates_.push_back(face);
        return false;
    }
    const bool left = walkClusters(node + 1, w);
    if (limitReached_) return false;
    const bool right = walkClusters(w.faces.rightChild(node), w);
    if (left || right) {
        nodeStamp_[node] = nodeRun_;
        nodeSide_[node] = 0;
    }
    return left || right;
}

bool FromPointQuery::worthSolids() const {
    // The checks cost a walk along one segment and a pass over the candidates: taken where
    // enough may be left out (ChainOptions::solidMinFaces; measured on the bunny, every point
    // exact: 16 candidates or any group seen from behind made the median evaluation 0.23 ->
    // 0.28 us).
    size_t behind = 0;  // faces in groups seen from behind
    for (const UsedCluster& c : usedClusters_)
        if (c.side < 0 && clusters_->componentOf(c.cluster) != FaceClusters::kNone)
            behind += clusterTree_->nodeItems(c.node).size();
    return candidates_.size() + behind / 4 >= chainOptions_.solidMinFaces;
}

std::optional<int> FromPointQuery::segmentCrossing(uint32_t face, const Vec3& v) {
    const PolygonMesh& mesh = *preparedMesh_;
    const auto& ids = mesh.faces[face];
    const PlaneOrient plane = facePlane(mesh, face).orient();
    const Sign sx = plane.sign(x_), sv = plane.sign(v);
    // x in its plane: the segment meets it at x only (the contact rule; a face through x is no
    // solid's, prepareSolids); v in it: at v only, and a face that holds v reaches L's plane.
    if (sx == Sign::Zero || sv == Sign::Zero || sx == sv) return 0;
    // Through the face's interior: the line on one strict side of every edge line.
    bool positive = false, negative = false, zero = false;
    for (size_t i = 0; i < ids.size(); ++i) {
        const Sign s =
            orientSign(x_, v, mesh.vertices[ids[i]], mesh.vertices[ids[(i + 1) % ids.size()]]);
        positive = positive || s == Sign::Positive;
        negative = negative || s == Sign::Negative;
        zero = zero || s == Sign::Zero;
    }
    if (positive && negative) return 0;
    if (zero) return std::nullopt;
    return sx == Sign::Positive ? 1 : -1;
}

bool FromPointQuery::prepareSolids() {
    if (solidState_ != SolidState::Unknown) return solidState_ == SolidState::Ready;
    solidState_ = SolidState::Off;
    const ClosedSurfaces& surfaces = clusters_->surfaces();
    const PolygonMesh& mesh = *preparedMesh_;
    const uint32_t n = surfaces.componentCount();
    if (n == 0 || clusterTree_->empty()) return false;
    stage_ = WorkStage::FindOccluders;
    if (componentStamp_.size() < n) {
        componentStamp_.resize(n, 0);
        componentWinding_.resize(n, 0);
        windingStamp_.resize(n, 0);
    }
    if (++solidRun_ == 0) {  // wrapped: no stale stamp may match
        std::fill(componentStamp_.begin(), componentStamp_.end(), 0);
        std::fill(windingStamp_.begin(), windingStamp_.end(), 0);
        solidRun_ = 1;
    }
    auto notSolid = [&](uint32_t component) { componentStamp_[component] = solidRun_; };
    auto solid = [&](uint32_t component) { return componentStamp_[component] != solidRun_; };
    const Sign xB = frontB_.orient.sign(x_);
    notSolid(surfaces.componentOf(preparedLight_));
    // x behind B's plane by a rounding: what lies in B's plane (B's own edges, the chords where
    // it cuts faces) may reach into the open cone near x; each such element must be shown to
    // miss it (missesCone), else its component is no solid.
    if (xB == Sign::Negative) {
        const auto& ids = mesh.faces[preparedReceiver_];
        for (size_t i = 0; i < ids.size(); ++i) {
            if (!spend(light_.size())) return false;
            if (lightSideOf(mesh.vertices[ids[i]], mesh.vertices[ids[(i + 1) % ids.size()]]) ==
                Sign::Zero)
                notSolid(surfaces.componentOf(preparedReceiver_));
        }
    }
    // Open edges in the pyramid (closed: an edge on its boundary counts).
    solidFound_.clear();
    if (!surfaces.openEdgeTree().empty() &&
        !spend(surfaces.openEdgeTree().notOutside(pyramid_, solidFound_, workBudgetLeft())))
        return false;
    for (uint32_t e : solidFound_) {
        const ClosedSurfaces::OpenEdge& o = surfaces.openEdges()[e];
        if (!solid(o.component)) continue;
        bool outside = false;
        for (const PlaneOrient& h : pyramid_) {
            if (!spend(2)) return false;
            if (h.sign(mesh.vertices[o.lo]) == Sign::Negative &&
                h.sign(mesh.vertices[o.hi]) == Sign::Negative) {
                outside = true;
                break;
            }
        }
        // Or L strictly on one side of the plane through x and the edge.
        if (!outside && !spend(light_.size())) return false;
        if (!outside && lightSideOf(mesh.vertices[o.lo], mesh.vertices[o.hi]) == Sign::Zero)
            notSolid(o.component);
    }
    // The faces in the pyramid are the walk's: its candidates, and the used groups' faces (a
    // group lies strictly in front of B's and L's planes, and x sees each of its faces strictly
    // from one side). Candidates that reach L's plane (or, x behind B's plane, B's) or pass
    // through x (x on the surface: its plane holds x, its box x; unless that is B's plane with
    // x on it) make their component no solid.
    const Bounds3& root = clusterTree_->nodeBox(0);
    const PlaneBoxCull inFrontOfL(PlaneOrient(frontL_.a, frontL_.c, frontL_.b), root.lo, root.hi);
    const PlaneBoxCull inFrontOfB(PlaneOrient(frontB_.a, frontB_.c, frontB_.b), root.lo, root.hi);
    // (Work counted in plane tests: a candidate's box tests are not.)
    auto reaches = [&](const OrientedPlane& plane, const std::vector<uint32_t>& ids) {
        for (uint32_t v : ids) {
            spend();
            if (plane.orient.sign(mesh.vertices[v]) != Sign::Positive) return true;
        }
        return false;
    };
    for (uint32_t f : candidates_) {
        if (f == preparedReceiver_ || f == preparedLight_ || !solid(surfaces.componentOf(f)))
            continue;
        if (limitReached_) return false;
        const Bounds3& box = clusterTree_->itemBox(f);
        const auto& ids = mesh.faces[f];
        if ((!inFrontOfL.negative(box.lo, box.hi) && reaches(frontL_, ids)) ||
            (xB == Sign::Negative && !inFrontOfB.negative(box.lo, box.hi) &&
             reaches(frontB_, ids) && (spend(3 * ids.size()), !missesCone(ids)))) {
            notSolid(surfaces.componentOf(f));
            continue;
        }
        if (!box.containsGrown(x_, 0)) continue;
        if (!spend() || occluderSide(facePlane(mesh, f).orient()) != Sign::Zero) continue;
        bool inB = xB == Sign::Zero;
        for (size_t i = 0; inB && i < ids.size(); ++i)
            inB = frontB_.orient.sign(mesh.vertices[ids[i]]) == Sign::Zero;
        if (!inB) notSolid(surfaces.componentOf(f));
    }
    // Each remaining component's winding along the segment from x to a vertex of L in front of
    // B's plane (one exists: L has area in front of it). The segment lies on the pyramid's
    // boundary, so the faces it crosses are among the walk's (their boxes touch the pyramid).
    const Vec3* v = nullptr;
    for (const Vec3& p : light_)
        if (v == nullptr && frontB_.orient.sign(p) == Sign::Positive) v = &p;
    if (v == nullptr) return false;
    windingComponents_.clear();
    auto count = [&](uint32_t f) {
        const uint32_t component = surfaces.componentOf(f);
        if (f == preparedReceiver_ || f == preparedLight_ || !solid(component)) return;
        if (!spend(mesh.faces[f].size() + 2)) return;
        const std::optional<int> crossing = segmentCrossing(f, *v);
        if (!crossing) {
            notSolid(component);  // through an edge of it: the count would not be its winding
        } else if (*crossing != 0) {
            if (windingStamp_[component] != solidRun_) {
                windingStamp_[component] = solidRun_;
                componentWinding_[component] = 0;
                windingComponents_.push_back(component);
            }
            componentWinding_[component] += *crossing;
        }
    };
    setLinePlanes(*v);
    std::array<PlaneBoxCull, 4> lineCull;
    const std::span<const PlaneBoxCull> onLine = clusterTree_->cullPlanes(linePlanes_, lineCull);
    for (uint32_t f : candidates_) {
        if (!BoxTree::outsideOne(onLine, clusterTree_->itemBox(f))) count(f);
        if (limitReached_) return false;
    }
    if (!usedClusters_.empty()) {
        clusterFacesOnLine([&](uint32_t f, int) {
            count(f);
            return limitReached_;
        });
    }
    if (limitReached_) return false;
    for (uint32_t component : windingComponents_)
        if (solid(component) && componentWinding_[component] != 0) solidHidden_ = true;
    solidState_ = SolidState::Ready;
    return true;
}

Sign FromPointQuery::lightSideOf(const Vec3& a, const Vec3& b) const {
    // (The whole light: its cone holds the cone over the part in front of B.)
    const PlaneOrient plane(x_, a, b);
    Sign side = Sign::Zero;
    for (const Vec3& p : light_) {
        const Sign s = plane.sign(p);
        if (s == Sign::Zero || (side != Sign::Zero && s != side)) return Sign::Zero;
        side = s;
    }
    return side;
}

bool FromPointQuery::missesCone(const std::vector<uint32_t>& ids) {
    const std::vector<Vec3>& v = preparedMesh_->vertices;
    // Strictly outside one side plane of the pyramid.
    for (const PlaneOrient& h : pyramid_) {
        bool outside = true;
        for (size_t i = 0; outside && i < ids.size(); ++i)
            outside = h.sign(v[ids[i]]) == Sign::Negative;
        if (outside) return true;
    }
    // Or on the closed other side of a plane through x and one of its edges from the light.
    for (size_t i = 0; i < ids.size(); ++i) {
        const Vec3& a = v[ids[i]];
        const Vec3& b = v[ids[(i + 1) % ids.size()]];
        const Sign light = lightSideOf(a, b);
        if (light == Sign::Zero) continue;
        const PlaneOrient plane(x_, a, b);
        bool apart = true;
        for (size_t k = 0; apart && k < ids.size(); ++k) apart = plane.sign(v[ids[k]]) != light;
        if (apart) return true;
    }
    return false;
}

void FromPointQuery::leaveOutSolidBacks() {
    size_t kept = 0;
    for (const UsedCluster& c : usedClusters_) {
        if (c.side < 0 && solidComponent(clusters_->componentOf(c.cluster))) {
            nodeStamp_[c.node] = nodeRun_ - 1;  // (no longer a used group for the line walks)
            ++solidGroupsLeft_;
            continue;
        }
        usedClusters_[kept++] = c;
    }
    usedClusters_.resize(kept);
}

const BoundedValue& FromPointQuery::clipPlaneAt(int which) {
    if (!clipValueKnown_[which]) {
        clipValue_[which] = (which == 0 ? frontB_ : frontL_).orient.value(x_);
        clipValueKnown_[which] = true;
    }
    return clipValue_[which];
}

void FromPointQuery::startRun() {
    clipValueKnown_[0] = clipValueKnown_[1] = false;
    contactAnswer_ = false;
    fragments_.clear();
    nodesVisited_ = 0;
    work_ = 0;
    stageWork_.fill(0);
    limitReached_ = false;
    stage_ = limitStage_ = WorkStage::Walk;
    active_.clear();
    activePlanes_.clear();
    activePencils_.clear();
    activePencilOnB_.clear();
    activePlaneEdges_.clear();
    chainBuilt_ = false;
    activeOrdered_ = false;
    lightTurn_ = Sign::Zero;
    chainCounts_ = {};
    lightChord_ = false;
    crossings_ = false;
    haveRef_ = false;
    crossLevel_ = kNoLevel;
    lastHit_ = 0;
    scanned_ = 0;
    activeBoxesBuilt_ = false;
    surface_ = nullptr;
    surfaceClipped_ = 0;
    clusters_ = nullptr;
    clusterTree_ = nullptr;
    usedClusters_.clear();
    clustersByExactSides_ = 0;
    clustersDissolved_ = false;
    solidState_ = SolidState::Unknown;
    solidHidden_ = false;
    solidGroupsLeft_ = solidFacesLeft_ = 0;
    recentClusterHits_.fill({0, 0});
    recentClusterNext_ = 0;
    recentHits_.fill(UINT32_MAX);
    recentNext_ = 0;
    deferredClips_ = 0;
    trace_ = nullptr;
    region_ = nullptr;
}

bool FromPointQuery::startPair(const PolygonMesh& mesh, uint32_t receiver, uint32_t light,
                               const Vec3& x) {
    preparePair(mesh, receiver, light);
    // The light emits only to its front: x must be strictly in front of L's plane.
    if (lightPlane_.sign(x) != Sign::Positive) return false;
    return lightClipped_.size() >= 3;
}

void FromPointQuery::clipCandidates(const PolygonMesh& mesh) {
    mesh_ = &mesh;
    tree_ = nullptr;
    stage_ = WorkStage::ActivateOccluders;
    if (clusters_ != nullptr && worthSolids()) {
        if (prepareSolids()) leaveOutSolidBacks();
        if (limitReached_ || solidHidden_) return;  // (hidden: no fragment)
    }
    for (uint32_t f : candidates_) {
        if (f == preparedReceiver_ || f == preparedLight_) continue;
        if (!spend()) return;
        activateFace(mesh, f);
    }
    if (clustersActive()) {
        // Fewer faces in all than the chain is for (ChainOptions::minOccluders): the groups'
        // faces are activated and the usual rule chooses between the chain and Algorithm 1.
        size_t grouped = 0;
        for (const UsedCluster& c : usedClusters_)
            grouped += clusterTree_->nodeItems(c.node).size();
        if (grouped + active_.size() < chainOptions_.minOccluders) dissolveClusters();
        if (limitReached_) return;
    }
    deferredPrepared_ = true;
    reachVisible(lightClipped_, 0);
}

const FragmentList& FromPointQuery::runDirect(const PolygonMesh& mesh, uint32_t receiver,
                                              uint32_t light, const AnsweredPoint& point,
                                              const BoxTree& faces, const FaceClusters* clusters) {
    startRun();
    if (receiver == light) return fragments_;
    const Vec3& x = point.at;
    input_ = point.input;
    moved_ = point.moved();
    if (!startPair(mesh, receiver, light, x)) return fragments_;
    x_ = x;
    preparePyramid();
    // The candidates in the order the hierarchy's walk finds them (a function of the mesh alone:
    // the answer is deterministic). Insertion order as the builder's (pair_occluders.h) would be
    // costlier to find than it saves; sorting them into face order cost the bunny's penumbra
    // points 4.6% of their time.
    if (clusters != nullptr && clusters->size() > 0 && chainOptions_.minOccluders != 0) {
        clusters_ = clusters;
        clusterTree_ = &faces;
        if (!findClustered(faces, *clusters)) return fragments_;
    } else if (!findCandidates(faces)) {
        return fragments_;
    }
    clipCandidates(mesh);
    return fragments_;
}

bool FromPointQuery::onContact(const HistoryTree& tree, const Vec3& x) const {
    for (const PlaneOrient& plane : tree.contactPlanes) {
        BoundedValue v;
        if (plane.filtered(x, v)) continue;  // certainly off the plane (the inline filter)
        if (plane.value(x).sign() == Sign::Zero) return true;
    }
    return false;
}

bool FromPointQuery::nearContact(const PolygonMesh& mesh, const HistoryTree& tree, const Vec3& x) {
    // The lines from x to L, followed back from x to B's plane, sweep the part R of the cone
    // with apex x over the reflected L that lies in front of B's plane: the convex hull of x and
    // the points x - t_i (l_i - x) with t_i = b(x) / (b(l_i) - b(x)), b the plane's orient3d
    // value (a common scale), for L's vertices l_i. So every point of R lies within
    // D = max_i b(x) |l_i - x| / (b(l_i) - b(x)) of x (in each coordinate), and below b(x):
    // an inserted occluder that does not reach B's plane is clear of it where b(x) stays below
    // contactClearance, and one that reaches it is where its box misses x +- D. Every bound
    // rounds outwards; where one fails the answer is "may" (the direct answer: the same exact
    // answer the contract asks for, only slower).
    if (tree.contactBoxes.empty() && !(tree.contactClearance < HUGE_VAL)) return false;
    preparePair(mesh, tree.receiver, tree.light);  // (once per pair: B's plane, L's vertices)
    const PlaneOrient& plane = frontB_.orient;
    // x on B's plane or behind it has no sliver. Where the filter cannot tell (a projected
    // point, almost always), its bound of b(x) from above goes to the tests first: they can
    // only answer "may" for a larger bound, so a "no" there is x's; only a "may" asks for the
    // exact sign and the tests again with the accurate value (the same decisions as the exact
    // value throughout, without the exact stage for every projected point: on the Cornell box
    // that stage was some 3% of the render's CPU).
    BoundedValue bx;
    if (plane.filtered(x, bx)) return bx.sign() == Sign::Positive && mayMeetSliver(tree, x, bx);
    if (!mayMeetSliver(tree, x, bx)) return false;
    bx = plane.value(x);
    return bx.sign() == Sign::Positive && mayMeetSliver(tree, x, bx);
}

bool FromPointQuery::mayMeetSliver(const HistoryTree& tree, const Vec3& x, const BoundedValue& bx) {
    // (nearContact's tests, for b(x) <= bx.value + bx.error; preparePair done.)
    const PlaneOrient& plane = frontB_.orient;
    const double high = bx.value + bx.error;
    if (!(high < tree.contactClearance)) return true;
    if (tree.contactBoxes.empty()) return false;
    if (!contactLightLowValid_) {
        contactLightLow_.clear();
        for (const Vec3& l : light_) {
            const BoundedValue bl = plane.value(l);
            contactLightLow_.push_back(bl.value - bl.error);
        }
        contactLightLowValid_ = true;
    }
    double reach = 0;
    for (size_t i = 0; i < light_.size(); ++i) {
        const Vec3& l = light_[i];
        const double gap = contactLightLow_[i] - high;
        if (!(gap > 0)) return true;
        const double dist = std::fabs(l.x - x.x) + std::fabs(l.y - x.y) + std::fabs(l.z - x.z);
        reach = std::fmax(reach, high * dist / gap);
    }
    // (|.|_1 bounds each coordinate; the pads cover the rounding of the quotient and of a box
    // grown by it near x.)
    const double pad = std::fmax(std::fabs(x.x), std::fmax(std::fabs(x.y), std::fabs(x.z)));
    reach = reach * (1 + 0x1p-40) + pad * 0x1p-50 + DBL_TRUE_MIN;
    // An occluder whose box reaches the sliver may still have it strictly on one side of its
    // plane: |P(p) - P(x)| = |n . (p - x)| <= (|n|_1 + 8u |perm|_1) D for p in R (the rounded
    // normal within 8u of its permanent of the exact one).
    for (size_t i = 0; i < tree.contactBoxes.size(); ++i) {
        if (!tree.contactBoxes[i].containsGrown(x, reach)) continue;
        const PlaneOrient& p = tree.contactPlanes[i];
        const BoundedValue px = p.value(x);
        const double slope = (p.normL1() + p.permanentL1() * 0x1p-50) * (1 + 0x1p-40);
        if (!(std::fabs(px.value) - px.error > slope * reach * (1 + 0x1p-40))) return true;
    }
    return false;
}

void FromPointQuery::preparePair(const PolygonMesh& mesh, uint32_t receiver, uint32_t light) {
    // What depends on the pair and not on x: reused while consecutive runs ask for the same pair.
    // Checked by value (the faces' vertex coordinates), so a changed or reloaded mesh is noticed.
    const auto& lightFace = mesh.faces[light];
    const auto& receiverFace = mesh.faces[receiver];
    bool same = preparedMesh_ == &mesh && preparedReceiver_ == receiver &&
                preparedLight_ == light && light_.size() == lightFace.size();
    for (size_t i = 0; same && i < lightFace.size(); ++i)
        same = light_[i] == mesh.vertices[lightFace[i]];
    for (size_t i = 0; same && i < 3; ++i)
        same = receiverPlane_[i] == mesh.vertices[receiverFace[i]];
    if (same) return;
    preparedMesh_ = &mesh;
    preparedReceiver_ = receiver;
    preparedLight_ = light;
    contactLightLowValid_ = false;
    light_.clear();
    for (uint32_t v : lightFace) light_.push_back(mesh.vertices[v]);
    for (size_t i = 0; i < 3; ++i) receiverPlane_[i] = mesh.vertices[receiverFace[i]];
    const FacePlane pl = facePlane(mesh, light);
    lightPlane_ = PlaneOrient(pl.a, pl.b, pl.c);
    // The receiver sees only its front hemisphere (B's plane, exact on input points).
    frontB_ = OrientedPlane{receiverPlane_[0], receiverPlane_[1], receiverPlane_[2]};
    frontL_ = OrientedPlane{pl.a, pl.b, pl.c};
    clipConvexInto(light_, frontB_, lightClipped_, discard_);
}

const FragmentList& FromPointQuery::run(const PolygonMesh& mesh, const HistoryTree& tree,
                                        const AnsweredPoint& point, std::vector<TraceStep>* trace,
                                        RegionDecisions* region) {
    if (region != nullptr && region->tree() != &tree)
        throw std::invalid_argument("FromPointQuery::run: region decisions of another tree");
    startRun();
    if (tree.kind == PairKind::BackFacing) return fragments_;
    const Vec3& x = point.at;
    input_ = point.input;
    moved_ = point.moved();
    // (A fully hidden pair is answered without touching the pair's setup unless x is on contact.)
    // A moved point is on contact where its input is (answered_point.h).
    const bool contact =
        onContact(tree, x) || (moved_ && onContact(tree, input_)) || nearContact(mesh, tree, x);
    if (tree.kind == PairKind::FullyHidden && !contact) return fragments_;
    if (!startPair(mesh, tree.receiver, tree.light, x)) return fragments_;
    if (tree.kind == PairKind::FullyVisible) {
        fragments_.add(lightClipped_);
        return fragments_;
    }
    x_ = x;
    if (contact) {
        // x lies in the plane of an occluder that reaches B's plane: it may stand on that
        // occluder's contact with B, where the tree's cells (closed sets of lines) give the limit
        // of the neighbouring points and the contract asks for more (a segment touching an
        // occluder only at x is not blocked). Answered from the pair's occluders directly, which
        // applies the contract exactly (activateFace). Measure zero: a rendered point is almost
        // never exactly there.
        contactAnswer_ = true;
        candidates_.assign(tree.occluders.begin(), tree.occluders.end());
        for (const DeferredOccluder& d : tree.deferred) candidates_.push_back(d.face);
        std::sort(candidates_.begin(), candidates_.end());
        candidates_.erase(std::unique(candidates_.begin(), candidates_.end()), candidates_.end());
        // A face whose every vertex lies strictly farther from L's plane than x (the filter's
        // bounds, which hold whether or not it certifies a sign) meets no segment from x to L:
        // those lie between L's plane and its parallel through x. (The common contact answer:
        // the floor below a wall whose plane cuts the light, an occluder of the wall's grown
        // patches; activating it took the exact stage for its chords' pencil planes.)
        BoundedValue bound;
        lightPlane_.filtered(x, bound);
        const double xHigh = bound.value + bound.error;
        std::erase_if(candidates_, [&](uint32_t f) {
            for (uint32_t v : mesh.faces[f]) {
                lightPlane_.filtered(mesh.vertices[v], bound);
                if (!(bound.value - bound.error > xHigh)) return false;
            }
            return true;
        });
        preparePyramid();
        clipCandidates(mesh);
        return fragments_;
    }
    if (tree.kind == PairKind::FullyHidden) return fragments_;
    mesh_ = &mesh;
    tree_ = &tree;
    trace_ = trace;
    region_ = region;
    deferredPrepared_ = !tree.partial();
    if (tree.nodes.empty())  // a partial tree with no node: one visible leaf
        reachVisible(lightClipped_, 0);
    else
        visit(0, lightClipped_, 0, 0);
    trace_ = nullptr;
    region_ = nullptr;
    return fragments_;
}

std::vector<uint32_t> traceNodes(std::span<const TraceStep> trace) {
    std::vector<uint32_t> out;
    out.reserve(trace.size());
    for (const TraceStep& s : trace) out.push_back(s.node);
    return out;
}

FromPointResult fromPointQuery(const PolygonMesh& mesh, const HistoryTree& tree,
                               const AnsweredPoint& x) {
    FromPointQuery query;
    FromPointResult out;
    const FragmentList& fragments = query.run(mesh, tree, x, &out.trace);
    out.answeredOnContact = query.answeredOnContact();
    out.fragments = fragments.polygons();
    out.nodesVisited = query.nodesVisited();
    out.deferredActive = query.deferredActive();
    out.deferredClips = query.deferredClips();
    return out;
}

}  // namespace penumbra::vis
