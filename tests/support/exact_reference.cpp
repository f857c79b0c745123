#include "tests/support/exact_reference.h"

#include <CGAL/Exact_predicates_exact_constructions_kernel.h>
#include <CGAL/Polygon_2.h>
#include <CGAL/Polygon_set_2.h>
#include <CGAL/Polygon_with_holes_2.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <iterator>
#include <numbers>
#include <vector>

#include "engine/scene/random.h"

namespace penumbra::test {

namespace {

using K = CGAL::Exact_predicates_exact_constructions_kernel;
using FT = K::FT;
using Point3 = K::Point_3;
using Vector3 = K::Vector_3;
using Point2 = K::Point_2;
using Polygon2 = CGAL::Polygon_2<K>;
using PolygonWithHoles2 = CGAL::Polygon_with_holes_2<K>;
using PolygonSet2 = CGAL::Polygon_set_2<K>;
using Poly3 = std::vector<Point3>;
using vis::Vec3;

Point3 exact(const Vec3& v) { return Point3(v.x, v.y, v.z); }

// The double nearest to x (ties to even). Lazy numbers' own to_double may return an
// approximation only good to a relative 1e-5; this decides on the exact value when the interval
// approximation does not pin the answer down.
double nearestDouble(const FT& x) {
    std::pair<double, double> iv = CGAL::to_interval(x);
    auto pinned = [](const std::pair<double, double>& i) {
        return i.first == i.second || std::nextafter(i.first, HUGE_VAL) == i.second;
    };
    if (!pinned(iv)) iv = CGAL::to_interval(CGAL::exact(x));  // tighten through the exact value
    if (iv.first == iv.second) return iv.first;
    if (!pinned(iv))
        return 0.5 * (iv.first + iv.second);  // not expected: exact intervals are tight
    // two candidates: compare x against their midpoint exactly
    const FT mid = (FT(iv.first) + FT(iv.second)) / 2;
    const CGAL::Comparison_result c = CGAL::compare(x, mid);
    if (c == CGAL::SMALLER) return iv.first;
    if (c == CGAL::LARGER) return iv.second;
    int e = 0;
    const double m = std::frexp(iv.first, &e);
    return std::fmod(std::ldexp(m, 53), 2.0) == 0 ? iv.first : iv.second;
}

// The halfspace { p : n . (p - o) >= 0 }.
struct HalfSpace {
    Vector3 n;
    Point3 o;
    FT value(const Point3& p) const { return n * (p - o); }
};

// Sutherland-Hodgman against one closed halfspace; exact.
Poly3 clip(const Poly3& poly, const HalfSpace& h) {
    Poly3 out;
    const size_t m = poly.size();
    if (m == 0) return out;
    std::vector<FT> v;
    std::vector<CGAL::Sign> s;
    v.reserve(m);
    s.reserve(m);
    bool allIn = true, allOut = true;
    for (const Point3& p : poly) {
        v.push_back(h.value(p));
        s.push_back(CGAL::sign(v.back()));
        allIn = allIn && s.back() != CGAL::NEGATIVE;
        allOut = allOut && s.back() != CGAL::POSITIVE;
    }
    if (allIn) return poly;
    if (allOut) {  // at most a face or edge on the boundary plane: measure zero
        return out;
    }
    for (size_t i = 0; i < m; ++i) {
        const size_t j = (i + 1) % m;
        if (s[i] != CGAL::NEGATIVE) out.push_back(poly[i]);
        if ((s[i] == CGAL::POSITIVE && s[j] == CGAL::NEGATIVE) ||
            (s[i] == CGAL::NEGATIVE && s[j] == CGAL::POSITIVE)) {
            const FT t = v[i] / (v[i] - v[j]);
            out.push_back(poly[i] + (poly[j] - poly[i]) * t);
        }
    }
    return out;
}

// Removes repeated and collinear vertices of a convex polygon (2D or 3D points). Leaves fewer
// than 3 vertices when the polygon has no area.
template <class P>
void removeDegenerateVertices(std::vector<P>& pts) {
    bool changed = true;
    while (changed && pts.size() >= 3) {
        changed = false;
        const size_t n = pts.size();
        for (size_t i = 0; i < n; ++i) {
            const P& prev = pts[(i + n - 1) % n];
            const P& next = pts[(i + 1) % n];
            if (pts[i] == next || CGAL::collinear(prev, pts[i], next)) {
                pts.erase(pts.begin() + static_cast<std::ptrdiff_t>(i));
                changed = true;
                break;
            }
        }
    }
    if (pts.size() < 3) pts.clear();
}

struct Box {
    Vec3 lo{HUGE_VAL, HUGE_VAL, HUGE_VAL}, hi{-HUGE_VAL, -HUGE_VAL, -HUGE_VAL};
    void add(const Vec3& p) {
        lo = {std::min(lo.x, p.x), std::min(lo.y, p.y), std::min(lo.z, p.z)};
        hi = {std::max(hi.x, p.x), std::max(hi.y, p.y), std::max(hi.z, p.z)};
    }
    bool meets(const Box& o) const {
        return lo.x <= o.hi.x && o.lo.x <= hi.x && lo.y <= o.hi.y && o.lo.y <= hi.y &&
               lo.z <= o.hi.z && o.lo.z <= hi.z;
    }
};

// Everything about L, x and the 2D frame of L's plane.
struct Frame {
    Point3 x;
    Point3 l0;
    Vector3 nL;        // front normal of L: (l1 - l0) x (l2 - l0)
    int drop = 2;      // dominant axis of nL, dropped for 2D
    int u = 0, v = 1;  // the kept axes, cyclic after `drop`
    int orient2d = 1;  // +1 if L's 3D orientation appears counter-clockwise in 2D

