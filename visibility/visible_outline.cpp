#include "visibility/visible_outline.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <unordered_map>

namespace penumbra::vis {

size_t VisibleOutline::edges() const {
    size_t n = 0;
    for (const auto& loop : loops) n += loop.size();
    return n;
}

double VisibleOutline::area() const {
    if (loops.empty()) return 0;
    const Vec3 o = loops[0][0];  // (relative to one vertex: better conditioned far from 0)
    Vec3 n{};
    for (const auto& loop : loops)
        for (size_t i = 0; i < loop.size(); ++i)
            n += cross(loop[i] - o, loop[i + 1 == loop.size() ? 0 : i + 1] - o);
    return 0.5 * length(n);
}

// (Its own namespace: in a unity build it shares a file with others that have a P2.)
namespace outline_detail {
namespace {

struct P2 {
    double x = 0, y = 0;
};
P2 operator-(const P2& a, const P2& b) { return {a.x - b.x, a.y - b.y}; }
double cross2(const P2& a, const P2& b) { return a.x * b.y - a.y * b.x; }
double dot2(const P2& a, const P2& b) { return a.x * b.x + a.y * b.y; }
double length2(const P2& a) { return std::hypot(a.x, a.y); }

// The fragments' vertices welded (weld()), and their edges.
class Outliner {
  public:
    explicit Outliner(std::span<const std::vector<Vec3>> fragments) : fragments_(fragments) {}

    VisibleOutline run() {
        if (!frame()) return {};
        weld();
        splitAndCancel();
        return chain();
    }

  private:
    // The plane's 2D frame: the axes left when the dominant one of the fragments' summed normal
    // is dropped, in cyclic order (a counter-clockwise turn about the normal stays one when that
    // component is positive: turn_ = +1), and the weld distance.
    bool frame() {
        Vec3 normal{};
        for (const auto& f : fragments_)
            for (size_t i = 1; i + 1 < f.size(); ++i) normal += cross(f[i] - f[0], f[i + 1] - f[0]);
        const double ax = std::fabs(normal.x), ay = std::fabs(normal.y), az = std::fabs(normal.z);
        drop_ = ax >= ay && ax >= az ? 0 : (ay >= az ? 1 : 2);
        turn_ = normal[drop_] >= 0 ? 1.0 : -1.0;
        double lo[2] = {INFINITY, INFINITY}, hi[2] = {-INFINITY, -INFINITY};
        for (const auto& f : fragments_)
            for (const Vec3& v : f) {
                const P2 p = project(v);
                lo[0] = std::min(lo[0], p.x), hi[0] = std::max(hi[0], p.x);
                lo[1] = std::min(lo[1], p.y), hi[1] = std::max(hi[1], p.y);
            }
        const double extent = std::max(hi[0] - lo[0], hi[1] - lo[1]);
        if (!(extent > 0) || !std::isfinite(extent)) return false;
        const double far =
            std::max({std::fabs(lo[0]), std::fabs(hi[0]), std::fabs(lo[1]), std::fabs(hi[1])});
        tol_ = extent * 0x1p-40 + far * 0x1p-46;
        origin_ = {lo[0], lo[1]};
        return true;
    }

    P2 project(const Vec3& v) const {
        switch (drop_) {
            case 0:
                return {v.y, v.z};
            case 1:
                return {v.z, v.x};
            default:
                return {v.x, v.y};
        }
    }

    // Each fragment as a cycle of welded vertex ids: a vertex within tol_ (in both coordinates)
    // of an earlier one is that one (a grid of cells tol_ wide, the 3 x 3 around it searched).
    void weld() {
        std::unordered_map<uint64_t, uint32_t> head;
        std::vector<uint32_t> next;
        constexpr uint32_t kNone = UINT32_MAX;
        // (Distinct cells may share a key: a found vertex is taken only within tol_.)
        auto cellKey = [](int64_t i, int64_t j) {
            return static_cast<uint64_t>(i) * 0x9E3779B97F4A7C15ull ^ static_cast<uint64_t>(j);
        };
        for (const auto& f : fragments_) {
            std::vector<uint32_t> ids;
            for (const Vec3& v : f) {
                const P2 p = project(v);
                const int64_t ci = static_cast<int64_t>(std::floor((p.x - origin_.x) / tol_));
                const int64_t cj = static_cast<int64_t>(std::floor((p.y - origin_.y) / tol_));
                uint32_t found = kNone;
                for (int64_t di = -1; di <= 1 && found == kNone; ++di)
                    for (int64_t dj = -1; dj <= 1 && found == kNone; ++dj) {
                        const auto it = head.find(cellKey(ci + di, cj + dj));
                        for (uint32_t k = it == head.end() ? kNone : it->second; k != kNone;
                             k = next[k])
                            if (std::fabs(points_[k].x - p.x) <= tol_ &&
                                std::fabs(points_[k].y - p.y) <= tol_) {
                                found = k;
                                break;
                            }
                    }
                if (found == kNone) {
                    found = static_cast<uint32_t>(points_.size());
                    points_.push_back(p);
                    vertices_.push_back(v);
                    auto [it, inserted] = head.try_emplace(cellKey(ci, cj), found);
                    next.push_back(inserted ? kNone : it->second);
                    if (!inserted) it->second = found;
                }
                if (ids.empty() || ids.back() != found) ids.push_back(found);
            }
            while (ids.size() > 1 && ids.front() == ids.back()) ids.pop_back();
            if (ids.size() >= 3) cycles_.push_back(std::move(ids));
        }
    }

