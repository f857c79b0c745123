#include "app/viewer/viewer_settings.h"

#include <cstdlib>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include "engine/io/atomic_file.h"

namespace penumbra::viewer {

std::filesystem::path defaultSettingsPath() {
    const char* xdg = std::getenv("XDG_CONFIG_HOME");
    if (xdg != nullptr && *xdg != 0) return std::filesystem::path(xdg) / "penumbra" / "viewer.json";
    const char* home = std::getenv("HOME");
    if (home != nullptr && *home != 0)
        return std::filesystem::path(home) / ".config" / "penumbra" / "viewer.json";
    return {};
}

namespace viewer_settings_detail {

ViewerSettings parseSettings(const std::string& text) {
    nlohmann::json j;
    try {
        j = nlohmann::json::parse(text);
    } catch (const nlohmann::json::parse_error& e) {
        // The parser quotes what it read last, which may be any bytes: only printable ASCII goes
        // into the warning (the status line, the state JSON).
        std::string what = e.what();
        for (char& c : what)
            if (static_cast<unsigned char>(c) < 0x20 || static_cast<unsigned char>(c) > 0x7e)
                c = '?';
        throw std::invalid_argument("not JSON (" + what + ")");
    }
    if (!j.is_object()) throw std::invalid_argument("expected a JSON object");
    ViewerSettings s;
    if (j.contains("helpSeen")) {
        if (!j["helpSeen"].is_boolean())
            throw std::invalid_argument("helpSeen: expected true or false");
        s.helpSeen = j["helpSeen"].get<bool>();
    }
    if (j.contains("columns")) {
        const nlohmann::json& c = j["columns"];
        if (!c.is_array() || c.size() != 2 || !c[0].is_number_integer() ||
            !c[1].is_number_integer() || c[0].get<int>() < 0 || c[1].get<int>() < 0)
            throw std::invalid_argument("columns: expected two widths in pixels (0: the default)");
        s.leftWidth = c[0].get<int>();
        s.rightWidth = c[1].get<int>();
    }
    if (j.contains("layout")) {
        try {
            s.panels = PanelArrangement::fromJson(j["layout"]);
        } catch (const std::invalid_argument& e) {
            throw std::invalid_argument(std::string("layout.") + e.what());
        }
    }
    return s;
}

}  // namespace viewer_settings_detail

SettingsRead readViewerSettings(const std::filesystem::path& path) {
    SettingsRead r;
    std::error_code ec;
    if (path.empty() || !std::filesystem::exists(path, ec)) return r;
    r.found = true;
    std::ifstream in(path, std::ios::binary);
    std::ostringstream text;
    text << in.rdbuf();
    if (!in) {
        r.warning =
            "cannot read the viewer settings '" + path.string() + "'; the default layout is used";
        return r;
    }
    try {
        r.settings = viewer_settings_detail::parseSettings(text.str());
    } catch (const std::invalid_argument& e) {
        r.warning = "the viewer settings '" + path.string() + "' are unreadable: " + e.what() +
                    "; the default layout is used and the file is left as it is (fix or delete it)";
    }
    return r;
}

void writeViewerSettings(const std::filesystem::path& path, const ViewerSettings& s) {
    const nlohmann::json j = {{"version", 1},
                              {"helpSeen", s.helpSeen},
                              {"columns", {s.leftWidth, s.rightWidth}},
                              {"layout", s.panels.toJson()}};
    std::error_code ec;
    if (path.has_parent_path()) std::filesystem::create_directories(path.parent_path(), ec);
    if (ec)
        throw std::runtime_error("cannot write '" + path.string() + "': cannot create " +
                                 path.parent_path().string() + ": " + ec.message());
    writeFileAtomically(path, j.dump(2) + "\n");
}

}  // namespace penumbra::viewer