    Point2 to2d(const Point3& p) const { return Point2(p.cartesian(u), p.cartesian(v)); }

    // Central projection from x onto L's plane, in 2D. p must not lie on the plane through x
    // parallel to L (checked by the caller).
    Point2 project2d(const Point3& p) const {
        const Vector3 d = p - x;
        const FT t = (nL * (l0 - x)) / (nL * d);
        return Point2(x.cartesian(u) + d.cartesian(u) * t, x.cartesian(v) + d.cartesian(v) * t);
    }
};

// A convex polygon (2D) made counter-clockwise; empty if it has no area.
bool makeCcw(std::vector<Point2> pts, Polygon2& out) {
    removeDegenerateVertices(pts);
    if (pts.size() < 3) return false;
    Polygon2 poly(pts.begin(), pts.end());
    const CGAL::Orientation o = poly.orientation();
    if (o == CGAL::COLLINEAR) return false;
    if (o == CGAL::CLOCKWISE) poly.reverse_orientation();
    out = std::move(poly);
    return true;
}

using Loop3 = std::vector<std::array<long double, 3>>;

// Lambert: sum over the loop's edges of Theta_i * (n . Gamma_i).
long double lambertSum(const Loop3& loop, const std::array<long double, 3>& x,
                       const std::array<long double, 3>& n) {
    long double sum = 0;
    const size_t m = loop.size();
    for (size_t i = 0; i < m; ++i) {
        const auto& p = loop[i];
        const auto& q = loop[(i + 1) % m];
        const long double a[3] = {p[0] - x[0], p[1] - x[1], p[2] - x[2]};
        const long double b[3] = {q[0] - x[0], q[1] - x[1], q[2] - x[2]};
        const long double c[3] = {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2],
                                  a[0] * b[1] - a[1] * b[0]};
        const long double cl = std::sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]);
        if (cl == 0) continue;
        const long double theta = std::atan2(cl, a[0] * b[0] + a[1] * b[1] + a[2] * b[2]);
        sum += theta * (n[0] * c[0] + n[1] * c[1] + n[2] * c[2]) / cl;
    }
    return sum;
}

// Lifts a 2D loop back onto L's plane (long double) .
Loop3 lift(const Polygon2& poly, const Frame& f) {
    const long double nl[3] = {nearestDouble(f.nL.x()), nearestDouble(f.nL.y()),
                               nearestDouble(f.nL.z())};
    const long double d = nearestDouble(f.nL * (f.l0 - CGAL::ORIGIN));
    Loop3 out;
    out.reserve(poly.size());
    for (auto it = poly.vertices_begin(); it != poly.vertices_end(); ++it) {
        std::array<long double, 3> p{};
        p[f.u] = nearestDouble(it->x());
        p[f.v] = nearestDouble(it->y());
        p[f.drop] = (d - nl[f.u] * p[f.u] - nl[f.v] * p[f.v]) / nl[f.drop];
        out.push_back(p);
    }
    return out;
}

