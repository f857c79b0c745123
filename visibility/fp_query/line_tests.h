// A cell's line against the per-point occluders: whether the line from x through a point y
// crosses one (lineBlocked, a label), or how many it crosses (countLine, c(y) of the boundary
// chain). Exact signs at y, an input point or a certified cell point; closed (a line along an
// occluder's edge counts as crossing it).
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <vector>

#include "visibility/fp_query/work_budget.h"
#include "visibility/predicates.h"

namespace penumbra::vis {

struct QueryParts;

// How a line from x meets an occluder: not, through its interior, or touching its boundary (a
// closed hit with a zero sign).
enum class LineHit { Miss, Through, Touch };

// c(y) counted occluder by occluder: a line through one's interior adds one; one touching its
// boundary is where c jumps, and ends the count (no count).
struct HitCount {
    int count = 0;
    bool touch = false;
    // Whether the count is over (touched, or the work limit was reached).
    bool add(LineHit h, const WorkBudget& budget) {
        if (h == LineHit::Touch) touch = true;
        if (h == LineHit::Through) ++count;
        return touch || budget.reached();
    }
};

class LineTests {
  public:
    explicit LineTests(QueryParts& q) : q_(q) {}

    void reset() {
        lastHit_ = 0;
        scanned_ = 0;
    }
    // Whether the line through y crosses one of the occluders (a cell's label).
    bool lineBlocked(const Vec3& y);
    // c(y), the number of occluders the line from x through y crosses, through their interiors;
    // empty where the line touches one's boundary (c jumps there) or the work limit stops it.
    std::optional<int> countLine(const Vec3& y);
    // The line through y against active occluder j (closed; exact signs at y).
    LineHit hitKind(size_t j, const Vec3& y);
    bool hits(size_t j, const Vec3& y) { return hitKind(j, y) != LineHit::Miss; }
    // The line from x through y against mesh face `face`, unclipped (closed; exact signs at y),
    // x strictly in front of its plane (side +1) or behind it (-1): a silhouette slot's face, or
    // a used group's.
    LineHit faceHitKind(uint32_t face, int side, const Vec3& y);
    // Four planes holding the line through x and y, at right angles: a box off one of them lies
    // off the line (linePlanes()).
    void setLinePlanes(const Vec3& y);
    const std::vector<PlaneOrient>& linePlanes() const { return linePlanes_; }

  private:
    // The lines against the occluders: all of them in turn, until a run has tested
    // kScanBeforeBoxes times their number; then through the hierarchy of their faces' boxes,
    // which returns every occluder whose box is not certainly off the line.
    static constexpr uint64_t kScanBeforeBoxes = 4;

    QueryParts& q_;
    uint32_t lastHit_ = 0;  // the occluder that hid the last hidden cell (tried first)
    uint64_t scanned_ = 0;
    std::vector<PlaneOrient> linePlanes_;
    std::vector<uint32_t> onLine_;
};

}  // namespace penumbra::vis
