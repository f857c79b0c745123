#include "visibility/history_tree.h"

#include <algorithm>
#include <utility>

namespace penumbra::vis {

std::string_view toString(PairKind k) {
    switch (k) {
        case PairKind::BackFacing:
            return "back-facing";
        case PairKind::FullyVisible:
            return "fully-visible";
        case PairKind::FullyHidden:
            return "fully-hidden";
        case PairKind::Penumbra:
            return "penumbra";
    }
    return "?";
}

std::span<const std::string_view> knownReasons() {
    static constexpr std::string_view kAll[] = {
        reasons::kBackFacing,      reasons::kNoOccluder,       reasons::kBlockNothing,
        reasons::kSingleBlocksAll, reasons::kTogetherBlockAll, reasons::kPenumbra,
        reasons::kPartial,
    };
    return kAll;
}

void indexDeferred(const PolygonMesh& mesh, HistoryTree& tree) {
    std::vector<Bounds3> boxes;
    boxes.reserve(tree.deferred.size());
    for (DeferredOccluder& d : tree.deferred) {
        d.box = Bounds3{};
        for (uint32_t v : mesh.faces[d.face]) d.box.add(mesh.vertices[v]);
        boxes.push_back(d.box);
    }
    tree.deferredIndex = BoxTree(boxes);
}

uint32_t HistoryTree::depth() const {
    if (nodes.empty()) return 0;
    uint32_t best = 0;
    std::vector<std::pair<uint32_t, uint32_t>> stack{{0, 1}};
    while (!stack.empty()) {
        auto [n, d] = stack.back();
        stack.pop_back();
        best = std::max(best, d);
        for (uint32_t c : nodes[n].child)
            if (!isLeaf(c)) stack.push_back({c, d + 1});
    }
    return best;
}

uint32_t HistoryTree::leafCount(bool visible) const {
    if (nodes.empty()) {
        // A leaf alone: FullyVisible (or a partial Penumbra tree with no node) is one visible
        // leaf, FullyHidden one hidden leaf, BackFacing none.
        const bool visibleLeaf = kind == PairKind::FullyVisible || kind == PairKind::Penumbra;
        return kind != PairKind::BackFacing && visibleLeaf == visible ? 1 : 0;
    }
    uint32_t count = 0;
    for (const HistoryNode& n : nodes)
        for (uint32_t c : n.child) count += c == (visible ? kVisibleLeaf : kHiddenLeaf);
    return count;
}

}  // namespace penumbra::vis
