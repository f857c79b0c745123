#include "visibility/expansion.h"

#include <cmath>
#include <utility>

namespace penumbra::vis {
namespace {

// Error-free transformations (round to nearest, no extended precision: x86-64 SSE2).
// twoSum: a + b = x + y exactly, x = fl(a + b).
inline void twoSum(double a, double b, double& x, double& y) {
    x = a + b;
    const double bv = x - a;
    const double av = x - bv;
    y = (a - av) + (b - bv);
}

// fastTwoSum requires |a| >= |b| (or a == 0).
inline void fastTwoSum(double a, double b, double& x, double& y) {
    x = a + b;
    y = b - (x - a);
}

// Veltkamp split: a = hi + lo, each with at most 26 significant bits.
inline void split(double a, double& hi, double& lo) {
    const double c = 134217729.0 * a;  // 2^27 + 1
    hi = c - (c - a);
    lo = a - hi;
}

// Dekker's product: a * b = x + y exactly, x = fl(a * b).
inline void twoProduct(double a, double b, double& x, double& y) {
    x = a * b;
    double ahi, alo, bhi, blo;
    split(a, ahi, alo);
    split(b, bhi, blo);
    const double err1 = x - ahi * bhi;
    const double err2 = err1 - alo * bhi;
    const double err3 = err2 - ahi * blo;
    y = alo * blo - err3;
}

// Expansions: components in increasing magnitude, nonoverlapping, zeros eliminated.
struct Expansion {
    static constexpr size_t kCapacity = 200;
    double c[kCapacity];
    size_t n = 0;
};

// h = e + b (Shewchuk's GROW-EXPANSION with zero elimination).
void grow(const Expansion& e, double b, Expansion& h) {
    h.n = 0;
    double q = b;
    for (size_t i = 0; i < e.n; ++i) {
        double sum, err;
        twoSum(q, e.c[i], sum, err);
        if (err != 0) h.c[h.n++] = err;
        q = sum;
    }
    if (q != 0 || h.n == 0) h.c[h.n++] = q;
}

void assign(Expansion& dst, const Expansion& src) {
    for (size_t i = 0; i < src.n; ++i) dst.c[i] = src.c[i];
    dst.n = src.n;
}

// e += f, component by component (EXPANSION-SUM): O(|e| |f|), fine for the short expansions here.
void add(Expansion& e, const Expansion& f, Expansion& scratch) {
    Expansion* cur = &e;
    Expansion* next = &scratch;
    for (size_t j = 0; j < f.n; ++j) {
        grow(*cur, f.c[j], *next);
        std::swap(cur, next);
    }
    if (cur != &e) assign(e, *cur);
}

// h = e * b (SCALE-EXPANSION with zero elimination).
void scale(const Expansion& e, double b, Expansion& h) {
    h.n = 0;
    if (e.n == 0 || b == 0) {
        h.c[h.n++] = 0;
        return;
    }
    double q, hh;
    twoProduct(e.c[0], b, q, hh);
    if (hh != 0) h.c[h.n++] = hh;
    for (size_t i = 1; i < e.n; ++i) {
        double t1, t0, q2;
        twoProduct(e.c[i], b, t1, t0);
        twoSum(q, t0, q2, hh);
        if (hh != 0) h.c[h.n++] = hh;
        fastTwoSum(t1, q2, q, hh);
        if (hh != 0) h.c[h.n++] = hh;
    }
    if (q != 0 || h.n == 0) h.c[h.n++] = q;
}

// h = e * f.
void multiply(const Expansion& e, const Expansion& f, Expansion& h, Expansion& s1, Expansion& s2) {
    h.n = 1;
    h.c[0] = 0;
    for (size_t j = 0; j < f.n; ++j) {
        scale(e, f.c[j], s1);
        add(h, s1, s2);
    }
}

void difference(double a, double b, Expansion& e) {
    e.n = 0;
    double x, y;
    twoSum(a, -b, x, y);
    if (y != 0) e.c[e.n++] = y;
    if (x != 0 || e.n == 0) e.c[e.n++] = x;
}

bool inRange(const Vec3& p) {
    for (int i = 0; i < 3; ++i) {
        const double m = std::fabs(p[i]);
        if (m != 0 && (m < 0x1p-200 || m > 0x1p200)) return false;
    }
    return true;
}

}  // namespace

bool orient3dExpansion(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d, int& sign,
                       double& approx) {
    if (!inRange(a) || !inRange(b) || !inRange(c) || !inRange(d)) return false;
    Expansion u[3], v[3], w[3];
    for (int i = 0; i < 3; ++i) {
        difference(b[i], a[i], u[i]);
        difference(c[i], a[i], v[i]);
        difference(d[i], a[i], w[i]);
    }
    Expansion det, vw, t, term, s1, s2;
    det.n = 1;
    det.c[0] = 0;
    // det = sum over i of u[i] * (v[j] w[k] - v[k] w[j]), (i, j, k) cyclic.
    for (int i = 0; i < 3; ++i) {
        const int j = (i + 1) % 3, k = (i + 2) % 3;
        multiply(v[j], w[k], vw, s1, s2);
        multiply(v[k], w[j], t, s1, s2);
        for (size_t m = 0; m < t.n; ++m) t.c[m] = -t.c[m];
        add(vw, t, s2);
        multiply(vw, u[i], term, s1, s2);
        add(det, term, s2);
    }
    // Nonoverlapping, increasing magnitude: the largest nonzero component carries the sign.
    sign = 0;
    approx = 0;
    for (size_t m = 0; m < det.n; ++m) approx += det.c[m];
    for (size_t m = det.n; m-- > 0;)
        if (det.c[m] != 0) {
            sign = det.c[m] > 0 ? 1 : -1;
            break;
        }
    if (sign != 0 && (approx == 0 || (approx > 0) != (sign > 0))) approx = det.c[det.n - 1];
    return true;
}

}  // namespace penumbra::vis
