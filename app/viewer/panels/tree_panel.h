// TreePanel: the history-tree browser panel. It shows the tree of the selected (receiver, light)
// pair with the path of the inspected point highlighted, through TreeGraphPanel
// (app/viewer/panels/tree_graph_panel.h, namespace penumbra::ui).
#pragma once

#include <cstdint>
#include <memory>
#include <span>

#include "visibility/history_tree.h"

namespace penumbra::viewer {

class TreePanel {
  public:
    TreePanel();
    ~TreePanel();
    TreePanel(const TreePanel&) = delete;
    TreePanel& operator=(const TreePanel&) = delete;

    // The tree (and the mesh it was built on, for vertex coordinates) must outlive the next
    // setTree (the store keeps it); nullptr shows "no tree".
    void setTree(const vis::HistoryTree* tree, std::span<const uint32_t> highlightedPath,
                 const vis::PolygonMesh* mesh = nullptr);
    void draw(const char* windowTitle);
    // True when the real widget (TreeGraphPanel) is built in.
    static bool hasGraphWidget();

  private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

}  // namespace penumbra::viewer
