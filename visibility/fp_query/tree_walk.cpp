#include "visibility/fp_query/tree_walk.h"

#include <type_traits>

#include "visibility/fp_query/query_parts.h"

namespace penumbra::vis {

const char* toString(NodeSide side) {
    switch (side) {
        case NodeSide::Positive:
            return "+";
        case NodeSide::Negative:
            return "-";
        case NodeSide::Both:
            return "both";
        case NodeSide::OnPlane:
            return "in plane (+)";
    }
    return "?";
}

std::vector<uint32_t> traceNodes(std::span<const TraceStep> trace) {
    std::vector<uint32_t> out;
    out.reserve(trace.size());
    for (const TraceStep& s : trace) out.push_back(s.node);
    return out;
}

void TreeWalk::walk(std::vector<TraceStep>* trace, RegionDecisions* region) {
    trace_ = trace;
    region_ = region;
    const HistoryTree& tree = *q_.run.tree;
    if (tree.nodes.empty())  // a partial tree with no node: one visible leaf
        q_.reachVisible(q_.run.pair.lightClipped(), 0);
    else
        visit(0, q_.run.pair.lightClipped(), 0, 0);
    trace_ = nullptr;
    region_ = nullptr;
}

void TreeWalk::visit(uint32_t node, std::span<const Vec3> poly, size_t depth, uint32_t treeDepth) {
    QueryRun& r = q_.run;
    // Down the tree while the plane leaves the polygon on one side (the common case: the same span
    // goes on, nothing is copied); recursion only where it is split in two.
    for (;;) {
        if (node == kVisibleLeaf) {
            q_.reachVisible(poly, depth);
            return;
        }
        if (node == kHiddenLeaf) return;
        if (r.budget.reached()) return;
        r.budget.enter(WorkStage::Walk);
        const size_t step = trace_ != nullptr ? trace_->size() : 0;
        if (trace_ != nullptr) trace_->push_back({node, treeDepth, NodeSide::Positive});
        ++nodesVisited_;
        const HistoryNode& n = r.tree->nodes[node];
        ++treeDepth;  // of the children
        if (region_ != nullptr) {
            const RegionDecisions::Decision d = region_->at(node);
            if (d == RegionDecisions::Decision::Positive) {
                node = n.child[0];
                continue;
            }
            if (d == RegionDecisions::Decision::Negative) {
                traceSide(step, NodeSide::Negative);
                node = n.child[1];
                continue;
            }
        }
        // The 5D test "which side of edge (v0,v1) does line(x, y) pass" is the 3D test
        // orient3d(x, y, v0, v1) = side of y against the plane through x, v0, v1: exact for the
        // vertices of L, filtered for constructed fragment vertices (an uncertain one counts as on
        // the plane: polygon_clip.h splitConstructed). When x, v0, v1 are collinear the plane is
        // undefined and every line through x meets the edge's line: all signs are zero and the
        // whole polygon follows child[0] (a measure-zero set of points x; documented rule).
        // orient3d(x, v0, v1, y) == orient3d(x, y, v0, v1) (a cyclic, hence even, permutation).
        const uint32_t c0 = n.child[0], c1 = n.child[1];
        if (c0 == kHiddenLeaf && c1 == kHiddenLeaf) return;  // (only without leaf merging)
        // A part bound for a hidden leaf is not written.
        const KeepParts keep = c0 == kHiddenLeaf   ? KeepParts::Negative
                               : c1 == kHiddenLeaf ? KeepParts::Positive
                                                   : KeepParts::Both;
        if (!r.budget.spend()) return;
        SplitParts& parts = r.partsAt(depth);
        const SplitOutcome outcome = split(n, poly, parts, keep);
        switch (outcome) {
            case SplitOutcome::OnPlane:  // measure zero: follows child[0] whole (see above)
                traceSide(step, NodeSide::OnPlane);
                node = c0;
                continue;
            case SplitOutcome::Positive:
                node = c0;
                continue;
            case SplitOutcome::Negative:
                traceSide(step, NodeSide::Negative);
                node = c1;
                continue;
            case SplitOutcome::Split: {
                traceSide(step, NodeSide::Both);
                // Spans into the parts' heap storage: they stay valid when deeper levels grow
                // parts_ (moving a vector keeps its buffer), and deeper levels use other entries.
                // One part left (the other is hidden): go on with it here, one level deeper.
                if (keep == KeepParts::Positive) {
                    poly = parts.positive();
                    node = c0;
                    ++depth;
                    continue;
                }
                if (keep == KeepParts::Negative) {
                    poly = parts.negative();
                    node = c1;
                    ++depth;
                    continue;
                }
                const std::span<const Vec3> positive = parts.positive();
                const std::span<const Vec3> negative = parts.negative();
                visit(c0, positive, depth + 1, treeDepth);
                visit(c1, negative, depth + 1, treeDepth);
                return;
            }
        }
    }
}

SplitOutcome TreeWalk::split(const HistoryNode& n, std::span<const Vec3> poly, SplitParts& parts,
                             KeepParts keep) {
    QueryRun& r = q_.run;
    if (!isClipEdge(n.v0)) {
        return splitBy(poly, PlaneOrient(r.x, r.mesh().vertices[n.v0], r.mesh().vertices[n.v1]),
                       parts, keep);
    }
    {
        // A chord of a clip: the plane through x and the meet of B's (or L's) plane with the
        // occluder's, as the pencil of the two (edge_line.h); exact for L's vertices too.
        const uint32_t face = n.v0 & ~kClipEdge;
        const auto& f = r.mesh().faces[face];
        const PlaneOrient occluderPlane(r.mesh().vertices[f[0]], r.mesh().vertices[f[1]],
                                        r.mesh().vertices[f[2]]);
        const bool onB = n.v1 == kReceiverPlaneEdge;
        const PlaneOrient& clip = onB ? r.pair.frontB().orient : r.pair.frontL().orient;
        return splitBy(poly, PencilPlane(r.x, clip, r.clipPlaneAt(onB ? 0 : 1), occluderPlane),
                       parts, keep);
    }
}

template <class Plane>
SplitOutcome TreeWalk::splitBy(std::span<const Vec3> poly, const Plane& plane, SplitParts& parts,
                               KeepParts keep) const {
    if constexpr (std::is_same_v<Plane, PlaneOrient>) {
        switch (q_.run.mode) {
            case PredicateMode::Filtered:
                break;
            case PredicateMode::AlwaysExact:
                return splitExact(poly, plane, parts);
            case PredicateMode::Naive:
                return splitNaive(poly, plane, parts);
        }
    }
    // (The chords' pencil planes have no naive or always-exact variant: the predicate study
    // measures input edges.)
    return splitConstructed(poly, plane, q_.run.light(), parts, keep);
}

}  // namespace penumbra::vis
