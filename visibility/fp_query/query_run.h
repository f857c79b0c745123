// The per-run context every strategy of a from-point query shares (from_point_query.h): the
// point, the pair, the pyramid and cone from x over L, the work budget and the answer. Each
// strategy keeps its own state; this is what they all read.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "visibility/fp_query/fragment_list.h"
#include "visibility/fp_query/from_point_query.h"
#include "visibility/fp_query/pair_setup.h"
#include "visibility/fp_query/work_budget.h"
#include "visibility/pair_occluders.h"
#include "visibility/polygon_clip.h"
#include "visibility/predicates.h"

namespace penumbra::vis {

struct QueryRun {
    explicit QueryRun(PredicateMode m) : mode(m) {}

    PredicateMode mode;
    ChainOptions chainOptions;
    PairSetup pair;
    // The tree walked (null on the direct path and for a contact answer).
    const HistoryTree* tree = nullptr;
    // The point answered, the run's input point (AnsweredPoint::input) and whether x was moved
    // off it: the contact rule is decided there (occluderSide).
    Vec3 x, input;
    bool moved = false;
    WorkBudget budget;
    FragmentList fragments;
    // The planes through x and the edges of L clipped to B's front, interior positive
    // (preparePyramid): a line from x to L lies inside.
    std::vector<PlaneOrient> pyramid;
    // The faces that may meet the pyramid (the direct path's and a contact answer's), in
    // increasing order or the order the hierarchy found them.
    std::vector<uint32_t> candidates;

    const PolygonMesh& mesh() const { return pair.mesh(); }
    const std::vector<Vec3>& light() const { return pair.lightPolygon(); }

    // The side of x against an occluder's plane under the contact rule: Zero where the run's
    // input point lies exactly in it (a moved point touches what its input touches:
    // answered_point.h), else x's exact side. Every strategy decides "x on the occluder's plane"
    // through it.
    Sign occluderSide(const PlaneOrient& plane) const {
        if (moved && plane.sign(input) == Sign::Zero) return Sign::Zero;
        return plane.sign(x);
    }

    void preparePyramid() {
        // The pyramid from x over L (clipped to B's front): a line from x to L lies inside it, so
        // an occluder with no vertex strictly inside one of its side planes blocks none of them.
        pyramidPlanes(x, pair.lightClipped(), pyramid);
    }
    // The cone from x over L itself, of exact planes (the pyramid over L clipped to B's front
    // has rounded vertices where B's plane cuts L): cells and their sample lines are bounded by
    // it. The occluders were gathered for the clipped pyramid, so c counts only them; in the
    // part of the cone beyond B's plane it is still a function constant on each cell, and on the
    // cells' part in front of B it is the answer.
    void prepareCone() {
        // Exact: every vertex of L strictly in front of B's plane (then the clip kept L as is).
        lightWhole_ = true;
        for (const Vec3& v : light())
            lightWhole_ = lightWhole_ && pair.frontB().side(v) == Sign::Positive;
        if (!lightWhole_) pyramidPlanes(x, light(), lightCone_);
    }
    // The planes through x and L's input edges: the pyramid itself when L lies wholly in front
    // of B (then L clipped is L), else the cone prepareCone made.
    const std::vector<PlaneOrient>& cone() const { return lightWhole_ ? pyramid : lightCone_; }

    // B's (0) or L's (1) plane evaluated at x, once per run (the pencil planes of chords).
    const BoundedValue& clipPlaneAt(int which) {
        if (!clipValueKnown_[which]) {
            clipValue_[which] = (which == 0 ? pair.frontB() : pair.frontL()).orient.value(x);
            clipValueKnown_[which] = true;
        }
        return clipValue_[which];
    }
    // The split parts per recursion depth, reused along the walk and across runs.
    SplitParts& partsAt(size_t depth) {
        if (parts_.size() <= depth) parts_.resize(depth + 1);
        return parts_[depth];
    }

    // A new run: the answer, the budget and x's plane values forgotten.
    void reset() {
        clipValueKnown_[0] = clipValueKnown_[1] = false;
        fragments.clear();
        budget.reset();
        tree = nullptr;
    }

  private:
    bool lightWhole_ = false;
    std::vector<PlaneOrient> lightCone_;
    std::vector<SplitParts> parts_;
    BoundedValue clipValue_[2];
    bool clipValueKnown_[2] = {false, false};
};

}  // namespace penumbra::vis
