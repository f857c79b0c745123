// Exact values as GMP rationals, for the few places that need more than a sign (the exact fallback
// of polytope certificates, and of the filters of edge_line.h). Kept out of predicates.h so that
// GMP's headers do not spread through the project.
#pragma once

#include <gmpxx.h>

#include "visibility/edge_line.h"
#include "visibility/vec3.h"

namespace penumbra::vis {

mpq_class orientExact(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d);

// pi1(y) pi2(z) - pi1(z) pi2(y) (edge_line.h), exactly.
mpq_class pencilExact(const PlaneOrient& p1, const PlaneOrient& p2, const Vec3& y, const Vec3& z);

// The side of line(y, z) against the edge's line, exactly.
mpq_class sideExact(const Vec3& y, const Vec3& z, const EdgeLine& e);

// An exact value as the nearest-below double with a bound that keeps its sign certain (an exact
// zero is {0, 0}; magnitudes beyond the double range are clamped to DBL_MAX, sign kept).
BoundedValue roundedExact(const mpq_class& q);

}  // namespace penumbra::vis
