// Floating-point expansion arithmetic (Priest 1991; Shewchuk 1997): a real number held exactly as
// a sum of doubles whose magnitudes do not overlap, built with error-free transformations
// (twoSum, twoProduct). Used for the exact stage of orient3d: no allocation, a few hundred
// flops, against microseconds for rationals.
//
// Exactness holds as long as no product overflows or underflows: orient3dExpansion checks its
// inputs' magnitudes and declines (returns false) outside the safe range; callers then fall back
// to GMP rationals.
#pragma once

#include <cstddef>

#include "visibility/vec3.h"

namespace penumbra::vis {

// The sign of det[b-a, c-a, d-a] (-1, 0, +1) and an approximation of its value (the sum of the
// expansion's components, from the smallest: relative error below 2^-50), computed exactly.
// Returns false (and leaves the outputs alone) when some coordinate is outside
// [2^-200, 2^200] in magnitude (zero is fine), where the products could leave the exact range.
bool orient3dExpansion(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d, int& sign,
                       double& approx);

}  // namespace penumbra::vis
