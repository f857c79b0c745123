// The per-point occluders of a from-point query (a partial tree's deferred ones, the direct
// path's, or a contact answer's): each mesh face clipped exactly to the region between B's and
// L's planes (clipped_occluder.h), with the planes through x and its edges and the side of them
// its blocked lines are on. Algorithm 1, the boundary chain and the line tests all read them.
#pragma once

#include <cstdint>
#include <span>
#include <utility>
#include <vector>

#include "visibility/box_tree.h"
#include "visibility/clipped_occluder.h"
#include "visibility/edge_line.h"
#include "visibility/polygon_clip.h"
#include "visibility/predicates.h"

namespace penumbra::vis {

struct QueryParts;

// plane.sign(y) (exact for an input point y) with the filter's path inlined, for both plane
// kinds (PlaneOrient::sign does this itself; PencilPlane's calls the out-of-line value()): these
// tests are the chain's innermost loop.
template <class Plane>
inline Sign exactSign(const Plane& plane, const Vec3& y) {
    BoundedValue b;
    if (plane.filtered(y, b)) return b.sign();
    return plane.value(y).sign();
}

class ActiveOccluders {
  public:
    struct Occluder {
        uint32_t firstPlane = 0, planeCount = 0;    // of its input edges, in planes()
        uint32_t firstPencil = 0, pencilCount = 0;  // of its chords, in pencils()
        Sign blocked = Sign::Zero;
        uint32_t face = 0;
    };
    // A ref names the plane through x and one occluder edge: an index in planes(), or with
    // kPencilRef in pencils().
    static constexpr uint32_t kPencilRef = 0x80000000u;

    explicit ActiveOccluders(QueryParts& q) : q_(q) {}

    // Forgets the occluders (and, with `run`, whether a chord on L's plane was seen).
    void clear(bool run);
    // Adds mesh face `face`, clipped exactly to the region in front of B's and L's planes, unless
    // it certainly blocks nothing from x (outside the pyramid, or x on its plane: the contact
    // rule), or it is seen from behind on a closed surface taken as a solid (solid_filter.h).
    void activate(uint32_t face);
    // Adds the plane through x and input edge (lo, hi) without an occluder (a chain edge that
    // remains of a face group or a silhouette); returns its ref.
    uint32_t addEdgePlane(uint32_t lo, uint32_t hi);
    // Puts the occluders in `order` (indices), e.g. Algorithm 1's.
    void reorder(std::span<const uint32_t> order);

    size_t size() const { return list_.size(); }
    bool empty() const { return list_.empty(); }
    const Occluder& operator[](size_t j) const { return list_[j]; }
    const PlaneOrient& plane(uint32_t i) const { return planes_[i]; }
    const PencilPlane& pencil(uint32_t i) const { return pencils_[i]; }
    // The input edge (mesh vertex ids) of plane(i), and whether pencil(i)'s chord lies on B's
    // plane (else L's).
    std::pair<uint32_t, uint32_t> planeEdge(uint32_t i) const { return planeEdges_[i]; }
    bool pencilOnB(uint32_t i) const { return pencilOnB_[i] != 0; }
    // An occluder was cut by L's plane (a chord on it) this run.
    bool lightChord() const { return lightChord_; }

    // f(plane) with the plane of `ref` (a PlaneOrient or a PencilPlane): every use of a ref's
    // plane goes through it; a loop that takes many signs against one plane calls it once, with
    // the filter inlined in the loop (exactSign(plane, y)).
    template <class F>
    decltype(auto) withRefPlane(uint32_t ref, F&& f) const {
        return (ref & kPencilRef) != 0 ? f(pencils_[ref & ~kPencilRef]) : f(planes_[ref]);
    }
    Sign refSign(uint32_t ref, const Vec3& y) const {
        return withRefPlane(ref, [&](const auto& plane) { return exactSign(plane, y); });
    }
    SplitOutcome splitByRef(uint32_t ref, std::span<const Vec3> poly, SplitParts& parts,
                            std::span<const Vec3> light) const {
        return withRefPlane(
            ref, [&](const auto& plane) { return splitConstructed(poly, plane, light, parts); });
    }

    // The hierarchy of the occluders' boxes: built on demand (and again when occluders were
    // activated since); built() says whether one is current enough to be used as it is.
    const BoxTree& boxes();
    bool boxesBuilt() const { return boxesBuilt_; }

  private:
    QueryParts& q_;
    std::vector<Occluder> list_, scratch_;
    std::vector<PlaneOrient> planes_;
    std::vector<PencilPlane> pencils_;
    std::vector<uint8_t> pencilOnB_;
    std::vector<std::pair<uint32_t, uint32_t>> planeEdges_;
    bool lightChord_ = false;
    ClippedOccluder clipped_;  // activate's scratch
    bool boxesBuilt_ = false;
    BoxTree boxes_;
    std::vector<Bounds3> boxList_;
};

}  // namespace penumbra::vis
