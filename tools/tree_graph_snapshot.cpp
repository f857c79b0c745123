// Pictures of the history-tree browser without a GPU or a window: the panel draws into ImGui draw
// lists as in the viewer, and a small software rasterizer (triangles, vertex colours, the font
// atlas; nearest texel, no sub-pixel coverage: approximate) turns them into PNG files. For checking
// the look of the widget by eye and in reviews.
//
//   build/tools/penumbra_tree_graph_snapshot OUTDIR
// writes OUTDIR/tree_graph_{stairs_fit,stairs_zoom,stairs_collapsed,random50k_fit,
// random50k_boxes}.png
#include <imgui.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <vector>

#include "app/viewer/panels/tree_graph_panel.h"
#include "engine/io/atomic_file.h"
#include "engine/io/image_io.h"
#include "engine/scene/procedural_scenes.h"
#include "tools/devkit/headless_imgui.h"
#include "tools/devkit/random_history_tree.h"
#include "visibility/fp_query/from_point_query.h"
#include "visibility/history_tree_builder.h"

namespace {

using namespace penumbra;

struct Image {
    int width, height;
    std::vector<float> rgb;  // linear in [0, 1] per channel, as ImGui blends (no gamma)
    Image(int w, int h) : width(w), height(h), rgb(size_t(w) * h * 3, 0.0f) {}
};

// Rasterizes the frame's draw data: every triangle, clipped to its command's clip rectangle,
// colour = vertex colour (interpolated) x the font atlas's alpha at the interpolated UV.
void rasterize(const ImDrawData* data, const unsigned char* atlas, int atlasW, int atlasH,
               Image& img) {
    for (int l = 0; l < data->CmdListsCount; ++l) {
        const ImDrawList* list = data->CmdLists[l];
        for (const ImDrawCmd& cmd : list->CmdBuffer) {
            if (cmd.UserCallback) continue;
            const int cx0 = std::max(0, int(cmd.ClipRect.x)),
                      cy0 = std::max(0, int(cmd.ClipRect.y));
            const int cx1 = std::min(img.width, int(std::ceil(cmd.ClipRect.z)));
            const int cy1 = std::min(img.height, int(std::ceil(cmd.ClipRect.w)));
            for (unsigned e = 0; e + 2 < cmd.ElemCount; e += 3) {
                const ImDrawVert* v[3];
                for (int k = 0; k < 3; ++k)
                    v[k] = &list->VtxBuffer[int(cmd.VtxOffset +
                                                list->IdxBuffer[int(cmd.IdxOffset + e + k)])];
                const float area = (v[1]->pos.x - v[0]->pos.x) * (v[2]->pos.y - v[0]->pos.y) -
                                   (v[2]->pos.x - v[0]->pos.x) * (v[1]->pos.y - v[0]->pos.y);
                if (std::fabs(area) < 1e-12f) continue;
                const int x0 = std::max(
                    cx0, int(std::floor(std::min({v[0]->pos.x, v[1]->pos.x, v[2]->pos.x}))));
                const int x1 = std::min(
                    cx1, int(std::ceil(std::max({v[0]->pos.x, v[1]->pos.x, v[2]->pos.x}))));
                const int y0 = std::max(
                    cy0, int(std::floor(std::min({v[0]->pos.y, v[1]->pos.y, v[2]->pos.y}))));
                const int y1 = std::min(
                    cy1, int(std::ceil(std::max({v[0]->pos.y, v[1]->pos.y, v[2]->pos.y}))));
                for (int y = y0; y < y1; ++y)
                    for (int x = x0; x < x1; ++x) {
                        const float px = x + 0.5f, py = y + 0.5f;
                        float w[3];
                        for (int k = 0; k < 3; ++k) {
                            const ImDrawVert* a = v[(k + 1) % 3];
                            const ImDrawVert* b = v[(k + 2) % 3];
                            w[k] = ((b->pos.x - a->pos.x) * (py - a->pos.y) -
                                    (px - a->pos.x) * (b->pos.y - a->pos.y)) /
                                   area;
                        }
                        if (w[0] < 0 || w[1] < 0 || w[2] < 0) continue;
                        float u = 0, t = 0, c[4] = {0, 0, 0, 0};
                        for (int k = 0; k < 3; ++k) {
                            u += w[k] * v[k]->uv.x;
                            t += w[k] * v[k]->uv.y;
                            const ImVec4 col = ImGui::ColorConvertU32ToFloat4(v[k]->col);
                            c[0] += w[k] * col.x, c[1] += w[k] * col.y, c[2] += w[k] * col.z,
                                c[3] += w[k] * col.w;
                        }
                        const int tx = std::clamp(int(u * atlasW), 0, atlasW - 1);
                        const int ty = std::clamp(int(t * atlasH), 0, atlasH - 1);
                        const float alpha =
                            c[3] * atlas[(size_t(ty) * atlasW + tx) * 4 + 3] / 255.0f;
                        float* dst = &img.rgb[(size_t(y) * img.width + x) * 3];
                        for (int k = 0; k < 3; ++k) dst[k] = dst[k] * (1 - alpha) + c[k] * alpha;
                    }
            }
        }
    }
}

class Snapshots {
  public:
    explicit Snapshots(std::filesystem::path dir) : dir_(std::move(dir)) {
        ImGui::StyleColorsDark();
    }

