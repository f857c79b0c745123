#include "visibility/pair_occluders.h"

#include <algorithm>
#include <cmath>
#include <optional>

#include "visibility/clipped_occluder.h"
#include "visibility/form_factor.h"
#include "visibility/polygon_clip.h"

namespace penumbra::vis {

std::vector<PlaneOrient> hullPlanes(std::span<const Vec3> b, std::span<const Vec3> l) {
    std::vector<PlaneOrient> planes;
    auto tryPlane = [&](const Vec3& p, const Vec3& q, const Vec3& r) {
        const PlaneOrient plane(p, q, r);
        bool pos = false, neg = false;
        for (std::span<const Vec3> poly : {b, l})
            for (const Vec3& v : poly) {
                const Sign s = plane.sign(v);
                pos |= s == Sign::Positive;
                neg |= s == Sign::Negative;
            }
        if (pos && neg) return;    // not a supporting plane
        if (!pos && !neg) return;  // every vertex on it: degenerate, no information
        planes.push_back(neg ? PlaneOrient(p, r, q) : plane);
    };
    for (auto [from, to] : {std::pair{b, l}, std::pair{l, b}})
        for (size_t i = 0; i < from.size(); ++i)
            for (const Vec3& v : to) tryPlane(from[i], from[(i + 1) % from.size()], v);
    // The polygons' own planes, where the other lies on one side (the caps of the hull).
    for (std::span<const Vec3> poly : {b, l})
        if (poly.size() >= 3) tryPlane(poly[0], poly[1], poly[2]);
    return planes;
}

void pyramidPlanes(const Vec3& apex, std::span<const Vec3> polygon, std::vector<PlaneOrient>& out) {
    out.clear();
    const size_t n = polygon.size();
    for (size_t i = 0; i < n; ++i) {
        const Vec3& a = polygon[i];
        const Vec3& b = polygon[(i + 1) % n];
        PlaneOrient plane(apex, a, b);
        const Sign inner = plane.sign(polygon[(i + 2) % n]);
        if (inner == Sign::Zero) continue;  // degenerate: no help
        if (inner == Sign::Negative) plane = PlaneOrient(apex, b, a);
        out.push_back(plane);
    }
}

bool outsideOnePlane(std::span<const PlaneOrient> planes, std::span<const Vec3> polygon) {
    for (const PlaneOrient& plane : planes) {
        bool inside = false;
        for (const Vec3& p : polygon) inside |= plane.sign(p) == Sign::Positive;
        if (!inside) return true;
    }
    return false;
}

namespace {

// Back-facing: L has no point strictly in front of B, or B none strictly in front of L (nor the
// receiver region, which is all of B or a patch of it).
bool backFacing(const PolygonMesh& mesh, uint32_t receiver, uint32_t light, const FacePlane& pb,
                const FacePlane& pl, std::span<const Vec3> receiverRegion) {
    auto anyFront = [&](const FacePlane& plane, uint32_t face) {
        for (uint32_t v : mesh.faces[face])
            if (plane.side(mesh.vertices[v]) == Sign::Positive) return true;
        return false;
    };
    bool regionInFront = false;
    for (const Vec3& p : receiverRegion) regionInFront |= pl.side(p) == Sign::Positive;
    return !anyFront(pb, light) || !anyFront(pl, receiver) || !regionInFront;
}

// The insertion order's key: the area of L a polygon hides from the centroid of B. The occluders
// that hide the most come first: a large early shadow makes the leaves behind it hidden, and later
// occluders there cost nothing. (A heuristic in doubles: any order gives an exact tree. Measured
// against the clipped area alone and against shadows summed over several points of B, this was
// the fastest on table and grids; penumbra_pair_stats.)
class ShadowArea {
  public:
    ShadowArea(const PolygonMesh& mesh, uint32_t light, std::span<const Vec3> lightPoints,
               std::span<const Vec3> receiverRegion)
        : lightPoints_(lightPoints), lightNormal_(mesh.faceAreaNormal(light)) {
        for (const Vec3& p : receiverRegion) eye_ += p / static_cast<double>(receiverRegion.size());
        // The side planes of the pyramid from eye over L. (An eye in L's plane gives none, where
        // every plane through it and an edge would be L's own; either way every shadow area is 0
        // then.)
        std::vector<PlaneOrient> eyePyramid;
        pyramidPlanes(eye_, lightPoints, eyePyramid);
        for (const PlaneOrient& p : eyePyramid) pyramid_.push_back(OrientedPlane{p.a, p.b, p.c});
    }

    double operator()(std::vector<Vec3> poly) const {
        for (const OrientedPlane& plane : pyramid_) {
            poly = clipConvexPositive(poly, plane);
            if (poly.size() < 3) return 0.0;
        }
        // Central projection from the eye onto L's plane, then the area there.
        const double offset = dot(lightNormal_, lightPoints_[0] - eye_);
        for (Vec3& p : poly) {
            const double denom = dot(lightNormal_, p - eye_);
            if (!(std::fabs(denom) > 0)) return 0.0;
            p = eye_ + (p - eye_) * (offset / denom);
        }
        return polygonArea(poly);
    }

