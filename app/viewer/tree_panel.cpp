#include "app/viewer/tree_panel.h"

#include <imgui.h>

#include <string>
#include <vector>

#if __has_include("app/tree_graph_panel.h")
#include "app/tree_graph_panel.h"
#define PENUMBRA_HAVE_TREE_GRAPH 1
#else
#define PENUMBRA_HAVE_TREE_GRAPH 0
#endif

namespace penumbra::viewer {

struct TreePanel::Impl {
    const vis::HistoryTree* tree = nullptr;
    std::vector<uint32_t> path;
#if PENUMBRA_HAVE_TREE_GRAPH
    TreeGraphPanel graph;
#endif
};

TreePanel::TreePanel() : impl_(std::make_unique<Impl>()) {}
TreePanel::~TreePanel() = default;

bool TreePanel::hasGraphWidget() { return PENUMBRA_HAVE_TREE_GRAPH != 0; }

void TreePanel::setTree(const vis::HistoryTree* tree, std::span<const uint32_t> highlightedPath) {
    impl_->tree = tree;
    impl_->path.assign(highlightedPath.begin(), highlightedPath.end());
#if PENUMBRA_HAVE_TREE_GRAPH
    impl_->graph.setTree(tree, impl_->path);
#endif
}

void TreePanel::draw(const char* windowTitle) {
#if PENUMBRA_HAVE_TREE_GRAPH
    impl_->graph.draw(windowTitle);
#else
    // PLACEHOLDER until the `treegraph` branch's TreeGraphPanel is merged: text only.
    if (ImGui::Begin(windowTitle)) {
        ImGui::TextColored(ImVec4(1, 0.6f, 0.2f, 1),
                           "[placeholder: TreeGraphPanel not merged yet]");
        const vis::HistoryTree* t = impl_->tree;
        if (t == nullptr) {
            ImGui::TextUnformatted("No tree: click a surface point.");
        } else {
            ImGui::Text("receiver %u, light face %u: %s", t->receiver, t->light,
                        std::string(vis::toString(t->kind)).c_str());
            ImGui::Text("%zu nodes, depth %u, %u visible / %u hidden leaves", t->nodes.size(),
                        t->depth(), t->leafCount(true), t->leafCount(false));
            ImGui::Text("highlighted path: %zu nodes", impl_->path.size());
            std::string line;
            for (size_t i = 0; i < impl_->path.size() && i < 64; ++i)
                line += (i ? " " : "") + std::to_string(impl_->path[i]);
            if (impl_->path.size() > 64) line += " ...";
            ImGui::TextWrapped("%s", line.c_str());
        }
    }
    ImGui::End();
#endif
}

}  // namespace penumbra::viewer
