#include "visibility/edge_line.h"

#include <cfloat>
#include <cmath>

#include "visibility/exact_orient.h"

namespace penumbra::vis {
namespace {

constexpr double kU = DBL_EPSILON / 2;  // unit roundoff

bool exactZero(const BoundedValue& v) { return v.value == 0 && v.error == 0; }

}  // namespace

BoundedValue differenceOfProducts(const BoundedValue& a, const BoundedValue& b,
                                  const BoundedValue& c, const BoundedValue& d) {
    const bool zeroAB = exactZero(a) || exactZero(b);
    const bool zeroCD = exactZero(c) || exactZero(d);
    if (zeroAB && zeroCD) return {0.0, 0.0};
    const double ab = zeroAB ? 0.0 : a.value * b.value;
    const double cd = zeroCD ? 0.0 : c.value * d.value;
    const double v = ab - cd;
    // |a b - a' b'| <= |a'| e_b + |b'| e_a + e_a e_b for each product; the two products and the
    // difference are rounded once each (at most u |ab| + u |cd| + u |v| <= 3u (|ab| + |cd|)); the
    // bound's own evaluation is covered by the factor (1 + 8u); the absolute term covers products
    // that underflow (each loses at most 2^-1075).
    double propagated = 0;
    if (!zeroAB)
        propagated += std::fabs(a.value) * b.error + std::fabs(b.value) * a.error + a.error * b.error;
    if (!zeroCD)
        propagated += std::fabs(c.value) * d.error + std::fabs(d.value) * c.error + c.error * d.error;
    const double err =
        propagated * (1 + 8 * kU) + 3 * kU * (std::fabs(ab) + std::fabs(cd)) + 0x1p-1066;
    return {v, err};  // an infinite or NaN bound is never certain: callers go exact
}

BoundedValue pencilValue(const PlaneOrient& p1, const PlaneOrient& p2, const Vec3& y,
                         const Vec3& z) {
    const BoundedValue r = differenceOfProducts(p1.value(y), p2.value(z), p1.value(z), p2.value(y));
    if (r.certain()) return r;
    return roundedExact(pencilExact(p1, p2, y, z));
}

BoundedValue sideValue(const Vec3& y, const Vec3& z, const EdgeLine& e) {
    if (e.kind == EdgeLine::Kind::Points) return orientValue(y, z, e.p, e.q);
    return pencilValue(e.first, e.second, y, z);
}

mpq_class pencilExact(const PlaneOrient& p1, const PlaneOrient& p2, const Vec3& y,
                      const Vec3& z) {
    return orientExact(p1.a, p1.b, p1.c, y) * orientExact(p2.a, p2.b, p2.c, z) -
           orientExact(p1.a, p1.b, p1.c, z) * orientExact(p2.a, p2.b, p2.c, y);
}

mpq_class sideExact(const Vec3& y, const Vec3& z, const EdgeLine& e) {
    if (e.kind == EdgeLine::Kind::Points) return orientExact(y, z, e.p, e.q);
    return pencilExact(e.first, e.second, y, z);
}

std::optional<Sign> sideSignFiltered(const Vec3& y, const Vec3& z, const EdgeLine& e) {
    if (e.kind == EdgeLine::Kind::Points) return orientSignFiltered(y, z, e.p, e.q);
    BoundedValue a, b, c, d;
    e.first.filtered(y, a);
    e.second.filtered(z, b);
    e.first.filtered(z, c);
    e.second.filtered(y, d);
    const BoundedValue r = differenceOfProducts(a, b, c, d);
    if (!(std::fabs(r.value) > r.error)) return std::nullopt;
    return r.sign();
}

namespace {

bool samePlane(const PlaneOrient& a, const PlaneOrient& b) {
    return a.sign(b.a) == Sign::Zero && a.sign(b.b) == Sign::Zero && a.sign(b.c) == Sign::Zero;
}

}  // namespace

bool sameLine(const EdgeLine& a, const EdgeLine& b, std::span<const Vec3> probes,
              int& orientation) {
    if (a.kind != b.kind) return false;
    if (a.kind == EdgeLine::Kind::Points) {
        if (!collinear(a.p, a.q, b.p) || !collinear(a.p, a.q, b.q)) return false;
        // Exactly collinear: each rounded difference has its exact component signs, so the dot
        // product of the two directions has its exact sign.
        orientation = dot(b.q - b.p, a.q - a.p) > 0 ? 1 : -1;
        return true;
    }
    if (!samePlane(a.first, b.first) || !samePlane(a.second, b.second)) return false;
    // Directions n1 x n2 and n1' x n2' with n1 ~ n1', n2 ~ n2' (parallel normals): alike iff the
    // products of the normals' orientations agree, read at a probe off each plane.
    int flips = 0;
    for (const auto* pair : {&a.first, &a.second}) {
        const PlaneOrient& pa = *pair;
        const PlaneOrient& pb = pair == &a.first ? b.first : b.second;
        bool found = false;
        for (const Vec3& probe : probes) {
            const Sign sa = pa.sign(probe);
            if (sa == Sign::Zero) continue;
            flips += sa == pb.sign(probe) ? 0 : 1;
            found = true;
            break;
        }
        if (!found) return false;
    }
    orientation = flips % 2 == 0 ? 1 : -1;
    return true;
}

PencilPlane::PencilPlane(const Vec3& x, const PlaneOrient& first, const PlaneOrient& second)
    : x_(x), first_(first), second_(second), alpha_(first.value(x)), beta_(second.value(x)) {}

bool PencilPlane::filtered(const Vec3& y, BoundedValue& out) const {
    // PlaneOrient::filtered leaves a rigorous bound even where it cannot certify the sign.
    BoundedValue p1, p2;
    first_.filtered(y, p1);
    second_.filtered(y, p2);
    out = differenceOfProducts(alpha_, p2, beta_, p1);
    return out.certain();
}

BoundedValue PencilPlane::value(const Vec3& y) const {
    BoundedValue out;
    if (filtered(y, out)) return out;
    // The planes' own exact stages first (tighter bounds), then rationals.
    out = differenceOfProducts(alpha_, second_.value(y), beta_, first_.value(y));
    if (out.certain()) return out;
    return roundedExact(pencilExact(first_, second_, x_, y));
}

EdgePlane::EdgePlane(const Vec3& x, const EdgeLine& e) {
    if (e.kind == EdgeLine::Kind::Points) {
        points_ = PlaneOrient(x, e.p, e.q);
    } else {
        pencil_ = true;
        planes_ = PencilPlane(x, e.first, e.second);
    }
}

}  // namespace penumbra::vis
