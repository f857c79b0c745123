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

AnsweredPoint answeredPoint(const PlaneOrient& receiverPlane, const Vec3& x) {
    // The filter first: most points are certified one way or the other without the exact stage.
    BoundedValue v;
    const Sign side = receiverPlane.filtered(x, v) ? v.sign() : receiverPlane.value(x).sign();
    if (side != Sign::Negative) return {x, x};
    // Behind: projected onto the plane (rounded), then onto its front side by the least step.
    const Vec3 n{receiverPlane.n[0], receiverPlane.n[1], receiverPlane.n[2]};
    const double nn = dot(n, n);
    const Vec3 projected = nn > 0 ? x - n * (dot(n, x - receiverPlane.a) / nn) : x;
    return {frontPoint(receiverPlane, projected), x};
}

}  // namespace penumbra::vis
