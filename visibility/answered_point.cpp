#include "visibility/answered_point.h"

#include <algorithm>
#include <cfloat>
#include <cmath>

namespace penumbra::vis {

Vec3 frontPoint(const PlaneOrient& plane, const Vec3& x) {
    BoundedValue v;
    if (plane.filtered(x, v) && v.value > 0) return x;  // certainly in front
    // Within the filter's error of the plane (most projections) or behind it.
    const Vec3 up{plane.n[0], plane.n[1], plane.n[2]};
    const double upLength = length(up);
    if (!(upLength > 0)) return x;
    const double ulp =
        std::max({std::fabs(x.x), std::fabs(x.y), std::fabs(x.z), DBL_MIN}) * 0x1p-52;
    double step = std::max(2 * (std::fabs(v.value) + v.error) / upLength, ulp);
    for (int i = 0; i < 32; ++i, step *= 2) {
        const Vec3 moved = x + up * (step / upLength);
        if (plane.filtered(moved, v) && v.value > 0) return moved;
    }
    return x;
}

namespace {

// Whether x is certainly on or in front of the plane, by cheap tests only: the filter, then for a
// plane of a coordinate (its three points share coordinate k, as a floor's or a box's) the exact
// sign, that of x[k] - a[k] (a difference of doubles) times that of the normal's k-th component
// (certain where it exceeds its rounding, 4u of its permanent, claimed 8u). No exact stage: a
// projected hit lies within ulps of its plane, so the filter alone almost never decides it, and
// the exact stage for every shading point cost the Cornell box's exact render some 12% of its
// time. A point these tests leave undecided is taken as behind (moved), which is always sound:
// the contact rule is decided at the input point whatever is answered.
bool certainlyNotBehind(const PlaneOrient& plane, const Vec3& x) {
    BoundedValue v;
    if (plane.filtered(x, v)) return v.value > 0;
    for (int k = 0; k < 3; ++k) {
        if (plane.a[k] != plane.b[k] || plane.a[k] != plane.c[k]) continue;
        if (!(std::fabs(plane.n[k]) > 0x1p-50 * plane.perm[k])) return false;
        const double d = x[k] - plane.a[k];
        return plane.n[k] > 0 ? d >= 0 : d <= 0;
    }
    return false;
}

}  // namespace

AnsweredPoint answeredPoint(const PlaneOrient& receiverPlane, const Vec3& x) {
    if (certainlyNotBehind(receiverPlane, x)) return {x, x};
    // Behind, or not certainly in front: projected onto the plane (rounded), then onto its front
    // side by the least step.
    const Vec3 n{receiverPlane.n[0], receiverPlane.n[1], receiverPlane.n[2]};
    const double nn = dot(n, n);
    const Vec3 projected = nn > 0 ? x - n * (dot(n, x - receiverPlane.a) / nn) : x;
    return {frontPoint(receiverPlane, projected), x};
}

}  // namespace penumbra::vis
