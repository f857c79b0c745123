#include "app/viewer/panel_arrangement.h"

#include <imgui.h>
#include <imgui_internal.h>  // ImGui::FindWindowByName: the window's place after its End

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace penumbra::viewer {

namespace panel_arrangement_detail {

// Dear ImGui floors window positions and sizes: a pixel of difference is no move of the user's.
bool differs(const PanelRect& a, const PanelRect& b) {
    return std::fabs(a.x - b.x) > 1 || std::fabs(a.y - b.y) > 1 ||
           std::fabs(a.width - b.width) > 1 || std::fabs(a.height - b.height) > 1;
}

// Inside the window below the menu bar, no smaller than Dear ImGui lets a window be.
PanelRect keepInside(PanelRect r, const Layout& l) {
    const float top = static_cast<float>(l.view.y);
    const float width = static_cast<float>(l.width), height = static_cast<float>(l.height) - top;
    ImVec2 minSize(32, 32);
    if (ImGui::GetCurrentContext() != nullptr) minSize = ImGui::GetStyle().WindowMinSize;
    r.width = std::clamp(r.width, minSize.x, std::max(minSize.x, width));
    r.height = std::clamp(r.height, minSize.y, std::max(minSize.y, height));
    r.x = std::clamp(r.x, 0.0f, std::max(0.0f, width - r.width));
    r.y = std::clamp(r.y, top, std::max(top, top + height - r.height));
    return r;
}

nlohmann::json rectJson(const PanelRect& r) { return {r.x, r.y, r.width, r.height}; }

}  // namespace panel_arrangement_detail

using namespace panel_arrangement_detail;

const std::vector<PanelName>& arrangeablePanels() {
    static const std::vector<PanelName> panels = {
        {"Scene", "Scene"},     {"Precompute", "Precompute"}, {"History tree", "History tree"},
        {"Preview", "Preview"}, {"Point", "Point"},           {"Light plane", "Light plane"},
        {"Path", "Path"},       {"Help", "Help (H)"}};
    return panels;
}

PanelRect defaultPanelRect(const Layout& l, const std::string& name) {
    if (name == "Scene") return l.scene;
    if (name == "Precompute") return l.precompute;
    if (name == "History tree") return l.tree;
    if (name == "Preview") return l.preview;
    if (name == "Point") return l.point;
    if (name == "Light plane") return l.lightPlane;
    if (name == "Path") return l.path;
    if (name == "Help") return l.help;
    return {};
}

PanelRect PanelArrangement::target(const std::string& name, const Layout& layout) const {
    if (name == enlarged_) return keepInside(layout.enlarged, layout);
    const auto it = placements_.find(name);
    if (it != placements_.end() && it->second.rect) return keepInside(*it->second.rect, layout);
    return keepInside(defaultPanelRect(layout, name), layout);
}

void PanelArrangement::place(const std::string& name, const Layout& layout) {
    Applied& a = applied_[name];
    // Opaque: panels may lie over one another now, and no text may show through.
    ImGui::SetNextWindowBgAlpha(1.0f);
    const PanelRect want = target(name, layout);
    if (!a.rect || differs(*a.rect, want)) {
        ImGui::SetNextWindowPos(ImVec2(want.x, want.y), ImGuiCond_Always);
        ImGui::SetNextWindowSize(ImVec2(want.width, want.height), ImGuiCond_Always);
        a.rect = want;
    }
    const auto it = placements_.find(name);
    const bool collapsed = name != enlarged_ && it != placements_.end() && it->second.collapsed;
    if (!a.collapsed || *a.collapsed != collapsed) {
        ImGui::SetNextWindowCollapsed(collapsed, ImGuiCond_Always);
        a.collapsed = collapsed;
    }
    if (a.focusFrames > 0) {
        ImGui::SetNextWindowFocus();
        --a.focusFrames;
    }
}

void PanelArrangement::observe(const std::string& name, const char* title) {
    const ImGuiWindow* w = ImGui::FindWindowByName(title);
    if (w == nullptr || w->LastFrameActive != ImGui::GetFrameCount()) return;
    Applied& a = applied_[name];
    const PanelRect full{w->Pos.x, w->Pos.y, w->SizeFull.x, w->SizeFull.y};
    if (a.rect && differs(full, *a.rect)) {
        // Moved or resized by the user (kept inside the window at the next place()).
        placements_[name].rect = full;
        if (enlarged_ == name) enlarged_.clear();
        a.rect = full;
    }
    if (a.collapsed && *a.collapsed != w->Collapsed) {
        placements_[name].collapsed = w->Collapsed;
        a.collapsed = w->Collapsed;
        if (w->Collapsed && enlarged_ == name) {
            // Collapsing an enlarged panel restores it first (collapsed in its own place).
            enlarged_.clear();
            a.rect.reset();
        }
    }
}

PanelRect PanelArrangement::shown(const std::string& name) const {
    for (const PanelName& p : arrangeablePanels())
        if (name == p.name) {
            const ImGuiWindow* w = ImGui::FindWindowByName(p.title);
            if (w == nullptr) return {};
            return {w->Pos.x, w->Pos.y, w->Size.x, w->Size.y};
        }
    return {};
}

void PanelArrangement::reset() {
    placements_.clear();
    enlarged_.clear();
}

void PanelArrangement::arrange(const std::string& name, const PanelRect& rect) {
    placements_[name].rect = rect;
    if (enlarged_ == name) enlarged_.clear();
}

void PanelArrangement::setCollapsed(const std::string& name, bool collapsed) {
    placements_[name].collapsed = collapsed;
}

void PanelArrangement::toggleEnlarged(const std::string& name) {
    if (enlarged_ == name) {
        enlarged_.clear();
        return;
    }
    enlarged_ = name;
    applied_[name].focusFrames = 2;  // in front of the panels it covers
}

nlohmann::json PanelArrangement::toJson() const {
    nlohmann::json panels = nlohmann::json::object();
    for (const auto& [name, p] : placements_) {
        nlohmann::json e = {{"collapsed", p.collapsed}};
        if (p.rect) e["rect"] = rectJson(*p.rect);
        panels[name] = e;
    }
    return {{"panels", panels},
            {"enlarged", enlarged_.empty() ? nlohmann::json(nullptr) : nlohmann::json(enlarged_)}};
}

PanelArrangement PanelArrangement::fromJson(const nlohmann::json& j) {
    if (!j.is_object()) throw std::invalid_argument("expected an object");
    const auto known = [](const std::string& name) {
        const auto& all = arrangeablePanels();
        return std::any_of(all.begin(), all.end(),
                           [&](const PanelName& p) { return name == p.name; });
    };
    PanelArrangement a;
    if (j.contains("panels")) {
        const nlohmann::json& panels = j["panels"];
        if (!panels.is_object()) throw std::invalid_argument("panels: expected an object");
        for (const auto& [name, e] : panels.items()) {
            const std::string where = "panels." + name;
            if (!known(name)) throw std::invalid_argument(where + ": no panel of this name");
            if (!e.is_object()) throw std::invalid_argument(where + ": expected an object");
            PanelPlacement p;
            if (e.contains("rect")) {
                const nlohmann::json& r = e["rect"];
                if (!r.is_array() || r.size() != 4 ||
                    !std::all_of(r.begin(), r.end(), [](const nlohmann::json& v) {
                        return v.is_number() && std::isfinite(v.get<double>());
                    }))
                    throw std::invalid_argument(where +
                                                ".rect: expected 4 numbers (x, y, width, height)");
                p.rect = PanelRect{r[0].get<float>(), r[1].get<float>(), r[2].get<float>(),
                                   r[3].get<float>()};
                if (!(p.rect->width > 0 && p.rect->height > 0))
                    throw std::invalid_argument(where + ".rect: width and height must be > 0");
            }
            if (e.contains("collapsed")) {
                if (!e["collapsed"].is_boolean())
                    throw std::invalid_argument(where + ".collapsed: expected true or false");
                p.collapsed = e["collapsed"].get<bool>();
            }
            a.placements_[name] = p;
        }
    }
    if (j.contains("enlarged") && !j["enlarged"].is_null()) {
        if (!j["enlarged"].is_string() || !known(j["enlarged"].get<std::string>()))
            throw std::invalid_argument("enlarged: expected a panel's name or null");
        a.enlarged_ = j["enlarged"].get<std::string>();
    }
    return a;
}

}  // namespace penumbra::viewer
