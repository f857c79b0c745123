// TreeGraphHighlight: the nodes the tree browser highlights (FPQuery's visited nodes, the path
// walked for the selected point): which ids were given, which of them name reachable nodes of the
// tree, and per node how many highlighted nodes its subtree holds, so that a collapsed node shows
// that it hides some. Made once per selection (O(n)), read per frame (O(1) per item).
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "app/viewer/panels/history_tree_topology.h"
#include "app/viewer/panels/tree_graph_layout.h"

namespace penumbra::ui {

class TreeGraphHighlight {
  public:
    // The ids to highlight in the tree of `topology` (null: no tree, every id ignored); ids out
    // of range or unreachable are ignored and counted, repeated ones highlighted once.
    void assign(const HistoryTreeTopology* topology, std::span<const uint32_t> ids);

    bool onPath(uint32_t node) const { return onPath_[node] != 0; }
    // Highlighted nodes in the subtree of `node`, itself included.
    uint32_t below(uint32_t node) const { return pathBelow_[node]; }
    // Whether an item is drawn highlighted: a node on the path, or a collapsed node hiding some.
    bool highlights(const GraphItem& it) const {
        if (it.kind == GraphItemKind::Node) return onPath_[it.node] != 0;
        if (it.kind == GraphItemKind::CollapsedNode) return pathBelow_[it.node] != 0;
        return false;
    }
    // The valid highlighted ids, in the order given (first occurrences).
    const std::vector<uint32_t>& nodes() const { return pathNodes_; }
    // How many ids were given, and how many of them were ignored.
    uint32_t requested() const { return pathSize_; }
    uint32_t ignored() const { return pathIgnored_; }

  private:
    std::vector<uint8_t> onPath_;      // per node
    std::vector<uint32_t> pathBelow_;  // per node: highlighted nodes in its subtree
    uint32_t pathSize_ = 0, pathIgnored_ = 0;
    std::vector<uint32_t> pathNodes_;  // the valid highlighted ids
};

}  // namespace penumbra::ui
