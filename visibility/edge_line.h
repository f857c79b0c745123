// EdgeLine: the supporting line of an occluder edge, held exactly as a function of input doubles.
//
// An occluder clipped to the region in front of B's and L's planes (pair_occluders.h) is a convex
// polygon whose edges lie on two kinds of lines, and neither needs a constructed point:
//   Points  an input edge p -> q of the face (a clipped sub-segment keeps the same line);
//   Planes  the line where two input planes meet: the occluder's own plane and B's or L's (the
//           new edge a clip leaves), directed as n_first x n_second.
// A plane through input points a, b, c is the affine function pi(y) = orient3d(a, b, c, y) =
// n . (y - a), n = (b - a) x (c - a) (PlaneOrient). The Plücker side of the line through y then z
// against an EdgeLine is
//   Points  orient3d(y, z, p, q)                          (degree 3 in the input coordinates)
//   Planes  pi1(y) pi2(z) - pi1(z) pi2(y)                 (degree 6)
// (With u = n1 x n2 and m = d1 n2 - d2 n1, d = -n . a, which is the Plücker line of the meet of the
// two planes, the side (z - y) . m + u . (y x z) expands to exactly that difference.) Both are
// exact: a floating-point filter with a rigorous error bound decides the common case, GMP
// rationals the rest. So is every sign below; nothing here rounds a point and then tests it.
#pragma once

#include <cstdint>
#include <optional>
#include <span>

#include "visibility/predicates.h"

namespace penumbra::vis {

struct EdgeLine {
    enum class Kind : uint8_t { Points, Planes };
    Kind kind = Kind::Points;
    Vec3 p, q;                  // Points: the line through p, directed towards q
    PlaneOrient first, second;  // Planes: where they meet, directed n_first x n_second

    static EdgeLine through(const Vec3& p, const Vec3& q) {
        EdgeLine e;
        e.p = p;
        e.q = q;
        return e;
    }
    static EdgeLine meet(const PlaneOrient& first, const PlaneOrient& second) {
        EdgeLine e;
        e.kind = Kind::Planes;
        e.first = first;
        e.second = second;
        return e;
    }
};

// a * b - c * d for four bounded values, with a rigorous bound on the result's error (the
// factors' errors propagated, the three roundings of this evaluation, and an absolute term for
// underflow). Exact zeros (error 0, value 0) stay exact: a product with one is an exact zero.
BoundedValue differenceOfProducts(const BoundedValue& a, const BoundedValue& b,
                                  const BoundedValue& c, const BoundedValue& d);

// pi1(y) pi2(z) - pi1(z) pi2(y): the side of line(y, z) against the meet of the two planes.
// The sign is exact (the filter above, GMP when it cannot certify); the value's error is bounded.
BoundedValue pencilValue(const PlaneOrient& p1, const PlaneOrient& p2, const Vec3& y,
                         const Vec3& z);

// The side of line(y, z) against the edge's line, exact sign, rigorous error bound.
BoundedValue sideValue(const Vec3& y, const Vec3& z, const EdgeLine& e);
inline Sign sideSign(const Vec3& y, const Vec3& z, const EdgeLine& e) {
    return sideValue(y, z, e).sign();
}

// The filter alone: the sign when it can certify it (never Zero), nullopt otherwise.
std::optional<Sign> sideSignFiltered(const Vec3& y, const Vec3& z, const EdgeLine& e);

// True only if a and b are exactly the same line (then `orientation` is +1 when they are directed
// alike, -1 otherwise). Input edges against input edges, and chords of the same clip plane on
// coplanar occluders, are decided; other pairs answer false (a conservative "not known": the
// caller then decides by its general means). `probes`: input points, one of them off the chords'
// occluder plane (the receiver's and light's vertices), to compare two chords' directions.
bool sameLine(const EdgeLine& a, const EdgeLine& b, std::span<const Vec3> probes, int& orientation);

// The plane through a point x and a Planes line, as the affine function of y it is:
//   value(y) = side of line(x, y) against the line = alpha pi2(y) - beta pi1(y),
//   alpha = pi1(x), beta = pi2(x)
// (a plane of the pencil through the line). FPQuery's split planes for the edges a clip made.
// Same interface as PlaneOrient: filtered() is the filter alone, value() has the exact sign.
class PencilPlane {
  public:
    PencilPlane() = default;
    PencilPlane(const Vec3& x, const PlaneOrient& first, const PlaneOrient& second);
    // With alpha = first.value(x) already known (FPQuery evaluates B's and L's planes at x once
    // per query, not once per node).
    PencilPlane(const Vec3& x, const PlaneOrient& first, const BoundedValue& alpha,
                const PlaneOrient& second);
    bool filtered(const Vec3& y, BoundedValue& out) const;
    BoundedValue value(const Vec3& y) const;
    Sign sign(const Vec3& y) const { return value(y).sign(); }
    // As PlaneOrient's (predicates.h): the rounded N within 2^-30 (signs of constructed points
    // by the snap rule) and within 2^-40 (crossings placed from the filter's values) of the
    // exact one, from the filter's error weights.
    bool wellConditioned() const { return conditionedWithin(0x1p-30); }
    bool placesWell() const { return conditionedWithin(0x1p-40); }
    // The value rounded from the exact one (relative error below 2^-48; the exact sign).
    BoundedValue accurate(const Vec3& y) const;

  private:
    void prepareFilter();
    bool conditionedWithin(double relative) const {
        return k_[0] + k_[1] + k_[2] <
               relative * (std::fabs(n_[0]) + std::fabs(n_[1]) + std::fabs(n_[2]));
    }

    Vec3 x_;
    PlaneOrient first_, second_;
    BoundedValue alpha_, beta_;
    // value(y) vanishes at x, so it is N . (y - x) with N = alpha n2 - beta n1: the filter is one
    // dot product, N rounded (n) with a per-component error weight (k) that bounds every rounding
    // (prepareFilter).
    double n_[3] = {0, 0, 0}, k_[3] = {0, 0, 0};
};

// The plane through x and any EdgeLine: a PlaneOrient (x, p, q) for an input edge, a PencilPlane
// for a meet of planes. What the deferred and direct paths of FPQuery keep per occluder edge.
class EdgePlane {
  public:
    EdgePlane() = default;
    EdgePlane(const Vec3& x, const EdgeLine& e);
    bool filtered(const Vec3& y, BoundedValue& out) const {
        return pencil_ ? planes_.filtered(y, out) : points_.filtered(y, out);
    }
    BoundedValue value(const Vec3& y) const {
        return pencil_ ? planes_.value(y) : points_.value(y);
    }
    Sign sign(const Vec3& y) const { return value(y).sign(); }
    bool placesWell() const { return pencil_ ? planes_.placesWell() : points_.placesWell(); }
    BoundedValue accurate(const Vec3& y) const {
        return pencil_ ? planes_.accurate(y) : points_.accurate(y);
    }

  private:
    bool pencil_ = false;
    PlaneOrient points_;
    PencilPlane planes_;
};

}  // namespace penumbra::vis
