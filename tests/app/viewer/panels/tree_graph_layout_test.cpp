// The history-tree browser's layout: every invariant is checked against facts the test derives
// from the tree by itself (its own traversal, its own grouping by layer, brute-force culling),
// on hand-built trees, random trees, deep chains and real trees of the stairs scene.
#include "app/viewer/panels/tree_graph_layout.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <random>
#include <set>
#include <utility>
#include <vector>

#include "app/viewer/panels/history_tree_topology.h"
#include "engine/scene/procedural_scenes.h"
#include "tests/support/test_scale.h"
#include "tools/devkit/random_history_tree.h"
#include "visibility/history_tree_builder.h"

namespace {

using penumbra::ui::GraphItem;
using penumbra::ui::GraphItemKind;
using penumbra::ui::GraphRect;
using penumbra::ui::HistoryTreeTopology;
using penumbra::ui::kNoIndex;
using penumbra::ui::TreeGraphLayout;
using penumbra::ui::TreeGraphStyle;
namespace vis = penumbra::vis;

constexpr double kEps = 1e-9;

// What should be drawn, derived from the tree alone: each displayed node with its depth (root 0)
// and whether it is drawn collapsed; each leaf occurrence (parent node, side) with its code.
struct Expected {
    std::map<uint32_t, std::pair<uint32_t, bool>> nodes;  // node -> (depth, collapsed)
    std::map<std::pair<uint32_t, int>, uint32_t> leaves;  // (parent, side) -> leaf code
    std::map<uint32_t, uint32_t> parentOf;                // displayed node -> parent node
};

Expected expectedDisplay(const vis::HistoryTree& t, const std::vector<uint8_t>& collapsed) {
    Expected e;
    if (t.nodes.empty()) return e;
    std::vector<std::pair<uint32_t, uint32_t>> stack{{0, 0}};
    while (!stack.empty()) {
        const auto [v, d] = stack.back();
        stack.pop_back();
        e.nodes[v] = {d, collapsed[v] != 0};
        if (collapsed[v]) continue;
        for (int s = 0; s < 2; ++s) {
            const uint32_t c = t.nodes[v].child[s];
            if (vis::isLeaf(c)) {
                e.leaves[{v, s}] = c;
            } else {
                e.parentOf[c] = v;
                stack.push_back({c, d + 1});
            }
        }
    }
    return e;
}

// All descendants of `node` (not itself), by the test's own traversal.
std::set<uint32_t> descendants(const vis::HistoryTree& t, uint32_t node) {
    std::set<uint32_t> out;
    std::vector<uint32_t> stack{node};
    while (!stack.empty()) {
        const uint32_t v = stack.back();
        stack.pop_back();
        for (uint32_t c : t.nodes[v].child)
            if (!vis::isLeaf(c)) {
                out.insert(c);
                stack.push_back(c);
            }
    }
    return out;
}

double halfW(const TreeGraphStyle& st, const GraphItem& it) {
    return 0.5 * (penumbra::ui::isLeafItem(it.kind) ? st.leafWidth : st.nodeWidth);
}

// The invariants of the layout, each checked independently of how the layout computed it.
// tightSiblings: also check that sibling subtrees touch (are exactly `gap` apart) at some
// common layer, O(n * depth): only for small trees.
void checkLayout(const vis::HistoryTree& t, const std::vector<uint8_t>& collapsed,
                 const TreeGraphLayout& layout, bool tightSiblings = false) {
    const TreeGraphStyle& st = layout.style();
    const Expected e = expectedDisplay(t, collapsed);
    const auto items = layout.items();
    ASSERT_EQ(items.size(), e.nodes.size() + e.leaves.size());

    // Every node and leaf occurrence placed exactly once, at its own layer, linked to its parent.
    std::map<uint32_t, uint32_t> itemOfNode;
    std::set<std::pair<uint32_t, int>> leavesSeen;
    for (uint32_t i = 0; i < items.size(); ++i) {
        const GraphItem& it = items[i];
        if (penumbra::ui::isLeafItem(it.kind)) {
            const auto key = std::make_pair(it.node, int(it.side));
            ASSERT_TRUE(e.leaves.count(key)) << "leaf item " << i << " of node " << it.node;
            EXPECT_TRUE(leavesSeen.insert(key).second) << "leaf placed twice";
            EXPECT_EQ(e.leaves.at(key) == vis::kVisibleLeaf, it.kind == GraphItemKind::VisibleLeaf);
            EXPECT_EQ(it.depth, e.nodes.at(it.node).first + 1);
            ASSERT_NE(it.parent, kNoIndex);
            EXPECT_EQ(items[it.parent].node, it.node);
            EXPECT_EQ(items[it.parent].child[it.side], i);
        } else {
            ASSERT_TRUE(e.nodes.count(it.node)) << "node " << it.node << " should be hidden";
            EXPECT_TRUE(itemOfNode.emplace(it.node, i).second) << "node placed twice";
            EXPECT_EQ(it.depth, e.nodes.at(it.node).first);
            EXPECT_EQ(it.kind == GraphItemKind::CollapsedNode, e.nodes.at(it.node).second);
            EXPECT_EQ(layout.itemOfNode(it.node), i);
            if (it.node == 0) {
                EXPECT_EQ(it.parent, kNoIndex);
            } else {
                ASSERT_NE(it.parent, kNoIndex);
                EXPECT_EQ(items[it.parent].node, e.parentOf.at(it.node));
            }
        }
        const GraphRect b = layout.box(i);
        EXPECT_NEAR(0.5 * (b.y0 + b.y1), it.depth * st.layerSpacing, kEps);
        EXPECT_NEAR(b.x1 - b.x0, 2 * halfW(st, it), kEps);
    }
    EXPECT_EQ(itemOfNode.size(), e.nodes.size());
    EXPECT_EQ(leavesSeen.size(), e.leaves.size());
    for (uint32_t v = 0; v < t.nodes.size(); ++v)
        if (!e.nodes.count(v)) {
            EXPECT_EQ(layout.itemOfNode(v), kNoIndex);
        }

    // Every expanded node centred over its two children, child[0] on the left.
    for (const GraphItem& it : items) {
        if (it.kind != GraphItemKind::Node) continue;
        const GraphItem& a = items[it.child[0]];
        const GraphItem& b = items[it.child[1]];
        EXPECT_LT(a.x, b.x);
        EXPECT_NEAR(it.x, 0.5 * (a.x + b.x), kEps * (1 + std::fabs(it.x)));
    }

    // No two boxes of a layer overlap (they are at least gap apart), by the test's own grouping.
    std::map<uint32_t, std::vector<uint32_t>> byDepth;
    for (uint32_t i = 0; i < items.size(); ++i) byDepth[items[i].depth].push_back(i);
    EXPECT_EQ(layout.layerCount(), byDepth.size());
    for (auto& [d, layer] : byDepth) {
        std::sort(layer.begin(), layer.end(),
                  [&](uint32_t a, uint32_t b) { return items[a].x < items[b].x; });
        for (size_t k = 1; k < layer.size(); ++k) {
            const GraphItem& l = items[layer[k - 1]];
            const GraphItem& r = items[layer[k]];
            EXPECT_GE((r.x - halfW(st, r)) - (l.x + halfW(st, l)), st.gap - 1e-7)
                << "layer " << d << " items " << layer[k - 1] << ", " << layer[k];
        }
        // The layout's own per-layer list is this same sorted order.
        const auto own = layout.layer(d);
        EXPECT_TRUE(std::equal(own.begin(), own.end(), layer.begin(), layer.end()));
    }

    // Bounds: hold every box and touch on every side; the left edge is at 0.
    const GraphRect bounds = layout.bounds();
    double x0 = 1e300, x1 = -1e300, y0 = 1e300, y1 = -1e300;
    for (uint32_t i = 0; i < items.size(); ++i) {
        const GraphRect b = layout.box(i);
        x0 = std::min(x0, b.x0), x1 = std::max(x1, b.x1);
        y0 = std::min(y0, b.y0), y1 = std::max(y1, b.y1);
    }
    EXPECT_NEAR(bounds.x0, 0.0, kEps);
    EXPECT_NEAR(bounds.x0, x0, kEps);
    EXPECT_NEAR(bounds.x1, x1, kEps * (1 + x1));
    EXPECT_NEAR(bounds.y0, y0, kEps);
    EXPECT_NEAR(bounds.y1, y1, kEps * (1 + y1));

    if (!tightSiblings) return;
    // Tidy: the two subtrees of every expanded node are pushed together until they are exactly
    // `gap` apart at some common layer (never spread further than needed).
    const auto subtreeExtents = [&](uint32_t root) {
        std::map<uint32_t, std::pair<double, double>> ext;  // depth -> (min x0, max x1)
        std::vector<uint32_t> stack{root};
        while (!stack.empty()) {
            const uint32_t i = stack.back();
            stack.pop_back();
            const GraphRect b = layout.box(i);
            auto [it, fresh] = ext.try_emplace(items[i].depth, b.x0, b.x1);
            if (!fresh)
                it->second = {std::min(it->second.first, b.x0), std::max(it->second.second, b.x1)};
            for (uint32_t c : items[i].child)
                if (c != kNoIndex) stack.push_back(c);
        }
        return ext;
    };
    for (uint32_t i = 0; i < items.size(); ++i) {
        if (items[i].kind != GraphItemKind::Node) continue;
        const auto l = subtreeExtents(items[i].child[0]);
        const auto r = subtreeExtents(items[i].child[1]);
        double closest = 1e300;
        for (const auto& [d, lr] : l)
            if (r.count(d)) closest = std::min(closest, r.at(d).first - lr.second);
        EXPECT_NEAR(closest, st.gap, 1e-7) << "node item " << i;
    }
}

// Random rectangles (inside, straddling and outside the bounds, some degenerate): the query
// returns exactly the items whose box intersects, each once.
void checkCulling(const TreeGraphLayout& layout, uint64_t seed, int rects) {
    std::mt19937_64 rng(seed);
    const GraphRect b = layout.bounds();
    const double w = b.x1 - b.x0 + 2, h = b.y1 - b.y0 + 2;
    std::uniform_real_distribution<double> ux(b.x0 - 0.2 * w, b.x1 + 0.2 * w);
    std::uniform_real_distribution<double> uy(b.y0 - 0.2 * h, b.y1 + 0.2 * h);
    std::uniform_real_distribution<double> size(0, 1);
    for (int k = 0; k < rects; ++k) {
        const double x = ux(rng), y = uy(rng);
        // Sizes from degenerate to a third of the drawing, skewed towards small views.
        const double f = k % 7 == 0 ? 0.0 : std::pow(size(rng), 3.0);
        const GraphRect r{x, y, x + f * w / 3, y + std::pow(size(rng), 2.0) * h / 2};
        std::vector<uint32_t> got;
        layout.query(r, got);
        std::vector<uint32_t> want;
        for (uint32_t i = 0; i < layout.itemCount(); ++i)
            if (layout.box(i).intersects(r)) want.push_back(i);
        std::sort(got.begin(), got.end());
        ASSERT_TRUE(std::adjacent_find(got.begin(), got.end()) == got.end()) << "duplicates";
        ASSERT_EQ(got, want) << "rect " << r.x0 << "," << r.y0 << " - " << r.x1 << "," << r.y1;
    }
    // A rectangle exactly touching one box's corner still returns it (closed boxes).
    if (layout.itemCount() > 0) {
        const GraphRect box = layout.box(layout.itemCount() - 1);
        std::vector<uint32_t> got;
        layout.query({box.x1, box.y1, box.x1 + 0.01, box.y1 + 0.01}, got);
        EXPECT_NE(std::find(got.begin(), got.end(), layout.itemCount() - 1), got.end());
    }
}

vis::HistoryTree handTree() {
    // 0: (+) 1, (-) 2;  1: (+) visible, (-) 3;  2: (+) hidden, (-) visible;
    // 3: (+) hidden, (-) 4;  4: (+) visible, (-) hidden
    vis::HistoryTree t;
    t.kind = vis::PairKind::Penumbra;
    t.nodes.resize(5);
    t.nodes[0].child[0] = 1, t.nodes[0].child[1] = 2;
    t.nodes[1].child[0] = vis::kVisibleLeaf, t.nodes[1].child[1] = 3;
    t.nodes[2].child[0] = vis::kHiddenLeaf, t.nodes[2].child[1] = vis::kVisibleLeaf;
    t.nodes[3].child[0] = vis::kHiddenLeaf, t.nodes[3].child[1] = 4;
    t.nodes[4].child[0] = vis::kVisibleLeaf, t.nodes[4].child[1] = vis::kHiddenLeaf;
    return t;
}

TEST(TreeGraphTopology, CountsOfAHandBuiltTree) {
    const vis::HistoryTree t = handTree();
    const HistoryTreeTopology topo(t);
    EXPECT_EQ(topo.reachableCount(), 5u);
    EXPECT_EQ(topo.maxDepth, 3u);
    EXPECT_EQ(topo.maxDepth + 1, t.depth());
    EXPECT_EQ(topo.subtreeNodes[0], 5u);
    EXPECT_EQ(topo.subtreeNodes[1], 3u);
    EXPECT_EQ(topo.subtreeNodes[3], 2u);
    EXPECT_EQ(topo.visibleLeaves[0], 3u);
    EXPECT_EQ(topo.hiddenLeaves[0], 3u);
    EXPECT_EQ(topo.visibleLeaves[1], 2u);
    EXPECT_EQ(topo.hiddenLeaves[1], 2u);
    EXPECT_EQ(topo.preorder, (std::vector<uint32_t>{0, 1, 3, 4, 2}));
    EXPECT_EQ(topo.parent[4], 3u);
    EXPECT_TRUE(topo.isAncestorOrSelf(1, 4));
    EXPECT_TRUE(topo.isAncestorOrSelf(4, 4));
    EXPECT_FALSE(topo.isAncestorOrSelf(2, 4));
    EXPECT_FALSE(topo.isAncestorOrSelf(4, 1));
}

TEST(TreeGraphTopology, MalformedTreesAreRejectedWithTheNode) {
    vis::HistoryTree t = handTree();
    t.nodes[3].child[1] = 17;
    try {
        HistoryTreeTopology topo(t);
        FAIL() << "no error";
    } catch (const std::invalid_argument& e) {
        EXPECT_NE(std::string(e.what()).find("node 3 child[1] = 17 is out of range"),
                  std::string::npos)
            << e.what();
    }
    t = handTree();
    t.nodes[2].child[0] = 3;  // node 3 gets two parents
    EXPECT_THROW(HistoryTreeTopology{t}, std::invalid_argument);
    t = handTree();
    t.nodes[4].child[0] = 1;  // a cycle 1 -> 3 -> 4 -> 1
    EXPECT_THROW(HistoryTreeTopology{t}, std::invalid_argument);
    t = handTree();
    t.nodes[4].child[0] = 0;  // back to the root
    EXPECT_THROW(HistoryTreeTopology{t}, std::invalid_argument);
    vis::HistoryTree empty;
    empty.kind = vis::PairKind::Penumbra;
    EXPECT_THROW(HistoryTreeTopology{empty}, std::invalid_argument);
}

TEST(TreeGraphTopology, UnreachableNodesAreLeftOut) {
    vis::HistoryTree t = handTree();
    t.nodes.push_back({});  // node 5: nobody points to it
    const HistoryTreeTopology topo(t);
    EXPECT_EQ(topo.reachableCount(), 5u);
    EXPECT_FALSE(topo.reachable(5));
    const std::vector<uint8_t> collapsed(t.nodes.size(), 0);
    const TreeGraphLayout layout(topo, t, collapsed);
    EXPECT_EQ(layout.itemOfNode(5), kNoIndex);
    checkLayout(t, collapsed, layout, true);
}

TEST(TreeGraphLayout, HandBuiltTree) {
    const vis::HistoryTree t = handTree();
    const HistoryTreeTopology topo(t);
    std::vector<uint8_t> collapsed(t.nodes.size(), 0);
    const TreeGraphLayout layout(topo, t, collapsed);
    checkLayout(t, collapsed, layout, true);
    EXPECT_EQ(layout.itemCount(), 11u);
    EXPECT_EQ(layout.layerCount(), 5u);
    // Hand-derived with the default style (node 1, leaf 0.5, gap 0.25): node 4's leaves are
    // 0.75 apart; node 3 = (hidden leaf, node 4): its leaf must clear node 4's box: distance
    // 0.25 + 0.5 + 0.25 = 1.0. Relative to the root the bottom leaves span the width.
    const GraphItem& n4 = layout.item(layout.itemOfNode(4));
    EXPECT_NEAR(layout.item(n4.child[1]).x - layout.item(n4.child[0]).x, 0.75, kEps);
    const GraphItem& n3 = layout.item(layout.itemOfNode(3));
    EXPECT_NEAR(layout.item(n3.child[1]).x - layout.item(n3.child[0]).x, 1.0, kEps);
    checkCulling(layout, 1, 300);

    collapsed[1] = 1;
    const TreeGraphLayout folded(topo, t, collapsed);
    checkLayout(t, collapsed, folded, true);
    EXPECT_EQ(folded.itemCount(), 5u);  // 0, collapsed 1, 2 and 2's two leaves
    EXPECT_EQ(folded.item(folded.itemOfNode(1)).kind, GraphItemKind::CollapsedNode);
    // Two node-wide boxes under the root, gap apart.
    EXPECT_NEAR(folded.item(folded.itemOfNode(2)).x - folded.item(folded.itemOfNode(1)).x, 1.25,
                kEps);
}

TEST(TreeGraphLayout, TreesWithoutNodesAreOneLeafOrNothing) {
    vis::HistoryTree t;
    t.kind = vis::PairKind::FullyHidden;
    TreeGraphLayout layout(HistoryTreeTopology(t), t, {});
    ASSERT_EQ(layout.itemCount(), 1u);
    EXPECT_EQ(layout.item(0).kind, GraphItemKind::HiddenLeaf);
    EXPECT_EQ(layout.item(0).node, kNoIndex);
    t.kind = vis::PairKind::BackFacing;
    layout = TreeGraphLayout(HistoryTreeTopology(t), t, {});
    EXPECT_EQ(layout.itemCount(), 0u);
    std::vector<uint32_t> got;
    layout.query({-1, -1, 1, 1}, got);
    EXPECT_TRUE(got.empty());
}

TEST(TreeGraphLayout, RandomTreesAndCollapsedSubtrees) {
    std::mt19937_64 rng(7);
    const int trees = penumbra::test::scaled(12);
    for (int k = 0; k < trees; ++k) {
        const uint32_t n = k < 8 ? 1 + uint32_t(rng() % 200) : 2000;
        SCOPED_TRACE("tree " + std::to_string(k) + ", " + std::to_string(n) + " nodes");
        const vis::HistoryTree t = penumbra::devkit::randomHistoryTree(n, 1000 + k);
        const HistoryTreeTopology topo(t);
        ASSERT_EQ(topo.reachableCount(), n);
        EXPECT_EQ(topo.maxDepth + 1, t.depth());
        EXPECT_EQ(topo.visibleLeaves[0], t.leafCount(true));
        EXPECT_EQ(topo.hiddenLeaves[0], t.leafCount(false));
        std::vector<uint8_t> collapsed(n, 0);
        const TreeGraphLayout full(topo, t, collapsed);
        checkLayout(t, collapsed, full, n <= 200);
        ASSERT_EQ(full.itemCount(), 2 * n + 1);
        checkCulling(full, k, 100);

        // Collapse one random node: exactly its descendants disappear, the rest stays.
        const uint32_t c = uint32_t(rng() % n);
        collapsed[c] = 1;
        const TreeGraphLayout one(topo, t, collapsed);
        checkLayout(t, collapsed, one, n <= 200);
        const std::set<uint32_t> gone = descendants(t, c);
        EXPECT_EQ(topo.subtreeNodes[c], gone.size() + 1);
        for (uint32_t v = 0; v < n; ++v)
            EXPECT_EQ(one.itemOfNode(v) == kNoIndex, gone.count(v) == 1) << "node " << v;
        EXPECT_EQ(one.item(one.itemOfNode(c)).kind, GraphItemKind::CollapsedNode);
        EXPECT_EQ(one.itemCount(), full.itemCount() - 2 * gone.size() - 2);

        // Many random collapsed nodes, nested ones included.
        for (uint32_t v = 0; v < n; ++v) collapsed[v] = rng() % 5 == 0;
        const TreeGraphLayout many(topo, t, collapsed);
        checkLayout(t, collapsed, many, n <= 200);
        checkCulling(many, k + 100, 50);
    }
}

TEST(TreeGraphLayout, DeepChainsDoNotOverflowTheStack) {
    const uint32_t n = 100000;
    for (bool zigzag : {false, true}) {
        SCOPED_TRACE(zigzag ? "zigzag" : "straight");
        const vis::HistoryTree t = penumbra::devkit::chainHistoryTree(n, zigzag);
        const HistoryTreeTopology topo(t);
        EXPECT_EQ(topo.maxDepth, n - 1);
        EXPECT_EQ(topo.subtreeNodes[0], n);
        std::vector<uint8_t> collapsed(n, 0);
        const TreeGraphLayout layout(topo, t, collapsed);
        checkLayout(t, collapsed, layout);
        EXPECT_EQ(layout.layerCount(), n + 1);
        checkCulling(layout, 3, 20);
        // A straight chain leans left at a constant slope: its width grows linearly, never
        // faster (each node is only pushed to clear its own leaf).
        if (!zigzag) {
            EXPECT_LT(layout.bounds().x1, 0.75 * n + 2);
        }
        collapsed[n / 2] = 1;
        const TreeGraphLayout half(topo, t, collapsed);
        EXPECT_EQ(half.itemCount(), (n / 2 + 1) + (n / 2));
        EXPECT_EQ(half.itemOfNode(n / 2 + 1), kNoIndex);
        EXPECT_EQ(half.item(half.itemOfNode(n / 2)).kind, GraphItemKind::CollapsedNode);
    }
}

TEST(TreeGraphLayout, RealTreesOfTheStairs) {
    const penumbra::Scene scene = penumbra::makeStairs();
    const uint32_t light = scene.lights.at(0);
    // Receivers whose trees take well under a second to build (face 201: 329 nodes).
    for (uint32_t receiver : {21u, 113u, 201u}) {
        SCOPED_TRACE("receiver " + std::to_string(receiver));
        const vis::HistoryTree t = vis::buildHistoryTree(scene.mesh, receiver, light);
        ASSERT_EQ(t.kind, vis::PairKind::Penumbra);
        const HistoryTreeTopology topo(t);
        EXPECT_EQ(topo.maxDepth + 1, t.depth());
        std::vector<uint8_t> collapsed(t.nodes.size(), 0);
        const TreeGraphLayout full(topo, t, collapsed);
        checkLayout(t, collapsed, full, true);
        checkCulling(full, receiver, 200);
        std::mt19937_64 rng(receiver);
        for (uint32_t v = 0; v < t.nodes.size(); ++v) collapsed[v] = rng() % 6 == 0;
        const TreeGraphLayout some(topo, t, collapsed);
        checkLayout(t, collapsed, some, true);
        checkCulling(some, receiver + 1, 100);
    }
}

TEST(TreeGraphLayout, OtherStylesKeepTheInvariants) {
    const vis::HistoryTree t = penumbra::devkit::randomHistoryTree(150, 99);
    const HistoryTreeTopology topo(t);
    const std::vector<uint8_t> collapsed(t.nodes.size(), 0);
    TreeGraphStyle st;
    st.nodeWidth = 3.0;
    st.leafWidth = 0.2;
    st.gap = 0.0;
    st.layerSpacing = 0.7;
    st.nodeHeight = 1.0;
    const TreeGraphLayout layout(topo, t, collapsed, st);
    checkLayout(t, collapsed, layout, true);
    checkCulling(layout, 5, 200);
}

TEST(TreeGraphLayout, ATopologyOfAnotherTreeIsAnErrorNotALoop) {
    const vis::HistoryTree t = handTree();
    const HistoryTreeTopology topo(t);
    vis::HistoryTree changed = t;
    changed.nodes[4].child[1] = 1;  // a cycle the topology never saw
    const std::vector<uint8_t> collapsed(t.nodes.size(), 0);
    EXPECT_THROW(TreeGraphLayout(topo, changed, collapsed), std::invalid_argument);
    changed = t;
    changed.nodes[4].child[1] = 40;  // out of range
    EXPECT_THROW(TreeGraphLayout(topo, changed, collapsed), std::invalid_argument);
}

TEST(TreeGraphLayout, WrongCollapsedSizeIsAnError) {
    const vis::HistoryTree t = handTree();
    const HistoryTreeTopology topo(t);
    const std::vector<uint8_t> collapsed(3, 0);
    EXPECT_THROW(TreeGraphLayout(topo, t, collapsed), std::invalid_argument);
}

}  // namespace
