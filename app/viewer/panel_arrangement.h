// PanelArrangement: where the user put each panel. Every panel is a Dear ImGui window the user
// moves (by its title bar), resizes (by its edges and corner), collapses (its arrow or a double
// click on the title) and enlarges (E over it, or the Panels menu) to most of the window; "reset
// layout" (Ctrl+L, or the menu) puts every panel back in its default place (layout.h).
//
// A panel the user has not moved follows the default layout (the columns' widths, the window's
// size); once moved or resized it stays where the user put it (kept inside the window) until the
// layout is reset. The arrangement is saved in the viewer's settings file (viewer_settings.h) as
// JSON: {"panels": {NAME: {"rect": [x, y, width, height], "collapsed": bool}}, "enlarged": NAME}.
//
// Each frame the viewer calls place() before a panel's window and observe() after it: place()
// sets the window's position, size and collapsed state only when they must change (a reset, an
// enlargement, a new default), so that Dear ImGui's own dragging works in between; observe()
// reads back what the user did.
#pragma once

#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "app/viewer/layout.h"

namespace penumbra::viewer {

struct PanelPlacement {
    std::optional<PanelRect> rect;  // where the user put it; none: the default layout's place
    bool collapsed = false;
};

// The arrangeable panels, by the names the state JSON and the settings file use, with their
// windows' titles.
struct PanelName {
    const char* name;
    const char* title;
};
const std::vector<PanelName>& arrangeablePanels();
// The default place of panel `name` in `layout` (an empty rectangle for an unknown name).
PanelRect defaultPanelRect(const Layout& layout, const std::string& name);

class PanelArrangement {
  public:
    // Before the panel's window: sets its place (the enlarged rectangle, the user's or the
    // default) when it differs from the last one set or seen.
    void place(const std::string& name, const Layout& layout);
    // After the panel's window (after its End): what the user did to it this frame. An enlarged
    // panel the user moves or resizes keeps the new place and is no longer enlarged.
    void observe(const std::string& name, const char* title);

    // Every panel back to its default place, expanded; none enlarged.
    void reset();
    // The user's actions, as the mouse does them (the command line's --panel, --collapse,
    // --enlarge; tests). `rect` is kept inside the window when placed.
    void arrange(const std::string& name, const PanelRect& rect);
    void setCollapsed(const std::string& name, bool collapsed);
    // Enlarges `name` (restoring the one enlarged before), or restores it when it is enlarged.
    void toggleEnlarged(const std::string& name);
    const std::string& enlarged() const { return enlarged_; }  // empty: none
    const std::map<std::string, PanelPlacement>& placements() const { return placements_; }

    // The rectangle the panel's window had in the last frame it was drawn (empty if never).
    PanelRect shown(const std::string& name) const;

    nlohmann::json toJson() const;
    // Throws std::invalid_argument naming the element at fault ("panels.Scene.rect: ...").
    static PanelArrangement fromJson(const nlohmann::json& j);

  private:
    // The place a panel should have now.
    PanelRect target(const std::string& name, const Layout& layout) const;

    std::map<std::string, PanelPlacement> placements_;  // the user's, by panel name
    std::string enlarged_;
    struct Applied {
        std::optional<PanelRect> rect;  // last set or seen
        std::optional<bool> collapsed;
        // Frames left to bring it to the front at place(): two, so that it is in front of the
        // windows first drawn after it too (a new window opens in front).
        int focusFrames = 0;
    };
    std::map<std::string, Applied> applied_;
};

}  // namespace penumbra::viewer
