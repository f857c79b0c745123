#include "visibility/orient2d.h"

#include <gmpxx.h>

#include <cfloat>
#include <cmath>

namespace penumbra::vis {
// (A named namespace: unity builds compile several files as one.)
namespace orient2d_detail {

int orient2dExact(const Point2& a, const Point2& b, const Point2& c) {
    // mpq_class(double) is exact, so is the rest.
    const mpq_class cu(c.u), cv(c.v);
    const mpq_class det = (mpq_class(a.u) - cu) * (mpq_class(b.v) - cv) -
                          (mpq_class(a.v) - cv) * (mpq_class(b.u) - cu);
    return sgn(det);
}

int signOf(double x) { return (x > 0) - (x < 0); }

}  // namespace orient2d_detail

using namespace orient2d_detail;

int orient2d(const Point2& a, const Point2& b, const Point2& c) {
    // The sign of a difference of doubles is exact. When a factor of one product is exactly zero
    // that product is exactly zero, and the sign of the determinant is the sign of the other
    // product, a product of two exact signs. This settles faces in coordinate planes without GMP.
    const double l1 = a.u - c.u, l2 = b.v - c.v, r1 = a.v - c.v, r2 = b.u - c.u;
    if (l1 == 0 || l2 == 0) return -signOf(r1) * signOf(r2);
    if (r1 == 0 || r2 == 0) return signOf(l1) * signOf(l2);
    if (const int sign = orient2dFiltered(a, b, c)) return sign;
    return orient2dExact(a, b, c);
}

bool collinear3(const Vec3& a, const Vec3& b, const Vec3& c) {
    // The filters are tried on all three projections first: one certain nonzero settles it.
    for (int axis = 0; axis < 3; ++axis) {
        const int u = (axis + 1) % 3, v = (axis + 2) % 3;
        if (orient2dFiltered(project(a, u, v), project(b, u, v), project(c, u, v)) != 0) {
            return false;
        }
    }
    for (int axis = 0; axis < 3; ++axis) {
        const int u = (axis + 1) % 3, v = (axis + 2) % 3;
        if (orient2d(project(a, u, v), project(b, u, v), project(c, u, v)) != 0) return false;
    }
    return true;
}

}  // namespace penumbra::vis