// Form factor of a 2D region (union of polygons with holes) lying in L's plane.
double formFactor(const std::vector<PolygonWithHoles2>& region, const Frame& f, const Vec3& x,
                  const Vec3& nB) {
    const std::array<long double, 3> xl{x.x, x.y, x.z};
    const long double nlen =
        std::sqrt(static_cast<long double>(nB.x) * nB.x + static_cast<long double>(nB.y) * nB.y +
                  static_cast<long double>(nB.z) * nB.z);
    if (nlen == 0) return 0;
    const std::array<long double, 3> n{nB.x / nlen, nB.y / nlen, nB.z / nlen};
    long double sum = 0;
    for (const PolygonWithHoles2& pwh : region) {
        sum += lambertSum(lift(pwh.outer_boundary(), f), xl, n);  // counter-clockwise in 2D
        for (auto h = pwh.holes_begin(); h != pwh.holes_end(); ++h)
            sum += lambertSum(lift(*h, f), xl, n);  // clockwise in 2D
    }
    // 2D counter-clockwise is L's orientation when orient2d > 0; L's orientation seen from a
    // point in front of L gives a negative sum, hence the minus sign.
    return static_cast<double>(-f.orient2d * sum / (2 * std::numbers::pi_v<long double>));
}

FT signedArea(const std::vector<PolygonWithHoles2>& region) {
    FT a = 0;
    for (const PolygonWithHoles2& pwh : region) {
        a += pwh.outer_boundary().area();
        for (auto h = pwh.holes_begin(); h != pwh.holes_end(); ++h) a += h->area();  // negative
    }
    return a;
}

// The face's vertices as exact points; one polygon if exactly planar, else a triangle fan.
std::vector<Poly3> exactPieces(const vis::PolygonMesh& mesh, uint32_t f) {
    const auto idx = mesh.face(f);
    Poly3 pts;
    for (uint32_t i : idx) pts.push_back(exact(mesh.vertex(i)));
    removeDegenerateVertices(pts);
    std::vector<Poly3> pieces;
    if (pts.size() < 3) return pieces;
    bool planar = true;
    for (size_t i = 3; i < pts.size() && planar; ++i)
        planar = CGAL::orientation(pts[0], pts[1], pts[2], pts[i]) == CGAL::COPLANAR;
    if (planar) {
        pieces.push_back(std::move(pts));
    } else {
        for (size_t i = 1; i + 1 < pts.size(); ++i) {
            Poly3 t{pts[0], pts[i], pts[i + 1]};
            if (!CGAL::collinear(t[0], t[1], t[2])) pieces.push_back(std::move(t));
        }
    }
    return pieces;
}

Vec3 newellNormal(const vis::PolygonMesh& mesh, uint32_t f) { return mesh.faceAreaNormal(f); }

}  // namespace

