// Plücker coordinates of lines in P^5 and the side operator.
//
// The line through p then q is pi(p,q) = (d, m) = (q - p, p x q). The side operator
// (permuted inner product) of two lines is side(l1, l2) = d1 . m2 + d2 . m1: zero iff the lines
// meet (or are parallel), and its sign says how l1 turns around l2. A point of P^5 is a real line
// iff side(x, x) = 0 (the Plücker quadric).
//
// For lines through input points, side(pi(p,q), pi(a,b)) == orient3d(p, q, a, b) (predicates.h),
// which is what every decision uses: sideSign() below is exact. The double-valued side() is
// approximate and only for display and tests.
#pragma once

#include <array>

#include "visibility/predicates.h"

namespace penumbra::vis {

struct PluckerLine {
    Vec3 d;  // direction q - p
    Vec3 m;  // moment p x q

    static PluckerLine through(const Vec3& p, const Vec3& q) { return {q - p, cross(p, q)}; }
    std::array<double, 6> coords() const { return {d.x, d.y, d.z, m.x, m.y, m.z}; }
};

// Approximate permuted inner product.
inline double side(const PluckerLine& a, const PluckerLine& b) {
    return dot(a.d, b.m) + dot(b.d, a.m);
}

// Exact sign of side(pi(p,q), pi(a,b)).
inline Sign sideSign(const Vec3& p, const Vec3& q, const Vec3& a, const Vec3& b) {
    return orientSign(p, q, a, b);
}

// side(pi(p,q), pi(a,b)) as a double with a rigorous error bound (exact sign when certain).
inline BoundedValue sideValue(const Vec3& p, const Vec3& q, const Vec3& a, const Vec3& b) {
    return orientValue(p, q, a, b);
}

}  // namespace penumbra::vis
