#include "engine/render/shading_point.h"

#include <algorithm>
#include <cfloat>
#include <cmath>

#include "visibility/face_plane.h"

namespace penumbra {

vis::Vec3 shadingPoint(const vis::PolygonMesh& mesh, uint32_t face, const vis::Vec3& hit,
                       const vis::Vec3& normal, const vis::Vec3& origin) {
    const vis::Vec3 x = hit - normal * dot(normal, hit - origin);
    const vis::PlaneOrient plane = vis::facePlane(mesh, face).orient();
    if (plane.sign(x) != vis::Sign::Negative) return x;
    const double ulp =
        std::max({std::fabs(x.x), std::fabs(x.y), std::fabs(x.z), DBL_MIN}) * 0x1p-52;
    for (double step = ulp; step < ulp * 0x1p20; step *= 2) {
        const vis::Vec3 moved = x + normal * step;
        if (plane.sign(moved) != vis::Sign::Negative) return moved;
    }
    return x;
}

vis::Vec3 shadingPoint(const vis::PolygonMesh& mesh, uint32_t face, const vis::Vec3& hit) {
    return shadingPoint(mesh, face, hit, normalize(mesh.faceAreaNormal(face)),
                        mesh.vertices[mesh.faces[face][0]]);
}

}  // namespace penumbra