ReferenceResult exactReference(const vis::PolygonMesh& mesh, uint32_t receiver, uint32_t light,
                               vis::Vec3 xd) {
    ReferenceResult r;
    r.lightArea = mesh.faceArea(light);

    const auto lidx = mesh.face(light);
    const auto bidx = mesh.face(receiver);
    Poly3 L;
    for (uint32_t i : lidx) L.push_back(exact(mesh.vertex(i)));
    removeDegenerateVertices(L);
    if (L.size() < 3 || bidx.size() < 3) return r;

    Frame f;
    f.x = exact(xd);
    f.l0 = L[0];
    f.nL = CGAL::cross_product(L[1] - L[0], L[2] - L[0]);
    // x strictly in front of L, or nothing is visible
    if (CGAL::sign(f.nL * (f.x - f.l0)) != CGAL::POSITIVE) return r;
    {
        int k = 0;
        FT best = CGAL::abs(f.nL.x());
        for (int i = 1; i < 3; ++i)
            if (CGAL::abs(f.nL.cartesian(i)) > best) best = CGAL::abs(f.nL.cartesian(i)), k = i;
        f.drop = k;
        f.u = (k + 1) % 3;
        f.v = (k + 2) % 3;
        f.orient2d = CGAL::sign(f.nL.cartesian(k)) == CGAL::POSITIVE ? 1 : -1;
    }

    // L' = L clipped to B's front halfspace (exact plane through B's first three vertices)
    const Point3 b0 = exact(mesh.vertex(bidx[0])), b1 = exact(mesh.vertex(bidx[1])),
                 b2 = exact(mesh.vertex(bidx[2]));
    const HalfSpace frontB{CGAL::cross_product(b1 - b0, b2 - b0), b0};
    Poly3 Lc = clip(L, frontB);
    removeDegenerateVertices(Lc);

    std::vector<Point2> l2;
    for (const Point3& p : L) l2.push_back(f.to2d(p));
    const FT lightArea2d = CGAL::abs(Polygon2(l2.begin(), l2.end()).area());
    if (Lc.size() < 3 || CGAL::sign(lightArea2d) == CGAL::ZERO) return r;

    Polygon2 lc2;
    {
        std::vector<Point2> pts;
        for (const Point3& p : Lc) pts.push_back(f.to2d(p));
        if (!makeCcw(pts, lc2)) return r;
    }
    const Vec3 nB = newellNormal(mesh, receiver);
    {
        std::vector<PolygonWithHoles2> full{PolygonWithHoles2(lc2)};
        r.unoccludedFormFactor = formFactor(full, f, xd, nB);
    }

    // the pyramid conv(x, L'): side planes through x and each edge of L', and L's plane
    std::vector<HalfSpace> pyramid;
    {
        Vector3 c = CGAL::NULL_VECTOR;
        for (const Point3& p : Lc) c = c + (p - CGAL::ORIGIN);
        const Point3 inside = CGAL::ORIGIN + c / FT(static_cast<int>(Lc.size()));
        pyramid.push_back(HalfSpace{f.nL, f.l0});  // nL . (p - l0) >= 0: x's side of L
        // (x is strictly in front of L, so points between x and L are in the halfspace)
        for (size_t i = 0; i < Lc.size(); ++i) {
            Vector3 n = CGAL::cross_product(Lc[i] - f.x, Lc[(i + 1) % Lc.size()] - f.x);
            if (CGAL::sign(n * (inside - f.x)) == CGAL::NEGATIVE) n = -n;
            pyramid.push_back(HalfSpace{n, f.x});
        }
    }
    Box cone;
    cone.add(xd);
    for (uint32_t i : lidx) cone.add(mesh.vertex(i));

    std::vector<Polygon2> shadows;
    for (uint32_t o = 0; o < mesh.faces.size(); ++o) {
        if (o == receiver || o == light || mesh.faces[o].size() < 3) continue;
        Box ob;
        for (uint32_t i : mesh.face(o)) ob.add(mesh.vertex(i));
        if (!ob.meets(cone)) continue;
        for (Poly3& piece : exactPieces(mesh, o)) {
            // in a plane through x: projects to a segment (measure zero)
            if (CGAL::orientation(piece[0], piece[1], piece[2], f.x) == CGAL::COPLANAR) continue;
            // in L's plane: touches the segments (x, y) only at their excluded endpoint y
            bool inLightPlane = true;
            for (const Point3& p : piece)
                inLightPlane = inLightPlane && CGAL::sign(f.nL * (p - f.l0)) == CGAL::ZERO;
            if (inLightPlane) continue;
            // Only the part in front of B's plane occludes (x may lie a rounding behind it: the
            // segment's part between x and B's plane is not between B and L); a piece with no
            // point strictly in front of it (one in B's plane) occludes nothing.
            Poly3 c = clip(piece, frontB);
            bool strictlyFront = false;
            for (const Point3& p : c)
                strictlyFront = strictlyFront || CGAL::sign(frontB.value(p)) == CGAL::POSITIVE;
            if (!strictlyFront) continue;
            for (const HalfSpace& h : pyramid) {
                c = clip(c, h);
                if (c.size() < 3) break;
            }
            removeDegenerateVertices(c);
            if (c.size() < 3) continue;
            // guard: every point of the clipped piece must be strictly on L's side of the plane
            // through x parallel to L (it is: it lies in the pyramid and does not contain x)
            bool bounded = true;
            for (const Point3& p : c)
                bounded = bounded && CGAL::sign(f.nL * (p - f.x)) == CGAL::NEGATIVE;
            if (!bounded) continue;
            std::vector<Point2> pts;
            pts.reserve(c.size());
            for (const Point3& p : c) pts.push_back(f.project2d(p));
            Polygon2 shadow;
            if (makeCcw(std::move(pts), shadow)) shadows.push_back(std::move(shadow));
        }
    }

    PolygonSet2 visible(lc2);
    if (!shadows.empty()) {
        PolygonSet2 occluded;
        occluded.join(shadows.begin(), shadows.end());
        visible.difference(occluded);
    }
    std::vector<PolygonWithHoles2> region;
    visible.polygons_with_holes(std::back_inserter(region));

    const FT fraction = signedArea(region) / lightArea2d;
    r.fraction = nearestDouble(fraction);
    r.visibleArea = r.fraction * r.lightArea;
    r.formFactor = formFactor(region, f, xd, nB);
    for (const PolygonWithHoles2& pwh : region)
        r.boundaryLoops += 1 + static_cast<int>(std::distance(pwh.holes_begin(), pwh.holes_end()));
    return r;
}

