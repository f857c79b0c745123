// Clipping a convex polygon by a plane, with the side of every vertex decided exactly.
#pragma once

#include <functional>
#include <span>
#include <vector>

#include "visibility/predicates.h"

namespace penumbra::vis {

// The plane through three points; side(y) = orient3d(a, b, c, y): exact sign for any double y.
struct OrientedPlane {
    OrientedPlane(const Vec3& a_, const Vec3& b_, const Vec3& c_)
        : a(a_), b(b_), c(c_), orient(a_, b_, c_) {}
    Vec3 a, b, c;
    PlaneOrient orient;  // the cross product formed once for many side tests
    Sign side(const Vec3& y) const { return orient.sign(y); }
    BoundedValue value(const Vec3& y) const { return orient.value(y); }
};

// Splits `polygon` into `positive` and `negative` (cleared first, capacity kept: callers reuse
// buffers in hot loops). Same rules as clipConvex.
void clipConvexInto(std::span<const Vec3> polygon, const OrientedPlane& plane,
                    std::vector<Vec3>& positive, std::vector<Vec3>& negative);

// The same split for polygons whose vertices are partly rounded constructions (the fragments of
// FPQuery). Vertices equal to one of `inputVertices` get their exact sign. Any other vertex whose
// sign the floating-point filter cannot certify is treated as lying on the plane (it goes to both
// parts, no new vertex): it is itself a rounded construction whose rounding error is of the order
// of the filter's bound, so the exact sign of the rounded point carries no information, and taking
// it would only create slivers of rounding width. Areas move by at most that rounding width.
void clipConstructedInto(std::span<const Vec3> polygon, const OrientedPlane& plane,
                         std::span<const Vec3> inputVertices, std::vector<Vec3>& positive,
                         std::vector<Vec3>& negative);

// For measuring what exactness costs (FromPointQuery's PredicateMode): every sign through the
// exact stage (no filter), or the plain double determinant's sign (approximate, can be wrong).
void clipExactInto(std::span<const Vec3> polygon, const OrientedPlane& plane,
                   std::vector<Vec3>& positive, std::vector<Vec3>& negative);
void clipNaiveInto(std::span<const Vec3> polygon, const OrientedPlane& plane,
                   std::vector<Vec3>& positive, std::vector<Vec3>& negative);

struct ClipResult {
    std::vector<Vec3> positive;  // part with side >= 0 (empty unless some vertex is strictly > 0)
    std::vector<Vec3> negative;  // part with side <= 0 (empty unless some vertex is strictly < 0)
};

// Splits a convex polygon. A vertex exactly on the plane goes to both parts and creates no new
// vertex, so a plane through a vertex leaves no sliver and loses no area; a part without a strict
// vertex has zero area and is returned empty. Crossing points are rounded constructions, placed on
// the segment between the two strictly separated vertices (never outside it).
ClipResult clipConvex(std::span<const Vec3> polygon, const OrientedPlane& plane);

// Only the part with side > 0 (same rules).
std::vector<Vec3> clipConvexPositive(std::span<const Vec3> polygon, const OrientedPlane& plane);

}  // namespace penumbra::vis
