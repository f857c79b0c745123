// TreeGraphLayout: a tidy layered drawing of a history tree with some subtrees collapsed.
//
// What is drawn (the "display tree"): every reachable node that has no collapsed proper ancestor.
// An expanded node has exactly two display children, one per child slot: a node, or a leaf glyph
// for a kVisibleLeaf / kHiddenLeaf code (leaves are shared codes in the tree, so every occurrence
// is its own glyph). A collapsed node is drawn as one box with no children; its hidden nodes and
// leaves are counted by HistoryTreeTopology.
//
// Geometry (layout units; the viewer scales them to pixels): depth d is layer d, its boxes centred
// at y = d * layerSpacing (y grows downwards, root on top). Within a layer boxes never overlap and
// are at least `gap` apart; child[0] (positive side) is drawn left of child[1]; every expanded node
// is centred exactly over the centres of its two children. Positions are those of the classic
// Reingold-Tilford algorithm for binary trees (contour threads, linear time and memory, no
// recursion): each pair of sibling subtrees is pushed together until their facing contours are
// `gap` apart at some layer, so sibling subtrees always touch somewhere (the drawing is as narrow
// as this rule allows, not globally minimal in width). The leftmost box edge is at x = 0.
// Coordinates are doubles: exact up to rounding of sums of the style's widths.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "app/viewer/panels/history_tree_topology.h"

namespace penumbra::ui {

struct TreeGraphStyle {
    double nodeWidth = 1.0;
    double nodeHeight = 0.6;
    double leafWidth = 0.5;
    double leafHeight = 0.5;
    double gap = 0.25;          // minimum horizontal distance between two boxes of one layer
    double layerSpacing = 1.5;  // vertical distance between the centres of consecutive layers
};

// An axis-aligned rectangle in layout units, closed: touching rectangles intersect.
struct GraphRect {
    double x0 = 0, y0 = 0, x1 = 0, y1 = 0;
    bool intersects(const GraphRect& o) const {
        return x0 <= o.x1 && o.x0 <= x1 && y0 <= o.y1 && o.y0 <= y1;
    }
    bool contains(double x, double y) const { return x0 <= x && x <= x1 && y0 <= y && y <= y1; }
};

enum class GraphItemKind : uint8_t { Node, CollapsedNode, VisibleLeaf, HiddenLeaf };

inline bool isLeafItem(GraphItemKind k) {
    return k == GraphItemKind::VisibleLeaf || k == GraphItemKind::HiddenLeaf;
}

// One drawn box. Items are stored in display pre-order (parent before children, child[0]'s
// subtree before child[1]'s), so item 0 is the root.
struct GraphItem {
    uint32_t node = kNoIndex;    // Node / CollapsedNode: the tree node; leaf: the parent node
                                 // (kNoIndex for the single leaf of a tree without nodes)
    uint32_t parent = kNoIndex;  // parent item, kNoIndex for the root
    uint32_t child[2] = {kNoIndex, kNoIndex};  // child items of an expanded node
    uint32_t depth = 0;                        // layer
    uint8_t side = 0;  // leaf: the child slot of `node` it occupies (0 positive, 1 negative)
    GraphItemKind kind = GraphItemKind::Node;
    double x = 0;  // centre
};

class TreeGraphLayout {
  public:
    TreeGraphLayout() = default;
    // collapsed[i] != 0 collapses node i (ignored where an ancestor is already collapsed); its
    // size must be the tree's node count. O(n) time and memory, n = drawn items.
    TreeGraphLayout(const HistoryTreeTopology& topology, const vis::HistoryTree& tree,
                    std::span<const uint8_t> collapsed, const TreeGraphStyle& style = {}) {
        compute(topology, tree, collapsed, style);
    }
    // The same, reusing this object's buffers (no fresh allocations: cheaper when the panel
    // relayouts after each collapse or expand). Throws std::invalid_argument when `collapsed`
    // has the wrong size.
    void compute(const HistoryTreeTopology& topology, const vis::HistoryTree& tree,
                 std::span<const uint8_t> collapsed, const TreeGraphStyle& style = {});

    const TreeGraphStyle& style() const { return style_; }
    std::span<const GraphItem> items() const { return items_; }
    const GraphItem& item(uint32_t i) const { return items_[i]; }
    uint32_t itemCount() const { return static_cast<uint32_t>(items_.size()); }
    // The item drawing node `node`, or kNoIndex when the node is hidden or unreachable.
    uint32_t itemOfNode(uint32_t node) const {
        return node < itemOfNode_.size() ? itemOfNode_[node] : kNoIndex;
    }

    double layerY(uint32_t depth) const { return depth * style_.layerSpacing; }
    double halfWidth(const GraphItem& it) const {
        return 0.5 * (isLeafItem(it.kind) ? style_.leafWidth : style_.nodeWidth);
    }
    double halfHeight(const GraphItem& it) const {
        return 0.5 * (isLeafItem(it.kind) ? style_.leafHeight : style_.nodeHeight);
    }
    GraphRect box(uint32_t i) const;
    GraphRect bounds() const { return bounds_; }  // of all boxes; all zero when empty

    uint32_t layerCount() const { return static_cast<uint32_t>(layerStart_.size()) - 1; }
    // The items of one layer, sorted by x (left to right).
    std::span<const uint32_t> layer(uint32_t depth) const {
        return std::span<const uint32_t>(layerItems_)
            .subspan(layerStart_[depth], layerStart_[depth + 1] - layerStart_[depth]);
    }
    // Appends to `out` every item whose box intersects `r`, layer by layer, left to right.
    // O(layers in r * log n + output): a binary search per layer.
    void query(const GraphRect& r, std::vector<uint32_t>& out) const;
    // Within layer `depth`: the position (index into layer(depth)) of the first item whose box
    // ends at or right of x, i.e. the first that can reach x or lie beyond it.
    uint32_t firstInLayerFrom(uint32_t depth, double x) const;

  private:
    // Per-item state of the Reingold-Tilford pass (see compute()), kept between computations.
    struct Contour {
        double rel = 0, threadOff = 0, elOff = 0, erOff = 0;
        uint32_t thread = kNoIndex, el = 0, er = 0, bottom = 0;
    };

    TreeGraphStyle style_;
    std::vector<Contour> contour_;
    std::vector<uint32_t> stackScratch_;
    std::vector<GraphItem> items_;
    std::vector<uint32_t> itemOfNode_;
    std::vector<uint32_t> layerStart_{0};  // layerCount() + 1 offsets into layerItems_
    std::vector<uint32_t> layerItems_;
    GraphRect bounds_;
};

}  // namespace penumbra::ui
