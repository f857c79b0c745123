#include "app/viewer/panels/history_tree_topology.h"

#include <algorithm>
#include <stdexcept>
#include <string>

namespace penumbra::ui {

HistoryTreeTopology::HistoryTreeTopology(const vis::HistoryTree& tree) {
    const size_t n = tree.nodes.size();
    if (n >= kNoIndex) throw std::invalid_argument("history tree: too many nodes");
    if (n == 0) {
        if (tree.kind == vis::PairKind::Penumbra && !tree.partial())
            throw std::invalid_argument("history tree: a penumbra pair with no nodes");
        // A partial tree with no node: one visible leaf (its occluders are all deferred).
        if (tree.kind == vis::PairKind::FullyVisible || tree.kind == vis::PairKind::Penumbra)
            rootLeaf = vis::kVisibleLeaf;
        if (tree.kind == vis::PairKind::FullyHidden) rootLeaf = vis::kHiddenLeaf;
        return;
    }
    parent.assign(n, kNoIndex);
    depth.assign(n, kNoIndex);
    subtreeNodes.assign(n, 0);
    visibleLeaves.assign(n, 0);
    hiddenLeaves.assign(n, 0);
    preorderIndex.assign(n, kNoIndex);
    preorder.reserve(n);

    // Pre-order with an explicit stack; child[1] is pushed first so child[0] is visited first.
    std::vector<uint32_t> stack{0};
    depth[0] = 0;
    while (!stack.empty()) {
        const uint32_t v = stack.back();
        stack.pop_back();
        preorderIndex[v] = static_cast<uint32_t>(preorder.size());
        preorder.push_back(v);
        maxDepth = std::max(maxDepth, depth[v]);
        for (int side = 1; side >= 0; --side) {
            const uint32_t c = tree.nodes[v].child[side];
            if (vis::isLeaf(c)) continue;
            if (c >= n)
                throw std::invalid_argument("history tree: node " + std::to_string(v) + " child[" +
                                            std::to_string(side) + "] = " + std::to_string(c) +
                                            " is out of range (" + std::to_string(n) + " nodes)");
            if (c == 0 || depth[c] != kNoIndex)
                throw std::invalid_argument("history tree: node " + std::to_string(c) +
                                            " is reached twice (again from node " +
                                            std::to_string(v) + " child[" + std::to_string(side) +
                                            "]): not a tree");
            parent[c] = v;
            depth[c] = depth[v] + 1;
            stack.push_back(c);
        }
    }
    // Children come after their parent in pre-order: accumulate the counts in reverse.
    for (size_t i = preorder.size(); i-- > 0;) {
        const uint32_t v = preorder[i];
        subtreeNodes[v] += 1;
        for (uint32_t c : tree.nodes[v].child) {
            if (c == vis::kVisibleLeaf) ++visibleLeaves[v];
            if (c == vis::kHiddenLeaf) ++hiddenLeaves[v];
        }
        const uint32_t p = parent[v];
        if (p == kNoIndex) continue;
        subtreeNodes[p] += subtreeNodes[v];
        visibleLeaves[p] += visibleLeaves[v];
        hiddenLeaves[p] += hiddenLeaves[v];
    }
}

}  // namespace penumbra::ui
