#include "visibility/polygon_clip.h"

#include <algorithm>

namespace penumbra::vis {

bool OrientedPlane::degenerate() const {
    // Collinear iff the cross product vanishes; test exactly with orient3d against the three
    // coordinate-offset points (a zero normal makes all three zero).
    const Vec3 ex = a + Vec3{1, 0, 0}, ey = a + Vec3{0, 1, 0}, ez = a + Vec3{0, 0, 1};
    return orientSign(a, b, c, ex) == Sign::Zero && orientSign(a, b, c, ey) == Sign::Zero &&
           orientSign(a, b, c, ez) == Sign::Zero;
}

namespace {

Vec3 crossing(const Vec3& p, const Vec3& q, double dp, double dq) {
    // dp and dq have opposite exact signs; their doubles may be tiny or even disagree in sign, so
    // clamp the parameter to the segment.
    double t = dp / (dp - dq);
    if (!(t >= 0)) t = 0;  // also catches NaN
    if (t > 1) t = 1;
    return p + (q - p) * t;
}

}  // namespace

ClipResult clipConvex(std::span<const Vec3> polygon, const OrientedPlane& plane) {
    ClipResult r;
    const size_t n = polygon.size();
    if (n < 3) return r;
    std::vector<Sign> s(n);
    std::vector<double> d(n);
    bool anyPos = false, anyNeg = false;
    for (size_t i = 0; i < n; ++i) {
        s[i] = plane.side(polygon[i]);
        d[i] = plane.value(polygon[i]);
        anyPos |= s[i] == Sign::Positive;
        anyNeg |= s[i] == Sign::Negative;
    }
    if (!anyNeg) {
        if (anyPos) r.positive.assign(polygon.begin(), polygon.end());
        return r;
    }
    if (!anyPos) {
        r.negative.assign(polygon.begin(), polygon.end());
        return r;
    }
    r.positive.reserve(n + 1);
    r.negative.reserve(n + 1);
    for (size_t i = 0; i < n; ++i) {
        const size_t j = (i + 1) % n;
        if (s[i] != Sign::Negative) r.positive.push_back(polygon[i]);
        if (s[i] != Sign::Positive) r.negative.push_back(polygon[i]);
        if (toInt(s[i]) * toInt(s[j]) < 0) {
            const Vec3 p = crossing(polygon[i], polygon[j], d[i], d[j]);
            r.positive.push_back(p);
            r.negative.push_back(p);
        }
    }
    return r;
}

std::vector<Vec3> clipConvexPositive(std::span<const Vec3> polygon, const OrientedPlane& plane) {
    return clipConvex(polygon, plane).positive;
}

}  // namespace penumbra::vis
