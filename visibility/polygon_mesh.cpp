#include "visibility/polygon_mesh.h"

namespace penumbra::vis {

Vec3 PolygonMesh::faceAreaNormal(uint32_t f) const {
    // Newell's sum over the edges, taken relative to the first vertex: the terms are the size of
    // the face, not of its coordinates (a small face far from the origin summed in absolute
    // coordinates loses its normal to cancellation: one of 2e-4 at 1e4 came out pointing
    // anywhere).
    const auto& idx = faces[f];
    Vec3 n{};
    if (idx.empty()) return n;
    const Vec3& o = vertices[idx[0]];
    for (size_t i = 1; i + 1 < idx.size(); ++i)
        n += cross(vertices[idx[i]] - o, vertices[idx[i + 1]] - o);
    return n;
}

double PolygonMesh::faceArea(uint32_t f) const { return 0.5 * length(faceAreaNormal(f)); }

Bounds3 PolygonMesh::faceBounds(uint32_t f) const {
    Bounds3 b;
    for (uint32_t v : faces[f]) b.add(vertices[v]);
    return b;
}

Bounds3 PolygonMesh::bounds() const {
    Bounds3 b;
    for (const Vec3& v : vertices) b.add(v);
    return b;
}

}  // namespace penumbra::vis
