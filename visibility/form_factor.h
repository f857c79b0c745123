// Exact shading quantities of polygons seen from a point.
#pragma once

#include <span>
#include <vector>

#include "visibility/vec3.h"

namespace penumbra::vis {

// Area of a planar polygon (any orientation). Approximate (double), Newell's method.
double polygonArea(std::span<const Vec3> polygon);

// Point-to-polygon form factor by Lambert's formula:
//   F = 1/(2 pi) * sum_i Theta_i * (n . Gamma_i)
// with Theta_i the angle subtended at x by edge i (from |a x b| and a . b by the half-angle
// identity, never acos) and
// Gamma_i the unit normal of the plane through x and edge i. n is the unit receiver normal.
// The polygon is taken as seen (no horizon clipping): clip it to n's hemisphere first.
// Returns a non-negative value for a polygon whose front faces x.
double formFactor(const Vec3& x, const Vec3& n, std::span<const Vec3> polygon);

// The same for a region given by its boundary: closed loops, each oriented with the region on
// the same side (outer boundaries one way, holes the other; visible_outline.h). Lambert's sum is
// over edges, so it is formFactor's sum taken over every loop before the absolute value.
double formFactorOfLoops(const Vec3& x, const Vec3& n, std::span<const std::vector<Vec3>> loops);

}  // namespace penumbra::vis
