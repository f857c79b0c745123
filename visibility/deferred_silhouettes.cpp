#include "visibility/deferred_silhouettes.h"

#include <algorithm>
#include <cmath>

#include "visibility/history_tree.h"
#include "visibility/pair_occluders.h"
#include "visibility/polygon_clip.h"

namespace penumbra::vis {

namespace silhouettes_detail {

// Q: B's box grown by a margin that holds the renderer's points on B (an Embree hit, rounded in
// float, then projected onto B's plane in doubles). Only a size: a point outside Q is answered
// without the silhouettes.
Bounds3 regionBox(const PolygonMesh& mesh, uint32_t receiver, std::span<const Vec3> patch) {
    Bounds3 box;
    if (patch.empty())
        for (uint32_t v : mesh.faces[receiver]) box.add(mesh.vertices[v]);
    for (const Vec3& p : patch) box.add(p);
    double extent = box.diagonal();
    for (double c : {box.lo.x, box.lo.y, box.lo.z, box.hi.x, box.hi.y, box.hi.z})
        extent = std::max(extent, std::abs(c));
    const double margin = 1e-6 * extent;
    box.lo = box.lo - Vec3{margin, margin, margin};
    box.hi = box.hi + Vec3{margin, margin, margin};
    return box;
}

// +1 or -1 when every corner of `box` lies strictly on that side of `plane` (exact signs; the
// plane's value is affine, so then every point of the box does), else 0.
int8_t sideOver(const PlaneOrient& plane, const Bounds3& box) {
    int8_t side = 0;
    for (int k = 0; k < 8; ++k) {
        const Vec3 corner{(k & 1) != 0 ? box.hi.x : box.lo.x, (k & 2) != 0 ? box.hi.y : box.lo.y,
                          (k & 4) != 0 ? box.hi.z : box.lo.z};
        const Sign s = plane.sign(corner);
        const int8_t v = static_cast<int8_t>(toInt(s));
        if (v == 0 || (k > 0 && v != side)) return 0;
        side = v;
    }
    return side;
}

using Use = DeferredSilhouettes::Use;
using EdgeKey = std::pair<uint32_t, uint32_t>;

EdgeKey edgeKey(const Use& u) { return {std::min(u.v0, u.v1), std::max(u.v0, u.v1)}; }
uint64_t packed(EdgeKey k) { return (static_cast<uint64_t>(k.first) << 32) | k.second; }

// The deferred faces sorted by kind: their slots and, for a Surface face, its uses; the edges of
// the Clipped faces (sorted); the slots in face order.
struct FaceKinds {
    std::vector<Use> uses;
    std::vector<EdgeKey> clippedEdges;
    std::vector<uint32_t> order;
};

FaceKinds classifyFaces(const PolygonMesh& mesh, const HistoryTree& tree,
                        const PlaneOrient (&planes)[2], DeferredSilhouettes& s) {
    FaceKinds out;
    s.slots.assign(tree.deferred.size(), DeferredSilhouettes::Slot::Empty);
    s.sides.assign(tree.deferred.size(), 0);
    // In face order (the deferred order is the insertion heuristic's: random over the mesh, and
    // a large mesh's faces and vertices are then one cache miss each).
    std::vector<uint32_t>& order = out.order;
    order.resize(tree.deferred.size());
    for (uint32_t slot = 0; slot < order.size(); ++slot) order[slot] = slot;
    std::sort(order.begin(), order.end(), [&](uint32_t a, uint32_t b) {
        return tree.deferred[a].face < tree.deferred[b].face;
    });
    for (uint32_t slot : order) {
        const auto& ids = mesh.faces[tree.deferred[slot].face];
        const size_t n = ids.size();
        if (n < 3) continue;
        bool front[2] = {false, false}, behind[2] = {false, false};
        for (int k = 0; k < 2; ++k) {
            for (uint32_t v : ids) {
                const Sign sg = planes[k].sign(mesh.vertices[v]);
                front[k] = front[k] || sg == Sign::Positive;
                behind[k] = behind[k] || sg == Sign::Negative;
            }
        }
        // As ClippedOccluder::clip decides it: no part of positive area in front of a plane.
        if (!front[0] || !front[1]) continue;
        s.totalUses += n;
        if (behind[0] || behind[1]) {
            s.slots[slot] = DeferredSilhouettes::Slot::Clipped;
            s.clipped.push_back(slot);
            for (size_t i = 0; i < n; ++i) {
                const uint32_t a = ids[i], b = ids[(i + 1) % n];
                out.clippedEdges.emplace_back(std::min(a, b), std::max(a, b));
            }
            continue;
        }
        s.slots[slot] = DeferredSilhouettes::Slot::Surface;
        for (size_t i = 0; i < n; ++i) out.uses.push_back({ids[i], ids[(i + 1) % n], slot, 0});
    }
    std::sort(out.clippedEdges.begin(), out.clippedEdges.end());
    std::sort(s.clipped.begin(), s.clipped.end());
    return out;
}

// The lone uses (an edge no other face shares) and the Clipped faces' (on the edges' keys alone:
// a CAD model's partial trees defer some 100k faces each).
uint64_t countLoneUses(const PolygonMesh& mesh, const HistoryTree& tree,
                       const DeferredSilhouettes& s, const FaceKinds& kinds) {
    uint64_t loneUses = 0;
    for (uint32_t slot : s.clipped) loneUses += mesh.faces[tree.deferred[slot].face].size();
    std::vector<uint64_t> keys;
    keys.reserve(kinds.uses.size());
    for (const Use& u : kinds.uses) keys.push_back(packed(edgeKey(u)));
    std::sort(keys.begin(), keys.end());
    std::vector<uint64_t> clippedKeys;
    clippedKeys.reserve(kinds.clippedEdges.size());
    for (const auto& e : kinds.clippedEdges) clippedKeys.push_back(packed(e));
    for (size_t i = 0; i < keys.size();) {
        size_t j = i + 1;
        while (j < keys.size() && keys[j] == keys[i]) ++j;
        if (j - i == 1 && !std::binary_search(clippedKeys.begin(), clippedKeys.end(), keys[i]))
            ++loneUses;
        i = j;
    }
    return loneUses;
}

// Each Surface face's side over Q, then the groups that cancel for every point of Q dropped:
// every face's side decided, no Clipped face on the edge (its use is the query's), and the
// signed directions summing to zero. Returns the kept groups' boxes.
std::vector<Bounds3> keepGroups(const PolygonMesh& mesh, const HistoryTree& tree,
                                const Bounds3& region, FaceKinds& kinds, DeferredSilhouettes& s) {
    for (uint32_t slot : kinds.order) {
        if (s.slots[slot] != DeferredSilhouettes::Slot::Surface) continue;
        s.sides[slot] = sideOver(facePlane(mesh, tree.deferred[slot].face).orient(), region);
    }
    std::vector<Use>& uses = kinds.uses;
    for (Use& u : uses) u.side = s.sides[u.slot];
    // Grouped by undirected edge (stable: a group keeps its faces' order).
    std::stable_sort(uses.begin(), uses.end(),
                     [&](const auto& a, const auto& b) { return edgeKey(a) < edgeKey(b); });
    std::vector<Bounds3> boxes;
    s.groupBegin.push_back(0);
    for (size_t i = 0; i < uses.size();) {
        size_t j = i;
        int sum = 0;
        bool decided = true;
        for (; j < uses.size() && edgeKey(uses[j]) == edgeKey(uses[i]); ++j) {
            decided = decided && uses[j].side != 0;
            sum += uses[j].side * (uses[j].v0 < uses[j].v1 ? 1 : -1);
        }
        const bool withClipped = std::binary_search(kinds.clippedEdges.begin(),
                                                    kinds.clippedEdges.end(), edgeKey(uses[i]));
        if (!(decided && sum == 0 && !withClipped)) {
            s.uses.insert(s.uses.end(), uses.begin() + static_cast<ptrdiff_t>(i),
                          uses.begin() + static_cast<ptrdiff_t>(j));
            s.groupBegin.push_back(static_cast<uint32_t>(s.uses.size()));
            s.groupWithClipped.push_back(withClipped);
            Bounds3 box;
            box.add(mesh.vertices[uses[i].v0]);
            box.add(mesh.vertices[uses[i].v1]);
            boxes.push_back(box);
        }
        i = j;
    }
    return boxes;
}

// Only the totals of `s` (what the bench reports of a patch whose silhouettes do not pay).
DeferredSilhouettes totalsOnly(const DeferredSilhouettes& s, uint64_t keptUses) {
    DeferredSilhouettes totals;
    totals.totalUses = s.totalUses;
    totals.keptUses = keptUses;
    totals.loneUses = s.loneUses;
    return totals;
}

}  // namespace silhouettes_detail

void prepareSilhouettes(const PolygonMesh& mesh, HistoryTree& tree,
                        std::span<const Vec3> receiverRegion, uint64_t maxKeptPercent) {
    using namespace silhouettes_detail;
    DeferredSilhouettes& s = tree.silhouettes;
    s = DeferredSilhouettes{};
    if (tree.deferred.empty() || tree.kind != PairKind::Penumbra ||
        tree.deferred.size() > kMaxSilhouetteFaces)
        return;
    // B's and L's planes as the query takes them (fp_query/pair_setup.cpp).
    const FacePlane pb = facePlane(mesh, tree.receiver), pl = facePlane(mesh, tree.light);
    const PlaneOrient planes[2] = {pb.orient(), pl.orient()};
    const Bounds3 region = regionBox(mesh, tree.receiver, receiverRegion);
    FaceKinds kinds = classifyFaces(mesh, tree, planes, s);
    // First only count the lone uses and the Clipped faces': where they are too many (separate
    // faces) nothing more is worth computing.
    s.loneUses = countLoneUses(mesh, tree, s, kinds);
    if (s.loneUses * kSilhouetteGain > s.totalUses) {
        // Separate faces (leaves): nothing can cancel, the per-point chain would only add work.
        s = totalsOnly(s, s.uses.size());  // (0: not computed)
        return;
    }
    const std::vector<Bounds3> boxes = keepGroups(mesh, tree, region, kinds, s);
    s.keptUses = s.uses.size();
    for (uint32_t slot : s.clipped) s.keptUses += mesh.faces[tree.deferred[slot].face].size();
    if (s.keptUses * 100 > s.totalUses * maxKeptPercent) {
        // Too little cancels for the whole patch: the query would look at nearly every edge
        // anyway, and Algorithm 1 costs less (only the totals are kept).
        s = totalsOnly(s, s.keptUses);
        return;
    }
    s.groups = BoxTree(boxes);
    s.region = region;
}

}  // namespace penumbra::vis
