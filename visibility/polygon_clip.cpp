#include "visibility/polygon_clip.h"

#include <algorithm>

namespace penumbra::vis {

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

void clipConvexInto(std::span<const Vec3> polygon, const OrientedPlane& plane,
                    std::vector<Vec3>& positive, std::vector<Vec3>& negative) {
    positive.clear();
    negative.clear();
    const size_t n = polygon.size();
    if (n < 3) return;
    constexpr size_t kInline = 32;
    BoundedValue inlineVals[kInline];
    std::vector<BoundedValue> heapVals;
    BoundedValue* d = inlineVals;
    if (n > kInline) {
        heapVals.resize(n);
        d = heapVals.data();
    }
    bool anyPos = false, anyNeg = false;
    for (size_t i = 0; i < n; ++i) {
        // orientValue's sign is exact (filtered, exact fallback), its value is for placement.
        d[i] = orientValue(plane.a, plane.b, plane.c, polygon[i]);
        anyPos |= d[i].value > 0;
        anyNeg |= d[i].value < 0;
    }
    if (!anyNeg) {
        if (anyPos) positive.assign(polygon.begin(), polygon.end());
        return;
    }
    if (!anyPos) {
        negative.assign(polygon.begin(), polygon.end());
        return;
    }
    for (size_t i = 0; i < n; ++i) {
        const size_t j = i + 1 == n ? 0 : i + 1;
        const double si = d[i].value, sj = d[j].value;
        if (si >= 0) positive.push_back(polygon[i]);
        if (si <= 0) negative.push_back(polygon[i]);
        if ((si > 0 && sj < 0) || (si < 0 && sj > 0)) {
            const Vec3 p = crossing(polygon[i], polygon[j], si, sj);
            positive.push_back(p);
            negative.push_back(p);
        }
    }
}

ClipResult clipConvex(std::span<const Vec3> polygon, const OrientedPlane& plane) {
    ClipResult r;
    clipConvexInto(polygon, plane, r.positive, r.negative);
    return r;
}

std::vector<Vec3> clipConvexPositive(std::span<const Vec3> polygon, const OrientedPlane& plane) {
    return clipConvex(polygon, plane).positive;
}

}  // namespace penumbra::vis
