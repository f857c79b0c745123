// Exact geometric predicates on input points.
//
// orient3d is the one predicate the visibility core is built on: the Plücker side operator of
// line(p,q) and line(a,b) *is* orient3d(p,q,a,b) (plucker.h), so every decision "which side of an
// occluder edge does this line pass" is an orient3d sign.
//
// What is exact here:
//   - orientSign() returns the exact sign of the determinant of the given doubles. A floating-point
//     filter (Shewchuk's static-permanent error bound for this evaluation order) decides the
//     common case; when the filter cannot certify the sign, the determinant is re-evaluated
//     exactly: in floating-point expansion arithmetic (expansion.h; no allocation), or in GMP
//     rationals for coordinates outside its safe range, so the answer is never wrong.
//   - orientValue() returns the determinant's value together with a rigorous bound on the error of
//     that double; an exact zero is reported with error 0, and a certified sign is guaranteed
//     whenever |value| > error.
// Rule for exact zeros: the predicates report Sign::Zero honestly (three-valued, as CGAL's
// Orientation). The algorithms that consume them state what they do with Zero; in the visibility
// core a zero always concerns a set of lines or points of measure zero (lines meeting an edge's
// supporting line, points on a splitting plane), which may go to either side without changing any
// area, so each algorithm assigns it to a fixed side (documented at the call site) instead of
// perturbing the input symbolically.
#pragma once

#include <cfloat>
#include <cmath>
#include <cstdint>
#include <optional>

#include "visibility/vec3.h"

namespace penumbra::vis {

enum class Sign : int8_t { Negative = -1, Zero = 0, Positive = 1 };

constexpr Sign operator-(Sign s) { return static_cast<Sign>(-static_cast<int>(s)); }
constexpr int toInt(Sign s) { return static_cast<int>(s); }

// A double together with a bound on its absolute error: |exact - value| <= error.
struct BoundedValue {
    double value = 0;
    double error = 0;

    // The exact sign when it is certain from the bound, Zero when the value is an exact zero.
    // `certain` is false when |value| <= error and the value is not an exact zero.
    constexpr bool certain() const { return error == 0 || std::fabs(value) > error; }
    constexpr Sign sign() const {
        return value > 0 ? Sign::Positive : (value < 0 ? Sign::Negative : Sign::Zero);
    }
};

// det[b-a, c-a, d-a] = (b-a) . ((c-a) x (d-a)). Positive when d lies on the side of the plane
// (a,b,c) that the normal (b-a)x(c-a) points to, i.e. (a,b,c) counter-clockwise seen from d.
double orient3dApprox(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d);

// Exact sign of orient3dApprox's determinant (filtered, exact fallback).
Sign orientSign(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d);

// The determinant as a double with a rigorous error bound. Where the filter fails the exact value
// is computed and rounded, so the sign of the result is always the exact sign.
BoundedValue orientValue(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d);
// The same value always from the exact stage: rounded from the exact determinant, relative error
// below 2^-48 (orientValue's filtered double may be off by up to its own magnitude).
BoundedValue orientValueAccurate(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d);

// orient3d(a, b, c, d) for one plane (a, b, c) and many points d: the cross product of b - a and
// c - a is formed once, and each point costs a dot product. The evaluation is that of
// orientValue(a, d, b, c) (the same determinant: a cyclic permutation of its columns), so the same
// filter bound holds; uncertain values go to the same exact stage. Same contract as orientValue.
struct PlaneOrient {
    PlaneOrient() = default;
    PlaneOrient(const Vec3& a, const Vec3& b, const Vec3& c);
    BoundedValue value(const Vec3& d) const;
    // The exact sign, with the filter inlined (the hot loops' path) before value().
    Sign sign(const Vec3& d) const {
        BoundedValue b;
        if (filtered(d, b)) return b.sign();
        return value(d).sign();
    }
    // The filter alone: false when it cannot certify the sign (then `out` holds the rounded value
    // and its error bound, |value| <= error). Inline: FPQuery calls it per vertex per node.
    bool filtered(const Vec3& d, BoundedValue& out) const;
    // True only if every point of the box is certainly strictly on the negative side (a test in
    // doubles with a rigorous error bound; false means "not certain").
    bool boxNegative(const Vec3& lo, const Vec3& hi) const;
    // Whether the rounded normal n points within about 2^-20 radians of the exact one: its length
    // above 2^-20 times its permanent. Not so for three nearly collinear points (e.g. x and an
    // edge that x sees under an angle of some ulps): then n is mostly rounding.
    bool wellConditioned() const { return normL1() > 0x1p-20 * permanentL1(); }
    // Whether the filter's rounded values place a split's crossings to within some ulps: the
    // rounded normal within 2^-40 of the exact one (its length above 2^-10 times its permanent).
    // A crossing's parameter is t = v(p) / (v(p) - v(q)); the filter's values are off by up to
    // 8u |u| perm, which on a plane whose normal is mostly rounding moves the crossing anywhere
    // on the segment (found on a tessellated sphere: a receiver point on the diagonal of a quad
    // whose two triangles cross each other's planes by a rounding; the light's fragments off by
    // 1e-4 of its area). Otherwise the split takes accurate().
    bool placesWell() const { return normL1() > 0x1p-10 * permanentL1(); }
    // |n|_1, and the sum of the permanent terms: each component of n is within 4u of its
    // permanent of the exact one (two rounded differences, two products, their difference).
    double normL1() const { return std::fabs(n[0]) + std::fabs(n[1]) + std::fabs(n[2]); }
    double permanentL1() const { return perm[0] + perm[1] + perm[2]; }
    // The determinant rounded from its exact value (relative error below 2^-48; the exact sign).
    BoundedValue accurate(const Vec3& d) const;

