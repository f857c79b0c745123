#include "visibility/pair_occluders.h"

#include <algorithm>

#include "visibility/form_factor.h"
#include "visibility/polygon_clip.h"

namespace penumbra::vis {

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

    const uint32_t meshVertexCount = static_cast<uint32_t>(mesh.vertices.size());
    const OrientedPlane clipB{pb.a, pb.b, pb.c}, clipL{pl.a, pl.b, pl.c};
    auto consider = [&](uint32_t f) {
        if (f == receiver || f == light) return;
        const auto& idx = mesh.faces[f];
        // Closed boxes, touching counts: conservative.
        if (!mesh.faceBounds(f).overlaps(shaft)) return;
        std::vector<Vec3> poly;
        for (uint32_t v : idx) poly.push_back(mesh.vertices[v]);
        poly = clipConvexPositive(poly, clipB);
        if (poly.size() < 3) return;
        poly = clipConvexPositive(poly, clipL);
        if (poly.size() < 3) return;
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
        for (const Vec3& p : poly) {
            auto it = std::find_if(idx.begin(), idx.end(),
                                   [&](uint32_t v) { return mesh.vertices[v] == p; });
            if (it != idx.end()) {
                occ.vertexIds.push_back(*it);
            } else {
                occ.vertexIds.push_back(meshVertexCount +
                                        static_cast<uint32_t>(out.extraVertices.size()));
                out.extraVertices.push_back(p);
            }
        }
        occ.area = polygonArea(poly);
        out.occluders.push_back(std::move(occ));
    };
    if (candidates.empty()) {
        for (uint32_t f = 0; f < mesh.faces.size(); ++f) consider(f);
    } else {
        for (uint32_t f : candidates) consider(f);
    }
    std::stable_sort(out.occluders.begin(), out.occluders.end(),
                     [](const Occluder& a, const Occluder& b) { return a.area > b.area; });
    return out;
}

}  // namespace penumbra::vis