namespace {

using Rng = SplitMix64;  // engine/scene/random.h

struct Occluder {
    std::vector<Vec3> v;
    Vec3 n;
    Box box;
};

// Does the open segment (x, y) cross the convex polygon? (Touching contacts, which have measure
// zero over the samples, may go either way.)
bool crosses(const Occluder& o, const Vec3& x, const Vec3& y) {
    const double d0 = vis::dot(o.n, x - o.v[0]);
    const double d1 = vis::dot(o.n, y - o.v[0]);
    if (!((d0 > 0 && d1 < 0) || (d0 < 0 && d1 > 0))) return false;
    const Vec3 q = x + (y - x) * (d0 / (d0 - d1));
    const size_t m = o.v.size();
    for (size_t i = 0; i < m; ++i) {
        const Vec3& a = o.v[i];
        const Vec3& b = o.v[(i + 1) % m];
        if (vis::dot(vis::cross(b - a, q - a), o.n) < 0) return false;
    }
    return true;
}

}  // namespace

double monteCarloFraction(const vis::PolygonMesh& mesh, uint32_t receiver, uint32_t light,
                          vis::Vec3 x, int samples, uint64_t seed, double* stddev) {
    if (stddev) *stddev = 0;
    const auto lidx = mesh.face(light);
    std::vector<Vec3> L;
    for (uint32_t i : lidx) L.push_back(mesh.vertex(i));
    const Vec3 nL = mesh.faceAreaNormal(light);
    const Vec3 nB = mesh.faceAreaNormal(receiver);
    if (samples <= 0 || L.size() < 3 || !(vis::dot(nL, x - L[0]) > 0)) return 0;

    // fan triangulation with cumulative areas
    std::vector<double> cdf;
    double total = 0;
    for (size_t i = 1; i + 1 < L.size(); ++i) {
        total += 0.5 * vis::length(vis::cross(L[i] - L[0], L[i + 1] - L[0]));
        cdf.push_back(total);
    }
    if (!(total > 0)) return 0;

    Box seg;
    seg.add(x);
    for (const Vec3& p : L) seg.add(p);
    std::vector<Occluder> occ;
    for (uint32_t o = 0; o < mesh.faces.size(); ++o) {
        if (o == receiver || o == light || mesh.faces[o].size() < 3) continue;
        Occluder oc;
        for (uint32_t i : mesh.face(o)) {
            oc.v.push_back(mesh.vertex(i));
            oc.box.add(mesh.vertex(i));
        }
        oc.n = mesh.faceAreaNormal(o);
        if (oc.box.meets(seg)) occ.push_back(std::move(oc));
    }

    Rng rng{seed};
    int64_t hits = 0;
    for (int s = 0; s < samples; ++s) {
        const double pick = rng.uniform() * total;
        const size_t t = static_cast<size_t>(
            std::min<std::ptrdiff_t>(std::upper_bound(cdf.begin(), cdf.end(), pick) - cdf.begin(),
                                     static_cast<std::ptrdiff_t>(cdf.size()) - 1));
        double r1 = rng.uniform(), r2 = rng.uniform();
        if (r1 + r2 > 1) r1 = 1 - r1, r2 = 1 - r2;
        const Vec3 y = L[0] + (L[t + 1] - L[0]) * r1 + (L[t + 2] - L[0]) * r2;
        if (!(vis::dot(nB, y - x) > 0)) continue;
        bool blocked = false;
        for (const Occluder& o : occ)
            if (crosses(o, x, y)) {
                blocked = true;
                break;
            }
        if (!blocked) ++hits;
    }
    const double p = static_cast<double>(hits) / samples;
    if (stddev) *stddev = std::sqrt(p * (1 - p) / samples);
    return p;
}

}  // namespace penumbra::test
