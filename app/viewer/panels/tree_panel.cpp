#include "app/viewer/panels/tree_panel.h"

#include <imgui.h>

#include <string>
#include <vector>

#include "app/viewer/panels/tree_graph_panel.h"

namespace penumbra::viewer {

struct TreePanel::Impl {
    const vis::HistoryTree* tree = nullptr;
    std::vector<uint32_t> path;
    ui::TreeGraphPanel graph;
};

TreePanel::TreePanel() : impl_(std::make_unique<Impl>()) {}
TreePanel::~TreePanel() = default;

bool TreePanel::hasGraphWidget() { return true; }

void TreePanel::setTree(const vis::HistoryTree* tree, std::span<const uint32_t> highlightedPath,
                        const vis::PolygonMesh* mesh) {
    impl_->tree = tree;
    impl_->path.assign(highlightedPath.begin(), highlightedPath.end());
    impl_->graph.setMesh(tree != nullptr ? mesh : nullptr);
    impl_->graph.setTree(tree, impl_->path);
}

void TreePanel::draw(const char* windowTitle) { impl_->graph.draw(windowTitle); }

}  // namespace penumbra::viewer
