#include "visibility/fp_query/solid_filter.h"

#include <algorithm>
#include <array>

#include "visibility/face_plane.h"
#include "visibility/fp_query/query_parts.h"

namespace penumbra::vis {

bool SolidFilter::worth() const {
    // The checks cost a walk along one segment and a pass over the candidates: taken where
    // enough may be left out (ChainOptions::solidMinFaces; measured on the bunny, every point
    // exact: 16 candidates or any group seen from behind made the median evaluation 0.23 ->
    // 0.28 us).
    const ClusterPath& groups = q_.clusters;
    size_t behind = 0;  // faces in groups seen from behind
    for (const ClusterPath::Used& c : groups.used())
        if (c.side < 0 && groups.clusters().componentOf(c.cluster) != FaceClusters::kNone)
            behind += groups.faces().nodeItems(c.node).size();
    return q_.run.candidates.size() + behind / 4 >= q_.run.chainOptions.solidMinFaces;
}

bool SolidFilter::leavesOut(uint32_t face) {
    if (state_ != State::Ready || !component(q_.clusters.clusters().surfaces().componentOf(face)))
        return false;
    ++facesLeft_;
    return true;
}

void SolidFilter::leaveOutBacks() {
    const FaceClusters& clusters = q_.clusters.clusters();
    groupsLeft_ += q_.clusters.leaveOut([&](const ClusterPath::Used& c) {
        return c.side < 0 && component(clusters.componentOf(c.cluster));
    });
}

bool SolidFilter::prepare() {
    if (state_ != State::Unknown) return state_ == State::Ready;
    state_ = State::Off;
    QueryRun& r = q_.run;
    const ClosedSurfaces& surfaces = q_.clusters.clusters().surfaces();
    const uint32_t n = surfaces.componentCount();
    if (n == 0 || q_.clusters.faces().empty()) return false;
    r.budget.enter(WorkStage::FindOccluders);
    if (componentStamp_.size() < n) {
        componentStamp_.resize(n, 0);
        componentWinding_.resize(n, 0);
        windingStamp_.resize(n, 0);
    }
    if (++run_ == 0) {  // wrapped: no stale stamp may match
        std::fill(componentStamp_.begin(), componentStamp_.end(), 0);
        std::fill(windingStamp_.begin(), windingStamp_.end(), 0);
        run_ = 1;
    }
    xB_ = r.pair.frontB().orient.sign(r.x);
    notSolid(surfaces.componentOf(r.pair.light()));
    if (!receiverEdges() || !openEdges() || !candidates() || !windings()) return false;
    state_ = State::Ready;
    return true;
}

bool SolidFilter::receiverEdges() {
    // x behind B's plane by a rounding: what lies in B's plane (B's own edges, the chords where
    // it cuts faces) may reach into the open cone near x; each such element must be shown to
    // miss it (missesCone), else its component is no solid.
    if (xB_ != Sign::Negative) return true;
    QueryRun& r = q_.run;
    const PolygonMesh& mesh = r.mesh();
    const ClosedSurfaces& surfaces = q_.clusters.clusters().surfaces();
    const auto& ids = mesh.faces[r.pair.receiver()];
    for (size_t i = 0; i < ids.size(); ++i) {
        if (!r.budget.spend(r.light().size())) return false;
        if (lightSideOf(mesh.vertices[ids[i]], mesh.vertices[ids[(i + 1) % ids.size()]]) ==
            Sign::Zero)
            notSolid(surfaces.componentOf(r.pair.receiver()));
    }
    return true;
}

bool SolidFilter::openEdges() {
    // Open edges in the pyramid (closed: an edge on its boundary counts).
    QueryRun& r = q_.run;
    const PolygonMesh& mesh = r.mesh();
    const ClosedSurfaces& surfaces = q_.clusters.clusters().surfaces();
    found_.clear();
    if (!surfaces.openEdgeTree().empty() &&
        !r.budget.spend(surfaces.openEdgeTree().notOutside(r.pyramid, found_, r.budget.left())))
        return false;
    for (uint32_t e : found_) {
        const ClosedSurfaces::OpenEdge& o = surfaces.openEdges()[e];
        if (!solid(o.component)) continue;
        bool outside = false;
        for (const PlaneOrient& h : r.pyramid) {
            if (!r.budget.spend(2)) return false;
            if (h.sign(mesh.vertices[o.lo]) == Sign::Negative &&
                h.sign(mesh.vertices[o.hi]) == Sign::Negative) {
                outside = true;
                break;
            }
        }
        // Or L strictly on one side of the plane through x and the edge.
        if (!outside && !r.budget.spend(r.light().size())) return false;
        if (!outside && lightSideOf(mesh.vertices[o.lo], mesh.vertices[o.hi]) == Sign::Zero)
            notSolid(o.component);
    }
    return true;
}

bool SolidFilter::candidates() {
    // The faces in the pyramid are the walk's: its candidates, and the used groups' faces (a
    // group lies strictly in front of B's and L's planes, and x sees each of its faces strictly
    // from one side). Candidates that reach L's plane (or, x behind B's plane, B's) or pass
    // through x (x on the surface: its plane holds x, its box x; unless that is B's plane with
    // x on it) make their component no solid.
    QueryRun& r = q_.run;
    const PolygonMesh& mesh = r.mesh();
    const ClosedSurfaces& surfaces = q_.clusters.clusters().surfaces();
    const BoxTree& faces = q_.clusters.faces();
    const OrientedPlane& frontB = r.pair.frontB();
    const OrientedPlane& frontL = r.pair.frontL();
    const Bounds3& root = faces.nodeBox(0);
    const PlaneBoxCull inFrontOfL(PlaneOrient(frontL.a, frontL.c, frontL.b), root.lo, root.hi);
    const PlaneBoxCull inFrontOfB(PlaneOrient(frontB.a, frontB.c, frontB.b), root.lo, root.hi);
    // (Work counted in plane tests: a candidate's box tests are not.)
    auto reaches = [&](const OrientedPlane& plane, const std::vector<uint32_t>& ids) {
        for (uint32_t v : ids) {
            r.budget.spend();
            if (plane.orient.sign(mesh.vertices[v]) != Sign::Positive) return true;
        }
        return false;
    };
    for (uint32_t f : r.candidates) {
        if (f == r.pair.receiver() || f == r.pair.light() || !solid(surfaces.componentOf(f)))
            continue;
        if (r.budget.reached()) return false;
        const Bounds3& box = faces.itemBox(f);
        const auto& ids = mesh.faces[f];
        if ((!inFrontOfL.negative(box.lo, box.hi) && reaches(frontL, ids)) ||
            (xB_ == Sign::Negative && !inFrontOfB.negative(box.lo, box.hi) &&
             reaches(frontB, ids) && (r.budget.spend(3 * ids.size()), !missesCone(ids)))) {
            notSolid(surfaces.componentOf(f));
            continue;
        }
        if (!box.containsGrown(r.x, 0)) continue;
        if (!r.budget.spend() || r.occluderSide(facePlane(mesh, f).orient()) != Sign::Zero)
            continue;
        bool inB = xB_ == Sign::Zero;
        for (size_t i = 0; inB && i < ids.size(); ++i)
            inB = frontB.orient.sign(mesh.vertices[ids[i]]) == Sign::Zero;
        if (!inB) notSolid(surfaces.componentOf(f));
    }
    return true;
}

bool SolidFilter::windings() {
    // Each remaining component's winding along the segment from x to a vertex of L in front of
    // B's plane (one exists: L has area in front of it). The segment lies on the pyramid's
    // boundary, so the faces it crosses are among the walk's (their boxes touch the pyramid).
    QueryRun& r = q_.run;
    const PolygonMesh& mesh = r.mesh();
    const ClosedSurfaces& surfaces = q_.clusters.clusters().surfaces();
    const BoxTree& faces = q_.clusters.faces();
    const Vec3* v = nullptr;
    for (const Vec3& p : r.light())
        if (v == nullptr && r.pair.frontB().orient.sign(p) == Sign::Positive) v = &p;
    if (v == nullptr) return false;
    windingComponents_.clear();
    auto count = [&](uint32_t f) {
        const uint32_t component = surfaces.componentOf(f);
        if (f == r.pair.receiver() || f == r.pair.light() || !solid(component)) return;
        if (!r.budget.spend(mesh.faces[f].size() + 2)) return;
        const std::optional<int> crossing = segmentCrossing(f, *v);
        if (!crossing) {
            notSolid(component);  // through an edge of it: the count would not be its winding
        } else if (*crossing != 0) {
            if (windingStamp_[component] != run_) {
                windingStamp_[component] = run_;
                componentWinding_[component] = 0;
                windingComponents_.push_back(component);
            }
            componentWinding_[component] += *crossing;
        }
    };
    q_.lines.setLinePlanes(*v);
    std::array<PlaneBoxCull, 4> lineCull;
    const std::span<const PlaneBoxCull> onLine = faces.cullPlanes(q_.lines.linePlanes(), lineCull);
    for (uint32_t f : r.candidates) {
        if (!BoxTree::outsideOne(onLine, faces.itemBox(f))) count(f);
        if (r.budget.reached()) return false;
    }
    if (!q_.clusters.used().empty()) {
        q_.clusters.facesOnLine(q_.lines.linePlanes(), r.budget, [&](uint32_t f, int) {
            count(f);
            return r.budget.reached();
        });
    }
    if (r.budget.reached()) return false;
    for (uint32_t component : windingComponents_)
        if (solid(component) && componentWinding_[component] != 0) hidden_ = true;
    return true;
}

std::optional<int> SolidFilter::segmentCrossing(uint32_t face, const Vec3& v) const {
    const QueryRun& r = q_.run;
    const PolygonMesh& mesh = r.mesh();
    const auto& ids = mesh.faces[face];
    const PlaneOrient plane = facePlane(mesh, face).orient();
    const Sign sx = plane.sign(r.x), sv = plane.sign(v);
    // x in its plane: the segment meets it at x only (the contact rule; a face through x is no
    // solid's, candidates()); v in it: at v only, and a face that holds v reaches L's plane.
    if (sx == Sign::Zero || sv == Sign::Zero || sx == sv) return 0;
    // Through the face's interior: the line on one strict side of every edge line.
    bool positive = false, negative = false, zero = false;
    for (size_t i = 0; i < ids.size(); ++i) {
        const Sign s =
            orientSign(r.x, v, mesh.vertices[ids[i]], mesh.vertices[ids[(i + 1) % ids.size()]]);
        positive = positive || s == Sign::Positive;
        negative = negative || s == Sign::Negative;
        zero = zero || s == Sign::Zero;
    }
    if (positive && negative) return 0;
    if (zero) return std::nullopt;
    return sx == Sign::Positive ? 1 : -1;
}

Sign SolidFilter::lightSideOf(const Vec3& a, const Vec3& b) const {
    // (The whole light: its cone holds the cone over the part in front of B.)
    const PlaneOrient plane(q_.run.x, a, b);
    Sign side = Sign::Zero;
    for (const Vec3& p : q_.run.light()) {
        const Sign s = plane.sign(p);
        if (s == Sign::Zero || (side != Sign::Zero && s != side)) return Sign::Zero;
        side = s;
    }
    return side;
}

bool SolidFilter::missesCone(const std::vector<uint32_t>& ids) const {
    const std::vector<Vec3>& v = q_.run.mesh().vertices;
    // Strictly outside one side plane of the pyramid.
    for (const PlaneOrient& h : q_.run.pyramid) {
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
        const PlaneOrient plane(q_.run.x, a, b);
        bool apart = true;
        for (size_t k = 0; apart && k < ids.size(); ++k) apart = plane.sign(v[ids[k]]) != light;
        if (apart) return true;
    }
    return false;
}

}  // namespace penumbra::vis
