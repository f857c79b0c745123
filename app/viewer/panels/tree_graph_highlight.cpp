#include "app/viewer/panels/tree_graph_highlight.h"

namespace penumbra::ui {

void TreeGraphHighlight::assign(const HistoryTreeTopology* topology,
                                std::span<const uint32_t> ids) {
    const uint32_t n = topology ? topology->nodeCount() : 0;
    onPath_.assign(n, 0);
    pathBelow_.assign(n, 0);
    pathNodes_.clear();
    pathSize_ = static_cast<uint32_t>(ids.size());
    pathIgnored_ = 0;
    for (uint32_t id : ids) {
        if (id >= n || !topology->reachable(id)) {
            ++pathIgnored_;
        } else if (!onPath_[id]) {
            onPath_[id] = 1;
            pathNodes_.push_back(id);
        }
    }
    if (!topology) return;
    const auto& pre = topology->preorder;
    for (size_t i = pre.size(); i-- > 0;) {
        const uint32_t v = pre[i];
        pathBelow_[v] += onPath_[v];
        if (topology->parent[v] != kNoIndex) pathBelow_[topology->parent[v]] += pathBelow_[v];
    }
}

}  // namespace penumbra::ui
