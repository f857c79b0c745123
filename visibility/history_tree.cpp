#include "visibility/history_tree.h"

#include <algorithm>
#include <cmath>
#include <utility>

#include "visibility/face_plane.h"
#include "visibility/polygon_clip.h"

namespace penumbra::vis {

std::string_view toString(PairKind k) {
    switch (k) {
        case PairKind::BackFacing:
            return "back-facing";
        case PairKind::FullyVisible:
            return "fully-visible";
        case PairKind::FullyHidden:
            return "fully-hidden";
        case PairKind::Penumbra:
            return "penumbra";
    }
    return "?";
}

bool horizonClipsLight(const PolygonMesh& mesh, uint32_t receiver, uint32_t light) {
    const FacePlane b = facePlane(mesh, receiver);
    std::vector<Vec3> polygon;
    for (uint32_t v : mesh.faces[light]) polygon.push_back(mesh.vertices[v]);
    return anyVertexBehind(polygon, OrientedPlane{b.a, b.b, b.c});
}

std::string_view describeKind(PairKind k, bool horizonClipped) {
    if (k == PairKind::FullyVisible && horizonClipped) return "unoccluded, horizon-clipped";
    return toString(k);
}

std::span<const std::string_view> knownReasons() {
    static constexpr std::string_view kAll[] = {
        reasons::kBackFacing,      reasons::kNoOccluder,       reasons::kBlockNothing,
        reasons::kSingleBlocksAll, reasons::kTogetherBlockAll, reasons::kPenumbra,
        reasons::kPartial,
    };
    return kAll;
}

void prepareForQueries(const PolygonMesh& mesh, HistoryTree& tree,
                       std::span<const Vec3> receiverRegion) {
    std::vector<Bounds3> boxes;
    boxes.reserve(tree.deferred.size());
    for (DeferredOccluder& d : tree.deferred) {
        d.box = Bounds3{};
        for (uint32_t v : mesh.faces[d.face]) d.box.add(mesh.vertices[v]);
        boxes.push_back(d.box);
    }
    tree.deferredIndex = BoxTree(boxes);
    prepareSilhouettes(mesh, tree, receiverRegion);
    tree.contactPlanes.clear();
    tree.contactBoxes.clear();
    tree.contactClearance = HUGE_VAL;
    if (tree.kind == PairKind::BackFacing) return;
    const PlaneOrient receiverPlane = facePlane(mesh, tree.receiver).orient();
    const auto& receiverIds = mesh.faces[tree.receiver];
    // (The deferred occluders are clipped from x itself: the contract's segments.)
    for (uint32_t f : tree.occluders) {
        bool reaches = false;
        double lowest = HUGE_VAL;  // a lower bound of the plane's value at the face's vertices
        for (uint32_t v : mesh.faces[f]) {
            // A vertex of B itself is on its plane (the common case of adjacent faces, where the
            // filter cannot tell a zero and the exact stage would be needed).
            if (std::find(receiverIds.begin(), receiverIds.end(), v) != receiverIds.end()) {
                reaches = true;
                break;
            }
            const BoundedValue b = receiverPlane.value(mesh.vertices[v]);
            reaches = b.sign() != Sign::Positive;
            if (reaches) break;
            lowest = std::fmin(lowest, b.value - b.error);
        }
        if (reaches) {
            tree.contactPlanes.push_back(facePlane(mesh, f).orient());
            tree.contactBoxes.push_back(mesh.faceBounds(f));
        } else {
            tree.contactClearance = std::fmin(tree.contactClearance, lowest);
        }
    }
}

EdgeLine edgeLine(const PolygonMesh& mesh, uint32_t receiver, uint32_t light, uint32_t v0,
                  uint32_t v1) {
    if (!isClipEdge(v0)) return EdgeLine::through(mesh.vertices[v0], mesh.vertices[v1]);
    // The chord of a clip: directed n_clip x n_face (clipped_occluder.h).
    const uint32_t face = v0 & ~kClipEdge;
    return EdgeLine::meet(facePlane(mesh, v1 == kReceiverPlaneEdge ? receiver : light).orient(),
                          facePlane(mesh, face).orient());
}

std::pair<Vec3, Vec3> edgeSegment(const PolygonMesh& mesh, uint32_t receiver, uint32_t light,
                                  uint32_t v0, uint32_t v1) {
    if (!isClipEdge(v0)) return {mesh.vertices[v0], mesh.vertices[v1]};
    const uint32_t face = v0 & ~kClipEdge;
    const PlaneOrient clip = facePlane(mesh, v1 == kReceiverPlaneEdge ? receiver : light).orient();
    const PlaneOrient other = facePlane(mesh, v1 == kReceiverPlaneEdge ? light : receiver).orient();
    // Where the face's boundary crosses the clip plane (doubles: display only), then the part of
    // that chord in front of the other plane.
    const auto& ids = mesh.faces[face];
    std::vector<Vec3> hits;
    for (size_t i = 0; i < ids.size(); ++i) {
        const Vec3 p = mesh.vertices[ids[i]], q = mesh.vertices[ids[(i + 1) % ids.size()]];
        const double dp = clip.value(p).value, dq = clip.value(q).value;
        if (dp == 0) hits.push_back(p);
        if ((dp < 0 && dq > 0) || (dp > 0 && dq < 0))
            hits.push_back(p + (q - p) * (dp / (dp - dq)));
    }
    if (hits.size() < 2) return {hits.empty() ? Vec3{} : hits[0], hits.empty() ? Vec3{} : hits[0]};
    Vec3 a = hits.front(), b = hits.back();
    const double da = other.value(a).value, db = other.value(b).value;
    if (da < 0 && db > 0) a = a + (b - a) * (da / (da - db));
    if (db < 0 && da > 0) b = b + (a - b) * (db / (db - da));
    // Directed as the chord: n_clip x n_face.
    const Vec3 nClip = cross(clip.b - clip.a, clip.c - clip.a);
    const FacePlane own = facePlane(mesh, face);
    const Vec3 nFace = cross(own.b - own.a, own.c - own.a);
    if (dot(b - a, cross(nClip, nFace)) < 0) std::swap(a, b);
    return {a, b};
}

uint32_t HistoryTree::depth() const {
    if (nodes.empty()) return 0;
    uint32_t best = 0;
    std::vector<std::pair<uint32_t, uint32_t>> stack{{0, 1}};
    while (!stack.empty()) {
        auto [n, d] = stack.back();
        stack.pop_back();
        best = std::max(best, d);
        for (uint32_t c : nodes[n].child)
            if (!isLeaf(c)) stack.push_back({c, d + 1});
    }
    return best;
}

uint32_t HistoryTree::leafCount(bool visible) const {
    if (nodes.empty()) {
        // A leaf alone: FullyVisible (or a partial Penumbra tree with no node) is one visible
        // leaf, FullyHidden one hidden leaf, BackFacing none.
        const bool visibleLeaf = kind == PairKind::FullyVisible || kind == PairKind::Penumbra;
        return kind != PairKind::BackFacing && visibleLeaf == visible ? 1 : 0;
    }
    uint32_t count = 0;
    for (const HistoryNode& n : nodes)
        for (uint32_t c : n.child) count += c == (visible ? kVisibleLeaf : kHiddenLeaf);
    return count;
}

}  // namespace penumbra::vis
