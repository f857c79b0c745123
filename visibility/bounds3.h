// Bounds3: an axis-aligned box. Approximate geometry: used only for conservative culling (closed
// boxes, touching counts) and for tolerances, never for a visibility decision.
#pragma once

#include <algorithm>
#include <limits>

#include "visibility/vec3.h"

namespace penumbra::vis {

struct Bounds3 {
    Vec3 lo{std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity(),
            std::numeric_limits<double>::infinity()};
    Vec3 hi{-std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity(),
            -std::numeric_limits<double>::infinity()};

    bool empty() const { return lo.x > hi.x; }
    void add(const Vec3& p) {
        lo = {std::min(lo.x, p.x), std::min(lo.y, p.y), std::min(lo.z, p.z)};
        hi = {std::max(hi.x, p.x), std::max(hi.y, p.y), std::max(hi.z, p.z)};
    }
    bool overlaps(const Bounds3& o) const {
        return lo.x <= o.hi.x && o.lo.x <= hi.x && lo.y <= o.hi.y && o.lo.y <= hi.y &&
               lo.z <= o.hi.z && o.lo.z <= hi.z;
    }
    bool containsGrown(const Vec3& p, double tol) const {
        return p.x >= lo.x - tol && p.x <= hi.x + tol && p.y >= lo.y - tol && p.y <= hi.y + tol &&
               p.z >= lo.z - tol && p.z <= hi.z + tol;
    }
    double diagonal() const { return empty() ? 0.0 : length(hi - lo); }
};

}  // namespace penumbra::vis
