// HistoryTreeTopology: the shape of a history tree as the tree browser needs it - parents, depths,
// subtree sizes and leaf counts, a depth-first order - computed once per tree in O(n) time and
// memory without recursion (trees can be tens of thousands of levels deep).
//
// The tree is validated on the way: every child index must name an existing node and every node
// must be reached at most once from the root (no node shared by two parents, no cycle). Nodes the
// root does not reach (the builder may leave some behind) are kept out of every count.
#pragma once

#include <cstdint>
#include <optional>
#include <vector>

#include "visibility/history_tree.h"

namespace penumbra::ui {

inline constexpr uint32_t kNoIndex = 0xFFFFFFFFu;

struct HistoryTreeTopology {
    // Throws std::invalid_argument naming the node and the problem when the tree is malformed
    // (a child index out of range, a node reached twice, a Penumbra tree without nodes).
    explicit HistoryTreeTopology(const vis::HistoryTree& tree);

    // When the tree has no nodes: the single leaf that stands for the whole pair (kVisibleLeaf for
    // FullyVisible, kHiddenLeaf for FullyHidden); none when there is nothing to draw (BackFacing)
    // or when the tree has nodes.
    std::optional<uint32_t> rootLeaf;

    // Per node (indexed like HistoryTree::nodes); kNoIndex / 0 for unreachable nodes.
    std::vector<uint32_t> parent;         // kNoIndex for the root
    std::vector<uint32_t> depth;          // root 0
    std::vector<uint32_t> subtreeNodes;   // inner nodes in the subtree, the node included
    std::vector<uint32_t> visibleLeaves;  // visible-leaf occurrences in the subtree
    std::vector<uint32_t> hiddenLeaves;   // hidden-leaf occurrences in the subtree
    // Reachable nodes in depth-first pre-order, child[0]'s subtree before child[1]'s.
    std::vector<uint32_t> preorder;
    std::vector<uint32_t>
        preorderIndex;      // position of each node in `preorder`; kNoIndex if unreachable
    uint32_t maxDepth = 0;  // deepest reachable node (the leaves below it are one deeper)

    uint32_t nodeCount() const { return static_cast<uint32_t>(parent.size()); }
    uint32_t reachableCount() const { return static_cast<uint32_t>(preorder.size()); }
    bool reachable(uint32_t node) const { return depth[node] != kNoIndex; }
    // True when `ancestor` is `node` or lies on the path from the root to it (both reachable).
    // O(1): a subtree is a contiguous range of the pre-order.
    bool isAncestorOrSelf(uint32_t ancestor, uint32_t node) const {
        const uint32_t a = preorderIndex[ancestor], n = preorderIndex[node];
        return a != kNoIndex && n != kNoIndex && a <= n && n - a < subtreeNodes[ancestor];
    }
};

}  // namespace penumbra::ui
