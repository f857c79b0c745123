#include "visibility/fp_query/line_tests.h"

#include <cmath>

#include "visibility/fp_query/query_parts.h"

namespace penumbra::vis {

std::optional<int> LineTests::countLine(const Vec3& y) {
    // Every occluder the line crosses, through its interior (a line that touches one's boundary
    // is where c jumps: no count).
    if (q_.silhouettes.active()) return q_.silhouettes.countLine(y);
    if (q_.edges.active()) return q_.edges.countLine(y);
    QueryRun& r = q_.run;
    HitCount c;
    auto add = [&](LineHit h) { return c.add(h, r.budget); };
    ActiveOccluders& active = q_.active;
    if (!active.boxesBuilt()) {  // (as lineBlocked: a scan first, the hierarchy once it pays)
        scanned_ += active.size();
        for (size_t j = 0; j < active.size(); ++j)
            if (add(hitKind(j, y))) return std::nullopt;
    } else {
        setLinePlanes(y);
        onLine_.clear();
        if (!r.budget.spend(active.boxes().notOutside(linePlanes_, onLine_))) return std::nullopt;
        for (uint32_t j : onLine_)
            if (add(hitKind(j, y))) return std::nullopt;
    }
    if (q_.clusters.active()) {  // and the used groups' faces
        setLinePlanes(y);
        q_.clusters.facesOnLine(linePlanes_, r.budget, [&](uint32_t face, int side) {
            return add(faceHitKind(face, side, y));
        });
        if (c.touch || r.budget.reached()) return std::nullopt;
    }
    return c.count;
}

bool LineTests::lineBlocked(const Vec3& y) {
    if (q_.silhouettes.active()) return q_.silhouettes.lineBlocked(y);
    if (q_.edges.active()) return q_.edges.lineBlocked(y);
    // The line through y against the occluders (closed), the last one that hid a cell first.
    QueryRun& r = q_.run;
    ActiveOccluders& active = q_.active;
    const size_t n = active.size();
    if (n == 0) return q_.clusters.active() && q_.clusters.lineBlocked(y);
    if (hits(lastHit_ % n, y)) return true;
    if (!active.boxesBuilt() && scanned_ >= kScanBeforeBoxes * n) active.boxes();
    if (active.boxesBuilt()) {
        setLinePlanes(y);
        onLine_.clear();
        if (!r.budget.spend(active.boxes().notOutside(linePlanes_, onLine_))) return false;
        for (uint32_t j : onLine_) {
            if (hits(j, y)) return true;
            if (r.budget.reached()) return false;
        }
    } else {
        for (size_t t = 1; t < n; ++t) {
            if (hits((lastHit_ + t) % n, y)) return true;
            if (r.budget.reached()) return false;
        }
        scanned_ += n;
    }
    return q_.clusters.active() && q_.clusters.lineBlocked(y);
}

LineHit LineTests::hitKind(size_t j, const Vec3& y) {
    const ActiveOccluders& active = q_.active;
    WorkBudget& budget = q_.run.budget;
    const ActiveOccluders::Occluder& o = active[j];
    const Sign unblocked = o.blocked == Sign::Positive ? Sign::Negative : Sign::Positive;
    bool touch = false;
    for (uint32_t e = 0; e < o.planeCount; ++e) {
        if (!budget.spend()) return LineHit::Miss;
        const Sign s = exactSign(active.plane(o.firstPlane + e), y);
        if (s == unblocked) return LineHit::Miss;
        touch = touch || s == Sign::Zero;
    }
    for (uint32_t e = 0; e < o.pencilCount; ++e) {
        if (!budget.spend()) return LineHit::Miss;
        const Sign s = exactSign(active.pencil(o.firstPencil + e), y);
        if (s == unblocked) return LineHit::Miss;
        touch = touch || s == Sign::Zero;
    }
    lastHit_ = static_cast<uint32_t>(j);
    return touch ? LineHit::Touch : LineHit::Through;
}

LineHit LineTests::faceHitKind(uint32_t face, int side, const Vec3& y) {
    // x in front of the face (side +1): the lines through it are on the negative side of the
    // planes through x and its edges (ActiveOccluders::activate), so a positive sign misses.
    QueryRun& r = q_.run;
    const auto& ids = r.mesh().faces[face];
    const std::vector<Vec3>& v = r.mesh().vertices;
    const Sign unblocked = side > 0 ? Sign::Positive : Sign::Negative;
    bool touch = false;
    for (size_t i = 0; i < ids.size(); ++i) {
        if (!r.budget.spend()) return LineHit::Miss;
        const PlaneOrient plane(r.x, v[ids[i]], v[ids[(i + 1) % ids.size()]]);
        const Sign sign = exactSign(plane, y);
        if (sign == unblocked) return LineHit::Miss;
        touch = touch || sign == Sign::Zero;
    }
    return touch ? LineHit::Touch : LineHit::Through;
}

void LineTests::setLinePlanes(const Vec3& y) {
    // A point of an occluder on the line lies in every plane through x and y: its box is on no
    // such plane's strictly negative side, whichever way it is turned. Two planes at right angles
    // about the line keep only boxes near it (two of nearly one plane would keep a whole slab):
    // through a third point p off the line, any double (the cull is rigorous for the plane
    // through x, y and p, which holds the line; planes made degenerate by rounding cull nothing:
    // still sound).
    const Vec3& x = q_.run.x;
    const Vec3 d = y - x;
    const double ax = std::abs(d.x), ay = std::abs(d.y), az = std::abs(d.z);
    const Vec3 axis = ax <= ay && ax <= az ? Vec3{1, 0, 0}
                      : ay <= az           ? Vec3{0, 1, 0}
                                           : Vec3{0, 0, 1};
    const Vec3 u = cross(d, axis), v = cross(d, u);
    const double lu = length(u), lv = length(v), ld = length(d);
    const Vec3 p1 = lu > 0 ? y + u * (ld / lu) : q_.run.light()[0];
    const Vec3 p2 = lv > 0 ? y + v * (ld / lv) : q_.run.light()[1];
    linePlanes_.clear();
    linePlanes_.emplace_back(x, y, p1);
    linePlanes_.emplace_back(x, p1, y);
    linePlanes_.emplace_back(x, y, p2);
    linePlanes_.emplace_back(x, p2, y);
}

}  // namespace penumbra::vis
