// Benchmark of the history-tree browser: layout time (whole tree, after collapsing) and the
// ImGui draw-list size and CPU time of one frame at several zoom levels, headless (no backend).
// Times are this thread's CPU time (CLOCK_THREAD_CPUTIME_ID), the best of several runs, so that
// other processes on a shared machine inflate them less (they still compete for the caches).
//
//   build/tools/penumbra_tree_graph_bench [nodes=50000]
#include <imgui.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <optional>
#include <vector>

#include "app/viewer/panels/tree_graph_panel.h"
#include "tools/devkit/headless_imgui.h"
#include "tools/devkit/random_history_tree.h"

namespace {

using namespace penumbra;
double cpuMs() {
    timespec ts{};
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
    return ts.tv_sec * 1e3 + ts.tv_nsec * 1e-6;
}

template <class F>
double bestMs(int runs, F&& f) {
    double best = 1e300;
    for (int k = 0; k < runs; ++k) {
        const double t0 = cpuMs();
        f();
        best = std::min(best, cpuMs() - t0);
    }
    return best;
}

struct Frame {
    size_t vertices = 0, indices = 0;
    double ms = 0;
};

Frame frame(ui::TreeGraphPanel& panel) {
    Frame f;
    f.ms = bestMs(5, [&] {
        ImGui::NewFrame();
        ImGui::SetNextWindowPos(ImVec2(0, 0));
        ImGui::SetNextWindowSize(ImGui::GetIO().DisplaySize);
        panel.draw("History tree");
        ImGui::Render();
    });
    const ImDrawData* d = ImGui::GetDrawData();
    for (int i = 0; i < d->CmdListsCount; ++i) {
        f.vertices += size_t(d->CmdLists[i]->VtxBuffer.Size);
        f.indices += size_t(d->CmdLists[i]->IdxBuffer.Size);
    }
    return f;
}

void benchTree(const char* name, const vis::HistoryTree& tree) {
    std::optional<ui::HistoryTreeTopology> topology;
    const double topoMs = bestMs(5, [&] { topology.emplace(tree); });
    const ui::HistoryTreeTopology& topo = *topology;
    std::vector<uint8_t> collapsed(tree.nodes.size(), 0);
    ui::TreeGraphLayout layout;
    // A fresh object (first layout of a tree: new buffers), then recomputations reusing them.
    const double firstMs = bestMs(1, [&] { ui::TreeGraphLayout(topo, tree, collapsed); });
    const double fullMs = bestMs(9, [&] { layout.compute(topo, tree, collapsed); });
    const uint32_t fullItems = layout.itemCount();
    const ui::GraphRect fullBounds = layout.bounds();
    // Collapse one node two levels down (a quarter of the tree, roughly) and relayout.
    uint32_t node = 0;
    for (int k = 0; k < 2 && !vis::isLeaf(tree.nodes[node].child[0]); ++k)
        node = tree.nodes[node].child[0];
    collapsed[node] = 1;
    const double oneMs = bestMs(9, [&] { layout.compute(topo, tree, collapsed); });
    std::printf(
        "%s: %zu nodes, depth %u, %u items, %.0f x %.0f units\n"
        "  topology %.2f ms | layout: first %.2f ms, again %.2f ms | after collapsing "
        "node %u: %.2f ms (%u items)\n",
        name, tree.nodes.size(), topo.maxDepth + 1, fullItems, fullBounds.x1, fullBounds.y1, topoMs,
        firstMs, fullMs, node, oneMs, layout.itemCount());

    ui::TreeGraphPanel panel;
    panel.setTree(&tree, {});
    panel.view().fit();
    frame(panel);
    const Frame fit = frame(panel);
    const auto fitStats = panel.lastFrameStats();
    const ui::TreeGraphLayout& l = *panel.layout();
    uint32_t busiest = 0;
    for (uint32_t d = 0; d < l.layerCount(); ++d)
        if (l.layer(d).size() > l.layer(busiest).size()) busiest = d;
    const uint32_t mid = l.layer(busiest)[l.layer(busiest).size() / 2];
    const double cx = l.item(mid).x, cy = l.layerY(busiest);
    struct View {
        const char* what;
        double zoom;
    };
    std::printf("  %-34s %9s %9s %8s %8s %7s %s\n", "view (1280x800 window)", "vertices", "indices",
                "items", "edges", "ms", "detail");
    const auto row = [&](const char* what, const Frame& f, const ui::TreeGraphFrameStats& s) {
        const char* detail = s.detail == ui::TreeGraphDetail::Raster  ? "raster"
                             : s.detail == ui::TreeGraphDetail::Boxes ? "boxes"
                                                                      : "labelled";
        std::printf("  %-34s %9zu %9zu %8u %8u %7.2f %s (%u runs)\n", what, f.vertices, f.indices,
                    s.itemsOnScreen, s.edgesDrawn, f.ms, detail, s.rasterRuns);
    };
    row("fit (whole tree)", fit, fitStats);
    for (const View v :
         {View{"busiest layer at 1 px/unit", 1.0}, View{"busiest layer at 2.5 px/unit", 2.5},
          View{"busiest layer at 6 px/unit", 6.0}, View{"busiest layer at 40 px/unit", 40.0}}) {
        panel.view().centreOn(cx, cy, v.zoom);
        const Frame f = frame(panel);
        row(v.what, f, panel.lastFrameStats());
    }
}

}  // namespace

int main(int argc, char** argv) {
    const uint32_t n = argc > 1 ? uint32_t(std::strtoul(argv[1], nullptr, 10)) : 50000;
    devkit::HeadlessImGui imgui;
    benchTree("random", devkit::randomHistoryTree(n, 1));
    benchTree("chain (straight)", devkit::chainHistoryTree(n, false));
    benchTree("chain (zigzag)", devkit::chainHistoryTree(n, true));
}