    // Every fragment edge, split where another vertex lies within tol_ of its inside (a sweep by
    // x), summed per undirected edge: +1 from the lower id to the higher, -1 the other way.
    void splitAndCancel() {
        std::vector<uint32_t> byX(points_.size());
        for (uint32_t i = 0; i < byX.size(); ++i) byX[i] = i;
        std::sort(byX.begin(), byX.end(),
                  [&](uint32_t a, uint32_t b) { return points_[a].x < points_[b].x; });
        std::vector<std::pair<double, uint32_t>> on;
        auto add = [&](uint32_t a, uint32_t b) {
            if (a == b) return;
            const uint64_t key = (static_cast<uint64_t>(std::min(a, b)) << 32) | std::max(a, b);
            net_[key] += a < b ? 1 : -1;
        };
        for (const auto& ids : cycles_) {
            for (size_t i = 0; i < ids.size(); ++i) {
                const uint32_t a = ids[i], b = ids[(i + 1) % ids.size()];
                const P2 pa = points_[a], pb = points_[b], d = pb - pa;
                const double len = length2(d);
                on.clear();
                const double x0 = std::min(pa.x, pb.x) - tol_, x1 = std::max(pa.x, pb.x) + tol_;
                const double y0 = std::min(pa.y, pb.y) - tol_, y1 = std::max(pa.y, pb.y) + tol_;
                auto it = std::lower_bound(byX.begin(), byX.end(), x0,
                                           [&](uint32_t k, double x) { return points_[k].x < x; });
                for (; it != byX.end() && points_[*it].x <= x1; ++it) {
                    const uint32_t w = *it;
                    if (w == a || w == b || points_[w].y < y0 || points_[w].y > y1) continue;
                    const P2 q = points_[w] - pa;
                    const double along = dot2(q, d) / len;
                    if (along <= tol_ || along >= len - tol_) continue;
                    if (std::fabs(cross2(d, q)) / len > tol_) continue;
                    on.emplace_back(along, w);
                }
                std::sort(on.begin(), on.end());
                uint32_t from = a;
                for (const auto& [along, w] : on) {
                    add(from, w);
                    from = w;
                }
                add(from, b);
            }
        }
    }

    // The edges left, chained into loops. At a vertex with several ways on, the one that turns
    // farthest left of the way in (the region on the left of the way the fragments turn).
    VisibleOutline chain() {
        std::vector<std::vector<uint32_t>> out(points_.size());
        for (const auto& [key, net] : net_) {
            const uint32_t lo = static_cast<uint32_t>(key >> 32), hi = key & 0xffffffffu;
            for (int k = 0; k < std::abs(net); ++k) {
                if (net > 0)
                    out[lo].push_back(hi);
                else
                    out[hi].push_back(lo);
            }
        }
        VisibleOutline outline;
        for (uint32_t start = 0; start < out.size(); ++start) {
            while (!out[start].empty()) {
                std::vector<uint32_t> loop{start};
                uint32_t prev = start, cur = out[start].back();
                out[start].pop_back();
                while (cur != start) {
                    loop.push_back(cur);
                    std::vector<uint32_t>& ways = out[cur];
                    if (ways.empty()) break;  // (not closed: only from inconsistent input)
                    const P2 in = points_[cur] - points_[prev];
                    size_t best = 0;
                    double bestAngle = -INFINITY;
                    for (size_t k = 0; k < ways.size(); ++k) {
                        const P2 o = points_[ways[k]] - points_[cur];
                        const double angle = std::atan2(turn_ * cross2(in, o), dot2(in, o));
                        if (angle > bestAngle) bestAngle = angle, best = k;
                    }
                    prev = cur;
                    cur = ways[best];
                    ways.erase(ways.begin() + static_cast<std::ptrdiff_t>(best));
                }
                mergeStraightRuns(loop);
                if (loop.size() < 3) continue;
                std::vector<Vec3>& points = outline.loops.emplace_back();
                for (uint32_t id : loop) points.push_back(vertices_[id]);
            }
        }
        return outline;
    }

    // Drops each vertex that lies within tol_ of the segment between its neighbours, inside it.
    void mergeStraightRuns(std::vector<uint32_t>& loop) const {
        bool changed = true;
        while (changed && loop.size() >= 3) {
            changed = false;
            for (size_t i = 0; i < loop.size() && loop.size() >= 3; ++i) {
                const size_t n = loop.size();
                const P2 a = points_[loop[(i + n - 1) % n]], v = points_[loop[i]],
                         b = points_[loop[(i + 1) % n]];
                const P2 d = b - a;
                const double len = length2(d);
                if (len == 0) continue;
                if (std::fabs(cross2(d, v - a)) / len > tol_ || dot2(v - a, d) <= 0 ||
                    dot2(b - v, d) <= 0)
                    continue;
                loop.erase(loop.begin() + static_cast<std::ptrdiff_t>(i));
                changed = true;
            }
        }
    }

    std::span<const std::vector<Vec3>> fragments_;
    int drop_ = 2;
    double turn_ = 1, tol_ = 0;
    P2 origin_;
    std::vector<P2> points_;      // per welded vertex, in the 2D frame
    std::vector<Vec3> vertices_;  // and its first fragment vertex
    std::vector<std::vector<uint32_t>> cycles_;
    std::unordered_map<uint64_t, int> net_;
};

}  // namespace
}  // namespace outline_detail

VisibleOutline visibleOutline(std::span<const std::vector<Vec3>> fragments) {
    return outline_detail::Outliner(fragments).run();
}

}  // namespace penumbra::vis
