#include "visibility/fp_query/edge_path.h"

#include <algorithm>

#include "visibility/face_plane.h"
#include "visibility/fp_query/query_parts.h"

namespace penumbra::vis {

// Why no edge of nonzero weight that meets the closed cone over L is missing from S_L. Such an
// edge e, met at p by a ray from x that reaches L at y, has a use by a face f1 of G. If e is not
// a manifold edge between consistently oriented faces it is in S_L. Else let f2 be its other
// face, P1 and P2 their planes; e left out of S_L means every vertex of L, so every point of L,
// lies strictly on one side of P1 and of P2, the same side of both. f1 is Front of L's plane, so
// p (on f1) is not beyond L: p lies between x and y, and p = y would put a point of L on P1.
//  - f2 in G with s2 != s1: x lies on different sides of P1 and P2, and y, past p on both planes,
//    on the opposite side of each: different sides too. Not so for a point of L.
//  - x on P2: the ray lies in P2, so y does.
//  - f2 Behind L: e (on f2 and f1) lies in L's plane, so p = y.
//  - f2 Across: the path is not taken where such a face's box may meet the cone (prepare), and e,
//    on it, would be outside the cone.
//  - f2 is L: L's vertices lie on P2 (zero signs keep e).
//  - f2 is B (x on or in front of P2): x on P2 is the case above; x strictly in front puts y
//    strictly behind B, and L would lie wholly behind B (no query) or not strictly on one side.
// So the chain of c' in the cone is found whole from S_L.

bool EdgePath::prepare(const BoxTree& faces, const LightEdgeIndex& index) {
    QueryRun& r = q_.run;
    const PolygonMesh& mesh = r.mesh();
    if (index.light() != r.pair.light() || index.faceCount() != mesh.faces.size() ||
        index.vertexCount() != mesh.vertices.size()) {
        decline_ = EdgeDecline::OtherIndex;
        return false;
    }
    // x strictly behind B's plane (an answered point is not: answered_point.h): its rays may
    // meet faces behind B that the clip to B's front leaves out.
    if (r.pair.frontB().orient.sign(r.x) == Sign::Negative) {
        decline_ = EdgeDecline::BehindReceiver;
        return false;
    }
    r.prepareCone();
    const std::vector<PlaneOrient>& cone = r.cone();
    // An Across face (other than B and L) that may meet the cone: its chord on L's plane may
    // bound a shadow. Culled by its box, then by its vertices (exact signs: a face with no
    // vertex strictly inside one of the cone's planes meets no ray strictly inside the cone).
    if (!index.acrossFaces().empty()) {
        r.budget.enter(WorkStage::FindOccluders);
        uint32_t visited = 0;
        const bool across = index.acrossFaces().anyNotOutside(
            cone,
            [&](uint32_t item) {
                const uint32_t f = index.acrossFace(item);
                if (f == r.pair.receiver() || f == r.pair.light()) return false;
                for (const PlaneOrient& h : cone) {
                    bool inside = false;
                    for (uint32_t v : mesh.faces[f]) {
                        r.budget.spend();
                        if (exactSign(h, mesh.vertices[v]) == Sign::Positive) {
                            inside = true;
                            break;
                        }
                    }
                    if (!inside) return false;
                }
                return true;
            },
            visited);
        r.budget.spend(visited);
        if (across) {
            decline_ = EdgeDecline::AcrossFace;
            return false;
        }
    }
    index_ = &index;
    faces_ = &faces;
    if (faceMemo_.size() < mesh.faces.size()) faceMemo_.resize(mesh.faces.size(), 0);
    if (localMemo_.size() < index.localFaceCount()) localMemo_.resize(index.localFaceCount(), 0);
    if (++runStamp_ == kStampEnd) {  // wrapped: no stale stamp may match
        std::fill(faceMemo_.begin(), faceMemo_.end(), 0);
        std::fill(localMemo_.begin(), localMemo_.end(), 0);
        std::fill(activeMemo_.begin(), activeMemo_.end(), 0);
        runStamp_ = 1;
    }
    // The S_L edges whose box is not certainly outside the cone (conservative: the exact test of
    // each segment against the cone is ChainBuild::keepEdgesInCone's), less the subtrees whose
    // edges x certainly sees none of as a silhouette (silhouette_cull.h: all of weight 0). B's
    // uses count for nothing here, so a subtree holding one of B's edges is searched; and where x
    // was moved, a face whose plane holds the input counts for nothing (occluderSide), so a
    // subtree is skipped only if the input is certainly off all its planes too.
    r.budget.enter(WorkStage::FindOccluders);
    found_.clear();
    receiverEdges_.clear();
    const auto& bFace = mesh.faces[r.pair.receiver()];
    for (size_t k = 0; k < bFace.size(); ++k) {
        const uint32_t v = bFace[k], w = bFace[(k + 1) % bFace.size()];
        if (const auto id = index.find(std::min(v, w), std::max(v, w)))
            receiverEdges_.push_back(*id);
    }
    const SilhouetteCull& cull = index.silhouettes();
    uint32_t skipped = 0;
    const BoxTree& tree = index.edgeBoxes();
    auto skip = [&](uint32_t node) {
        if (!cull.noSilhouetteFrom(node, r.x)) return false;
        if (r.moved && !cull.oneSideOfEvery(node, r.input)) return false;
        const std::span<const uint32_t> items = tree.nodeItems(node);
        for (uint32_t id : receiverEdges_)
            if (id >= items.front() && id <= items.back()) return false;
        skipped += static_cast<uint32_t>(items.size());
        return true;
    };
    if (!r.budget.spend(tree.notOutsideUnless(cone, skip, found_, r.budget.left()))) return true;
    examined_ = static_cast<uint32_t>(found_.size());
    nearCone_ = examined_ + skipped;
    // Each one's weight from its faces' exact sides.
    r.budget.enter(WorkStage::BuildChain);
    remaining_.clear();
    for (uint32_t i : found_) {
        int w = 0;
        const std::span<const MeshEdges::Use> uses = index.uses(i);
        const std::span<const uint32_t> locals = index.useLocalFaces(i);
        for (size_t k = 0; k < uses.size(); ++k) {
            const int s = localSide(locals[k]);
            w += uses[k].forward ? s : -s;
        }
        if (r.budget.reached()) return true;
        if (w != 0) remaining_.push_back({index.edge(i).lo, index.edge(i).hi, w});
    }
    return true;
}

namespace {

// A memo word: the run's stamp above two bits of s_f + 1 (one word per face, one read).
uint32_t memoWord(uint32_t stamp, int side) { return stamp << 2 | static_cast<uint32_t>(side + 1); }
bool memoHolds(uint32_t memo, uint32_t stamp) { return memo >> 2 == stamp; }
int memoSide(uint32_t memo) { return static_cast<int>(memo & 3) - 1; }

}  // namespace

int EdgePath::sideOf(uint32_t face, const FacePlane& plane) {
    QueryRun& r = q_.run;
    if (face == r.pair.receiver() || face == r.pair.light() || !r.budget.spend()) return 0;
    return toInt(r.occluderSide(plane.orient()));
}

int EdgePath::faceSide(uint32_t face) {
    uint32_t& memo = faceMemo_[face];
    if (memoHolds(memo, runStamp_)) return memoSide(memo);
    const int side = index_->side(face) == LightEdgeIndex::Side::Front
                         ? sideOf(face, facePlane(q_.run.mesh(), face))
                         : 0;
    memo = memoWord(runStamp_, side);
    return side;
}

int EdgePath::localSide(uint32_t local) {
    if (local == LightEdgeIndex::kNotFront) return 0;
    uint32_t& memo = localMemo_[local];
    if (memoHolds(memo, runStamp_)) return memoSide(memo);
    const int side = sideOf(index_->localFace(local),
                            facePlane(index_->localVertices(), index_->localCorners(local)));
    memo = memoWord(runStamp_, side);
    return side;
}

void EdgePath::activateRest() {
    if (restActivated_) return;
    restActivated_ = true;
    QueryRun& r = q_.run;
    r.budget.enter(WorkStage::FindOccluders);
    r.candidates.clear();
    if (!r.budget.spend(faces_->notOutside(r.pyramid, r.candidates, r.budget.left()))) return;
    activate(r.candidates);
}

void EdgePath::activateNear(std::span<const Vec3> poly) {
    if (restActivated_) return;
    QueryRun& r = q_.run;
    // The faces that may meet the cell's hull: those whose box is not certainly outside the
    // pyramid nor one of the hull's planes (OccluderClip::hullCone: exact signs of the cell's
    // vertices; Algorithm 1 culls its occluders for the cell by the same planes). Where no plane
    // holds the cell (a rounded sliver that is not convex), every face in the pyramid.
    const std::vector<PlaneOrient>& hull = q_.clip.hullCone(poly);
    if (r.budget.reached()) return;
    if (hull.empty()) {
        activateRest();
        return;
    }
    nearPlanes_.assign(r.pyramid.begin(), r.pyramid.end());
    nearPlanes_.insert(nearPlanes_.end(), hull.begin(), hull.end());
    r.budget.enter(WorkStage::FindOccluders);
    nearFaces_.clear();
    if (!r.budget.spend(faces_->notOutside(nearPlanes_, nearFaces_, r.budget.left()))) return;
    activate(nearFaces_);
}

void EdgePath::activate(std::span<const uint32_t> faces) {
    QueryRun& r = q_.run;
    r.budget.enter(WorkStage::ActivateOccluders);
    if (activeMemo_.size() < faceMemo_.size()) activeMemo_.resize(faceMemo_.size(), 0);
    for (uint32_t f : faces) {
        if (f == r.pair.receiver() || f == r.pair.light()) continue;
        if (activeMemo_[f] == runStamp_) continue;  // activated for an earlier cell of this run
        activeMemo_[f] = runStamp_;
        if (!r.budget.spend()) return;
        q_.active.activate(f);
    }
}

void EdgePath::setRayPlanes(const Vec3& y) {
    // The line's planes (LineTests::setLinePlanes), then the cone's and L's plane turned to x's
    // side: y is certified strictly inside the cone, so every point of the ray from x through y
    // lies strictly inside the cone's planes, and a box strictly outside one holds no face the
    // ray meets (this drops the line behind x); a box strictly behind L's plane holds only faces
    // Behind L, which count for nothing. Conservative: only boxes certainly off are skipped.
    QueryRun& r = q_.run;
    q_.lines.setLinePlanes(y);
    rayPlanes_ = q_.lines.linePlanes();
    const std::vector<PlaneOrient>& cone = r.cone();
    rayPlanes_.insert(rayPlanes_.end(), cone.begin(), cone.end());
    rayPlanes_.push_back(r.pair.frontL().orient);
}

bool EdgePath::lineBlocked(const Vec3& y) {
    QueryRun& r = q_.run;
    LineTests& lines = q_.lines;
    auto hit = [&](uint32_t face) {
        const int s = faceSide(face);
        return s != 0 && lines.faceHitKind(face, s, y) != LineHit::Miss;
    };
    for (uint32_t k = 0; k < kRecentHits; ++k) {
        const uint32_t face = recentHits_[(recentNext_ + kRecentHits - 1 - k) % kRecentHits];
        if (face != UINT32_MAX && hit(face)) return !r.budget.reached();
    }
    // Each face on the ray as the hierarchy finds it: the first hit ends the search.
    setRayPlanes(y);
    uint32_t visited = 0;
    const bool blocked = faces_->anyNotOutside(
        rayPlanes_,
        [&](uint32_t face) {
            if (r.budget.reached()) return true;
            if (!hit(face)) return false;
            if (std::find(recentHits_.begin(), recentHits_.end(), face) == recentHits_.end()) {
                recentHits_[recentNext_] = face;
                recentNext_ = (recentNext_ + 1) % kRecentHits;
            }
            return true;
        },
        visited);
    r.budget.spend(visited);
    return blocked && !r.budget.reached();
}

std::optional<int> EdgePath::countLine(const Vec3& y) {
    QueryRun& r = q_.run;
    LineTests& lines = q_.lines;
    HitCount c;
    setRayPlanes(y);
    uint32_t visited = 0;
    faces_->anyNotOutside(
        rayPlanes_,
        [&](uint32_t face) {
            if (r.budget.reached()) return true;
            const int s = faceSide(face);
            return s != 0 && c.add(lines.faceHitKind(face, s, y), r.budget);
        },
        visited);
    r.budget.spend(visited);
    if (c.touch || r.budget.reached()) return std::nullopt;
    return c.count;
}

}  // namespace penumbra::vis
