// The point of a face that a ray hit stands for (surfacePoint), and the point every query answers
// there (shadingPoint: vis::answeredPoint of it).
//
// Embree's hit, computed in float, lies a hair off the face's plane, so it is projected onto the
// plane in double; the projection is rounded and lands on either side of it. A projection behind
// the plane, or one that cheap tests cannot certify on or in front of it, is answered from its
// front side, some ulps away, with the contact rule decided at the projection itself
// (visibility/answered_point.h): by the tree walk and by the direct query alike, so that the
// renderer's two paths, the viewer's click and `query` answer one point.
#pragma once

#include <cstdint>

#include "visibility/answered_point.h"
#include "visibility/polygon_mesh.h"

namespace penumbra {

// The hit projected onto the face's plane: `normal` its unit normal, `origin` a point of it (its
// first vertex).
inline vis::Vec3 surfacePoint(const vis::Vec3& hit, const vis::Vec3& normal,
                              const vis::Vec3& origin) {
    return hit - normal * dot(normal, hit - origin);
}

// The point answered for a hit on `face`: answeredPoint of surfacePoint, from the mesh.
vis::AnsweredPoint shadingPoint(const vis::PolygonMesh& mesh, uint32_t face, const vis::Vec3& hit);

}  // namespace penumbra
