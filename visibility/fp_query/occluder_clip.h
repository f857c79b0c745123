// Algorithm 1 of Mora & Aveneau in 3D from x: L's pieces clipped occluder by occluder against the
// per-point occluders (active_occluders.h), largest solid angle first, each piece against those
// whose box may meet its pyramid from x. Its cost follows the number of fragments.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <utility>
#include <vector>

#include "visibility/predicates.h"

namespace penumbra::vis {

struct QueryParts;

class OccluderClip {
  public:
    explicit OccluderClip(QueryParts& q) : q_(q) {}

    void reset() {
        ordered_ = false;
        lightTurn_ = Sign::Zero;
        clips_ = 0;
    }
    // `poly` clipped against every occluder, in Algorithm 1's order (the occluders are put in it
    // once per run); what is left visible goes to the run's fragments.
    void clipOrdered(std::span<const Vec3> poly, size_t depth);
    // The same in the occluders' present order (a chain cell whose point could not be
    // certified).
    void clip(std::span<const Vec3> poly, size_t depth) { clipByOccluders(poly, 0, depth); }
    // The clips that changed a piece (split or removed it) this run.
    uint32_t clips() const { return clips_; }
    // The planes through x and `poly`'s edges that have no vertex of it strictly on their
    // negative side (exact signs of its vertices: a rounded polygon that is not quite convex
    // loses only the planes that would cut it), oriented as L is seen from x: each holds the
    // polygon's hull, so a face whose box lies strictly outside one blocks none of it. Valid
    // until the next call; its n sign tests are spent from the run's budget.
    const std::vector<PlaneOrient>& hullCone(std::span<const Vec3> poly);

  private:
    // `poly` clipped against the occluders from `from` on (those that may meet it).
    void clipByOccluders(std::span<const Vec3> poly, size_t from, size_t depth);
    // The same against `count` occluders: clipList_[listBase..] when `culled`, else the
    // occluders from `from` on.
    void clipListed(std::span<const Vec3> poly, size_t listBase, size_t count, bool culled,
                    size_t from, size_t depth);
    // Appends to clipList_ the indices from `from` on of the occluders whose box is not
    // certainly outside the pyramid from x over `poly`'s hull, in increasing order; false when
    // the work limit stopped it.
    bool cullFor(std::span<const Vec3> poly, size_t from);
    // Puts the occluders in the order Algorithm 1 clips them: largest solid angle from x first.
    void order();
    // Below kCullMin occluders a polygon is clipped against each in turn; from it on, against
    // those its pyramid's box query returns. A piece split off inherits the rest of its
    // polygon's list, queried again for it only when that is kRecullMin long or more (each query
    // costs a hierarchy walk; 64 measured fastest on the table scene, 16 to 128 tried).
    static constexpr size_t kCullMin = 16, kRecullMin = 64;

    QueryParts& q_;
    bool ordered_ = false;
    // The side of the plane through x, L[0] and L[1] that L[2] is on (the turn of every polygon
    // that is part of L, seen from x; cullFor).
    Sign lightTurn_ = Sign::Zero;
    uint32_t clips_ = 0;
    std::vector<std::pair<double, uint32_t>> orderKeys_;
    std::vector<uint32_t> order_;
    std::vector<PlaneOrient> hullCone_;
    std::vector<uint32_t> cullOut_;
    // The candidate lists, one above the other per active call (a stack).
    std::vector<uint32_t> clipList_;
    // The free parts of the occluder being clipped, per active call (a stack).
    std::vector<std::span<const Vec3>> freeParts_;
};

}  // namespace penumbra::vis