    Vec3 a, b, c;
    double n[3] = {0, 0, 0};     // (b - a) x (c - a), rounded as evaluate() rounds it
    double perm[3] = {0, 0, 0};  // the matching permanent terms
};

// Shewchuk, "Adaptive precision floating-point arithmetic and fast robust geometric predicates"
// (1997): for orient3d evaluated as three translated vectors, then expansion by minors, the
// rounding error is at most (7 + 56 eps) eps times the permanent. eps = 2^-53.
inline constexpr double kOrient3dErrorBound = (7.0 + 56.0 * (DBL_EPSILON / 2)) * (DBL_EPSILON / 2);

inline PlaneOrient::PlaneOrient(const Vec3& a_, const Vec3& b_, const Vec3& c_)
    : a(a_), b(b_), c(c_) {
    // As evaluate(a, d, b, c): u = d - a, v = b - a, w = c - a; det = u . (v x w). (From the
    // arguments, not the members just written: reading those back stalled on store forwarding.)
    const double vx = b_.x - a_.x, vy = b_.y - a_.y, vz = b_.z - a_.z;
    const double wx = c_.x - a_.x, wy = c_.y - a_.y, wz = c_.z - a_.z;
    const double m1 = vy * wz, m2 = vz * wy;
    const double m3 = vz * wx, m4 = vx * wz;
    const double m5 = vx * wy, m6 = vy * wx;
    n[0] = m1 - m2;
    n[1] = m3 - m4;
    n[2] = m5 - m6;
    perm[0] = std::fabs(m1) + std::fabs(m2);
    perm[1] = std::fabs(m3) + std::fabs(m4);
    perm[2] = std::fabs(m5) + std::fabs(m6);
}

inline bool PlaneOrient::filtered(const Vec3& d, BoundedValue& out) const {
    const double ux = d.x - a.x, uy = d.y - a.y, uz = d.z - a.z;
    const double det = ux * n[0] + uy * n[1] + uz * n[2];
    const double permanent =
        std::fabs(ux) * perm[0] + std::fabs(uy) * perm[1] + std::fabs(uz) * perm[2];
    const double bound = kOrient3dErrorBound * permanent;
    out = {det, bound};
    return std::fabs(det) > bound;
}

inline bool PlaneOrient::boxNegative(const Vec3& lo, const Vec3& hi) const {
    // Rigorous: an upper bound, in doubles, on the maximum over the box of the exact value
    // (y - a) . N (N the exact normal (b - a) x (c - a)); the box is strictly negative if that
    // bound is. Per component the maximum of (y_i - a_i) N_i over [lo_i, hi_i] is at the end the
    // sign of n_i picks (hi_i - a_i >= lo_i - a_i after rounding too: rounding is monotone).
    // Error, with r_i = max(|lo_i - a_i|, |hi_i - a_i|): the rounded normal (|N_i - n_i| <= 4u
    // perm_i: two rounded differences, two products, their difference; 8u claimed), the rounded
    // differences (u r_i |n_i|), the products and the sum (3u |term|), with |n_i| <= (1 + u)
    // perm_i: at most 16.0001u sum r_i perm_i; 17u covers the bound's own rounding. The absolute
    // term covers underflow. No scale-dependent margin: the same certainty near the origin and at
    // 1e15. (Ternaries, not std::fmax: this is the box hierarchy's inner loop.)
    constexpr double u = DBL_EPSILON / 2;
    double sum = 0, reachPerm = 0;
    const double lo3[3] = {lo.x - a.x, lo.y - a.y, lo.z - a.z};
    const double hi3[3] = {hi.x - a.x, hi.y - a.y, hi.z - a.z};
    for (int i = 0; i < 3; ++i) {
        sum += (n[i] > 0 ? hi3[i] : lo3[i]) * n[i];
        const double l = std::fabs(lo3[i]), h = std::fabs(hi3[i]);
        reachPerm += (l > h ? l : h) * perm[i];
    }
    return sum + (17 * u * reachPerm + 0x1p-1060) < 0;  // NaN or infinity: false (not certain)
}

// PlaneOrient::boxNegative for the many boxes of a hierarchy, all inside one region box: the
// error term, which boxNegative bounds per box from the box's reach r_i = max(|lo_i - a_i|,
// |hi_i - a_i|), is bounded once from the region's reach instead (rounding is monotone, so a box
// inside the region never reaches further in any rounded difference), and each box then costs
// three differences, three products and a sum. Rigorous for boxes inside the region only; looser
// than boxNegative by the ratio of the reaches, which only costs work (a box not culled).
class PlaneBoxCull {
  public:
    PlaneBoxCull() = default;
    PlaneBoxCull(const PlaneOrient& plane, const Vec3& regionLo, const Vec3& regionHi);
    // True only if every point of the box (which must lie inside the region) is certainly
    // strictly on the plane's negative side.
    bool negative(const Vec3& lo, const Vec3& hi) const {
        const double sx = (n_[0] > 0 ? hi.x : lo.x) - a_[0];
        const double sy = (n_[1] > 0 ? hi.y : lo.y) - a_[1];
        const double sz = (n_[2] > 0 ? hi.z : lo.z) - a_[2];
        double sum = 0;
        sum += sx * n_[0];
        sum += sy * n_[1];
        sum += sz * n_[2];
        return sum + margin_ < 0;  // NaN: false (not certain)
    }

