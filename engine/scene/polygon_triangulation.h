// PolygonTriangulation: the load-time split of a face that is not an exactly planar, strictly
// convex polygon (non-planar, concave, with collinear or repeated vertices, or weakly simple: an
// n-gon with a hole written as one loop that walks in to the hole and back out along a bridge)
// into triangles of its own vertices.
//
// What is exact: every decision is an exact orientation sign of input coordinates (orient2d.h) in
// one coordinate projection, so no new vertex is made or rounded and the triangles cover exactly
// the projected polygon. The projection drops the dominant axis of the polygon's Newell normal (an
// approximate choice: it only decides which exact projection is used; if the polygon is not
// simple in it, the other axes are tried). The result is independent of where the vertex list
// starts: the polygon is first rotated to start at its lexicographically smallest sequence of
// positions, and everything after that is deterministic.
//
// Refused (an error, nothing split): a polygon whose projections all self-intersect (two edges
// that cross, or a vertex on another edge's interior), whose vertices are all collinear, or that
// has more than kMaxVertices vertices.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "visibility/orient2d.h"
#include "visibility/vec3.h"

namespace penumbra {

class PolygonTriangulation {
  public:
    using Triangle = std::array<uint32_t, 3>;  // positions in the input list, in its order
    // The most distinct vertices a polygon may have to be split (ear clipping costs their square,
    // their cube at worst): a larger one is refused, never a hang.
    static constexpr size_t kMaxVertices = 512;

    // Splits the polygon `points` (in order, counter-clockwise seen from its front) into
    // triangles, turning the same way; positions repeated one after the other are taken once, and
    // a triangle of zero area is left out. Returns nullopt on success (triangles() holds them),
    // else why it cannot be split.
    std::optional<std::string> run(std::span<const vis::Vec3> points);
    const std::vector<Triangle>& triangles() const { return triangles_; }

  private:
    bool simpleIn(int u, int v);  // the projection on (u, v) is weakly simple (exact)
    bool clipEars(int sign);      // ear clipping in the projection q_, turning `sign`

    std::span<const vis::Vec3> points_;
    std::vector<uint32_t> ring_;         // the canonical cycle: indices into points_
    std::vector<vis::Point2> q_;         // ring_'s points projected
    std::vector<uint32_t> prev_, next_;  // the remaining polygon, a cyclic list over ring_
    std::vector<Triangle> triangles_;
};

}  // namespace penumbra
