#include "app/viewer/panels/tree_graph_layout.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <stdexcept>
#include <string>

namespace penumbra::ui {
namespace {

// The display tree in pre-order, built with an explicit stack.
void buildItems(const HistoryTreeTopology& topo, const vis::HistoryTree& tree,
                std::span<const uint8_t> collapsed, std::vector<GraphItem>& items,
                std::vector<uint32_t>& itemOfNode) {
    itemOfNode.assign(topo.nodeCount(), kNoIndex);
    if (topo.rootLeaf) {
        GraphItem leaf;
        leaf.kind = *topo.rootLeaf == vis::kVisibleLeaf ? GraphItemKind::VisibleLeaf
                                                        : GraphItemKind::HiddenLeaf;
        items.push_back(leaf);
        return;
    }
    if (topo.nodeCount() == 0) return;
    if (collapsed.size() != topo.nodeCount())
        throw std::invalid_argument("tree graph layout: collapsed flags for " +
                                    std::to_string(collapsed.size()) + " nodes, tree has " +
                                    std::to_string(topo.nodeCount()));
    // Each expanded node adds two items: reserve for the whole tree expanded.
    items.reserve(2 * size_t(topo.reachableCount()) + 1);
    struct Pending {
        uint32_t code;        // node index or leaf code
        uint32_t parentItem;  // kNoIndex for the root
        uint8_t side;
    };
    std::vector<Pending> stack{{0, kNoIndex, 0}};
    while (!stack.empty()) {
        const Pending p = stack.back();
        stack.pop_back();
        const uint32_t index = static_cast<uint32_t>(items.size());
        GraphItem it;
        it.parent = p.parentItem;
        it.side = p.side;
        if (p.parentItem != kNoIndex) {
            items[p.parentItem].child[p.side] = index;
            it.depth = items[p.parentItem].depth + 1;
        }
        if (vis::isLeaf(p.code)) {
            it.kind = p.code == vis::kVisibleLeaf ? GraphItemKind::VisibleLeaf
                                                  : GraphItemKind::HiddenLeaf;
            it.node = items[p.parentItem].node;
            items.push_back(it);
            continue;
        }
        // Checked again here (HistoryTreeTopology validated the tree): a layout must never loop or
        // read out of range, even for a topology that does not match the tree.
        if (p.code >= itemOfNode.size() || itemOfNode[p.code] != kNoIndex)
            throw std::invalid_argument("tree graph layout: node " + std::to_string(p.code) +
                                        " is out of range or reached twice: not a tree, or not "
                                        "the tree the topology was computed for");
        it.node = p.code;
        it.kind = collapsed[p.code] ? GraphItemKind::CollapsedNode : GraphItemKind::Node;
        itemOfNode[p.code] = index;
        items.push_back(it);
        if (it.kind == GraphItemKind::Node) {
            // child[1] first so that child[0]'s subtree comes first in pre-order.
            stack.push_back({tree.nodes[p.code].child[1], index, 1});
            stack.push_back({tree.nodes[p.code].child[0], index, 0});
        }
    }
}

}  // namespace

void TreeGraphLayout::compute(const HistoryTreeTopology& topology, const vis::HistoryTree& tree,
                              std::span<const uint8_t> collapsed, const TreeGraphStyle& style) {
    style_ = style;
    items_.clear();
    layerStart_.assign(1, 0);
    layerItems_.clear();
    bounds_ = {};
    buildItems(topology, tree, collapsed, items_, itemOfNode_);
    const uint32_t m = static_cast<uint32_t>(items_.size());
    if (m == 0) return;

    // Reingold-Tilford, bottom-up (reverse pre-order visits children before parents).
    //   rel: x of the item relative to its parent (final once the parent is processed);
    //   thread, threadOff: for a childless item on a contour, the next contour item one layer
    //     down and its x relative to this one (set when a shallower sibling subtree is merged);
    //   el/er: leftmost / rightmost item on the deepest layer of the item's subtree, elOff/erOff
    //     their x relative to the item; bottom: that deepest layer.
    // Merging the two subtrees of v walks the right contour of the left one and the left contour
    // of the right one down to the shallower one's bottom: O(n) in all (each step of the walk
    // is paid by a contour node that the merge then hides inside the combined subtree).
    // One record per item (one cache line) rather than eight arrays: the contour walks jump.
    std::vector<Contour>& ct = contour_;
    ct.assign(m, Contour{});
    const auto half = [&](uint32_t i) { return halfWidth(items_[i]); };
    // Next node down the right (left) contour and the x step to it.
    const auto nextRight = [&](uint32_t v, double& step) {
        const uint32_t c = items_[v].child[1];
        if (c != kNoIndex) {
            step = ct[c].rel;
            return c;
        }
        step = ct[v].threadOff;
        return ct[v].thread;
    };
    const auto nextLeft = [&](uint32_t v, double& step) {
        const uint32_t c = items_[v].child[0];
        if (c != kNoIndex) {
            step = ct[c].rel;
            return c;
        }
        step = ct[v].threadOff;
        return ct[v].thread;
    };
    for (uint32_t v = m; v-- > 0;) {
        const GraphItem& it = items_[v];
        if (it.child[0] == kNoIndex) {
            ct[v].el = ct[v].er = v;
            ct[v].bottom = it.depth;
            continue;
        }
        const uint32_t left = it.child[0], right = it.child[1];
        // Walk both facing contours; offsets are relative to the roots of the two subtrees.
        uint32_t l = left, r = right;
        double lOff = 0, rOff = 0, distance = 0;
        uint32_t nl, nr;
        double stepL, stepR;
        for (;;) {
            distance = std::max(distance, lOff - rOff + half(l) + half(r) + style_.gap);
            nl = nextRight(l, stepL);
            nr = nextLeft(r, stepR);
            if (nl == kNoIndex || nr == kNoIndex) break;
            lOff += stepL;
            rOff += stepR;
            l = nl;
            r = nr;
        }
        ct[left].rel = -0.5 * distance;
        ct[right].rel = 0.5 * distance;
        if (nl != kNoIndex) {
            // The left subtree is deeper: the right contour continues from the right subtree's
            // bottom-right item into the left subtree.
            const uint32_t from = ct[right].er;
            ct[from].thread = nl;
            ct[from].threadOff = (ct[left].rel + lOff + stepL) - (ct[right].rel + ct[right].erOff);
        } else if (nr != kNoIndex) {
            const uint32_t from = ct[left].el;
            ct[from].thread = nr;
            ct[from].threadOff = (ct[right].rel + rOff + stepR) - (ct[left].rel + ct[left].elOff);
        }
        const uint32_t lowL = ct[left].bottom >= ct[right].bottom ? left : right;
        const uint32_t lowR = ct[right].bottom >= ct[left].bottom ? right : left;
        ct[v].el = ct[lowL].el;
        ct[v].elOff = ct[lowL].rel + ct[lowL].elOff;
        ct[v].er = ct[lowR].er;
        ct[v].erOff = ct[lowR].rel + ct[lowR].erOff;
        ct[v].bottom = std::max(ct[left].bottom, ct[right].bottom);
    }

    // Absolute positions top-down (pre-order: parents first), then shift the left edge to 0.
    double minX = 0;
    for (uint32_t v = 0; v < m; ++v) {
        GraphItem& it = items_[v];
        if (it.parent != kNoIndex) it.x = items_[it.parent].x + ct[v].rel;
        minX = std::min(minX, it.x - halfWidth(it));
    }
    bounds_ = {0, 0, 0, 0};
    double maxX = 0, maxY = 0, minY = 0;
    bool first = true;
    for (GraphItem& it : items_) {
        it.x -= minX;
        const double y = layerY(it.depth);
        const double x0 = it.x - halfWidth(it), x1 = it.x + halfWidth(it);
        const double y0 = y - halfHeight(it), y1 = y + halfHeight(it);
        maxX = first ? x1 : std::max(maxX, x1);
        minY = first ? y0 : std::min(minY, y0);
        maxY = first ? y1 : std::max(maxY, y1);
        bounds_.x0 = first ? x0 : std::min(bounds_.x0, x0);
        first = false;
    }
    bounds_.x1 = maxX;
    bounds_.y0 = minY;
    bounds_.y1 = maxY;

    // Layers by counting sort on depth. Pre-order meets each layer's items left to right (sibling
    // subtrees never interleave within a layer), so each bucket comes out sorted by x.
    uint32_t layers = 0;
    for (const GraphItem& it : items_) layers = std::max(layers, it.depth + 1);
    layerStart_.assign(layers + 1, 0);
    for (const GraphItem& it : items_) ++layerStart_[it.depth + 1];
    for (uint32_t d = 0; d < layers; ++d) layerStart_[d + 1] += layerStart_[d];
    layerItems_.assign(m, 0);
    std::vector<uint32_t>& fill = stackScratch_;
    fill.assign(layerStart_.begin(), layerStart_.end() - 1);
    for (uint32_t v = 0; v < m; ++v) layerItems_[fill[items_[v].depth]++] = v;
#ifndef NDEBUG
    for (uint32_t d = 0; d < layers; ++d) {
        const auto l = layer(d);
        assert(std::is_sorted(l.begin(), l.end(),
                              [&](uint32_t a, uint32_t b) { return items_[a].x < items_[b].x; }));
    }
#endif
}

GraphRect TreeGraphLayout::box(uint32_t i) const {
    const GraphItem& it = items_[i];
    const double y = layerY(it.depth);
    return {it.x - halfWidth(it), y - halfHeight(it), it.x + halfWidth(it), y + halfHeight(it)};
}

uint32_t TreeGraphLayout::firstInLayerFrom(uint32_t depth, double x) const {
    // Boxes of a layer are disjoint and sorted, so their right edges are sorted too.
    const auto l = layer(depth);
    const auto it = std::partition_point(
        l.begin(), l.end(), [&](uint32_t i) { return items_[i].x + halfWidth(items_[i]) < x; });
    return static_cast<uint32_t>(it - l.begin());
}

void TreeGraphLayout::query(const GraphRect& r, std::vector<uint32_t>& out) const {
    // (Also rejects NaN coordinates.)
    if (items_.empty() || !(r.x0 <= r.x1 && r.y0 <= r.y1)) return;
    // Layers whose tallest possible box may reach [y0, y1] (rounded outwards; the exact test is
    // the box test below).
    const double reach = 0.5 * std::max(style_.nodeHeight, style_.leafHeight);
    const double s = style_.layerSpacing;
    const double lo = std::floor((r.y0 - reach) / s), hi = std::ceil((r.y1 + reach) / s);
    if (hi < 0 || lo > double(layerCount()) - 1) return;
    const uint32_t d0 = lo < 0 ? 0 : static_cast<uint32_t>(lo);
    const uint32_t d1 = std::min<double>(hi, layerCount() - 1);
    for (uint32_t d = d0; d <= d1; ++d) {
        const auto l = layer(d);
        for (uint32_t k = firstInLayerFrom(d, r.x0); k < l.size(); ++k) {
            const uint32_t i = l[k];
            if (items_[i].x - halfWidth(items_[i]) > r.x1) break;
            if (box(i).intersects(r)) out.push_back(i);
        }
    }
}

}  // namespace penumbra::ui
