#include "visibility/polygon_clip.h"

#include <algorithm>
#include <cfloat>
#include <cmath>

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

// Splits the polygon given each vertex's signed value (its sign decides, zero = on the plane).
template <typename ValueOf>
void splitBy(std::span<const Vec3> polygon, ValueOf valueOf, std::vector<Vec3>& positive,
             std::vector<Vec3>& negative) {
    positive.clear();
    negative.clear();
    const size_t n = polygon.size();
    if (n < 3) return;
    constexpr size_t kInline = 32;
    double inlineVals[kInline];
    std::vector<double> heapVals;
    double* d = inlineVals;
    if (n > kInline) {
        heapVals.resize(n);
        d = heapVals.data();
    }
    bool anyPos = false, anyNeg = false;
    for (size_t i = 0; i < n; ++i) {
        d[i] = valueOf(polygon[i]);
        anyPos |= d[i] > 0;
        anyNeg |= d[i] < 0;
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
        const double si = d[i], sj = d[j];
        if (si >= 0) positive.push_back(polygon[i]);
        if (si <= 0) negative.push_back(polygon[i]);
        if ((si > 0 && sj < 0) || (si < 0 && sj > 0)) {
            const Vec3 p = crossing(polygon[i], polygon[j], si, sj);
            positive.push_back(p);
            negative.push_back(p);
        }
    }
}

}  // namespace

void clipConvexInto(std::span<const Vec3> polygon, const OrientedPlane& plane,
                    std::vector<Vec3>& positive, std::vector<Vec3>& negative) {
    // The value's sign is exact (filtered, exact fallback), its magnitude is for placement.
    splitBy(
        polygon, [&](const Vec3& y) { return plane.value(y).value; }, positive, negative);
}

void clipConstructedInto(std::span<const Vec3> polygon, const OrientedPlane& plane,
                         std::span<const Vec3> inputVertices, std::vector<Vec3>& positive,
                         std::vector<Vec3>& negative) {
    splitBy(
        polygon,
        [&](const Vec3& y) {
            BoundedValue v;
            if (plane.orient.filtered(y, v)) return v.value;
            for (const Vec3& input : inputVertices)
                if (input.x == y.x && input.y == y.y && input.z == y.z) return plane.value(y).value;
            return 0.0;
        },
        positive, negative);
}

void clipExactInto(std::span<const Vec3> polygon, const OrientedPlane& plane,
                   std::vector<Vec3>& positive, std::vector<Vec3>& negative) {
    splitBy(
        polygon,
        [&](const Vec3& y) {
            const double v = orient3dApprox(plane.a, plane.b, plane.c, y);
            const Sign s = orientSignExact(plane.a, plane.b, plane.c, y);
            // The exact sign with the double's magnitude for placement.
            if (s == Sign::Zero) return 0.0;
            const double m = std::max(std::fabs(v), DBL_TRUE_MIN);
            return toInt(s) > 0 ? m : -m;
        },
        positive, negative);
}

void clipNaiveInto(std::span<const Vec3> polygon, const OrientedPlane& plane,
                   std::vector<Vec3>& positive, std::vector<Vec3>& negative) {
    splitBy(polygon, [&](const Vec3& y) { return orient3dApprox(plane.a, plane.b, plane.c, y); },
            positive, negative);
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
