// The exact value of orient3d as a GMP rational, for the few places that need more than its sign
// (the exact fallback of polytope certificates). Kept out of predicates.h so that GMP's headers
// do not spread through the project.
#pragma once

#include <gmpxx.h>

#include "visibility/vec3.h"

namespace penumbra::vis {

mpq_class orientExact(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d);

}  // namespace penumbra::vis
