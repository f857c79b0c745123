// Exact 2D orientation and 3D collinearity of input points: the signs the face checks, the
// load-time triangulation and the receiver patches' lookup decide with. Exact for every finite
// double input: a floating-point filter (Shewchuk's bound) settles the common case, GMP the rest.
#pragma once

#include <cmath>

#include "visibility/vec3.h"

namespace penumbra::vis {

struct Point2 {
    double u = 0, v = 0;
    friend bool operator==(const Point2&, const Point2&) = default;
};

// The projection of p onto the coordinate plane (u, v) = (p[u], p[v]).
inline Point2 project(const Vec3& p, int u, int v) { return {p[u], p[v]}; }

// The projection that drops coordinate `axis`: (p[axis + 1], p[axis + 2]) cyclically, so that a
// polygon counter-clockwise about +axis stays counter-clockwise.
inline Point2 projectDropping(const Vec3& p, int axis) {
    return project(p, (axis + 1) % 3, (axis + 2) % 3);
}

// Exact sign of the turn a -> b -> c: +1 left (counter-clockwise), -1 right, 0 collinear.
// Inputs must be finite.
int orient2d(const Point2& a, const Point2& b, const Point2& c);

// The sign of orient2d when the floating-point filter alone settles it, 0 when it does not.
// Shewchuk (1997), ccwerrboundA: for det = (a.u-c.u)(b.v-c.v) - (a.v-c.v)(b.u-c.u) evaluated in
// doubles, |det - exact| <= (3 + 16 eps) eps (|detleft| + |detright|), eps = 2^-53, as long as
// nothing overflows or underflows; below 2^-960 or on overflow the filter gives up. Inline: the
// receiver patches' lookup calls it per point.
inline int orient2dFiltered(const Point2& a, const Point2& b, const Point2& c) {
    constexpr double eps = 0x1p-53;
    constexpr double bound = (3.0 + 16.0 * eps) * eps;
    const double detLeft = (a.u - c.u) * (b.v - c.v);
    const double detRight = (a.v - c.v) * (b.u - c.u);
    const double det = detLeft - detRight;
    const double sum = std::fabs(detLeft) + std::fabs(detRight);
    if (!(sum >= 0x1p-960 && sum <= 1.7976931348623157e308)) return 0;
    const double error = bound * sum;
    return det > error ? 1 : (det < -error ? -1 : 0);
}

// Exact: is c on the line through a and b (a != b)? True iff the three coordinate-plane
// projections of the cross product (b - a) x (c - a) all vanish.
bool collinear3(const Vec3& a, const Vec3& b, const Vec3& c);

}  // namespace penumbra::vis
