// ViewerSettings: what the viewer remembers between runs, in one JSON file per user:
// $XDG_CONFIG_HOME/penumbra/viewer.json, else ~/.config/penumbra/viewer.json (`penumbra view
// --settings FILE` names another; `penumbra screenshot` reads and writes one only when given
// --settings). It holds the panels' arrangement (panel_arrangement.h), the columns' dragged widths
// and whether Help was shown once (it opens on the first run only):
//
//   {"version": 1, "helpSeen": true, "columns": [LEFT, RIGHT],
//    "layout": {"panels": {"History tree": {"rect": [x, y, w, h], "collapsed": false}},
//               "enlarged": null}}
//
// The file is written atomically (engine/io/atomic_file.h) when the viewer closes. A file that
// cannot be read (not JSON, or an element of the wrong kind) is never fatal: the viewer warns,
// naming the file and the element, starts from the default layout and leaves the file as it is.
#pragma once

#include <filesystem>
#include <string>

#include "app/viewer/panel_arrangement.h"

namespace penumbra::viewer {

struct ViewerSettings {
    PanelArrangement panels;
    int leftWidth = 0, rightWidth = 0;  // the columns' dragged widths (0: the default)
    bool helpSeen = false;
};

// The user's settings file (empty when neither $XDG_CONFIG_HOME nor $HOME is set).
std::filesystem::path defaultSettingsPath();

struct SettingsRead {
    ViewerSettings settings;  // the defaults when the file is missing or unreadable
    bool found = false;       // the file exists
    std::string warning;      // why it could not be read ("" when read or missing)
};
SettingsRead readViewerSettings(const std::filesystem::path& path);

// Creates the file's directory if needed. Throws std::runtime_error naming the file.
void writeViewerSettings(const std::filesystem::path& path, const ViewerSettings& settings);

}  // namespace penumbra::viewer
