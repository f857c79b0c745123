// Exact 2D orientation and 3D collinearity of input points: the signs the face checks, the
// load-time triangulation and the receiver patches' lookup decide with. Exact for every finite
// double input: a floating-point filter (Shewchuk's bound) settles the common case, GMP the rest.
#pragma once

#include "visibility/vec3.h"

namespace penumbra::vis {

struct Point2 {
    double u = 0, v = 0;
    friend bool operator==(const Point2&, const Point2&) = default;
};

// The projection of p onto the coordinate plane (u, v) = (p[u], p[v]).
inline Point2 project(const Vec3& p, int u, int v) { return {p[u], p[v]}; }

// Exact sign of the turn a -> b -> c: +1 left (counter-clockwise), -1 right, 0 collinear.
// Inputs must be finite.
int orient2d(const Point2& a, const Point2& b, const Point2& c);

// The sign of orient2d when the floating-point filter alone settles it, 0 when it does not.
int orient2dFiltered(const Point2& a, const Point2& b, const Point2& c);

// Exact: is c on the line through a and b (a != b)? True iff the three coordinate-plane
// projections of the cross product (b - a) x (c - a) all vanish.
bool collinear3(const Vec3& a, const Vec3& b, const Vec3& c);

}  // namespace penumbra::vis
