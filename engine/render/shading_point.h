// The point of a face that a ray hit stands for (surfacePoint), and the point a query without a
// history tree takes there (frontPoint).
//
// Embree's hit, computed in float, lies a hair off the face's plane, so it is projected onto the
// plane in double; the projection is rounded and lands on either side of it. Seen from a point
// strictly behind the plane the exact query takes for the receiver (vis::facePlane), the chords
// where that plane cuts the occluders cut a strip some ulps wide along B's edge of the light,
// which the direct query labels cell by cell; from a point on or in front they change no cell
// (FromPointQuery::buildChain). frontPoint moves the point along that plane's normal by a few
// ulps, the least step the filter certifies strictly in front (the step that moves the value past
// the filter's error, doubled until it does): a point as good for the pixel (the hit was already
// a rounding of the ray's). Either point's answer is exact; the front one costs less on the
// direct path: on the motorbike's points over the work limit, every point exact, 5.2 -> 4.0 ms
// mean and 0.99 -> 0.64 ms median (48x48 camera points, light 0); its render with every point
// exact at 96x96, 1 spp, 11.4 -> 8.5 s CPU. A tree's walk takes the projection: from strictly in
// front of B a point next to an occluder standing on B costs it the near-contact test
// (FromPointQuery::nearContact), and moving every point made the Cornell box's and the stairs'
// renders 7-10% slower. Filtered tests only: from a point within ulps of the plane the exact test
// goes to its exact stage, which costs more than the shading.
#pragma once

#include <cstdint>

#include "visibility/polygon_mesh.h"
#include "visibility/predicates.h"

namespace penumbra {

// The hit projected onto the face's plane: `normal` its unit normal, `origin` a point of it (its
// first vertex).
inline vis::Vec3 surfacePoint(const vis::Vec3& hit, const vis::Vec3& normal,
                              const vis::Vec3& origin) {
    return hit - normal * dot(normal, hit - origin);
}

// x itself where the filter certifies it strictly in front of `plane` (a face's
// vis::facePlane(mesh, face).orient()), else x moved along the plane's normal by the least such
// step. A plane whose rounded normal is zero keeps x (the query still answers it exactly).
vis::Vec3 frontPoint(const vis::PlaneOrient& plane, const vis::Vec3& x);

// The viewer's click, answered by the direct query: frontPoint of surfacePoint, from the mesh.
vis::Vec3 shadingPoint(const vis::PolygonMesh& mesh, uint32_t face, const vis::Vec3& hit);

}  // namespace penumbra
