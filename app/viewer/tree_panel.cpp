#include "app/viewer/tree_panel.h"

#include <imgui.h>

#include <string>
#include <vector>

// PENUMBRA_HAVE_TREE_GRAPH comes from app/CMakeLists.txt: 1 when the penumbra_tree_graph library
// (branch treegraph) is part of the build.
#if PENUMBRA_HAVE_TREE_GRAPH
#include "app/tree_graph_panel.h"
#endif

namespace penumbra::viewer {

struct TreePanel::Impl {
    const vis::HistoryTree* tree = nullptr;
    std::vector<uint32_t> path;
#if PENUMBRA_HAVE_TREE_GRAPH
    ui::TreeGraphPanel graph;
#endif
};

TreePanel::TreePanel() : impl_(std::make_unique<Impl>()) {}
TreePanel::~TreePanel() = default;

bool TreePanel::hasGraphWidget() { return PENUMBRA_HAVE_TREE_GRAPH != 0; }

void TreePanel::setTree(const vis::HistoryTree* tree, std::span<const uint32_t> highlightedPath,
                        const vis::PolygonMesh* mesh) {
    impl_->tree = tree;
    impl_->path.assign(highlightedPath.begin(), highlightedPath.end());
#if PENUMBRA_HAVE_TREE_GRAPH
    impl_->graph.setMesh(tree != nullptr ? mesh : nullptr);
    impl_->graph.setTree(tree, impl_->path);
#else
    (void)mesh;
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
