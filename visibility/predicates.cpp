#include "visibility/predicates.h"

#include <gmpxx.h>

#include <cfloat>
#include <cmath>

#include "visibility/exact_orient.h"
#include "visibility/expansion.h"

namespace penumbra::vis {
namespace {

constexpr double kEps = DBL_EPSILON / 2;
constexpr double kOrientBound = kOrient3dErrorBound;  // predicates.h

struct Evaluated {
    double det;
    double permanent;
};

Evaluated evaluate(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
    const double ux = b.x - a.x, uy = b.y - a.y, uz = b.z - a.z;
    const double vx = c.x - a.x, vy = c.y - a.y, vz = c.z - a.z;
    const double wx = d.x - a.x, wy = d.y - a.y, wz = d.z - a.z;
    const double m1 = vy * wz, m2 = vz * wy;
    const double m3 = vz * wx, m4 = vx * wz;
    const double m5 = vx * wy, m6 = vy * wx;
    const double det = ux * (m1 - m2) + uy * (m3 - m4) + uz * (m5 - m6);
    const double perm = std::fabs(ux) * (std::fabs(m1) + std::fabs(m2)) +
                        std::fabs(uy) * (std::fabs(m3) + std::fabs(m4)) +
                        std::fabs(uz) * (std::fabs(m5) + std::fabs(m6));
    return {det, perm};
}

// GMP rationals: the exact stage of last resort (inputs outside the expansion's safe range).
mpq_class exactDet(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
    // mpq_class(double) is exact, so is everything below.
    const mpq_class ax(a.x), ay(a.y), az(a.z);
    const mpq_class ux = mpq_class(b.x) - ax, uy = mpq_class(b.y) - ay, uz = mpq_class(b.z) - az;
    const mpq_class vx = mpq_class(c.x) - ax, vy = mpq_class(c.y) - ay, vz = mpq_class(c.z) - az;
    const mpq_class wx = mpq_class(d.x) - ax, wy = mpq_class(d.y) - ay, wz = mpq_class(d.z) - az;
    return ux * (vy * wz - vz * wy) + uy * (vz * wx - vx * wz) + uz * (vx * wy - vy * wx);
}

Sign signOf(const mpq_class& q) {
    const int s = sgn(q);
    return s > 0 ? Sign::Positive : (s < 0 ? Sign::Negative : Sign::Zero);
}

Sign signOf(int s) { return s > 0 ? Sign::Positive : (s < 0 ? Sign::Negative : Sign::Zero); }

// Exact zeros the filter cannot certify and the exact stage need not compute: two equal points
// (a zero column, or two equal columns, after the translation by a), or four points in one plane
// x, y or z = const (a zero row). Both are common in modelled scenes (shared vertices; floors,
// walls and steps aligned with the axes, an occluder standing on its receiver), and each is an
// exact statement about the input doubles.
bool trivialZero(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
    if (a == b || a == c || a == d || b == c || b == d || c == d) return true;
    return (a.x == b.x && a.x == c.x && a.x == d.x) || (a.y == b.y && a.y == c.y && a.y == d.y) ||
           (a.z == b.z && a.z == c.z && a.z == d.z);
}

// The exact stage: expansion arithmetic (no allocation), GMP rationals outside its safe range.
Sign exactSign(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
    if (trivialZero(a, b, c, d)) return Sign::Zero;
    int s;
    double approx;
    if (orient3dExpansion(a, b, c, d, s, approx)) return signOf(s);
    return signOf(exactDet(a, b, c, d));
}

}  // namespace

double orient3dApprox(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
    return evaluate(a, b, c, d).det;
}

Sign orientSign(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
    const Evaluated e = evaluate(a, b, c, d);
    const double bound = kOrientBound * e.permanent;
    if (e.det > bound) {
        return Sign::Positive;
    }
    if (e.det < -bound) {
        return Sign::Negative;
    }
    return exactSign(a, b, c, d);
}

BoundedValue orientValue(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
    const Evaluated e = evaluate(a, b, c, d);
    const double bound = kOrientBound * e.permanent;
    if (std::fabs(e.det) > bound) {
        return {e.det, bound};
    }
    return orientValueAccurate(a, b, c, d);
}

BoundedValue orientValueAccurate(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
    if (trivialZero(a, b, c, d)) return {0.0, 0.0};
    int s;
    double approx;
    if (orient3dExpansion(a, b, c, d, s, approx)) {
        if (s == 0) return {0.0, 0.0};
        // approx has the exact sign and a relative error below 2^-50 (expansion.h); claim 2^-48.
        return {approx, std::fabs(approx) * 0x1p-48};
    }
    return roundedExact(exactDet(a, b, c, d));
}

BoundedValue PlaneOrient::accurate(const Vec3& d) const { return orientValueAccurate(a, b, c, d); }

BoundedValue roundedExact(const mpq_class& q) {
    if (sgn(q) == 0) return {0.0, 0.0};
    // mpq_get_d truncates towards zero: the result has the exact sign unless it underflows to
    // zero (then the smallest subnormal keeps the sign) or lies beyond the double range.
    double v = q.get_d();
    if (v == 0) v = sgn(q) > 0 ? DBL_TRUE_MIN : -DBL_TRUE_MIN;
    if (!std::isfinite(v)) v = sgn(q) > 0 ? DBL_MAX : -DBL_MAX;
    const double mag = std::fabs(v);
    const double ulp = std::nextafter(mag, INFINITY) - mag;
    // Strictly smaller than |v| unless v is the smallest subnormal; keep the sign certain.
    return {v, std::fmin(ulp, mag * 0.5)};
}

BoundedValue PlaneOrient::value(const Vec3& d) const {
    BoundedValue v;
    if (filtered(d, v)) return v;
    return orientValue(a, b, c, d);
}

bool collinear(const Vec3& a, const Vec3& b, const Vec3& c) {
    // Two equal points are collinear with any third (exactly; the common case of edges that share
    // a vertex, where the filter below always fails and the rationals would be needed).
    if (a == b || a == c || b == c) return true;
    // Filter: each cross-product component is a 2x2 determinant of differences; Shewchuk's orient2d
    // bound (3 + 16 eps) eps times its permanent certifies a non-zero component.
    const double ux = b.x - a.x, uy = b.y - a.y, uz = b.z - a.z;
    const double vx = c.x - a.x, vy = c.y - a.y, vz = c.z - a.z;
    const double comps[3][2] = {{uy * vz, uz * vy}, {uz * vx, ux * vz}, {ux * vy, uy * vx}};
    for (const auto& p : comps)
        if (std::fabs(p[0] - p[1]) >
            (3.0 + 16.0 * kEps) * kEps * (std::fabs(p[0]) + std::fabs(p[1])))
            return false;
    const mpq_class ax(a.x), ay(a.y), az(a.z);
    const mpq_class qux = mpq_class(b.x) - ax, quy = mpq_class(b.y) - ay, quz = mpq_class(b.z) - az;
    const mpq_class qvx = mpq_class(c.x) - ax, qvy = mpq_class(c.y) - ay, qvz = mpq_class(c.z) - az;
    return quy * qvz == quz * qvy && quz * qvx == qux * qvz && qux * qvy == quy * qvx;
}

mpq_class orientExact(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
    return exactDet(a, b, c, d);
}

Sign orientSignExact(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
    return exactSign(a, b, c, d);
}

std::optional<Sign> orientSignFiltered(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
    const Evaluated e = evaluate(a, b, c, d);
    const double bound = kOrientBound * e.permanent;
    if (e.det > bound) return Sign::Positive;
    if (e.det < -bound) return Sign::Negative;
    return std::nullopt;
}

Sign orientSignNaive(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
    const double v = evaluate(a, b, c, d).det;
    return v > 0 ? Sign::Positive : (v < 0 ? Sign::Negative : Sign::Zero);
}

}  // namespace penumbra::vis
