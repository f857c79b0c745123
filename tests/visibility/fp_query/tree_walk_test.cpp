// FromPointQuery's trace (the nodes the walk visited, their depths and the side the light polygon
// went to), which the debugger's Path panel and tree browser show. Checked against the tree's
// structure (a child is on the trace exactly when its side was taken, one level deeper) and, at
// the root, against an independent exact evaluation of the split: the signs of orient3d(x, y, v0,
// v1) over the light's input vertices y (the walk splits constructed polygons with filtered
// predicates; the reference uses the exact predicate on the input alone).
#include <gtest/gtest.h>

#include <map>
#include <random>

#include "engine/scene/procedural_scenes.h"
#include "tests/support/random_points.h"
#include "tests/support/test_scale.h"
#include "visibility/fp_query/from_point_query.h"
#include "visibility/history_tree_builder.h"
#include "visibility/pair_occluders.h"
#include "visibility/predicates.h"

namespace penumbra {
namespace {

using vis::NodeSide;
using vis::Vec3;

// The side of the root's plane the whole light polygon lies on, from the exact predicate on L's
// input vertices (valid when L lies strictly in front of B's plane: the walk starts from L itself).
NodeSide rootSideReference(const vis::PolygonMesh& m, const vis::HistoryTree& t, const Vec3& x) {
    const vis::HistoryNode& n = t.nodes[0];
    const Vec3 v0 = m.vertices[n.v0], v1 = m.vertices[n.v1];
    bool pos = false, neg = false;
    for (uint32_t v : m.faces[t.light]) {
        const vis::Sign s = vis::orientSignExact(x, m.vertices[v], v0, v1);
        pos |= s == vis::Sign::Positive;
        neg |= s == vis::Sign::Negative;
    }
    return pos && neg ? NodeSide::Both
           : pos      ? NodeSide::Positive
           : neg      ? NodeSide::Negative
                      : NodeSide::OnPlane;
}

bool lightStrictlyInFrontOfReceiver(const vis::PolygonMesh& m, uint32_t receiver, uint32_t light) {
    const vis::FacePlane b = vis::facePlane(m, receiver);
    for (uint32_t v : m.faces[light])
        if (b.side(m.vertices[v]) != vis::Sign::Positive) return false;
    return true;
}

TEST(FromPointQueryTrace, FollowsTheTreeAndTheRootSideIsTheExactOne) {
    std::mt19937_64 rng(7);
    size_t traces = 0, rootsChecked = 0, splits = 0, steps = 0;
    for (const Scene& scene : {makeStairs(), makeGrids(), makeCornellBox()}) {
        const vis::PolygonMesh& m = scene.mesh;
        const uint32_t light = scene.lights.at(0);
        for (uint32_t receiver = 0; receiver < m.faces.size(); ++receiver) {
            if (receiver == light) continue;
            const vis::HistoryTree tree = vis::buildHistoryTree(m, receiver, light);
            if (tree.kind != vis::PairKind::Penumbra || tree.nodes.empty()) continue;
            const bool rootCheckable = lightStrictlyInFrontOfReceiver(m, receiver, light) &&
                                       !vis::isClipEdge(tree.nodes[0].v0);
            for (int k = 0; k < test::scaled(4); ++k) {
                const Vec3 x = test::randomPointOn(m, receiver, rng);
                const vis::FromPointResult r = vis::fromPointQuery(m, tree, x);
                if (r.trace.empty() || r.answeredOnContact) continue;
                ++traces;
                steps += r.trace.size();
                // Depth-first from the root; each node once.
                ASSERT_EQ(r.trace.front().node, 0u);
                EXPECT_EQ(r.trace.front().depth, 0u);
                std::map<uint32_t, uint32_t> depthOf;
                for (const vis::TraceStep& s : r.trace) {
                    ASSERT_LT(s.node, tree.nodes.size());
                    EXPECT_TRUE(depthOf.emplace(s.node, s.depth).second) << "node twice";
                }
                for (const vis::TraceStep& s : r.trace) {
                    const vis::HistoryNode& n = tree.nodes[s.node];
                    const bool pos = s.side != NodeSide::Negative;
                    const bool neg = s.side == NodeSide::Negative || s.side == NodeSide::Both;
                    for (int c = 0; c < 2; ++c) {
                        if (vis::isLeaf(n.child[c])) continue;
                        const auto it = depthOf.find(n.child[c]);
                        EXPECT_EQ(it != depthOf.end(), c == 0 ? pos : neg)
                            << "node " << s.node << " side " << vis::toString(s.side);
                        if (it != depthOf.end()) {
                            EXPECT_EQ(it->second, s.depth + 1);
                        }
                    }
                    splits += s.side == NodeSide::Both;
                }
                if (rootCheckable) {
                    EXPECT_EQ(r.trace.front().side, rootSideReference(m, tree, x))
                        << "receiver " << receiver;
                    ++rootsChecked;
                }
            }
        }
    }
    // Not vacuous: penumbrae (splits), roots checked against the reference, deep walks.
    EXPECT_GT(traces, 20u);
    EXPECT_GT(rootsChecked, 10u);
    EXPECT_GT(splits, 10u);
    EXPECT_GT(steps, 3 * traces);
}

}  // namespace
}  // namespace penumbra
