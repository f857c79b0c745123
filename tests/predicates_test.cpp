// The predicates against exact rational arithmetic computed here (an independent reference), on
// inputs built to be hard: exactly coplanar points, and points perturbed by an ulp off a plane.
#include <gtest/gtest.h>
#include <gmpxx.h>

#include <cmath>
#include <random>

#include "visibility/plucker.h"
#include "visibility/predicates.h"

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
    const Vec3 a = o + Vec3{1, 2, 0}, b = o + Vec3{3, -1, 0}, c = o + Vec3{-2, 5, 0}, d = o + Vec3{7, 7, 0};
    EXPECT_EQ(orientSign(a, b, c, d), Sign::Zero);
    EXPECT_EQ(orientValue(a, b, c, d).value, 0.0);
    EXPECT_EQ(orientValue(a, b, c, d).error, 0.0);
}

TEST(Predicates, FilteredValueBoundHoldsAgainstExact) {
    std::mt19937_64 rng(2);
    std::uniform_real_distribution<double> u(-1e3, 1e3);
    for (int i = 0; i < 2000; ++i) {
        const Vec3 a{u(rng), u(rng), u(rng)}, b{u(rng), u(rng), u(rng)}, c{u(rng), u(rng), u(rng)},
            d{u(rng), u(rng), u(rng)};
        const BoundedValue v = orientValue(a, b, c, d);
        // Exact value: expand det[b-a, c-a, d-a] in rationals.
        const mpq_class ux = mpq_class(b.x) - a.x, uy = mpq_class(b.y) - a.y, uz = mpq_class(b.z) - a.z;
        const mpq_class vx = mpq_class(c.x) - a.x, vy = mpq_class(c.y) - a.y, vz = mpq_class(c.z) - a.z;
        const mpq_class wx = mpq_class(d.x) - a.x, wy = mpq_class(d.y) - a.y, wz = mpq_class(d.z) - a.z;
        const mpq_class exact = ux * (vy * wz - vz * wy) + uy * (vz * wx - vx * wz) + uz * (vx * wy - vy * wx);
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
