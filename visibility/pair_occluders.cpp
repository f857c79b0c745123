#include "visibility/pair_occluders.h"

#include <algorithm>
#include <cmath>

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

FacePlane facePlane(const PolygonMesh& mesh, uint32_t face) {
    const auto& f = mesh.faces[face];
    return {mesh.vertices[f[0]], mesh.vertices[f[1]], mesh.vertices[f[2]]};
}

PairOccluders gatherOccluders(const PolygonMesh& mesh, uint32_t receiver, uint32_t light,
                              std::span<const uint32_t> candidates,
                              std::span<const Vec3> receiverRegion) {
    PairOccluders out;
    const FacePlane pb = facePlane(mesh, receiver), pl = facePlane(mesh, light);
    // Back-facing: L has no point strictly in front of B, or B none strictly in front of L.
    auto anyFront = [&](const FacePlane& plane, uint32_t face) {
        for (uint32_t v : mesh.faces[face])
            if (plane.side(mesh.vertices[v]) == Sign::Positive) return true;
        return false;
    };
    bool regionInFront = false;
    for (const Vec3& p : receiverRegion) regionInFront |= pl.side(p) == Sign::Positive;
    if (!anyFront(pb, light) || !anyFront(pl, receiver) || !regionInFront) {
        out.backFacing = true;
        return out;
    }
    Bounds3 shaft;
    for (const Vec3& p : receiverRegion) shaft.add(p);
    for (uint32_t v : mesh.faces[light]) shaft.add(mesh.vertices[v]);

    std::vector<Vec3> lightPoints;
    for (uint32_t v : mesh.faces[light]) lightPoints.push_back(mesh.vertices[v]);
    const std::vector<PlaneOrient> hull = hullPlanes(receiverRegion, lightPoints);

    // Insertion order: the occluders that hide the most of L from the centroid of B first. A
    // large early shadow makes the leaves behind it hidden, and later occluders there cost
    // nothing. (A heuristic in doubles: any order gives an exact tree. Measured against the
    // clipped area alone and against shadows summed over several points of B, this was the
    // fastest on table and grids; penumbra_pair_stats.)
    Vec3 eye{};
    for (const Vec3& p : receiverRegion) eye += p / static_cast<double>(receiverRegion.size());
    // The side planes of the pyramid from eye over L. (An eye in L's plane gives none, where every
    // plane through it and an edge would be L's own; either way every shadow area is 0 then.)
    std::vector<PlaneOrient> eyePyramid;
    pyramidPlanes(eye, lightPoints, eyePyramid);
    std::vector<OrientedPlane> pyramid;
    for (const PlaneOrient& p : eyePyramid) pyramid.push_back(OrientedPlane{p.a, p.b, p.c});
    const Vec3 lightNormal = mesh.faceAreaNormal(light);
    auto shadowArea = [&](std::vector<Vec3> poly) {
        for (const OrientedPlane& plane : pyramid) {
            poly = clipConvexPositive(poly, plane);
            if (poly.size() < 3) return 0.0;
        }
        // Central projection from the eye onto L's plane, then the area there.
        const double offset = dot(lightNormal, lightPoints[0] - eye);
        for (Vec3& p : poly) {
            const double denom = dot(lightNormal, p - eye);
            if (!(std::fabs(denom) > 0)) return 0.0;
            p = eye + (p - eye) * (offset / denom);
        }
        return polygonArea(poly);
    };

    const OrientedPlane clipB{pb.a, pb.b, pb.c}, clipL{pl.a, pl.b, pl.c};
    ClippedOccluder clipped;
    std::vector<Vec3> facePoints;
    auto outsideHull = [&](std::span<const Vec3> poly) { return outsideOnePlane(hull, poly); };
    auto consider = [&](uint32_t f) {
        if (f == receiver || f == light) return;
        // Closed boxes, touching counts: conservative.
        if (!mesh.faceBounds(f).overlaps(shaft)) return;
        // Outside the hull as a whole face: its clipped part is too (exact; before any clip).
        std::vector<Vec3>& face = facePoints;
        face.clear();
        for (uint32_t v : mesh.faces[f]) face.push_back(mesh.vertices[v]);
        if (outsideHull(face)) return;
        clipped.clip(mesh, f, clipB.orient, clipL.orient);
        if (clipped.empty()) return;
        // Outside the hull of B and L (or touching it only): blocks no segment of positive
        // measure. Exact on the symbolic vertices (a corner of the two chords counts as inside).
        for (const PlaneOrient& h : hull)
            if (clipped.outside(h)) return;
        // Which way do segments from B to L cross the occluder's plane?
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
        // No segment from B to L crosses the plane strictly: it blocks nothing of positive measure.
        if ((bNeg == 0 && lNeg == 0) || (bPos == 0 && lPos == 0)) return;
        Occluder occ;
        occ.face = f;
        if (bPos == 0 && lNeg == 0)
            occ.blockedSign = +1;  // B behind, L in front: segments go up through a CCW polygon
        else if (bNeg == 0 && lPos == 0)
            occ.blockedSign = -1;
        else
            occ.blockedSign = 0;
        occ.edges.assign(clipped.edges().begin(), clipped.edges().end());
        // The insertion order's heuristics, in doubles: the rounded clip of the face (it may be
        // empty where the exact one is a sliver; then the occluder just comes last).
        std::vector<Vec3> poly(clipped.facePoints().begin(), clipped.facePoints().end());
        if (clipped.clipped()) poly = clipConvexPositive(clipConvexPositive(poly, clipB), clipL);
        occ.area = poly.size() >= 3 ? polygonArea(poly) : 0.0;
        occ.shadow = poly.size() >= 3 ? shadowArea(poly) : 0.0;
        out.occluders.push_back(std::move(occ));
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
