// The walk of a history tree from a point x (Algorithm 2): down the tree with the plane through x
// and each node's edge, L split where the plane cuts it; what reaches a visible leaf goes on to
// the per-point occluders of a partial tree (QueryParts::reachVisible).
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "visibility/fp_query/fragment_list.h"
#include "visibility/history_tree.h"
#include "visibility/polygon_clip.h"
#include "visibility/region_decisions.h"

namespace penumbra::vis {

struct QueryParts;

class TreeWalk {
  public:
    explicit TreeWalk(QueryParts& q) : q_(q) {}

    // Walks the run's tree with L clipped to B's front from its root. `trace` and `region` as
    // FromPointQuery::run.
    void walk(std::vector<TraceStep>* trace, RegionDecisions* region);
    uint32_t nodesVisited() const { return nodesVisited_; }
    void reset() { nodesVisited_ = 0; }

  private:
    // `depth` indexes the split scratch (QueryRun::partsAt), `treeDepth` is the node's depth (for
    // the trace).
    void visit(uint32_t node, std::span<const Vec3> poly, size_t depth, uint32_t treeDepth);
    // `poly` split by the plane through x and node n's edge (an input edge, or a chord of a clip).
    SplitOutcome split(const HistoryNode& n, std::span<const Vec3> poly, SplitParts& parts,
                       KeepParts keep);
    // A node's split with the predicates of the run's mode (input edges) or the filtered ones
    // (chords).
    template <class Plane>
    SplitOutcome splitBy(std::span<const Vec3> poly, const Plane& plane, SplitParts& parts,
                         KeepParts keep) const;
    // Records the side the current node sent the polygon to (the trace's entry `index`).
    void traceSide(size_t index, NodeSide side) {
        if (trace_ != nullptr) (*trace_)[index].side = side;
    }

    QueryParts& q_;
    std::vector<TraceStep>* trace_ = nullptr;
    RegionDecisions* region_ = nullptr;
    uint32_t nodesVisited_ = 0;
};

}  // namespace penumbra::vis