    void frame(ui::TreeGraphPanel& panel) {
        imgui_.frame([&] { panel.draw("History tree"); });
    }
    void save(ui::TreeGraphPanel& panel, const std::string& name) {
        frame(panel);
        frame(panel);
        Image img(1280, 800);
        rasterize(ImGui::GetDrawData(), imgui_.atlasPixels(), imgui_.atlasWidth(),
                  imgui_.atlasHeight(), img);
        std::vector<unsigned char> bytes(img.rgb.size());
        for (size_t i = 0; i < bytes.size(); ++i)
            bytes[i] = (unsigned char)std::lround(std::clamp(img.rgb[i], 0.0f, 1.0f) * 255);
        const std::filesystem::path path = dir_ / ("tree_graph_" + name + ".png");
        writeFileAtomically(path, encodePng(img.width, img.height, 3, bytes.data()));
        std::printf("%s\n", path.c_str());
    }
    void hover(ImVec2 p) { ImGui::GetIO().MousePos = p; }

  private:
    devkit::HeadlessImGui imgui_;  // first: the context outlives nothing that uses it
    std::filesystem::path dir_;
};

}  // namespace

int main(int argc, char** argv) try {
    if (argc != 2) {
        std::fprintf(stderr, "usage: %s OUTDIR\n", argv[0]);
        return 2;
    }
    std::filesystem::create_directories(argv[1]);
    Snapshots shots(argv[1]);

    // A real tree: stairs, receiver face 203 and the light; the path of the receiver's centroid.
    const Scene scene = makeStairs();
    const uint32_t receiver = 203;
    const vis::HistoryTree tree = vis::buildHistoryTree(scene.mesh, receiver, scene.lights.at(0));
    vis::Vec3 c{};
    for (uint32_t v : scene.mesh.faces[receiver]) c += scene.mesh.vertices[v];
    c = c / double(scene.mesh.faces[receiver].size());
    const std::vector<uint32_t> path =
        vis::traceNodes(vis::fromPointQuery(scene.mesh, tree, c).trace);
    ui::TreeGraphPanel panel;
    panel.setTree(&tree, path);
    panel.setMesh(&scene.mesh);
    shots.hover(ImVec2(-100, -100));
    shots.save(panel, "stairs_fit");
    // Zoomed in on the deepest node of the path, hovering it (tooltip).
    const ui::TreeGraphLayout& l = *panel.layout();
    const auto& deepest = l.item(l.itemOfNode(path.back()));
    panel.view().centreOn(deepest.x, l.layerY(deepest.depth) - 2.0, 28.0);
    shots.frame(panel);
    if (auto p = panel.screenPosOfNode(path.back())) shots.hover(*p);
    shots.save(panel, "stairs_zoom");
    shots.hover(ImVec2(-100, -100));
    panel.collapseToDepth(5);
    panel.view().fit();
    shots.save(panel, "stairs_collapsed");

    const vis::HistoryTree big = devkit::randomHistoryTree(50000, 1);
    ui::TreeGraphPanel bigPanel;
    bigPanel.setTree(&big, {});
    shots.save(bigPanel, "random50k_fit");
    const ui::TreeGraphLayout& bl = *bigPanel.layout();
    uint32_t busiest = 0;
    for (uint32_t d = 0; d < bl.layerCount(); ++d)
        if (bl.layer(d).size() > bl.layer(busiest).size()) busiest = d;
    bigPanel.view().centreOn(bl.item(bl.layer(busiest)[bl.layer(busiest).size() / 2]).x,
                             bl.layerY(busiest), 6.0);
    shots.save(bigPanel, "random50k_boxes");
} catch (const std::exception& e) {
    std::fprintf(stderr, "penumbra_tree_graph_snapshot: error: %s\n", e.what());
    return 1;
}
