// TreeGraphPanel: a Dear ImGui window that draws one history tree as a node graph (the viewer's
// history-tree browser). Only ImGui calls and ImDrawList primitives: the host provides the backend.
//
// Interaction on the canvas: drag (any button) pans, the wheel zooms at the mouse (with Shift only
// horizontally, with Ctrl only vertically), a left click on
// a node collapses or expands its subtree (the node stays under the mouse), hovering shows the
// details of a node or leaf. Buttons: fit (x and y scaled independently), 1:1 (same scale on
// both axes), expand all, collapse to depth N, reveal path (expand the ancestors of every
// highlighted node). Visible and hidden leaves have their own colour and shape
// (legend in the header); the highlighted path (FPQuery's visited nodes) is drawn thick.
// What the canvas shows and at what scale is the panel's TreeGraphView (tree_graph_view.h); the
// highlighted nodes are its TreeGraphHighlight (tree_graph_highlight.h).
//
// Cost per frame: the layout is recomputed only when the tree or its collapsed set changes (O(n));
// drawing visits only the items on screen (TreeGraphLayout::query). Level of detail by the
// on-screen node width: boxes with labels, plain boxes, or - when nodes are under 3 pixels wide - a
// per-pixel-row raster of merged runs, so the draw list is bounded by the canvas size rather than
// the tree size.
#pragma once

#include <imgui.h>

#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "app/viewer/panels/history_tree_topology.h"
#include "app/viewer/panels/tree_graph_highlight.h"
#include "app/viewer/panels/tree_graph_layout.h"
#include "app/viewer/panels/tree_graph_view.h"

namespace penumbra::ui {

enum class TreeGraphDetail : uint8_t { Raster, Boxes, Labelled };

// What the last draw() put on screen (for tests and the viewer's statistics).
struct TreeGraphFrameStats {
    uint32_t itemsOnScreen = 0;   // items the culling query returned
    uint32_t edgesDrawn = 0;      // path edges included
    uint32_t pathEdgesDrawn = 0;  // thick edges between two highlighted nodes
    uint32_t rasterRuns = 0;      // merged rectangles drawn in Raster mode
    TreeGraphDetail detail = TreeGraphDetail::Labelled;
};

class TreeGraphPanel {
  public:
    // The tree to show (null: none) and the node ids to highlight (e.g. FromPointResult::path;
    // copied; ids that are out of range or unreachable are ignored and counted in the header).
    // The panel keeps the pointer: the tree must stay alive and unchanged until the next
    // setTree() (VisibilityStore's trees never change once published; after its clear(), call
    // setTree again). Passing the same tree again only replaces the highlight and keeps collapsed
    // subtrees and the view; it costs O(n) (the highlight's subtree counts), so call it when the
    // selection changes rather than every frame.
    // A malformed tree is not drawn; the window shows why.
    void setTree(const vis::HistoryTree* tree, std::span<const uint32_t> highlightedPath);
    // Optional: the mesh the tree was built on, for vertex coordinates in the tooltips. It must
    // stay alive while set.
    void setMesh(const vis::PolygonMesh* mesh) { mesh_ = mesh; }
    // Draws the window (ImGui::Begin/End inside). Call once per frame between NewFrame and Render.
    void draw(const char* windowTitle);

    // Programmatic control (what the buttons do; also for tests). The view: fit, centre and scale
    // (applied at the next draw()).
    TreeGraphView& view() { return view_; }
    void toggleCollapsed(uint32_t node);
    void expandAll();
    void collapseToDepth(uint32_t depth);  // nodes at that depth collapse, shallower ones expand
    void revealPath();

    bool isCollapsed(uint32_t node) const { return node < collapsed_.size() && collapsed_[node]; }
    // Null without a (well-formed) tree. Recomputed lazily: valid after draw() or ensureLayout().
    const TreeGraphLayout* layout() const { return topology_ ? &layout_ : nullptr; }
    void ensureLayout();
    double lastLayoutMilliseconds() const { return layoutMs_; }
    const TreeGraphFrameStats& lastFrameStats() const { return stats_; }
    // Centre of the node's box on screen in the last drawn frame; nullopt when the node is hidden
    // or nothing was drawn yet.
    std::optional<ImVec2> screenPosOfNode(uint32_t node) const;
    const std::string& error() const { return error_; }

  private:
    void drawHeader();
    void drawCanvas();
    void drawRaster(ImDrawList* dl, const std::vector<uint32_t>& visible);
    void drawBoxes(ImDrawList* dl, const std::vector<uint32_t>& visible, bool labels);
    void drawEdges(ImDrawList* dl);
    void drawPath(ImDrawList* dl);
    void drawTooltip(uint32_t item);
    uint32_t pick(ImVec2 mouse) const;
    // The on-screen rectangle of an item's glyph: its layout box, but no taller than it would be
    // at the view's horizontal scale (a vertically stretched view spreads the layers, not the
    // boxes).
    void glyphRect(uint32_t item, ImVec2& a, ImVec2& c) const;
    void relayoutKeeping(uint32_t node);

    const vis::HistoryTree* tree_ = nullptr;
    const vis::HistoryNode* nodesData_ = nullptr;  // with receiver_, light_: "same tree" check
    uint32_t receiver_ = 0, light_ = 0;
    const vis::PolygonMesh* mesh_ = nullptr;
    std::optional<HistoryTreeTopology> topology_;
    std::string error_;
    std::vector<uint8_t> collapsed_;
    TreeGraphHighlight highlight_;

    TreeGraphLayout layout_;
    bool layoutDirty_ = true;
    double layoutMs_ = 0;

    TreeGraphView view_;
    bool drawn_ = false;
    int collapseDepth_ = 4;

    TreeGraphFrameStats stats_;
    std::vector<uint32_t> scratch_;  // culling results, reused per frame
    // Raster mode: per pixel column of the current row, differences of item counts.
    struct RasterCell {
        int32_t visible = 0, hidden = 0, nodes = 0, collapsed = 0, highlighted = 0;
    };
    std::vector<RasterCell> rasterDiff_;
};

}  // namespace penumbra::ui
