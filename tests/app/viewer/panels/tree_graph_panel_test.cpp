// The history-tree browser panel, headless: an ImGui context without a backend (display size set,
// font atlas built, NewFrame / draw / Render), a 50k-node tree, simulated mouse input.
#include "app/viewer/panels/tree_graph_panel.h"

#include <gtest/gtest.h>
#include <imgui.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "engine/scene/procedural_scenes.h"
#include "tools/devkit/headless_imgui.h"
#include "tools/devkit/random_history_tree.h"
#include "visibility/fp_query/from_point_query.h"
#include "visibility/history_tree_builder.h"

namespace {

using penumbra::ui::GraphItemKind;
using penumbra::ui::kNoIndex;
using penumbra::ui::TreeGraphDetail;
using penumbra::ui::TreeGraphPanel;
namespace vis = penumbra::vis;

// One ImGui context for one test (tools/devkit/headless_imgui.h); frames drawn with the panel's
// window filling the display.
class ImGuiHost {
  public:
    ImDrawData* frame(TreeGraphPanel& panel) {
        return imgui_.frame([&] { panel.draw("History tree"); });
    }
    static size_t vertices(const ImDrawData* d) {
        return penumbra::devkit::HeadlessImGui::vertices(d);
    }
    // Left click at p: move there, press, release (one frame each).
    void click(TreeGraphPanel& panel, ImVec2 p) {
        ImGuiIO& io = ImGui::GetIO();
        io.MousePos = p;
        frame(panel);
        io.MouseDown[0] = true;
        frame(panel);
        io.MouseDown[0] = false;
        frame(panel);
    }