  private:
    std::span<const Vec3> lightPoints_;
    Vec3 lightNormal_;
    Vec3 eye_{};
    std::vector<OrientedPlane> pyramid_;
};

// Which way the segments from B to L cross the plane of face f: +1 when B is behind it and L in
// front (segments go up through a CCW polygon), -1 the other way round, 0 when both occur;
// nullopt when no segment crosses it strictly (it blocks nothing of positive measure).
std::optional<int> blockedSign(const PolygonMesh& mesh, uint32_t f, uint32_t light,
                               std::span<const Vec3> receiverRegion) {
    const FacePlane po = facePlane(mesh, f);
    int bPos = 0, bNeg = 0, lPos = 0, lNeg = 0;
    for (const Vec3& p : receiverRegion) {
        const Sign s = po.side(p);
        bPos += s == Sign::Positive;
        bNeg += s == Sign::Negative;
    }
    for (uint32_t v : mesh.faces[light]) {
        const Sign s = po.side(mesh.vertices[v]);
        lPos += s == Sign::Positive;
        lNeg += s == Sign::Negative;
    }
    if ((bNeg == 0 && lNeg == 0) || (bPos == 0 && lPos == 0)) return std::nullopt;
    if (bPos == 0 && lNeg == 0) return +1;
    if (bNeg == 0 && lPos == 0) return -1;
    return 0;
}

// The candidate faces of one (receiver, light) pair, one at a time: what the pair's shaft, hull
// and clip planes leave of each.
class OccluderClipper {
  public:
    OccluderClipper(const PolygonMesh& mesh, uint32_t receiver, uint32_t light,
                    std::span<const Vec3> receiverRegion, const FacePlane& pb, const FacePlane& pl,
                    std::span<const Vec3> lightPoints)
        : mesh_(mesh),
          receiver_(receiver),
          light_(light),
          receiverRegion_(receiverRegion),
          hull_(hullPlanes(receiverRegion, lightPoints)),
          shadowArea_(mesh, light, lightPoints, receiverRegion),
          clipB_{pb.a, pb.b, pb.c},
          clipL_{pl.a, pl.b, pl.c} {
        for (const Vec3& p : receiverRegion) shaft_.add(p);
        for (uint32_t v : mesh.faces[light]) shaft_.add(mesh.vertices[v]);
    }

    // Face f as an occluder of the pair; nullopt when it blocks no segment from B to L of positive
    // measure (or is B or L).
    std::optional<Occluder> clip(uint32_t f) {
        if (f == receiver_ || f == light_) return std::nullopt;
        // Closed boxes, touching counts: conservative.
        if (!mesh_.faceBounds(f).overlaps(shaft_)) return std::nullopt;
        // Outside the hull as a whole face: its clipped part is too (exact; before any clip).
        std::vector<Vec3>& face = facePoints_;
        face.clear();
        for (uint32_t v : mesh_.faces[f]) face.push_back(mesh_.vertices[v]);
        if (outsideOnePlane(hull_, face)) return std::nullopt;
        clipped_.clip(mesh_, f, clipB_.orient, clipL_.orient);
        if (clipped_.empty()) return std::nullopt;
        // Outside the hull of B and L (or touching it only): blocks no segment of positive
        // measure. Exact on the symbolic vertices (a corner of the two chords counts as inside).
        for (const PlaneOrient& h : hull_)
            if (clipped_.outside(h)) return std::nullopt;
        const std::optional<int> sign = blockedSign(mesh_, f, light_, receiverRegion_);
        if (!sign) return std::nullopt;
        Occluder occ;
        occ.face = f;
        occ.blockedSign = *sign;
        occ.edges.assign(clipped_.edges().begin(), clipped_.edges().end());
        // The insertion order's heuristics, in doubles: the rounded clip of the face (it may be
        // empty where the exact one is a sliver; then the occluder just comes last).
        std::vector<Vec3> poly(clipped_.facePoints().begin(), clipped_.facePoints().end());
        if (clipped_.clipped()) poly = clipConvexPositive(clipConvexPositive(poly, clipB_), clipL_);
        occ.area = poly.size() >= 3 ? polygonArea(poly) : 0.0;
        occ.shadow = poly.size() >= 3 ? shadowArea_(poly) : 0.0;
        return occ;
    }

  private:
    const PolygonMesh& mesh_;
    uint32_t receiver_, light_;
    std::span<const Vec3> receiverRegion_;
    Bounds3 shaft_;
    std::vector<PlaneOrient> hull_;
    ShadowArea shadowArea_;
    OrientedPlane clipB_, clipL_;
    ClippedOccluder clipped_;
    std::vector<Vec3> facePoints_;
};

}  // namespace

PairOccluders gatherOccluders(const PolygonMesh& mesh, uint32_t receiver, uint32_t light,
                              std::span<const uint32_t> candidates,
                              std::span<const Vec3> receiverRegion) {
    PairOccluders out;
    const FacePlane pb = facePlane(mesh, receiver), pl = facePlane(mesh, light);
    if (backFacing(mesh, receiver, light, pb, pl, receiverRegion)) {
        out.backFacing = true;
        return out;
    }
    std::vector<Vec3> lightPoints;
    for (uint32_t v : mesh.faces[light]) lightPoints.push_back(mesh.vertices[v]);
    OccluderClipper clipper(mesh, receiver, light, receiverRegion, pb, pl, lightPoints);
    auto consider = [&](uint32_t f) {
        if (std::optional<Occluder> occ = clipper.clip(f)) out.occluders.push_back(std::move(*occ));
    };
    if (candidates.empty()) {
        for (uint32_t f = 0; f < mesh.faces.size(); ++f) consider(f);
    } else {
        for (uint32_t f : candidates) consider(f);
    }
    std::stable_sort(out.occluders.begin(), out.occluders.end(),
                     [](const Occluder& a, const Occluder& b) {
                         return a.shadow != b.shadow ? a.shadow > b.shadow : a.area > b.area;
                     });
    return out;
}

}  // namespace penumbra::vis
