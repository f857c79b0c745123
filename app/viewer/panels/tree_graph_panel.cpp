#include "app/viewer/panels/tree_graph_panel.h"

#include <imgui_internal.h>  // NextWindowData: respect a size the host has set

#include <algorithm>
#include <chrono>
#include <climits>
#include <cmath>
#include <cstdio>
#include <initializer_list>
#include <tuple>

#include "app/viewer/panels/flow_layout.h"

namespace penumbra::ui {
namespace {

constexpr ImU32 kColorBackground = IM_COL32(24, 26, 30, 255);
constexpr ImU32 kColorNode = IM_COL32(72, 92, 128, 255);
constexpr ImU32 kColorNodeBorder = IM_COL32(150, 170, 210, 255);
constexpr ImU32 kColorCollapsed = IM_COL32(112, 112, 120, 255);
constexpr ImU32 kColorCollapsedBorder = IM_COL32(225, 225, 235, 255);
// Visible leaves: lit, warm yellow discs. Hidden leaves: in shadow, violet squares. The shapes
// differ too, so the two stay apart without colour vision.
constexpr ImU32 kColorVisible = IM_COL32(250, 205, 60, 255);
constexpr ImU32 kColorHidden = IM_COL32(150, 70, 200, 255);
constexpr ImU32 kColorEdge = IM_COL32(115, 125, 145, 255);
constexpr ImU32 kColorHighlight = IM_COL32(0, 230, 255, 255);
constexpr ImU32 kColorText = IM_COL32(235, 235, 240, 255);
constexpr ImU32 kColorError = IM_COL32(255, 110, 100, 255);

constexpr float kRasterBelowPx = 3.0f;        // node width under which nodes become pixel runs
constexpr float kLabelsFromPx = 14.0f;        // node width from which boxes get borders and labels
constexpr uint32_t kRasterEdgeBudget = 4000;  // edges drawn in Raster mode only below this
constexpr size_t kBoxBudget = 20000;          // more items on screen than this: Raster mode
constexpr float kPickRadiusPx = 4.0f;

ImU32 lerpColor(ImU32 a, ImU32 b, float t) {
    const auto channel = [&](int shift) {
        const float ca = float((a >> shift) & 0xFF), cb = float((b >> shift) & 0xFF);
        return ImU32(std::lround(ca + (cb - ca) * t)) << shift;
    };
    return channel(IM_COL32_R_SHIFT) | channel(IM_COL32_G_SHIFT) | channel(IM_COL32_B_SHIFT) |
           (0xFFu << IM_COL32_A_SHIFT);
}

// Text of a node's edge: a chord (face and plane) or an input edge (vertex ids), with the
// coordinates of a segment of it when the mesh is known and the ids are valid.
std::string edgeText(const vis::HistoryTree& tree, const vis::PolygonMesh* mesh,
                     const vis::HistoryNode& n) {
    char buf[256];
    const bool chord = vis::isClipEdge(n.v0);
    const uint32_t face = n.v0 & ~vis::kClipEdge;
    const char* plane = n.v1 == vis::kReceiverPlaneEdge ? "receiver" : "light";
    if (chord)
        std::snprintf(buf, sizeof buf, "face %u meets the %s plane", face, plane);
    else
        std::snprintf(buf, sizeof buf, "v%u -> v%u", n.v0, n.v1);
    std::string text = buf;
    if (!mesh) return text;
    const bool valid = chord ? face < mesh->faces.size()
                             : n.v0 < mesh->vertices.size() && n.v1 < mesh->vertices.size();
    if (!valid) return text + " (out of range)";
    const auto [a, b] = vis::edgeSegment(*mesh, tree.receiver, tree.light, n.v0, n.v1);
    std::snprintf(buf, sizeof buf, " (%.5g, %.5g, %.5g) -> (%.5g, %.5g, %.5g)", a.x, a.y, a.z, b.x,
                  b.y, b.z);
    return text + buf;
}

const char* childText(uint32_t c, char* buf, size_t size) {
    if (c == vis::kVisibleLeaf) return "visible leaf";
    if (c == vis::kHiddenLeaf) return "hidden leaf";
    std::snprintf(buf, size, "node %u", c);
    return buf;
}

void legendSwatch(ImU32 color, const char* label, bool disc) {
    ImDrawList* dl = ImGui::GetWindowDrawList();
    const float h = ImGui::GetTextLineHeight();
    const ImVec2 p = ImGui::GetCursorScreenPos();
    if (disc)
        dl->AddCircleFilled(ImVec2(p.x + 0.5f * h, p.y + 0.5f * h), 0.4f * h, color, 12);
    else
        dl->AddRectFilled(ImVec2(p.x + 0.1f * h, p.y + 0.1f * h),
                          ImVec2(p.x + 0.9f * h, p.y + 0.9f * h), color);
    ImGui::Dummy(ImVec2(h, h));
    ImGui::SameLine();
    ImGui::TextUnformatted(label);
}

// The legend: its swatches on as few lines as the panel's width allows.
void legend(std::initializer_list<std::tuple<ImU32, const char*, bool>> items) {
    bool first = true;
    for (const auto& [color, label, disc] : items) {
        if (!first)
            viewer::sameLineIfFits(ImGui::GetTextLineHeight() + ImGui::GetStyle().ItemSpacing.x +
                                       ImGui::CalcTextSize(label).x,
                                   2 * ImGui::GetStyle().ItemSpacing.x);
        first = false;
        legendSwatch(color, label, disc);
    }
}

}  // namespace

// ---- state ------------------------------------------------------------------------------------

void TreeGraphPanel::setTree(const vis::HistoryTree* tree,
                             std::span<const uint32_t> highlightedPath) {
    // The same tree again (e.g. a new highlighted path): keep collapsed subtrees and the view.
    const bool same = tree && tree == tree_ && topology_ && tree->nodes.data() == nodesData_ &&
                      topology_->nodeCount() == tree->nodes.size() &&
                      collapsed_.size() == tree->nodes.size() && tree->receiver == receiver_ &&
                      tree->light == light_;
    if (!same) {
        tree_ = tree;
        nodesData_ = tree ? tree->nodes.data() : nullptr;
        receiver_ = tree ? tree->receiver : 0;
        light_ = tree ? tree->light : 0;
        topology_.reset();
        error_.clear();
        layout_ = TreeGraphLayout();
        layoutDirty_ = true;
        view_.fit();
        drawn_ = false;
        if (tree_) {
            try {
                topology_.emplace(*tree_);
            } catch (const std::invalid_argument& e) {
                error_ = e.what();
            }
        }
        collapsed_.assign(topology_ ? topology_->nodeCount() : 0, 0);
    }
    highlight_.assign(topology_ ? &*topology_ : nullptr, highlightedPath);
}

void TreeGraphPanel::ensureLayout() {
    if (!topology_ || !layoutDirty_) return;
    const auto t0 = std::chrono::steady_clock::now();
    try {
        layout_.compute(*topology_, *tree_, collapsed_);
    } catch (const std::invalid_argument& e) {
        error_ = e.what();
        topology_.reset();
        layout_ = TreeGraphLayout();
        return;
    }
    layoutMs_ =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    layoutDirty_ = false;
}

// Recomputes the layout after a change to the collapsed set, shifting the view so that `node`
// keeps its place on screen.
void TreeGraphPanel::relayoutKeeping(uint32_t node) {
    const uint32_t before = layout_.itemOfNode(node);
    const double oldX = before != kNoIndex ? layout_.item(before).x : 0.0;
    layoutDirty_ = true;
    ensureLayout();
    const uint32_t after = layout_.itemOfNode(node);
    if (before != kNoIndex && after != kNoIndex) view_.moveBy(layout_.item(after).x - oldX, 0);
}

void TreeGraphPanel::toggleCollapsed(uint32_t node) {
    if (!topology_ || node >= collapsed_.size() || !topology_->reachable(node)) return;
    ensureLayout();
    collapsed_[node] ^= 1;
    relayoutKeeping(node);
}

void TreeGraphPanel::expandAll() {
    if (!topology_) return;
    ensureLayout();
    std::fill(collapsed_.begin(), collapsed_.end(), 0);
    relayoutKeeping(0);
}

void TreeGraphPanel::collapseToDepth(uint32_t depth) {
    if (!topology_) return;
    ensureLayout();
    for (uint32_t v : topology_->preorder) collapsed_[v] = topology_->depth[v] == depth;
    relayoutKeeping(0);
}

void TreeGraphPanel::revealPath() {
    if (!topology_ || highlight_.nodes().empty()) return;
    ensureLayout();
    // Expand every highlighted node and its ancestors; stop a walk at a node already expanded by
    // this pass (its ancestors are done), so the whole pass is O(n).
    std::vector<uint8_t> done(collapsed_.size(), 0);
    for (uint32_t v : highlight_.nodes()) {
        for (uint32_t a = v; a != kNoIndex && !done[a]; a = topology_->parent[a]) {
            done[a] = 1;
            collapsed_[a] = 0;
        }
    }
    relayoutKeeping(highlight_.nodes().front());
}

std::optional<ImVec2> TreeGraphPanel::screenPosOfNode(uint32_t node) const {
    if (!topology_ || !drawn_ || layoutDirty_) return std::nullopt;
    const uint32_t i = layout_.itemOfNode(node);
    if (i == kNoIndex) return std::nullopt;
    return view_.toScreen(layout_.item(i).x, layout_.layerY(layout_.item(i).depth));
}

void TreeGraphPanel::glyphRect(uint32_t item, ImVec2& a, ImVec2& c) const {
    const GraphItem& it = layout_.item(item);
    const ImVec2 centre = view_.toScreen(it.x, layout_.layerY(it.depth));
    const float hx = float(layout_.halfWidth(it) * view_.zoomX());
    const float hy = float(layout_.halfHeight(it) * std::min(view_.zoomY(), view_.zoomX()));
    a = ImVec2(centre.x - hx, centre.y - hy);
    c = ImVec2(centre.x + hx, centre.y + hy);
}

uint32_t TreeGraphPanel::pick(ImVec2 mouse) const {
    const auto [x, y] = view_.toLayout(mouse);
    const double rx = kPickRadiusPx / view_.zoomX(), ry = kPickRadiusPx / view_.zoomY();
    std::vector<uint32_t> near;
    layout_.query({x - rx, y - ry, x + rx, y + ry}, near);
    uint32_t best = kNoIndex;
    double bestD = 0;
    for (uint32_t i : near) {
        // Inside a box beats near one; boxes never overlap, so at most one contains the point.
        const GraphRect b = layout_.box(i);
        // Distance in pixels.
        const double dx = (layout_.item(i).x - x) * view_.zoomX();
        const double dy = (layout_.layerY(layout_.item(i).depth) - y) * view_.zoomY();
        const double d = b.contains(x, y) ? -1.0 : dx * dx + dy * dy;
        if (best == kNoIndex || d < bestD) {
            best = i;
            bestD = d;
        }
    }
    return best;
}

// ---- drawing ----------------------------------------------------------------------------------

void TreeGraphPanel::draw(const char* windowTitle) {
    if (!(ImGui::GetCurrentContext()->NextWindowData.Flags & ImGuiNextWindowDataFlags_HasSize))
        ImGui::SetNextWindowSize(ImVec2(760, 560), ImGuiCond_FirstUseEver);
    if (!ImGui::Begin(windowTitle, nullptr,
                      ImGuiWindowFlags_NoScrollbar | ImGuiWindowFlags_NoScrollWithMouse)) {
        ImGui::End();
        return;
    }
    drawHeader();
    if (topology_ && (topology_->rootLeaf || topology_->nodeCount() > 0)) drawCanvas();
    ImGui::End();
}

void TreeGraphPanel::drawHeader() {
    if (!tree_) {
        ImGui::TextWrapped(
            "No history tree selected: pick a (receiver, light) pair, e.g. by clicking a point.");
        return;
    }
    // (A tree drawn without its mesh, or not of it, says its kind alone.)
    const bool ofMesh = mesh_ != nullptr && tree_->receiver < mesh_->faces.size() &&
                        tree_->light < mesh_->faces.size();
    const std::string_view kind = vis::describeKind(
        tree_->kind, ofMesh && vis::horizonClipsLight(*mesh_, tree_->receiver, tree_->light));
    ImGui::TextWrapped("receiver face %u, light face %u: %.*s", tree_->receiver, tree_->light,
                       int(kind.size()), kind.data());
    if (!error_.empty()) {
        ImGui::PushStyleColor(ImGuiCol_Text, kColorError);
        ImGui::TextWrapped("Cannot draw this tree: %s", error_.c_str());
        ImGui::PopStyleColor();
        return;
    }
    if (tree_->partial())
        ImGui::TextWrapped(
            "Partial tree: the build budget stopped it; %zu more occluders are clipped by each "
            "point's query (the answer is exact all the same).",
            tree_->deferred.size());
    if (tree_->kind != vis::PairKind::Penumbra || topology_->nodeCount() == 0) {
        ImGui::TextWrapped("No tree nodes for this pair (%.*s).", int(tree_->why.size()),
                           tree_->why.data());
        if (!topology_->rootLeaf) return;
    } else {
        const HistoryTreeTopology& t = *topology_;
        // Wrapped, and the buttons flowed onto as many lines as the panel's width needs: the
        // panel may be a narrow column or enlarged to most of the window.
        ImGui::TextWrapped(
            "nodes %zu (%u reachable)   depth %u   leaves %u visible / %u hidden   %zu bytes",
            tree_->nodes.size(), t.reachableCount(), t.maxDepth + 1, t.visibleLeaves[0],
            t.hiddenLeaves[0], tree_->bytes());
        if (highlight_.requested() > 0) {
            if (highlight_.ignored() > 0)
                ImGui::TextWrapped("path: %zu nodes (%u ids ignored: out of range)",
                                   highlight_.nodes().size(), highlight_.ignored());
            else
                ImGui::TextWrapped("path: %zu nodes", highlight_.nodes().size());
        }
        if (ImGui::Button("Fit")) view_.fit();
        if (ImGui::IsItemHovered())
            ImGui::SetTooltip("Whole tree in view, x and y scaled independently");
        viewer::sameLineIfFits(viewer::buttonWidth("1:1"));
        if (ImGui::Button("1:1")) view_.sameScale();
        viewer::sameLineIfFits(viewer::buttonWidth("Expand all"));
        if (ImGui::Button("Expand all")) expandAll();
        const float depthWidth = 5 * ImGui::GetFontSize();
        viewer::sameLineIfFits(viewer::buttonWidth("Collapse to depth") +
                               ImGui::GetStyle().ItemSpacing.x + depthWidth);
        if (ImGui::Button("Collapse to depth")) collapseToDepth(uint32_t(collapseDepth_));
        ImGui::SameLine();
        ImGui::SetNextItemWidth(depthWidth);
        ImGui::InputInt("##collapse_depth", &collapseDepth_);
        collapseDepth_ = std::clamp(collapseDepth_, 0, int(t.maxDepth));
        viewer::sameLineIfFits(viewer::buttonWidth("Reveal path"));
        if (ImGui::Button("Reveal path")) revealPath();
        if (ImGui::IsItemHovered())
            ImGui::SetTooltip("Expand the highlighted nodes and their ancestors");
        ImGui::PushStyleColor(ImGuiCol_Text, ImGui::GetStyle().Colors[ImGuiCol_TextDisabled]);
        ImGui::TextWrapped("layout %.2f ms, %u items, %.3g x %.3g px/unit", layoutMs_,
                           layout_.itemCount(), view_.zoomX(), view_.zoomY());
        ImGui::PopStyleColor();
    }
    legend({{kColorNode, "node", false},
            {kColorCollapsed, "collapsed (+hidden)", false},
            {kColorVisible, "visible leaf", true},
            {kColorHidden, "hidden leaf", false},
            {kColorHighlight, "path", false}});
}

void TreeGraphPanel::drawCanvas() {
    ensureLayout();
    ImGuiIO& io = ImGui::GetIO();
    const ImVec2 p0 = ImGui::GetCursorScreenPos();
    ImVec2 size = ImGui::GetContentRegionAvail();
    size.x = std::max(size.x, 64.0f);
    size.y = std::max(size.y, 64.0f);
    const bool released = ImGui::InvisibleButton("##tree_graph_canvas", size,
                                                 ImGuiButtonFlags_MouseButtonLeft |
                                                     ImGuiButtonFlags_MouseButtonRight |
                                                     ImGuiButtonFlags_MouseButtonMiddle);
    const bool hovered = ImGui::IsItemHovered();
    const bool active = ImGui::IsItemActive();
    view_.beginFrame(p0, size, layout_.bounds());

    // Pan with any button dragged; zoom at the mouse with the wheel.
    const bool dragging = ImGui::IsMouseDragging(ImGuiMouseButton_Left) ||
                          ImGui::IsMouseDragging(ImGuiMouseButton_Right) ||
                          ImGui::IsMouseDragging(ImGuiMouseButton_Middle);
    if (active && dragging) view_.pan(io.MouseDelta);
    if (hovered && io.MouseWheel != 0.0f)
        view_.zoomAt(io.MousePos, double(io.MouseWheel), !io.KeyCtrl, !io.KeyShift);
    // A left click that did not drag toggles the node under the mouse.
    const float threshold = io.MouseDragThreshold;
    if (released && ImGui::IsMouseReleased(ImGuiMouseButton_Left) &&
        io.MouseDragMaxDistanceSqr[ImGuiMouseButton_Left] < threshold * threshold) {
        const uint32_t i = pick(io.MousePos);
        if (i != kNoIndex && !isLeafItem(layout_.item(i).kind))
            toggleCollapsed(layout_.item(i).node);
    }

    ImDrawList* dl = ImGui::GetWindowDrawList();
    const ImVec2 p1(p0.x + size.x, p0.y + size.y);
    dl->PushClipRect(p0, p1, true);
    dl->AddRectFilled(p0, p1, kColorBackground);

    const GraphRect view = view_.visible();
    scratch_.clear();
    layout_.query(view, scratch_);
    stats_ = {};
    stats_.itemsOnScreen = static_cast<uint32_t>(scratch_.size());
    const float nodePx = float(layout_.style().nodeWidth * view_.zoomX());
    const float layerPx = float(layout_.style().layerSpacing * view_.zoomY());
    // Raster when boxes would be under kRasterBelowPx wide or layers closer than that, or when
    // so many are on screen that one primitive each would make a large draw list.
    if (nodePx < kRasterBelowPx || layerPx < kRasterBelowPx || scratch_.size() > kBoxBudget) {
        stats_.detail = TreeGraphDetail::Raster;
        if (layerPx >= 2.0f && scratch_.size() <= kRasterEdgeBudget) drawEdges(dl);
        drawPath(dl);
        drawRaster(dl, scratch_);
    } else {
        const bool labels = nodePx >= kLabelsFromPx;
        stats_.detail = labels ? TreeGraphDetail::Labelled : TreeGraphDetail::Boxes;
        drawEdges(dl);
        drawPath(dl);
        drawBoxes(dl, scratch_, labels);
    }

    if (hovered && !dragging) {
        const uint32_t i = pick(io.MousePos);
        if (i != kNoIndex) {
            ImVec2 a, c;
            glyphRect(i, a, c);
            dl->AddRect(ImVec2(a.x - 2, a.y - 2), ImVec2(c.x + 2, c.y + 2), kColorText, 0, 0, 1.5f);
            drawTooltip(i);
        }
    }
    dl->PopClipRect();
    drawn_ = true;
}

// Edges are found per layer rather than from the culled items: an edge can cross the view while
// both its ends are off screen.
void TreeGraphPanel::drawEdges(ImDrawList* dl) {
    const TreeGraphStyle& st = layout_.style();
    const GraphRect view = view_.visible();
    const double x0 = view.x0, x1 = view.x1;
    const double y0 = view.y0, y1 = view.y1;
    if (layout_.layerCount() < 2) return;
    const double glyphScaleY = std::min(view_.zoomY(), view_.zoomX());  // as glyphRect()
    // Child layers whose edges (from the parent's layer to theirs) can reach the view.
    const double lo = std::floor(y0 / st.layerSpacing), hi = std::ceil(y1 / st.layerSpacing) + 1;
    if (hi < 1 || lo > layout_.layerCount() - 1) return;
    const uint32_t d0 = uint32_t(std::max(1.0, lo));
    const uint32_t d1 = uint32_t(std::min<double>(hi, layout_.layerCount() - 1));
    for (uint32_t d = d0; d <= d1; ++d) {
        const auto l = layout_.layer(d);
        // Items inside [x0, x1], plus one more on each side: consecutive layers' edges never
        // cross, so if any edge from an off-screen child crosses the view, the nearest
        // off-screen child's edge does too (or reaches it).
        uint32_t k0 = layout_.firstInLayerFrom(d, x0);
        k0 = k0 > 0 ? k0 - 1 : 0;
        for (uint32_t k = k0; k < l.size(); ++k) {
            const GraphItem& c = layout_.item(l[k]);
            const GraphItem& p = layout_.item(c.parent);
            ImVec2 a = view_.toScreen(p.x, layout_.layerY(p.depth));
            ImVec2 b = view_.toScreen(c.x, layout_.layerY(c.depth));
            a.y += float(layout_.halfHeight(p) * glyphScaleY);
            b.y -= float(layout_.halfHeight(c) * glyphScaleY);
            if (std::fabs(a.x - b.x) >= 1.0f || std::fabs(a.y - b.y) >= 1.0f) {
                dl->AddLine(a, b, kColorEdge, 1.0f);
                ++stats_.edgesDrawn;
            }
            if (c.x - layout_.halfWidth(c) > x1) break;  // this one was the right neighbour
        }
    }
}

void TreeGraphPanel::drawPath(ImDrawList* dl) {
    const ImVec2 lo = view_.canvasOrigin(), size = view_.canvasSize();
    const ImVec2 hi(lo.x + size.x, lo.y + size.y);
    for (uint32_t v : highlight_.nodes()) {
        const uint32_t i = layout_.itemOfNode(v);
        if (i == kNoIndex) continue;
        const GraphItem& c = layout_.item(i);
        if (c.parent == kNoIndex || !highlight_.onPath(layout_.item(c.parent).node)) continue;
        const GraphItem& p = layout_.item(c.parent);
        const ImVec2 a = view_.toScreen(p.x, layout_.layerY(p.depth));
        const ImVec2 b = view_.toScreen(c.x, layout_.layerY(c.depth));
        if (std::max(a.x, b.x) < lo.x || std::min(a.x, b.x) > hi.x || std::max(a.y, b.y) < lo.y ||
            std::min(a.y, b.y) > hi.y)
            continue;
        dl->AddLine(a, b, kColorHighlight, 3.5f);
        ++stats_.edgesDrawn;
        ++stats_.pathEdgesDrawn;
    }
}

void TreeGraphPanel::drawBoxes(ImDrawList* dl, const std::vector<uint32_t>& visible, bool labels) {
    char buf[32];
    const float fontSize = ImGui::GetFontSize();
    for (uint32_t i : visible) {
        const GraphItem& it = layout_.item(i);
        ImVec2 a, c;
        glyphRect(i, a, c);
        const bool highlight = highlight_.highlights(it);
        switch (it.kind) {
            case GraphItemKind::Node:
            case GraphItemKind::CollapsedNode: {
                const bool col = it.kind == GraphItemKind::CollapsedNode;
                dl->AddRectFilled(a, c, col ? kColorCollapsed : kColorNode);
                if (!labels) break;
                dl->AddRect(a, c, col ? kColorCollapsedBorder : kColorNodeBorder, 0, 0,
                            col ? 2.0f : 1.0f);
                if (col)
                    std::snprintf(buf, sizeof buf, "+%u", topology_->subtreeNodes[it.node] - 1);
                else
                    std::snprintf(buf, sizeof buf, "%u", it.node);
                const ImVec2 ts = ImGui::CalcTextSize(buf);
                if (ts.x <= c.x - a.x - 2 && fontSize <= c.y - a.y)
                    dl->AddText(ImVec2(0.5f * (a.x + c.x - ts.x), 0.5f * (a.y + c.y - ts.y)),
                                kColorText, buf);
                break;
            }
            case GraphItemKind::VisibleLeaf:
                if (labels)
                    dl->AddCircleFilled(ImVec2(0.5f * (a.x + c.x), 0.5f * (a.y + c.y)),
                                        0.5f * std::min(c.x - a.x, c.y - a.y), kColorVisible, 12);
                else
                    dl->AddRectFilled(a, c, kColorVisible);
                break;
            case GraphItemKind::HiddenLeaf:
                dl->AddRectFilled(a, c, kColorHidden);
                break;
        }
        if (highlight)
            dl->AddRect(ImVec2(a.x - 2, a.y - 2), ImVec2(c.x + 2, c.y + 2), kColorHighlight, 0, 0,
                        2.5f);
    }
}

// Raster mode: boxes under kRasterBelowPx wide, or layers closer than that. All items that fall
// on one pixel row are accumulated per pixel column (difference arrays: O(1) per item, O(width)
// per row), then each row is drawn as runs of equal colour: at most one rectangle per colour
// change, however many items there are. A pixel's colour: the highlight if it holds a highlighted
// item; else, if it holds leaves, the visible or the hidden colour when at least two thirds of
// them are of that kind, and their half-way mix otherwise (approximate by design: an overview);
// else the collapsed or node colour.
void TreeGraphPanel::drawRaster(ImDrawList* dl, const std::vector<uint32_t>& visible) {
    const ImVec2 origin = view_.canvasOrigin();
    const double x0 = view_.x0(), zoomX = view_.zoomX();
    const int width = std::max(1, int(std::ceil(view_.canvasSize().x)));
    rasterDiff_.assign(size_t(width) + 1, RasterCell{});
    // Rows as bands: as tall as the boxes, but leaving at least 40% of a layer free.
    const float glyphPx =
        std::clamp(float(layout_.style().nodeHeight * view_.zoomY()), 1.0f,
                   std::max(1.0f, 0.6f * float(layout_.style().layerSpacing * view_.zoomY())));
    const ImU32 mixed = lerpColor(kColorVisible, kColorHidden, 0.5f);
    int row = INT_MIN, minCol = width, maxCol = -1;
    float rowY = 0;
    const auto flush = [&] {
        std::optional<ImU32> runColor;
        int runStart = 0;
        RasterCell sum;
        for (int c = minCol; c <= maxCol + 1; ++c) {
            std::optional<ImU32> col;
            if (c <= maxCol) {
                const RasterCell& d = rasterDiff_[size_t(c)];
                sum.visible += d.visible, sum.hidden += d.hidden, sum.nodes += d.nodes;
                sum.collapsed += d.collapsed, sum.highlighted += d.highlighted;
                if (sum.highlighted > 0)
                    col = kColorHighlight;
                else if (sum.visible + sum.hidden > 0)
                    col = 3 * sum.hidden <= sum.visible + sum.hidden    ? kColorVisible
                          : 3 * sum.visible <= sum.visible + sum.hidden ? kColorHidden
                                                                        : mixed;
                else if (sum.collapsed > 0)
                    col = kColorCollapsed;
                else if (sum.nodes > 0)
                    col = kColorNode;
            }
            if (col != runColor) {
                if (runColor) {
                    dl->AddRectFilled(ImVec2(origin.x + runStart, rowY - 0.5f * glyphPx),
                                      ImVec2(origin.x + c, rowY + 0.5f * glyphPx), *runColor);
                    ++stats_.rasterRuns;
                }
                runColor = col;
                runStart = c;
            }
            rasterDiff_[size_t(c)] = RasterCell{};
        }
        minCol = width;
        maxCol = -1;
    };
    for (uint32_t i : visible) {
        const GraphItem& it = layout_.item(i);
        const float y = view_.toScreen(0, layout_.layerY(it.depth)).y;
        const int r = int(std::floor(y));
        if (r != row) {
            flush();
            row = r;
            rowY = float(r) + 0.5f;
        }
        const double hw = layout_.halfWidth(it);
        const int c0 = std::clamp(int(std::floor((it.x - hw - x0) * zoomX)), 0, width - 1);
        const int c1 = std::clamp(int(std::floor((it.x + hw - x0) * zoomX)), c0, width - 1);
        minCol = std::min(minCol, c0);
        maxCol = std::max(maxCol, c1);
        // +1 over columns [c0, c1]: at c0, -1 at c1 + 1 (the array has width + 1 cells).
        RasterCell& on = rasterDiff_[size_t(c0)];
        RasterCell& off = rasterDiff_[size_t(c1) + 1];
        int32_t RasterCell::*field = &RasterCell::nodes;
        switch (it.kind) {
            case GraphItemKind::Node:
                field = &RasterCell::nodes;
                break;
            case GraphItemKind::CollapsedNode:
                field = &RasterCell::collapsed;
                break;
            case GraphItemKind::VisibleLeaf:
                field = &RasterCell::visible;
                break;
            case GraphItemKind::HiddenLeaf:
                field = &RasterCell::hidden;
                break;
        }
        ++(on.*field);
        --(off.*field);
        if (highlight_.highlights(it)) {
            ++on.highlighted;
            --off.highlighted;
        }
    }
    flush();
}

void TreeGraphPanel::drawTooltip(uint32_t item) {
    const GraphItem& it = layout_.item(item);
    ImGui::BeginTooltip();
    char a[32], b[32];
    if (isLeafItem(it.kind)) {
        const bool visible = it.kind == GraphItemKind::VisibleLeaf;
        ImGui::TextColored(ImGui::ColorConvertU32ToFloat4(visible ? kColorVisible : kColorHidden),
                           "%s leaf", visible ? "visible" : "hidden");
        ImGui::TextUnformatted(visible ? "lines in this cell reach the light"
                                       : "lines in this cell are blocked");
        if (it.node != kNoIndex)
            ImGui::Text("child[%u] (%s side) of node %u", unsigned(it.side),
                        it.side == 0 ? "positive" : "negative", it.node);
        else
            ImGui::TextUnformatted("the whole pair (no tree needed)");
        ImGui::Text("depth %u", it.depth);
    } else {
        const vis::HistoryNode& n = tree_->nodes[it.node];
        const HistoryTreeTopology& t = *topology_;
        const bool collapsed = it.kind == GraphItemKind::CollapsedNode;
        ImGui::Text("node %u%s", it.node, collapsed ? " (collapsed)" : "");
        ImGui::Text("edge %s", edgeText(*tree_, mesh_, n).c_str());
        if (it.node < tree_->nodeOccluder.size())
            ImGui::Text("occluder face %u", tree_->nodeOccluder[it.node]);
        else
            ImGui::TextUnformatted("occluder face: not recorded");
        ImGui::Text("depth %u", it.depth);
        ImGui::Text("subtree: %u nodes, %u visible / %u hidden leaves", t.subtreeNodes[it.node],
                    t.visibleLeaves[it.node], t.hiddenLeaves[it.node]);
        ImGui::Text("child[0] (+): %s   child[1] (-): %s", childText(n.child[0], a, sizeof a),
                    childText(n.child[1], b, sizeof b));
        if (highlight_.onPath(it.node))
            ImGui::TextColored(ImGui::ColorConvertU32ToFloat4(kColorHighlight),
                               "on the highlighted path");
        else if (collapsed && highlight_.below(it.node))
            ImGui::TextColored(ImGui::ColorConvertU32ToFloat4(kColorHighlight),
                               "hides %u highlighted nodes", highlight_.below(it.node));
        if (collapsed)
            ImGui::TextDisabled("%u nodes hidden: click to expand", t.subtreeNodes[it.node] - 1);
        else
            ImGui::TextDisabled("click to collapse");
    }
    ImGui::EndTooltip();
}

}  // namespace penumbra::ui