  private:
    penumbra::devkit::HeadlessImGui imgui_;
};

// The root-to-leaf path that always follows child[0] while it is a node.
std::vector<uint32_t> leftmostPath(const vis::HistoryTree& t) {
    std::vector<uint32_t> path{0};
    while (!vis::isLeaf(t.nodes[path.back()].child[0]))
        path.push_back(t.nodes[path.back()].child[0]);
    return path;
}

TEST(TreeGraphPanel, FiftyThousandNodesDrawBoundedAndClicksCollapse) {
    ImGuiHost host;
    const uint32_t n = 50000;
    const vis::HistoryTree tree = penumbra::devkit::randomHistoryTree(n, 42);
    const std::vector<uint32_t> path = leftmostPath(tree);
    TreeGraphPanel panel;
    panel.setTree(&tree, path);

    // Zoomed out to fit: the raster level of detail; the draw list is bounded by the canvas,
    // not by the 100,001 items (a plain quad per item alone would be 400,004 vertices).
    host.frame(panel);
    const ImDrawData* fitted = host.frame(panel);
    ASSERT_NE(panel.layout(), nullptr);
    const uint32_t items = panel.layout()->itemCount();
    ASSERT_EQ(items, 2 * n + 1);
    EXPECT_EQ(panel.lastFrameStats().detail, TreeGraphDetail::Raster);
    EXPECT_EQ(panel.lastFrameStats().itemsOnScreen, items);  // everything is in view
    // The whole highlighted path is drawn, even at this level of detail.
    EXPECT_EQ(panel.lastFrameStats().pathEdgesDrawn, path.size() - 1);
    const size_t fitVertices = ImGuiHost::vertices(fitted);
    EXPECT_GT(fitVertices, 0u);
    EXPECT_LT(fitVertices, size_t(items));  // under one vertex per item

    const uint32_t fitRuns = panel.lastFrameStats().rasterRuns;
    EXPECT_GT(fitRuns, 0u);

    // Zoomed in on the middle of the busiest layer: labelled boxes, only what is on screen.
    const auto* layout = panel.layout();
    uint32_t busiest = 0;
    for (uint32_t d = 0; d < layout->layerCount(); ++d)
        if (layout->layer(d).size() > layout->layer(busiest).size()) busiest = d;
    const auto mid = layout->layer(busiest)[layout->layer(busiest).size() / 2];
    panel.view().centreOn(layout->item(mid).x, layout->layerY(busiest), 40.0);
    const ImDrawData* zoomed = host.frame(panel);
    EXPECT_EQ(panel.lastFrameStats().detail, TreeGraphDetail::Labelled);
    const uint32_t onScreen = panel.lastFrameStats().itemsOnScreen;
    EXPECT_GT(onScreen, 50u);
    EXPECT_LT(onScreen, 2000u);
    const size_t zoomVertices = ImGuiHost::vertices(zoomed);
    EXPECT_GT(zoomVertices, 0u);
    EXPECT_LT(zoomVertices, size_t(items));
    std::printf(
        "50k nodes: fit %zu vertices (%u runs); zoomed in %zu vertices, %u items on screen\n",
        fitVertices, fitRuns, zoomVertices, onScreen);

    // Zoomed in on the root's child[0].
    const uint32_t target = tree.nodes[0].child[0];
    ASSERT_FALSE(vis::isLeaf(target));
    const auto& targetItem = layout->item(layout->itemOfNode(target));
    panel.view().centreOn(targetItem.x, layout->layerY(targetItem.depth) + 2.0, 40.0);
    host.frame(panel);

    // Click it: its subtree collapses, and it stays under the mouse.
    const uint32_t grandchild = path.size() > 2 ? path[2] : kNoIndex;
    const auto pos = panel.screenPosOfNode(target);
    ASSERT_TRUE(pos.has_value());
    host.click(panel, *pos);
    EXPECT_TRUE(panel.isCollapsed(target));
    layout = panel.layout();
    EXPECT_EQ(layout->item(layout->itemOfNode(target)).kind, GraphItemKind::CollapsedNode);
    if (grandchild != kNoIndex) {
        EXPECT_EQ(layout->itemOfNode(grandchild), kNoIndex);
    }
    const auto after = panel.screenPosOfNode(target);
    ASSERT_TRUE(after.has_value());
    EXPECT_NEAR(after->x, pos->x, 0.5f);
    EXPECT_NEAR(after->y, pos->y, 0.5f);
    // Hovering it shows a tooltip: a second window's draw list.
    EXPECT_GE(ImGui::GetDrawData()->CmdListsCount, 2);

    // Click again: expanded, the whole tree is back.
    host.click(panel, *after);
    EXPECT_FALSE(panel.isCollapsed(target));
    EXPECT_EQ(panel.layout()->itemCount(), items);
}

TEST(TreeGraphPanel, DragPansWheelZoomsAtTheMouseAndNeitherCollapses) {
    ImGuiHost host;
    const vis::HistoryTree tree = penumbra::devkit::randomHistoryTree(300, 5);
    TreeGraphPanel panel;
    panel.setTree(&tree, {});
    panel.ensureLayout();
    panel.view().centreOn(panel.layout()->item(0).x, 3.0, 30.0);
    host.frame(panel);
    const auto start = panel.screenPosOfNode(0);
    ASSERT_TRUE(start.has_value());

    // Drag from the root by 100 px right and 40 px down in steps larger than the drag threshold.
    ImGuiIO& io = ImGui::GetIO();
    io.MousePos = *start;
    host.frame(panel);
    io.MouseDown[0] = true;
    host.frame(panel);
    for (int k = 1; k <= 5; ++k) {
        io.MousePos = ImVec2(start->x + 20.0f * k, start->y + 8.0f * k);
        host.frame(panel);
    }
    io.MouseDown[0] = false;
    host.frame(panel);
    EXPECT_FALSE(panel.isCollapsed(0));
    const auto moved = panel.screenPosOfNode(0);
    ASSERT_TRUE(moved.has_value());
    EXPECT_NEAR(moved->x - start->x, 100.0f, 0.5f);
    EXPECT_NEAR(moved->y - start->y, 40.0f, 0.5f);

    // Wheel at a point 50 px left of the root: that point stays, the root's distance to it
    // grows by 1.2 per notch.
    const ImVec2 anchor(moved->x - 50.0f, moved->y);
    io.MousePos = anchor;
    host.frame(panel);
    io.MouseWheel = 2.0f;
    host.frame(panel);
    const auto zoomed = panel.screenPosOfNode(0);
    ASSERT_TRUE(zoomed.has_value());
    EXPECT_NEAR(zoomed->x - anchor.x, 50.0f * 1.44f, 0.5f);
    EXPECT_NEAR(zoomed->y - anchor.y, 0.0f, 0.5f);
    EXPECT_FALSE(panel.isCollapsed(0));
}

TEST(TreeGraphPanel, ButtonsActionsAndOddTrees) {
    ImGuiHost host;
    const vis::HistoryTree tree = penumbra::devkit::randomHistoryTree(2000, 8);
    TreeGraphPanel panel;
    // Path ids out of range are ignored, not a crash.
    const std::vector<uint32_t> path{0, tree.nodes[0].child[0], 999999};
    panel.setTree(&tree, path);
    host.frame(panel);
    panel.collapseToDepth(2);
    // Only nodes at depth <= 2 remain; those at depth 2 are collapsed.
    const auto* layout = panel.layout();
    for (const auto& it : layout->items()) {
        EXPECT_LE(it.depth, 3u);
        if (!penumbra::ui::isLeafItem(it.kind)) {
            EXPECT_EQ(it.kind == GraphItemKind::CollapsedNode, it.depth == 2);
        }
    }
    panel.revealPath();  // path nodes are at depth <= 1: nothing hidden, nothing changes
    panel.expandAll();
    EXPECT_EQ(panel.layout()->itemCount(), 2 * 2000u + 1);
    host.frame(panel);

    // A deep path hidden by a collapse is revealed again.
    const std::vector<uint32_t> deep = leftmostPath(tree);
    panel.setTree(&tree, deep);  // same tree: keeps the view and collapsed set
    panel.collapseToDepth(1);
    ASSERT_GT(deep.size(), 2u);
    EXPECT_EQ(panel.layout()->itemOfNode(deep.back()), kNoIndex);
    panel.revealPath();
    EXPECT_NE(panel.layout()->itemOfNode(deep.back()), kNoIndex);
    host.frame(panel);

    // A malformed tree is reported, not drawn.
    vis::HistoryTree bad = tree;
    bad.nodes[5].child[1] = 123456789;
    panel.setTree(&bad, {});
    host.frame(panel);
    EXPECT_NE(panel.error().find("out of range"), std::string::npos);
    EXPECT_EQ(panel.layout(), nullptr);

    // Pairs without a tree: one leaf glyph, or nothing.
    vis::HistoryTree lit;
    lit.kind = vis::PairKind::FullyVisible;
    panel.setTree(&lit, {});
    host.frame(panel);
    ASSERT_NE(panel.layout(), nullptr);
    EXPECT_EQ(panel.layout()->itemCount(), 1u);
    vis::HistoryTree back;
    back.kind = vis::PairKind::BackFacing;
    panel.setTree(&back, {});
    host.frame(panel);
    panel.setTree(nullptr, {});
    host.frame(panel);
    EXPECT_EQ(panel.layout(), nullptr);
}

TEST(TreeGraphPanel, RealTreeWithTheQueryPathOfAPoint) {
    ImGuiHost host;
    const penumbra::Scene scene = penumbra::makeStairs();
    const uint32_t receiver = 21;
    const vis::HistoryTree tree = vis::buildHistoryTree(scene.mesh, receiver, scene.lights.at(0));
    ASSERT_EQ(tree.kind, vis::PairKind::Penumbra);
    // A point on the receiver: the centroid of its face.
    vis::Vec3 c{};
    for (uint32_t v : scene.mesh.faces[receiver]) c += scene.mesh.vertices[v];
    c = c / double(scene.mesh.faces[receiver].size());
    const std::vector<uint32_t> path =
        vis::traceNodes(vis::fromPointQuery(scene.mesh, tree, c).trace);
    ASSERT_FALSE(path.empty());
    // The query's path is a subtree hanging from the root: each node but the root has its parent
    // on the path (checked on the tree itself), so it has path.size() - 1 edges.
    std::vector<uint32_t> parent(tree.nodes.size(), kNoIndex);
    for (uint32_t v = 0; v < tree.nodes.size(); ++v)
        for (uint32_t ch : tree.nodes[v].child)
            if (!vis::isLeaf(ch)) parent[ch] = v;
    EXPECT_EQ(path.front(), 0u);
    for (size_t k = 1; k < path.size(); ++k)
        EXPECT_NE(std::find(path.begin(), path.end(), parent[path[k]]), path.end());

    TreeGraphPanel panel;
    panel.setMesh(&scene.mesh);
    panel.setTree(&tree, path);
    host.frame(panel);
    host.frame(panel);
    EXPECT_EQ(panel.lastFrameStats().pathEdgesDrawn, path.size() - 1);
    EXPECT_EQ(panel.lastFrameStats().itemsOnScreen, panel.layout()->itemCount());
    // Hover the deepest path node: a tooltip (the mesh is set: coordinates are formatted).
    const auto p = panel.screenPosOfNode(path.back());
    ASSERT_TRUE(p.has_value());
    ImGui::GetIO().MousePos = *p;
    host.frame(panel);
    host.frame(panel);  // a new tooltip window is hidden on its first frame (auto-sizing)
    EXPECT_GE(ImGui::GetDrawData()->CmdListsCount, 2);
    // Collapsing the root hides the path but one node: no path edge is left to draw.
    panel.toggleCollapsed(0);
    host.frame(panel);
    EXPECT_EQ(panel.lastFrameStats().pathEdgesDrawn, 0u);
    panel.revealPath();
    host.frame(panel);
    EXPECT_EQ(panel.lastFrameStats().pathEdgesDrawn, path.size() - 1);
}

}  // namespace