  private:
    double a_[3] = {0, 0, 0}, n_[3] = {0, 0, 0};
    double margin_ = 0;
};

inline PlaneBoxCull::PlaneBoxCull(const PlaneOrient& plane, const Vec3& regionLo,
                                  const Vec3& regionHi)
    : a_{plane.a.x, plane.a.y, plane.a.z}, n_{plane.n[0], plane.n[1], plane.n[2]} {
    // boxNegative's bound (17u sum r_i perm_i plus an absolute term for underflow), with the
    // region's reach R_i >= every box's r_i.
    constexpr double u = DBL_EPSILON / 2;
    const double lo3[3] = {regionLo.x - a_[0], regionLo.y - a_[1], regionLo.z - a_[2]};
    const double hi3[3] = {regionHi.x - a_[0], regionHi.y - a_[1], regionHi.z - a_[2]};
    double reachPerm = 0;
    for (int i = 0; i < 3; ++i) {
        const double l = std::fabs(lo3[i]), h = std::fabs(hi3[i]);
        reachPerm += (l > h ? l : h) * plane.perm[i];
    }
    margin_ = 17 * u * reachPerm + 0x1p-1060;
    if (!(margin_ < INFINITY)) margin_ = INFINITY;  // NaN or overflow: nothing is certain
}

// Exactly: do a, b, c lie on one line (a zero cross product (b-a) x (c-a))?
bool collinear(const Vec3& a, const Vec3& b, const Vec3& c);

// Same sign as orientSign but always through the exact stage (for benchmarks and tests).
Sign orientSignExact(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d);

// The floating-point filter alone: the sign when the filter certifies it, Zero-free; nullopt when
// the exact fallback would be needed (benchmarks count these).
std::optional<Sign> orientSignFiltered(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d);

// The naive double determinant's sign, no filter: what "plain double predicates" would decide.
// Approximate; used only by the benchmark that measures what exactness costs.
Sign orientSignNaive(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d);

}  // namespace penumbra::vis
