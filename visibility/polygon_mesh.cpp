#include "visibility/polygon_mesh.h"

namespace penumbra::vis {

Vec3 PolygonMesh::faceAreaNormal(uint32_t f) const {
    const auto& idx = faces[f];
    Vec3 n{};
    for (size_t i = 0; i < idx.size(); ++i) {
        const Vec3& a = vertices[idx[i]];
        const Vec3& b = vertices[idx[(i + 1) % idx.size()]];
        n += cross(a, b);
    }
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
