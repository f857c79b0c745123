#include "visibility/form_factor.h"

#include <cmath>
#include <numbers>

namespace penumbra::vis {

double polygonArea(std::span<const Vec3> polygon) {
    if (polygon.size() < 3) return 0;
    // Newell's normal relative to the first vertex (better conditioned far from the origin).
    const Vec3 o = polygon[0];
    Vec3 n{};
    for (size_t i = 1; i + 1 < polygon.size(); ++i) n += cross(polygon[i] - o, polygon[i + 1] - o);
    return 0.5 * length(n);
}

namespace {

// Lambert's signed sum over the closed loop `polygon` (2 pi times its signed form factor).
long double lambertSum(const Vec3& x, const Vec3& n, std::span<const Vec3> polygon) {
    if (polygon.size() < 3) return 0;
    long double sum = 0;
    const size_t count = polygon.size();
    for (size_t i = 0; i < count; ++i) {
        const Vec3 a = polygon[i] - x;
        const Vec3 b = polygon[i + 1 == count ? 0 : i + 1] - x;
        const Vec3 c = cross(a, b);
        const double cl = length(c);
        if (cl == 0) continue;  // edge collinear with x: subtends no angle
        // The angle between a and b by the half-angle identity tan(theta / 2) = |a x b| /
        // (|a||b| + a.b), or for an obtuse angle its complement's, so that the denominator never
        // cancels: as accurate as atan2(|a x b|, a.b) (a few ulps), at less than half its cost.
        const double d = dot(a, b);
        const double ab = std::sqrt(dot(a, a) * dot(b, b));
        const double theta =
            d >= 0 ? 2 * std::atan(cl / (ab + d)) : std::numbers::pi - 2 * std::atan(cl / (ab - d));
        sum += static_cast<long double>(theta) * (dot(n, c) / cl);
    }
    return sum;
}

}  // namespace

double formFactor(const Vec3& x, const Vec3& n, std::span<const Vec3> polygon) {
    return static_cast<double>(std::fabs(lambertSum(x, n, polygon)) /
                               (2 * std::numbers::pi_v<long double>));
}

double formFactorOfLoops(const Vec3& x, const Vec3& n, std::span<const std::vector<Vec3>> loops) {
    long double sum = 0;
    for (const std::vector<Vec3>& loop : loops) sum += lambertSum(x, n, loop);
    return static_cast<double>(std::fabs(sum) / (2 * std::numbers::pi_v<long double>));
}

}  // namespace penumbra::vis
