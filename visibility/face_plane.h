// FacePlane: the plane of a mesh face for exact side tests, from its first three input vertices.
// Loaded faces are exactly planar and strictly convex (engine/scene/scene_validation.h: a face
// that is not is split into triangles on load), so any three consecutive vertices span the same
// plane with the same orientation: the exact sign of a point against it does not depend on where
// the face's vertex list starts. Every side test of a point against a face's plane, and every
// PlaneOrient of one, goes through facePlane().
#pragma once

#include <array>
#include <cstdint>
#include <span>

#include "visibility/polygon_mesh.h"
#include "visibility/predicates.h"

namespace penumbra::vis {

struct FacePlane {
    Vec3 a, b, c;
    Sign side(const Vec3& y) const { return orientSign(a, b, c, y); }
    PlaneOrient orient() const { return PlaneOrient(a, b, c); }
};

inline FacePlane facePlane(const PolygonMesh& mesh, uint32_t face) {
    const auto& f = mesh.faces[face];
    return {mesh.vertices[f[0]], mesh.vertices[f[1]], mesh.vertices[f[2]]};
}

// The same plane from copies of those three vertices, indexed by `corners` in `vertices`
// (LightEdgeIndex::localFace).
inline FacePlane facePlane(std::span<const Vec3> vertices, const std::array<uint32_t, 3>& corners) {
    return {vertices[corners[0]], vertices[corners[1]], vertices[corners[2]]};
}

}  // namespace penumbra::vis
