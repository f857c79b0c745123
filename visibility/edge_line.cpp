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
        propagated +=
            std::fabs(a.value) * b.error + std::fabs(b.value) * a.error + a.error * b.error;
    if (!zeroCD)
        propagated +=
            std::fabs(c.value) * d.error + std::fabs(d.value) * c.error + c.error * d.error;
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

mpq_class pencilExact(const PlaneOrient& p1, const PlaneOrient& p2, const Vec3& y, const Vec3& z) {
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
    : x_(x), first_(first), second_(second), alpha_(first.value(x)), beta_(second.value(x)) {
    prepareFilter();
}

void PencilPlane::prepareFilter() {
    // N_i = alpha n2_i - beta n1_i. Each PlaneOrient normal component is within 4u perm_i of the
    // exact one (two rounded differences, two products, their difference; 8u claimed). So
    // |N_i - n_i| <= (|a|+ea) 8u perm2_i + ea |n2_i| + (|b|+eb) 8u perm1_i + eb |n1_i|
    //               + 3u (|a n2_i| + |b n1_i|)                  (the two products, the difference).
    // Per vertex y, with d = fl(y - x) (|d_i - exact| <= u |d_i|), the dot product adds at most
    // u |n_i d_i| per difference and 3u sum |n_i d_i| for its products and sums: so the error of
    // n . d is at most sum |d_i| k_i with k_i = (E_i (1 + u) + 4u |n_i|), padded by (1 + 8u) for
    // the evaluation of the bound itself.
    constexpr double u = DBL_EPSILON / 2;
    const double a = alpha_.value, ea = alpha_.error, b = beta_.value, eb = beta_.error;
    for (int i = 0; i < 3; ++i) {
        const double n2 = second_.n[i], n1 = first_.n[i];
        n_[i] = a * n2 - b * n1;
        const double e = (std::fabs(a) + ea) * 8 * u * second_.perm[i] + ea * std::fabs(n2) +
                         (std::fabs(b) + eb) * 8 * u * first_.perm[i] + eb * std::fabs(n1) +
                         3 * u * (std::fabs(a * n2) + std::fabs(b * n1));
        k_[i] = (e * (1 + u) + 4 * u * std::fabs(n_[i])) * (1 + 8 * u);
    }
}

PencilPlane::PencilPlane(const Vec3& x, const PlaneOrient& first, const BoundedValue& alpha,
                         const PlaneOrient& second)
    : x_(x), first_(first), second_(second), alpha_(alpha), beta_(second.value(x)) {
    prepareFilter();
}

bool PencilPlane::filtered(const Vec3& y, BoundedValue& out) const {
    const double dx = y.x - x_.x, dy = y.y - x_.y, dz = y.z - x_.z;
    const double v = n_[0] * dx + n_[1] * dy + n_[2] * dz;
    const double err =
        std::fabs(dx) * k_[0] + std::fabs(dy) * k_[1] + std::fabs(dz) * k_[2] + 0x1p-1060;
    out = {v, err};
    return std::fabs(v) > err;
}

BoundedValue PencilPlane::value(const Vec3& y) const {
    BoundedValue out;
    if (filtered(y, out)) return out;
    // The two planes' values at y (their own exact stages where needed), then rationals.
    out = differenceOfProducts(alpha_, second_.value(y), beta_, first_.value(y));
    if (out.certain()) return out;
    return roundedExact(pencilExact(first_, second_, x_, y));
}

BoundedValue PencilPlane::accurate(const Vec3& y) const {
    BoundedValue out = differenceOfProducts(alpha_, second_.value(y), beta_, first_.value(y));
    if (out.error <= std::fabs(out.value) * 0x1p-48) return out;
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
