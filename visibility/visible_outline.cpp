#include "visibility/visible_outline.h"

#include <algorithm>
#include <cmath>
#include <cstdint>

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

// The fragments' vertices welded, their edges split and summed, the rest chained: flat arrays
// and sorts (no hash tables), since the viewer builds an outline on every click.
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

    // Each input vertex gets the id of the first vertex (in x order) within tol_ of it in both
    // coordinates, or its own; each fragment becomes a cycle of ids (cycles_ from cycleStart_),
    // without repeats, dropped below three.
    void weld() {
        struct In {
            P2 p;
            Vec3 v;
        };
        std::vector<In> in;
        for (const auto& f : fragments_)
            for (const Vec3& v : f) in.push_back({project(v), v});
        std::vector<uint32_t> order(in.size());
        for (uint32_t i = 0; i < order.size(); ++i) order[i] = i;
        std::sort(order.begin(), order.end(), [&](uint32_t a, uint32_t b) {
            return in[a].p.x < in[b].p.x || (in[a].p.x == in[b].p.x && a < b);
        });
        std::vector<uint32_t> id(in.size());
        for (size_t k = 0; k < order.size(); ++k) {
            const In& here = in[order[k]];
            uint32_t found = UINT32_MAX;
            for (size_t j = k; j-- > 0 && here.p.x - in[order[j]].p.x <= tol_;)
                if (std::fabs(here.p.y - in[order[j]].p.y) <= tol_) found = id[order[j]];
            if (found == UINT32_MAX) {
                found = static_cast<uint32_t>(points_.size());
                points_.push_back(here.p);
                vertices_.push_back(here.v);
            }
            id[order[k]] = found;
        }
        size_t next = 0;
        for (const auto& f : fragments_) {
            const size_t begin = cycles_.size();
            for (size_t i = 0; i < f.size(); ++i, ++next)
                if (cycles_.size() == begin || cycles_.back() != id[next])
                    cycles_.push_back(id[next]);
            while (cycles_.size() > begin + 1 && cycles_[begin] == cycles_.back())
                cycles_.pop_back();
            if (cycles_.size() - begin < 3)
                cycles_.resize(begin);
            else
                cycleStart_.push_back(begin);
        }
        cycleStart_.push_back(cycles_.size());
        // The welded points in x order, for the T-junction sweep.
        byX_.resize(points_.size());
        for (uint32_t i = 0; i < byX_.size(); ++i) byX_[i] = i;
        std::sort(byX_.begin(), byX_.end(),
                  [&](uint32_t a, uint32_t b) { return points_[a].x < points_[b].x; });
    }

    // Every fragment edge, split where another vertex lies within tol_ of its inside, then
    // summed per undirected edge (+1 from the lower id to the higher, -1 the other way, sorted
    // by the pair): edges_ holds those whose sum is not 0, as often as it says, directed.
    void splitAndCancel() {
        std::vector<std::pair<uint64_t, int>> uses;
        std::vector<std::pair<double, uint32_t>> on;
        auto add = [&](uint32_t a, uint32_t b) {
            if (a == b) return;
            uses.emplace_back((static_cast<uint64_t>(std::min(a, b)) << 32) | std::max(a, b),
                              a < b ? 1 : -1);
        };
        for (size_t c = 0; c + 1 < cycleStart_.size(); ++c) {
            const size_t begin = cycleStart_[c], n = cycleStart_[c + 1] - begin;
            for (size_t i = 0; i < n; ++i) {
                const uint32_t a = cycles_[begin + i], b = cycles_[begin + (i + 1) % n];
                const P2 pa = points_[a], pb = points_[b], d = pb - pa;
                const double len = length2(d);
                on.clear();
                const double x0 = std::min(pa.x, pb.x) - tol_, x1 = std::max(pa.x, pb.x) + tol_;
                const double y0 = std::min(pa.y, pb.y) - tol_, y1 = std::max(pa.y, pb.y) + tol_;
                auto it = std::lower_bound(byX_.begin(), byX_.end(), x0,
                                           [&](uint32_t k, double x) { return points_[k].x < x; });
                for (; it != byX_.end() && points_[*it].x <= x1; ++it) {
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
        std::sort(uses.begin(), uses.end());
        for (size_t i = 0; i < uses.size();) {
            const uint64_t key = uses[i].first;
            int net = 0;
            for (; i < uses.size() && uses[i].first == key; ++i) net += uses[i].second;
            const uint32_t lo = static_cast<uint32_t>(key >> 32), hi = key & 0xffffffffu;
            for (int k = 0; k < std::abs(net); ++k)
                edges_.emplace_back(net > 0 ? lo : hi, net > 0 ? hi : lo);
        }
    }

    // The edges left, chained into loops. At a vertex with several ways on, the one that turns
    // farthest left of the way in (the region on the left of the way the fragments turn).
    VisibleOutline chain() {
        // Per vertex, its outgoing edges (counting sort by the start).
        std::vector<uint32_t> first(points_.size() + 1, 0), to(edges_.size());
        for (const auto& [a, b] : edges_) ++first[a + 1];
        for (size_t v = 0; v < points_.size(); ++v) first[v + 1] += first[v];
        std::vector<uint32_t> fill(first.begin(), first.end() - 1);
        for (const auto& [a, b] : edges_) to[fill[a]++] = b;
        std::vector<uint8_t> used(edges_.size(), 0);
        std::vector<uint32_t> left(points_.size());  // outgoing edges not used yet
        for (size_t v = 0; v < points_.size(); ++v) left[v] = first[v + 1] - first[v];
        // The way on from cur, coming from prev: the only one left, or the one that turns
        // farthest left.
        auto take = [&](uint32_t prev, uint32_t cur) {
            uint32_t best = UINT32_MAX;
            double bestAngle = -INFINITY;
            const P2 in = points_[cur] - points_[prev];
            for (uint32_t k = first[cur]; k < first[cur + 1]; ++k) {
                if (used[k]) continue;
                if (left[cur] == 1) {
                    best = k;
                    break;
                }
                const P2 o = points_[to[k]] - points_[cur];
                const double angle = std::atan2(turn_ * cross2(in, o), dot2(in, o));
                if (angle > bestAngle) {
                    bestAngle = angle;
                    best = k;
                }
            }
            if (best != UINT32_MAX) {
                used[best] = 1;
                --left[cur];
            }
            return best;
        };
        VisibleOutline outline;
        std::vector<uint32_t> loop;
        for (uint32_t start = 0; start < points_.size(); ++start) {
            while (left[start] > 0) {
                uint32_t k = first[start];
                while (used[k]) ++k;
                used[k] = 1;
                --left[start];
                loop.assign(1, start);
                uint32_t prev = start, cur = to[k];
                while (cur != start) {
                    loop.push_back(cur);
                    const uint32_t next = take(prev, cur);
                    if (next == UINT32_MAX) break;  // (not closed: only from inconsistent input)
                    prev = cur;
                    cur = to[next];
                }
                mergeStraightRuns(loop);
                if (loop.size() < 3) continue;
                std::vector<Vec3>& points = outline.loops.emplace_back();
                for (uint32_t v : loop) points.push_back(vertices_[v]);
            }
        }
        return outline;
    }

    // Whether v lies within tol_ of the segment a-b, inside it.
    bool onSegment(uint32_t a, uint32_t v, uint32_t b) const {
        const P2 d = points_[b] - points_[a], q = points_[v] - points_[a];
        const double len = length2(d);
        return len > 0 && std::fabs(cross2(d, q)) / len <= tol_ && dot2(q, d) > 0 &&
               dot2(points_[b] - points_[v], d) > 0;
    }

    // Drops each vertex that lies within tol_ of the segment between its neighbours, inside it
    // (one pass with a stack, then the seam where the loop closes).
    void mergeStraightRuns(std::vector<uint32_t>& loop) const {
        std::vector<uint32_t>& out = scratch_;
        out.clear();
        for (uint32_t v : loop) {
            while (out.size() >= 2 && onSegment(out[out.size() - 2], out.back(), v)) out.pop_back();
            out.push_back(v);
        }
        size_t head = 0;
        for (bool changed = true; changed && out.size() - head >= 3;) {
            changed = false;
            const size_t n = out.size();
            if (onSegment(out[n - 2], out[n - 1], out[head])) {
                out.pop_back();
                changed = true;
            } else if (onSegment(out[n - 1], out[head], out[head + 1])) {
                ++head;
                changed = true;
            }
        }
        loop.assign(out.begin() + static_cast<std::ptrdiff_t>(head), out.end());
    }

    std::span<const std::vector<Vec3>> fragments_;
    int drop_ = 2;
    double turn_ = 1, tol_ = 0;
    std::vector<P2> points_;      // per welded vertex, in the 2D frame
    std::vector<Vec3> vertices_;  // and its first fragment vertex in x order
    std::vector<uint32_t> byX_;   // the welded vertices in x order
    std::vector<uint32_t> cycles_;
    std::vector<size_t> cycleStart_;  // per fragment kept, where its cycle starts in cycles_
    std::vector<std::pair<uint32_t, uint32_t>> edges_;
    mutable std::vector<uint32_t> scratch_;
};

}  // namespace
}  // namespace outline_detail

VisibleOutline visibleOutline(std::span<const std::vector<Vec3>> fragments) {
    return outline_detail::Outliner(fragments).run();
}

}  // namespace penumbra::vis
