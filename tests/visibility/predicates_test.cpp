// The predicates against exact rational arithmetic computed here (an independent reference), on
// inputs built to be hard: exactly coplanar points, and points perturbed by an ulp off a plane.
#include "visibility/predicates.h"

#include <gmpxx.h>
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "visibility/expansion.h"
#include "visibility/plucker.h"

namespace penumbra::vis {
namespace {

// det[b-a, c-a, d-a] in rationals, written independently of predicates.cpp (cofactors of the
// 4x4 homogeneous matrix).
int referenceSign(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
    const Vec3* p[4] = {&a, &b, &c, &d};
    mpq_class m[4][4];
    for (int i = 0; i < 4; ++i) {
        m[i][0] = p[i]->x;
        m[i][1] = p[i]->y;
        m[i][2] = p[i]->z;
        m[i][3] = 1;
    }
    // Gaussian elimination, exact.
    int sign = 1;
    for (int col = 0; col < 4; ++col) {
        int piv = -1;
        for (int r = col; r < 4; ++r)
            if (sgn(m[r][col]) != 0) {
                piv = r;
                break;
            }
        if (piv < 0) return 0;
        if (piv != col) {
            for (int k = 0; k < 4; ++k) std::swap(m[piv][k], m[col][k]);
            sign = -sign;
        }
        for (int r = col + 1; r < 4; ++r) {
            const mpq_class f = m[r][col] / m[col][col];
            for (int k = col; k < 4; ++k) m[r][k] -= f * m[col][k];
        }
    }
    mpq_class det = sign;
    for (int i = 0; i < 4; ++i) det *= m[i][i];
    // det of [p 1] rows equals -det[b-a, c-a, d-a].
    return -sgn(det);
}

TEST(Predicates, OrientationConvention) {
    // d above the counter-clockwise triangle (a, b, c) seen from +z.
    EXPECT_EQ(orientSign({0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}), Sign::Positive);
    EXPECT_EQ(orientSign({0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, -1}), Sign::Negative);
    EXPECT_EQ(orientSign({0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {5, 7, 0}), Sign::Zero);
}

TEST(Predicates, NearCoplanarPointsGetTheExactSign) {
    std::mt19937_64 rng(1);
    std::uniform_real_distribution<double> u(-1, 1);
    int naiveWrong = 0, cases = 0;
    for (int i = 0; i < 20000; ++i) {
        // A point on the plane through a, b, c (as a rounded combination), nudged by 0-2 ulps.
        const Vec3 a{u(rng), u(rng), u(rng)}, b{u(rng), u(rng), u(rng)}, c{u(rng), u(rng), u(rng)};
        const double s = u(rng), t = u(rng);
        Vec3 d = a + (b - a) * s + (c - a) * t;
        const int nudge = static_cast<int>(rng() % 5) - 2;
        for (int k = 0; k < std::abs(nudge); ++k) d.z = std::nextafter(d.z, nudge > 0 ? 2.0 : -2.0);
        const int ref = referenceSign(a, b, c, d);
        EXPECT_EQ(toInt(orientSign(a, b, c, d)), ref);
        const BoundedValue v = orientValue(a, b, c, d);
        EXPECT_TRUE(v.certain());
        EXPECT_EQ(toInt(v.sign()), ref);
        naiveWrong += toInt(orientSignNaive(a, b, c, d)) != ref;
        ++cases;
    }
    // The test is only meaningful if plain doubles do get these wrong.
    EXPECT_GT(naiveWrong, cases / 20);
}

TEST(Predicates, ExactlyCoplanarIntegerGridIsZero) {
    // Large coordinates, far from the origin: exact zeros must stay zeros.
    const Vec3 o{1e5, 1e5, 1e5};
    const Vec3 a = o + Vec3{1, 2, 0}, b = o + Vec3{3, -1, 0}, c = o + Vec3{-2, 5, 0},
               d = o + Vec3{7, 7, 0};
    EXPECT_EQ(orientSign(a, b, c, d), Sign::Zero);
    EXPECT_EQ(orientValue(a, b, c, d).value, 0.0);
    EXPECT_EQ(orientValue(a, b, c, d).error, 0.0);
}

// The exact zeros decided without the exact stage (two equal points; four points in one plane
// x, y or z = const, as on a floor or a wall) and their near misses (the fourth point an ulp off
// that plane, or only three of them on it): every sign equals the rational reference, through
// orientSign, orientValue and PlaneOrient, and the near misses are not zeros.
TEST(Predicates, AxisPlaneAndRepeatedPointZerosAreExactAndOnlyZeros) {
    std::mt19937_64 rng(11);
    std::uniform_real_distribution<double> u(-1, 1);
    const double offsets[] = {0.0, 0.7, -3.1e6};
    int zeros = 0, nearMissesNonZero = 0, unfiltered = 0;
    auto check = [&](const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
        const int ref = referenceSign(a, b, c, d);
        EXPECT_EQ(toInt(orientSign(a, b, c, d)), ref);
        const BoundedValue v = orientValue(a, b, c, d);
        EXPECT_TRUE(v.certain());
        EXPECT_EQ(toInt(v.sign()), ref);
        const BoundedValue w = PlaneOrient(a, b, c).value(d);
        EXPECT_TRUE(w.certain());
        EXPECT_EQ(toInt(w.sign()), ref);
        return ref;
    };
    for (int i = 0; i < 3000; ++i) {
        const double off = offsets[i % 3];
        Vec3 p[4];
        for (Vec3& q : p) q = Vec3{u(rng), u(rng), u(rng)} + Vec3{off, off, off};
        // Two equal points, each of the six pairs in turn.
        const int pairs[6][2] = {{0, 1}, {0, 2}, {0, 3}, {1, 2}, {1, 3}, {2, 3}};
        Vec3 r[4] = {p[0], p[1], p[2], p[3]};
        r[pairs[i % 6][1]] = r[pairs[i % 6][0]];
        zeros += check(r[0], r[1], r[2], r[3]) == 0;
        // Four points in the plane axis = off + k (a floor, a wall).
        const int axis = i % 3;
        const double level = off + u(rng);
        Vec3 q[4] = {p[0], p[1], p[2], p[3]};
        for (Vec3& v : q) (axis == 0 ? v.x : axis == 1 ? v.y : v.z) = level;
        zeros += check(q[0], q[1], q[2], q[3]) == 0;
        // Near misses: one of them an ulp off that plane, on either side.
        const int moved = static_cast<int>(rng() % 4);
        double& m = axis == 0 ? q[moved].x : axis == 1 ? q[moved].y : q[moved].z;
        m = std::nextafter(m, (i & 8) != 0 ? 1e300 : -1e300);
        nearMissesNonZero += check(q[0], q[1], q[2], q[3]) != 0;
        // Near misses the filter cannot decide: a, b, c in the plane and almost collinear in it
        // (c an ulp off the line through a and b), d just off the plane. Only the exact stage
        // gets these right; a shortcut that took "three points on the plane" for "four" would not.
        Vec3 t[4] = {p[0], p[1], p[2], p[3]};
        for (Vec3& v : t) (axis == 0 ? v.x : axis == 1 ? v.y : v.z) = level;
        t[2] = t[0] + (t[1] - t[0]) * 0.375;
        double& along = axis == 0 ? t[2].y : t[2].x;
        along = std::nextafter(along, (i & 16) != 0 ? 1e300 : -1e300);
        double& lift = axis == 0 ? t[3].x : axis == 1 ? t[3].y : t[3].z;
        lift = std::nextafter(lift, (i & 32) != 0 ? 1e300 : -1e300);
        unfiltered += !orientSignFiltered(t[0], t[1], t[2], t[3]).has_value();
        nearMissesNonZero += check(t[0], t[1], t[2], t[3]) != 0;
    }
    EXPECT_EQ(zeros, 6000);
    // Random points off the plane: the moved one is almost never exactly coplanar with the rest.
    EXPECT_GT(nearMissesNonZero, 5800);
    EXPECT_GT(unfiltered, 1000);  // the second kind does reach the exact stage
}

// det[b-a, c-a, d-a] in rationals by cofactor expansion (for values, not only signs).
mpq_class referenceValue(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
    const mpq_class ux = mpq_class(b.x) - a.x, uy = mpq_class(b.y) - a.y, uz = mpq_class(b.z) - a.z;
    const mpq_class vx = mpq_class(c.x) - a.x, vy = mpq_class(c.y) - a.y, vz = mpq_class(c.z) - a.z;
    const mpq_class wx = mpq_class(d.x) - a.x, wy = mpq_class(d.y) - a.y, wz = mpq_class(d.z) - a.z;
    return ux * (vy * wz - vz * wy) + uy * (vz * wx - vx * wz) + uz * (vx * wy - vy * wx);
}

// The exact stage alone (expansion arithmetic), over magnitudes from 1e-40 to 1e40, far from the
// origin, on exactly coplanar points and points nudged by ulps off their plane: the sign equals the
// rational reference, and the approximation is within its claimed relative error.
TEST(Predicates, ExpansionStageIsExact) {
    std::mt19937_64 rng(3);
    std::uniform_real_distribution<double> u(-1, 1);
    const double scales[] = {1e-40, 1e-7, 1.0, 3.7e5, 1e40};
    const double offsets[] = {0.0, 1e5, -7.25e8};
    int zeros = 0, nonzeros = 0;
    for (double scale : scales)
        for (double offset : offsets)
            for (int i = 0; i < 400; ++i) {
                const Vec3 o{offset * scale, -offset * scale, 0.5 * offset * scale};
                const Vec3 a = o + Vec3{u(rng), u(rng), u(rng)} * scale;
                const Vec3 b = o + Vec3{u(rng), u(rng), u(rng)} * scale;
                const Vec3 c = o + Vec3{u(rng), u(rng), u(rng)} * scale;
                Vec3 d;
                if (i % 3 == 0) {
                    // Exactly coplanar points on a power-of-two grid (exactly representable).
                    const double g = scale * 0x1p-10;
                    const Vec3 base{std::round(o.x / g) * g, std::round(o.y / g) * g,
                                    std::round(o.z / g) * g};
                    const Vec3 pa = base + Vec3{1, 2, 0} * g, pb = base + Vec3{3, -1, 0} * g,
                               pc = base + Vec3{-2, 5, 0} * g,
                               pd = base + Vec3{double(rng() % 100), double(rng() % 100), 0} * g;
                    int s;
                    double approx;
                    ASSERT_TRUE(orient3dExpansion(pa, pb, pc, pd, s, approx));
                    const int ref = sgn(referenceValue(pa, pb, pc, pd));
                    EXPECT_EQ(s, ref);
                    EXPECT_EQ(toInt(orientSign(pa, pb, pc, pd)), ref);
                    zeros += ref == 0;
                    continue;
                }
                d = a + (b - a) * u(rng) + (c - a) * u(rng);
                const int nudge = static_cast<int>(rng() % 5) - 2;
                for (int k = 0; k < std::abs(nudge); ++k)
                    d.z = std::nextafter(d.z, nudge > 0 ? INFINITY : -INFINITY);
                int s;
                double approx;
                ASSERT_TRUE(orient3dExpansion(a, b, c, d, s, approx));
                const mpq_class exact = referenceValue(a, b, c, d);
                EXPECT_EQ(s, sgn(exact));
                EXPECT_EQ(toInt(orientSign(a, b, c, d)), sgn(exact));
                if (sgn(exact) != 0) {
                    ++nonzeros;
                    const mpq_class rel = abs((exact - mpq_class(approx)) / exact);
                    EXPECT_LE(rel.get_d(), 0x1p-48);
                    const BoundedValue v = orientValue(a, b, c, d);
                    EXPECT_LE(std::fabs(mpq_class(exact - mpq_class(v.value)).get_d()), v.error);
                    EXPECT_EQ(toInt(v.sign()), sgn(exact));
                }
            }
    EXPECT_GT(zeros, 100);
    EXPECT_GT(nonzeros, 1000);
    // Outside the safe range the stage declines (the GMP stage takes over).
    int s;
    double approx;
    EXPECT_FALSE(orient3dExpansion({1e300, 0, 0}, {0, 1, 0}, {0, 0, 1}, {1, 1, 1}, s, approx));
    EXPECT_EQ(orientSign({1e300, 0, 0}, {0, 1, 0}, {0, 0, 1}, {1e300, 0, 0}), Sign::Zero);
}

TEST(Predicates, FilteredValueBoundHoldsAgainstExact) {
    std::mt19937_64 rng(2);
    std::uniform_real_distribution<double> u(-1e3, 1e3);
    for (int i = 0; i < 2000; ++i) {
        const Vec3 a{u(rng), u(rng), u(rng)}, b{u(rng), u(rng), u(rng)}, c{u(rng), u(rng), u(rng)},
            d{u(rng), u(rng), u(rng)};
        const BoundedValue v = orientValue(a, b, c, d);
        // Exact value: expand det[b-a, c-a, d-a] in rationals.
        const mpq_class ux = mpq_class(b.x) - a.x, uy = mpq_class(b.y) - a.y,
                        uz = mpq_class(b.z) - a.z;
        const mpq_class vx = mpq_class(c.x) - a.x, vy = mpq_class(c.y) - a.y,
                        vz = mpq_class(c.z) - a.z;
        const mpq_class wx = mpq_class(d.x) - a.x, wy = mpq_class(d.y) - a.y,
                        wz = mpq_class(d.z) - a.z;
        const mpq_class exact =
            ux * (vy * wz - vz * wy) + uy * (vz * wx - vx * wz) + uz * (vx * wy - vy * wx);
        const mpq_class diff = exact - mpq_class(v.value);
        EXPECT_LE(std::fabs(diff.get_d()), v.error);
    }
}

TEST(Plucker, SideOperatorIsOrient3d) {
    std::mt19937_64 rng(3);
    std::uniform_real_distribution<double> u(-1, 1);
    for (int i = 0; i < 1000; ++i) {
        const Vec3 p{u(rng), u(rng), u(rng)}, q{u(rng), u(rng), u(rng)}, a{u(rng), u(rng), u(rng)},
            b{u(rng), u(rng), u(rng)};
        const double s = side(PluckerLine::through(p, q), PluckerLine::through(a, b));
        const double o = orient3dApprox(p, q, a, b);
        EXPECT_NEAR(s, o, 1e-12);
        if (std::fabs(s) > 1e-9) {
            EXPECT_EQ(toInt(sideSign(p, q, a, b)), s > 0 ? 1 : -1);
        }
    }
    // Lines through a common point meet: side 0 exactly.
    EXPECT_EQ(sideSign({0, 0, 0}, {1, 2, 3}, {0, 0, 0}, {-4, 1, 2}), Sign::Zero);
    // A real line lies on the Plücker quadric.
    const PluckerLine l = PluckerLine::through({1, 2, 3}, {-2, 0.5, 4});
    EXPECT_NEAR(side(l, l), 0, 1e-12);
}

TEST(Predicates, Collinear) {
    EXPECT_TRUE(collinear({0, 0, 0}, {1, 1, 1}, {3, 3, 3}));
    EXPECT_TRUE(collinear({1e5, 1e5, 0}, {1e5 + 1, 1e5 + 2, 0}, {1e5 + 3, 1e5 + 6, 0}));
    EXPECT_FALSE(collinear({0, 0, 0}, {1, 1, 1}, {3, 3, std::nextafter(3.0, 4.0)}));
    EXPECT_FALSE(collinear({0, 0, 0}, {1, 0, 0}, {0, 1, 0}));
}

}  // namespace
}  // namespace penumbra::vis

namespace penumbra::vis {
namespace {

// A plane through points around o (|o| up to `scale`) and a box beside it, both from `rng`: the
// box centred near the plane and offset along its normal by a tiny signed amount; every second
// box (even i) a few units in the last place of the coordinates wide and away.
struct NearPlaneBox {
    Vec3 a, b, c;  // the plane's points
    Vec3 lo, hi;   // the box
    double ulp = 0;
};

NearPlaneBox nearPlaneBox(std::mt19937_64& rng, double scale, int i) {
    std::uniform_real_distribution<double> u(-1, 1);
    NearPlaneBox r;
    const Vec3 o{scale * u(rng), scale * u(rng), scale * u(rng)};
    r.a = o;
    r.b = o + Vec3{u(rng), u(rng), u(rng)};
    r.c = o + Vec3{u(rng), u(rng), u(rng)};
    const Vec3 n = normalize(cross(r.b - r.a, r.c - r.a));
    const double off = std::ldexp(u(rng), -static_cast<int>(rng() % 60));
    const Vec3 v{u(rng), u(rng), u(rng)};
    const Vec3 centre = o + (v - n * dot(n, v)) * 0.5;  // in the plane, up to rounding
    r.ulp = scale * 0x1p-52;
    const bool inUlps = i % 2 == 0;
    const Vec3 p =
        centre + n * (inUlps ? r.ulp * std::round(8 * u(rng)) : off * std::max(1.0, scale * 1e-15));
    const double half = inUlps ? r.ulp * std::round(4 * std::fabs(u(rng)))
                               : std::ldexp(std::fabs(u(rng)), -static_cast<int>(rng() % 50));
    r.lo = {p.x - half, p.y - half, p.z - half};
    r.hi = {p.x + half, p.y + half, p.z + half};
    return r;
}

// boxNegative must only say "strictly negative" when every corner of the box is (the value is
// affine, so the corners decide), at every magnitude: boxes just beside a plane through points
// around the origin and around 1e4 .. 1e15, some touching or straddling it by less than a unit in
// the last place of their coordinates.
TEST(Predicates, BoxNegativeIsCertainAtEveryMagnitude) {
    std::mt19937_64 rng(17);
    int said = 0, checked = 0;
    for (double scale : {1.0, 1e4, 1e8, 1e12, 1e15}) {
        for (int i = 0; i < 4000; ++i) {
            const NearPlaneBox t = nearPlaneBox(rng, scale, i);
            const Vec3 &a = t.a, &b = t.b, &c = t.c, &lo = t.lo, &hi = t.hi;
            const PlaneOrient plane(a, b, c);
            if (!plane.boxNegative(lo, hi)) continue;
            ++said;
            for (int k = 0; k < 8; ++k) {
                const Vec3 corner{k & 1 ? hi.x : lo.x, k & 2 ? hi.y : lo.y, k & 4 ? hi.z : lo.z};
                EXPECT_EQ(orientSignExact(a, b, c, corner), Sign::Negative)
                    << "scale " << scale << " box " << toString(lo) << " .. " << toString(hi);
                ++checked;
            }
            if (::testing::Test::HasFailure()) return;
        }
    }
    EXPECT_GT(said, 2000);  // it does decide most boxes that are not too close
}

// PlaneBoxCull (the box hierarchy's cull, its error bounded once for a region) must only say
// "strictly negative" when every corner of the box is, for boxes anywhere inside the region: the
// boxes of the test above, each inside a region that reaches up to 2^20 times further, on either
// side; and with the box as its own region it decides what boxNegative decides.
TEST(Predicates, PlaneBoxCullIsCertainForEveryBoxInsideItsRegion) {
    std::mt19937_64 rng(19);
    std::uniform_real_distribution<double> u(-1, 1);
    int said = 0, asBoxNegative = 0, boxNegativeSaid = 0;
    for (double scale : {1.0, 1e4, 1e8, 1e12, 1e15}) {
        for (int i = 0; i < 4000; ++i) {
            const NearPlaneBox t = nearPlaneBox(rng, scale, i);
            const Vec3 &a = t.a, &b = t.b, &c = t.c, &lo = t.lo, &hi = t.hi;
            const PlaneOrient plane(a, b, c);
            const double half = 0.5 * (hi.x - lo.x), ulp = t.ulp;
            // A region around the box, grown unevenly.
            const double grow =
                std::ldexp(std::fabs(u(rng)), static_cast<int>(rng() % 21)) * std::max(half, ulp);
            const Vec3 rlo{lo.x - grow * std::fabs(u(rng)), lo.y - grow * std::fabs(u(rng)),
                           lo.z - grow * std::fabs(u(rng))};
            const Vec3 rhi{hi.x + grow * std::fabs(u(rng)), hi.y + grow * std::fabs(u(rng)),
                           hi.z + grow * std::fabs(u(rng))};
            const bool own = PlaneBoxCull(plane, lo, hi).negative(lo, hi);
            const bool reference = plane.boxNegative(lo, hi);
            boxNegativeSaid += reference;
            asBoxNegative += own == reference;
            for (const bool negative : {PlaneBoxCull(plane, rlo, rhi).negative(lo, hi), own}) {
                if (!negative) continue;
                ++said;
                for (int k = 0; k < 8; ++k) {
                    const Vec3 corner{k & 1 ? hi.x : lo.x, k & 2 ? hi.y : lo.y,
                                      k & 4 ? hi.z : lo.z};
                    EXPECT_EQ(orientSignExact(a, b, c, corner), Sign::Negative)
                        << "scale " << scale << " box " << toString(lo) << " .. " << toString(hi);
                }
            }
            if (::testing::Test::HasFailure()) return;
        }
    }
    EXPECT_GT(said, 3000);               // it does decide most boxes not too close
    EXPECT_EQ(asBoxNegative, 5 * 4000);  // its own region: boxNegative's decisions
    EXPECT_GT(boxNegativeSaid, 1000);
}

// The filters' error bounds assume that each product and sum is rounded on its own. A fused
// multiply-add (-ffp-contract=fast on a target with FMA) would round a * b - c * d once, and the
// values below would differ from the two-step evaluation: this fails if the build contracts.
TEST(Predicates, FiltersAreEvaluatedWithoutContraction) {
    std::mt19937_64 rng(5);
    std::uniform_real_distribution<double> u(-1, 1);
    int differs = 0;
    for (int i = 0; i < 1000; ++i) {
        const Vec3 a{u(rng), u(rng), u(rng)}, b{u(rng), u(rng), u(rng)}, c{u(rng), u(rng), u(rng)},
            d{u(rng), u(rng), u(rng)};
        // PlaneOrient's evaluation, step by step through volatile temporaries (never fused).
        volatile double vx = b.x - a.x, vy = b.y - a.y, vz = b.z - a.z;
        volatile double wx = c.x - a.x, wy = c.y - a.y, wz = c.z - a.z;
        volatile double m1 = vy * wz, m2 = vz * wy, m3 = vz * wx, m4 = vx * wz, m5 = vx * wy,
                        m6 = vy * wx;
        volatile double n0 = m1 - m2, n1 = m3 - m4, n2 = m5 - m6;
        volatile double ux = d.x - a.x, uy = d.y - a.y, uz = d.z - a.z;
        volatile double t0 = ux * n0, t1 = uy * n1, t2 = uz * n2;
        volatile double s01 = t0 + t1;
        const double stepwise = s01 + t2;
        BoundedValue out;
        PlaneOrient(a, b, c).filtered(d, out);
        EXPECT_EQ(out.value, stepwise) << "contracted evaluation at sample " << i;
        // The fused value, for the record: it does differ on these inputs.
        const double fused = std::fma(uz, n2, std::fma(uy, n1, ux * n0));
        differs += fused != stepwise;
    }
    EXPECT_GT(differs, 0);  // the inputs can tell a contracted evaluation from a plain one
}

}  // namespace
}  // namespace penumbra::vis
