// Closed surfaces as solids on the direct path with face groups (closed_surfaces.h). For a
// component S of the mesh whose open edges lie outside the pyramid, the count of S's faces a
// segment from x to L crosses seen from the front, minus those seen from behind, is the winding
// number of S's faces' boundaries seen from x, the same for every segment in the open cone when
// nothing else of that sum lies in it: the chords where B's or L's plane cuts S's faces and the
// edges of B and L themselves, left out as occluders. With x on or in front of B's plane, what
// lies in B's plane is seen outside the open cone; what lies in L's plane is not, so a component
// with a face reaching L's plane in the pyramid is no solid for x, nor L's own; with x behind B's
// plane by a rounding, neither is B's (or one with a face that B's plane cuts) unless each of B's
// edges (that face) is shown to miss the open cone (missesCone); nor is one with a face through x
// (x on its surface: the winding changes across that face's plane, unless it is B's plane with x
// on it). Each remaining component's winding is counted once along the segment from x to a
// vertex of L (exact signs; a segment through an edge of S makes S no solid): 0 and a segment
// that crosses S's faces crosses one seen from the front, so those seen from behind are left out;
// not 0 and every segment is blocked. Decided once per run (prepare), after the walk, where
// enough is to be left out (worth).
#pragma once

#include <cstdint>
#include <optional>
#include <vector>

#include "visibility/face_clusters.h"
#include "visibility/predicates.h"

namespace penumbra::vis {

struct QueryParts;

class SolidFilter {
  public:
    explicit SolidFilter(QueryParts& q) : q_(q) {}

    void reset() {
        state_ = State::Unknown;
        hidden_ = false;
        groupsLeft_ = facesLeft_ = 0;
    }
    // Whether the checks pay for this run's candidates and groups (ChainOptions::solidMinFaces).
    bool worth() const;
    // Decides which components x may take as solids; false: none (or the work limit was reached).
    bool prepare();
    // The used groups x sees from behind, of components taken as solids, left out.
    void leaveOutBacks();
    // A face x sees from behind, of a component taken as a solid: left out (and counted).
    bool leavesOut(uint32_t face);
    // Such a surface blocked every segment from x to L.
    bool hidden() const { return hidden_; }
    uint32_t groupsLeftOut() const { return groupsLeft_; }
    uint32_t facesLeftOut() const { return facesLeft_; }

  private:
    enum class State : uint8_t { Unknown, Ready, Off };
    // Whether x may take `component` (FaceClusters::kNone: none) as a solid (prepare).
    bool component(uint32_t c) const {
        return state_ == State::Ready && c != FaceClusters::kNone && componentStamp_[c] != run_;
    }
    // prepare's steps: no solid where B's edges (x behind B's plane), open edges in the pyramid,
    // or candidates reaching L's plane or through x say so; then each remaining component's
    // winding along a segment from x to L. False: the work limit was reached.
    bool receiverEdges();
    bool openEdges();
    bool candidates();
    bool windings();
    void notSolid(uint32_t c) { componentStamp_[c] = run_; }
    bool solid(uint32_t c) const { return componentStamp_[c] != run_; }
    // Whether the segment from x to v crosses `face`'s interior: +1 seen from the front, -1 from
    // behind, 0 not; nullopt where a sign is zero on its boundary (the segment touches an edge).
    std::optional<int> segmentCrossing(uint32_t face, const Vec3& v) const;
    // The side of the plane through x, a and b that every vertex of L lies strictly on, or Zero
    // when they do not (exact signs).
    Sign lightSideOf(const Vec3& a, const Vec3& b) const;
    // Whether the convex face on vertex ids `ids` certainly misses the open cone from x over L:
    // strictly outside one of the pyramid's planes, or on the closed side of a plane through x
    // and one of its edges that L lies strictly off (exact signs).
    bool missesCone(const std::vector<uint32_t>& ids) const;

    QueryParts& q_;
    State state_ = State::Unknown;
    bool hidden_ = false;
    uint32_t groupsLeft_ = 0, facesLeft_ = 0;
    Sign xB_ = Sign::Zero;                  // x's side of B's plane (prepare)
    std::vector<uint32_t> componentStamp_;  // per component: run_ when it is no solid
    std::vector<int32_t> componentWinding_;
    std::vector<uint32_t> windingStamp_;  // per component: run_ when its winding is set
    std::vector<uint32_t> windingComponents_;
    std::vector<uint32_t> found_;
    uint32_t run_ = 0;
};

}  // namespace penumbra::vis
