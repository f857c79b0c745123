#include "engine/scene/polygon_triangulation.h"

#include <algorithm>
#include <cmath>

namespace penumbra {
namespace {

using vis::orient2d;
using vis::Point2;
using vis::project;

bool lexLess(const vis::Vec3& a, const vis::Vec3& b) {
    if (a.x != b.x) return a.x < b.x;
    if (a.y != b.y) return a.y < b.y;
    return a.z < b.z;
}

// c on the closed segment [a, b], given orient2d(a, b, c) == 0 (exact: comparisons only).
bool withinSegment(const Point2& a, const Point2& b, const Point2& c) {
    return std::min(a.u, b.u) <= c.u && c.u <= std::max(a.u, b.u) && std::min(a.v, b.v) <= c.v &&
           c.v <= std::max(a.v, b.v);
}

}  // namespace

std::optional<std::string> PolygonTriangulation::run(std::span<const vis::Vec3> points) {
    points_ = points;
    triangles_.clear();
    ring_.clear();
    // Positions repeated one after the other (a zero-length edge) are taken once.
    for (uint32_t i = 0; i < points.size(); ++i)
        if (ring_.empty() || !(points[ring_.back()] == points[i])) ring_.push_back(i);
    while (ring_.size() > 1 && points[ring_.back()] == points[ring_.front()]) ring_.pop_back();
    const size_t n = ring_.size();
    if (n < 3) return "fewer than 3 distinct vertices";
    if (n > kMaxVertices)
        return "it has " + std::to_string(n) + " vertices, more than the " +
               std::to_string(kMaxVertices) + " a split takes (its cost grows as their square)";
    // The canonical start: the rotation whose sequence of positions is lexicographically least
    // (a position can occur several times in a weakly simple polygon; ties go on to the next).
    size_t start = 0;
    for (size_t s = 1; s < n; ++s) {
        for (size_t k = 0; k < n; ++k) {
            const vis::Vec3& a = points[ring_[(s + k) % n]];
            const vis::Vec3& b = points[ring_[(start + k) % n]];
            if (lexLess(a, b)) {
                start = s;
                break;
            }
            if (lexLess(b, a)) break;
        }
    }
    std::rotate(ring_.begin(), ring_.begin() + static_cast<std::ptrdiff_t>(start), ring_.end());
    // Newell's normal relative to the first vertex (approximate: it picks the projection).
    const vis::Vec3 o = points[ring_[0]];
    vis::Vec3 normal{};
    for (size_t i = 0; i < n; ++i)
        normal += vis::cross(points[ring_[i]] - o, points[ring_[(i + 1) % n]] - o);
    int order[3] = {0, 1, 2};
    std::stable_sort(order, order + 3,
                     [&](int a, int b) { return std::fabs(normal[a]) > std::fabs(normal[b]); });
    for (int d : order) {
        if (!(normal[d] != 0)) continue;
        const int u = (d + 1) % 3, v = (d + 2) % 3;
        if (!simpleIn(u, v)) continue;
        triangles_.clear();
        if (clipEars(normal[d] > 0 ? 1 : -1)) return std::nullopt;
    }
    triangles_.clear();
    return "self-intersecting: no coordinate projection of it is a simple polygon";
}

bool PolygonTriangulation::simpleIn(int u, int v) {
    const size_t n = ring_.size();
    q_.resize(n);
    for (size_t i = 0; i < n; ++i) q_[i] = project(points_[ring_[i]], u, v);
    // Two edges may share end points (positions), or be one segment walked both ways (a
    // bridge); any other contact (a crossing, a vertex inside another edge, an overlap) is not
    // simple. Adjacent edges must not fold back onto each other (a spike).
    auto meet = [&](const Point2& a, const Point2& b, const Point2& c, const Point2& d) {
        // Whether the closed segments [a, b] and [c, d] meet other than at shared end points.
        const int o1 = orient2d(a, b, c), o2 = orient2d(a, b, d);
        const int o3 = orient2d(c, d, a), o4 = orient2d(c, d, b);
        const bool sharedC = c == a || c == b, sharedD = d == a || d == b;
        if (o1 == 0 && o2 == 0) {                  // collinear: overlap beyond shared end points?
            if (sharedC && sharedD) return false;  // the same segment (a bridge)
            // An end point of one strictly inside the other, or a shared end with an overlap.
            auto inside = [&](const Point2& p, const Point2& s0, const Point2& s1) {
                return !(p == s0) && !(p == s1) && withinSegment(s0, s1, p);
            };
            if (inside(c, a, b) || inside(d, a, b) || inside(a, c, d) || inside(b, c, d))
                return true;
            return false;
        }
        if (sharedC || sharedD) {
            // Touching at a shared end point only, unless the other end lies on the first
            // segment (handled as collinear above when both are on its line).
            if (sharedC && o2 == 0 && withinSegment(a, b, d) && !(d == a || d == b)) return true;
            if (sharedD && o1 == 0 && withinSegment(a, b, c) && !(c == a || c == b)) return true;
            if (o3 == 0 && withinSegment(c, d, a) && !(a == c || a == d)) return true;
            if (o4 == 0 && withinSegment(c, d, b) && !(b == c || b == d)) return true;
            return false;
        }
        if (o1 == 0 && withinSegment(a, b, c)) return true;
        if (o2 == 0 && withinSegment(a, b, d)) return true;
        if (o3 == 0 && withinSegment(c, d, a)) return true;
        if (o4 == 0 && withinSegment(c, d, b)) return true;
        return o1 * o2 < 0 && o3 * o4 < 0;
    };
    for (size_t i = 0; i < n; ++i) {
        const Point2 &a = q_[i], &b = q_[(i + 1) % n], &c = q_[(i + 2) % n];
        if (a == b) return false;  // an edge seen end-on in this projection
        // A spike: b's neighbours on one side of it along one line.
        if (orient2d(a, b, c) == 0 && !withinSegment(a, c, b)) return false;
    }
    for (size_t i = 0; i < n; ++i)
        for (size_t j = i + 2; j < n; ++j) {
            if (i == 0 && j == n - 1) continue;  // adjacent through the closing edge
            if (meet(q_[i], q_[(i + 1) % n], q_[j], q_[(j + 1) % n])) return false;
        }
    return true;
}

bool PolygonTriangulation::clipEars(int sign) {
    const size_t n = ring_.size();
    prev_.resize(n);
    next_.resize(n);
    for (uint32_t i = 0; i < n; ++i) {
        prev_[i] = static_cast<uint32_t>((i + n - 1) % n);
        next_[i] = static_cast<uint32_t>((i + 1) % n);
    }
    // Whether a position occurs twice (a weakly simple polygon).
    bool repeats = false;
    {
        std::vector<Point2> sorted(q_.begin(), q_.end());
        std::sort(sorted.begin(), sorted.end(), [](const Point2& x, const Point2& y) {
            return x.u < y.u || (x.u == y.u && x.v < y.v);
        });
        repeats = std::adjacent_find(sorted.begin(), sorted.end()) != sorted.end();
    }
    size_t remaining = n;
    uint32_t b = 0;
    size_t sinceClip = 0;  // vertices looked at since the last ear
    auto isEar = [&](uint32_t ia, uint32_t ib, uint32_t ic) {
        const Point2 &a = q_[ia], &pb = q_[ib], &c = q_[ic];
        if (orient2d(a, pb, c) != sign) return false;
        // No other remaining vertex in the closed triangle (positions of a, b and c aside: a
        // weakly simple polygon visits them twice). In a simple polygon a vertex that turns the
        // polygon's way strictly cannot lie in an ear without a reflex or straight one there
        // too, so only those are tested; with a position visited twice (a bridge), every one.
        for (uint32_t p = next_[ic]; p != ia; p = next_[p]) {
            const Point2& r = q_[p];
            if (r == a || r == pb || r == c) continue;
            if (!repeats && orient2d(q_[prev_[p]], r, q_[next_[p]]) == sign) continue;
            if (orient2d(a, pb, r) * sign >= 0 && orient2d(pb, c, r) * sign >= 0 &&
                orient2d(c, a, r) * sign >= 0)
                return false;
        }
        return true;
    };
    while (remaining > 3) {
        const uint32_t a = prev_[b], c = next_[b];
        if (isEar(a, b, c)) {
            triangles_.push_back({ring_[a], ring_[b], ring_[c]});
        } else if (orient2d(q_[a], q_[b], q_[c]) != 0 || !withinSegment(q_[a], q_[c], q_[b])) {
            // Not an ear, and not a vertex on the segment between its neighbours.
            b = c;
            if (++sinceClip > remaining) {
                // No ear left: the rest is collinear (zero area) or the clipping is stuck.
                for (uint32_t p = next_[b]; p != b; p = next_[p])
                    if (orient2d(q_[prev_[p]], q_[p], q_[next_[p]]) != 0) return false;
                return true;
            }
            continue;
        }
        // Clipped: an ear, or a vertex between its neighbours on one line (zero area).
        next_[a] = c;
        prev_[c] = a;
        --remaining;
        sinceClip = 0;
        b = a;  // the neighbours' turns changed: look at them again
    }
    const uint32_t a = prev_[b], c = next_[b];
    if (orient2d(q_[a], q_[b], q_[c]) == sign) triangles_.push_back({ring_[a], ring_[b], ring_[c]});
    return !triangles_.empty();
}

}  // namespace penumbra
