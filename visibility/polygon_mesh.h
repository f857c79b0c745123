// PolygonMesh: the geometry the visibility core sees. Vertices and convex planar faces, each face
// a counter-clockwise (seen from its front) list of vertex indices. No materials, no file formats:
// the engine's Scene owns one of these and adds the rest.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "visibility/bounds3.h"
#include "visibility/vec3.h"

namespace penumbra::vis {

struct PolygonMesh {
    std::vector<Vec3> vertices;
    std::vector<std::vector<uint32_t>> faces;

    std::span<const uint32_t> face(uint32_t f) const { return faces[f]; }
    Vec3 vertex(uint32_t v) const { return vertices[v]; }
    // Area-weighted normal (length = 2 * area), Newell's method. Approximate.
    Vec3 faceAreaNormal(uint32_t f) const;
    double faceArea(uint32_t f) const;
    Bounds3 faceBounds(uint32_t f) const;
    Bounds3 bounds() const;  // of all vertices
};

}  // namespace penumbra::vis
