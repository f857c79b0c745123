#include "engine/render/shading_point.h"

#include "visibility/face_plane.h"

namespace penumbra {

vis::AnsweredPoint shadingPoint(const vis::PolygonMesh& mesh, uint32_t face, const vis::Vec3& hit) {
    const vis::Vec3 x =
        surfacePoint(hit, normalize(mesh.faceAreaNormal(face)), mesh.vertices[mesh.faces[face][0]]);
    return vis::answeredPoint(vis::facePlane(mesh, face).orient(), x);
}

}  // namespace penumbra
