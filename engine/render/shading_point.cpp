#include "engine/render/shading_point.h"

#include <algorithm>
#include <cfloat>
#include <cmath>

#include "visibility/face_plane.h"

namespace penumbra {

vis::Vec3 frontPoint(const vis::PlaneOrient& plane, const vis::Vec3& x) {
    vis::BoundedValue v;
    if (plane.filtered(x, v) && v.value > 0) return x;  // certainly in front
    // Within the filter's error of the plane (most projections) or behind it.
    const vis::Vec3 up{plane.n[0], plane.n[1], plane.n[2]};
    const double upLength = length(up);
    if (!(upLength > 0)) return x;
    const double ulp =
        std::max({std::fabs(x.x), std::fabs(x.y), std::fabs(x.z), DBL_MIN}) * 0x1p-52;
    double step = std::max(2 * (std::fabs(v.value) + v.error) / upLength, ulp);
    for (int i = 0; i < 32; ++i, step *= 2) {
        const vis::Vec3 moved = x + up * (step / upLength);
        if (plane.filtered(moved, v) && v.value > 0) return moved;
    }
    return x;
}

vis::Vec3 shadingPoint(const vis::PolygonMesh& mesh, uint32_t face, const vis::Vec3& hit) {
    const vis::Vec3 x =
        surfacePoint(hit, normalize(mesh.faceAreaNormal(face)), mesh.vertices[mesh.faces[face][0]]);
    return frontPoint(vis::facePlane(mesh, face).orient(), x);
}

}  // namespace penumbra
