// Tests of the panels the user arranges (app/viewer/panel_arrangement.h) and of the settings file
// that keeps them (app/viewer/viewer_settings.h): the file's reader refuses what is not a layout,
// naming the element; through `penumbra screenshot` (OSMesa), a layout arranged and saved is
// restored from the file at the positions and sizes given, reset restores a fresh start's layout,
// a corrupt file warns naming it and falls back to the default, the enlarged history tree fills
// most of the window, Help opens over the Path panel on the first run only, and no panel's label
// is cut off at the default size at content scales 1, 1.5 and 2.
#include "app/viewer/panel_arrangement.h"

#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

#include "app/viewer/viewer_settings.h"
#include "tests/app/viewer/viewer_test_support.h"

namespace penumbra {
namespace panel_arrangement_test {

namespace fs = std::filesystem;
using nlohmann::json;

std::string readText(const fs::path& p) {
    std::ifstream in(p);
    std::ostringstream s;
    s << in.rdbuf();
    return s.str();
}

void expectRect(const json& actual, const std::array<double, 4>& expected,
                const std::string& what) {
    ASSERT_TRUE(actual.is_array() && actual.size() == 4) << what << ": " << actual;
    for (int i = 0; i < 4; ++i)
        EXPECT_NEAR(actual[i].get<double>(), expected[i], 1.0) << what << " [" << i << "]";
}

const std::vector<std::string> kPanels = {"Scene", "Precompute",  "History tree", "Preview",
                                          "Point", "Light plane", "Path"};

TEST(ViewerSettingsFile, RefusesWhatIsNotALayoutNamingTheElement) {
    const fs::path dir = test::scratchDir("viewer_settings_refuse");
    const auto warningOf = [&](const std::string& text) {
        std::ofstream(dir / "s.json") << text;
        const viewer::SettingsRead r = viewer::readViewerSettings(dir / "s.json");
        EXPECT_TRUE(r.found);
        EXPECT_TRUE(r.settings.panels.placements().empty()) << "not the default layout";
        return r.warning;
    };
    EXPECT_NE(warningOf("{ \"layout\": ").find("not JSON"), std::string::npos);
    EXPECT_NE(warningOf("[1, 2]").find("expected a JSON object"), std::string::npos);
    EXPECT_NE(warningOf(R"({"layout": {"panels": {"Point": {"rect": [1, 2, 3]}}}})")
                  .find("layout.panels.Point.rect: expected 4 numbers"),
              std::string::npos);
    EXPECT_NE(warningOf(R"({"layout": {"panels": {"Point": {"rect": [1, 2, -3, 4]}}}})")
                  .find("width and height must be > 0"),
              std::string::npos);
    EXPECT_NE(warningOf(R"({"layout": {"panels": {"Pointt": {}}}})")
                  .find("layout.panels.Pointt: no panel of this name"),
              std::string::npos);
    EXPECT_NE(warningOf(R"({"layout": {"enlarged": 3}})").find("layout.enlarged"),
              std::string::npos);
    EXPECT_NE(warningOf(R"({"helpSeen": "yes"})").find("helpSeen"), std::string::npos);
    EXPECT_NE(warningOf(R"({"columns": [10]})").find("columns"), std::string::npos);
    // Each warning names the file.
    EXPECT_NE(warningOf("{").find((dir / "s.json").string()), std::string::npos);
    // A missing file is a first run, not an error.
    const viewer::SettingsRead missing = viewer::readViewerSettings(dir / "none.json");
    EXPECT_FALSE(missing.found);
    EXPECT_TRUE(missing.warning.empty());
}

TEST(ViewerSettingsFile, WrittenSettingsReadBackAsWritten) {
    const fs::path dir = test::scratchDir("viewer_settings_roundtrip");
    viewer::ViewerSettings s;
    s.panels.arrange("History tree", {310, 42, 640, 480.5f});
    s.panels.setCollapsed("Scene", true);
    s.panels.toggleEnlarged("Path");
    s.leftWidth = 300;
    s.helpSeen = true;
    const fs::path file = dir / "nested" / "viewer.json";  // the folder is created
    viewer::writeViewerSettings(file, s);
    const viewer::SettingsRead r = viewer::readViewerSettings(file);
    ASSERT_TRUE(r.warning.empty()) << r.warning;
    const auto& p = r.settings.panels.placements();
    ASSERT_TRUE(p.count("History tree") && p.at("History tree").rect);
    const viewer::PanelRect t = *p.at("History tree").rect;
    EXPECT_EQ(t.x, 310);
    EXPECT_EQ(t.y, 42);
    EXPECT_EQ(t.width, 640);
    EXPECT_EQ(t.height, 480.5f);
    ASSERT_TRUE(p.count("Scene"));
    EXPECT_TRUE(p.at("Scene").collapsed);
    EXPECT_FALSE(p.at("Scene").rect);
    EXPECT_EQ(r.settings.panels.enlarged(), "Path");
    EXPECT_EQ(r.settings.leftWidth, 300);
    EXPECT_EQ(r.settings.rightWidth, 0);
    EXPECT_TRUE(r.settings.helpSeen);
}

// The first run arranges the panels and writes the file; the second reads it back: the panels
// where the first put them (the numbers given, not read from the first run), the collapsed one
// collapsed, and Help off.
TEST(ViewerLayoutFile, SavedLayoutIsRestored) {
    const fs::path dir = test::scratchDir("viewer_layout_restore");
    const fs::path settings = dir / "viewer.json";
    const std::array<double, 4> tree = {300, 60, 700, 500}, point = {880, 420, 380, 260};
    const json first = test::shootCornell(
        dir, {"--settings", settings.string(), "--panel", "History tree=300,60,700,500", "--panel",
              "Point=880,420,380,260", "--collapse", "Scene"});
    ASSERT_FALSE(first.empty());
    EXPECT_EQ(first["panels"]["help"], true) << "Help opens on the first run";
    expectRect(first["panelRects"]["History tree"], tree, "first run, tree");
    // The file holds the arrangement.
    ASSERT_TRUE(fs::exists(settings));
    const json file = test::readJson(settings);
    expectRect(file["layout"]["panels"]["History tree"]["rect"], tree, "file, tree");
    expectRect(file["layout"]["panels"]["Point"]["rect"], point, "file, point");
    EXPECT_EQ(file["layout"]["panels"]["Scene"]["collapsed"], true);
    EXPECT_EQ(file["helpSeen"], true);

    const json second = test::shootCornell(dir, {"--settings", settings.string()});
    ASSERT_FALSE(second.empty());
    expectRect(second["panelRects"]["History tree"], tree, "second run, tree");
    expectRect(second["panelRects"]["Point"], point, "second run, point");
    // Collapsed: its title bar only.
    const json& scene = second["panelRects"]["Scene"];
    EXPECT_LT(scene[3].get<double>(), 40) << scene;
    EXPECT_EQ(second["panels"]["help"], false) << "Help is off after the first run";
    EXPECT_FALSE(second["panelRects"].contains("Help"));
}

// Reset gives every panel the place a fresh start gives it, whatever the file said.
TEST(ViewerLayoutFile, ResetRestoresTheDefault) {
    const fs::path dir = test::scratchDir("viewer_layout_reset");
    const fs::path settings = dir / "viewer.json";
    const json fresh = test::shootCornell(dir, {});
    (void)test::shootCornell(
        dir, {"--settings", settings.string(), "--panel", "History tree=300,60,700,500", "--panel",
              "Path=500,300,300,300", "--collapse", "Preview", "--enlarge", "Light plane"});
    const json reset = test::shootCornell(dir, {"--settings", settings.string(), "--reset-layout"});
    ASSERT_FALSE(fresh.empty());
    ASSERT_FALSE(reset.empty());
    for (const std::string& name : kPanels) {
        SCOPED_TRACE(name);
        ASSERT_TRUE(reset["panelRects"].contains(name));
        const json& f = fresh["panelRects"][name];
        expectRect(reset["panelRects"][name], {f[0], f[1], f[2], f[3]}, name);
    }
    EXPECT_GT(std::abs(reset["panelRects"]["History tree"][2].get<double>() - 700), 5);
    EXPECT_TRUE(reset["layout"]["panels"].empty()) << reset["layout"];
    EXPECT_TRUE(reset["layout"]["enlarged"].is_null());
    // The default layout: the columns tile the window below the menu bar.
    const double menu = fresh["layout"]["menuBarHeight"].get<double>();
    EXPECT_GT(menu, 10);
    EXPECT_NEAR(fresh["panelRects"]["Scene"][1].get<double>(), menu, 1);
    EXPECT_NEAR(fresh["panelRects"]["Point"][1].get<double>(), menu, 1);
    const json& view = fresh["panelRects"]["3D view"];
    EXPECT_NEAR(view[1].get<double>(), menu, 1);
    EXPECT_NEAR(fresh["panelRects"]["Scene"][2].get<double>(), view[0].get<double>(), 1);
}

// A file that is not a layout: a warning naming the file on stderr and in the status line, the
// default layout, exit status 0, and the file left as it was.
TEST(ViewerLayoutFile, CorruptFileWarnsAndFallsBackToTheDefault) {
    const fs::path dir = test::scratchDir("viewer_layout_corrupt");
    const json fresh = test::shootCornell(dir, {});
    for (const std::string& text :
         {std::string("{\"layout\": {\"panels\": {\"Point\": "),
          std::string(R"({"layout": {"panels": {"Point": {"rect": [1, 2, "x", 4]}}}})"),
          std::string("\x89PNG\r\n\x1a\n binary")}) {
        SCOPED_TRACE(text);
        const fs::path settings = dir / "corrupt.json";
        std::ofstream(settings, std::ios::binary) << text;
        test::ProcessResult r;
        const json state =
            test::shootCornell(dir, {"--settings", settings.string()}, "1280x800", &r);
        ASSERT_FALSE(state.empty());
        EXPECT_NE(r.err.find("warning"), std::string::npos) << r.err;
        EXPECT_NE(r.err.find(settings.string()), std::string::npos) << r.err;
        EXPECT_NE(r.err.find("default layout"), std::string::npos) << r.err;
        EXPECT_NE(state["panelText"].value("Status", "").find(settings.string()), std::string::npos)
            << state["panelText"];
        for (const std::string& name : kPanels) {
            const json& f = fresh["panelRects"][name];
            expectRect(state["panelRects"][name], {f[0], f[1], f[2], f[3]}, name);
        }
        EXPECT_EQ(readText(settings), text) << "the unreadable file was overwritten";
    }
}

// The enlarged history tree covers most of the window (the enlarged rectangle: the window below
// the menu bar less a margin of 4% of its smaller side), in front of the panels.
TEST(ViewerLayoutFile, EnlargedTreeFillsMostOfTheWindow) {
    const fs::path dir = test::scratchDir("viewer_layout_enlarge");
    const json state =
        test::shootCornell(dir, {"--point", "278,0,280", "--enlarge", "History tree"});
    ASSERT_FALSE(state.empty());
    const json& t = state["panelRects"]["History tree"];
    const double area = t[2].get<double>() * t[3].get<double>();
    EXPECT_GT(area, 0.8 * 1280 * 800) << t;
    EXPECT_EQ(state["layout"]["enlarged"], "History tree");
    // Its graph is drawn: the tree of the inspected point's pair.
    EXPECT_NE(state["panelText"].value("History tree", "").find("receiver face"),
              std::string::npos);
}

// Help opens over the Path panel (empty before a click), never over the 3D view.
TEST(ViewerLayoutFile, HelpOpensOverThePathPanelNotTheView) {
    const fs::path dir = test::scratchDir("viewer_layout_help");
    const json state = test::shootCornell(dir, {});
    ASSERT_FALSE(state.empty());
    const json& help = state["panelRects"]["Help"];
    const json& path = state["panelRects"]["Path"];
    const json& view = state["panelRects"]["3D view"];
    expectRect(help, {path[0], path[1], path[2], path[3]}, "Help");
    EXPECT_GE(help[0].get<double>(), view[0].get<double>() + view[2].get<double>() - 1);
}

// At the default window size (1280x800 in screen units: the framebuffer is that times the content
// scale) and content scales 1, 1.5 and 2, with a point inspected and every preview mode's legend:
// no item of any panel reaches past its panel's (or its table column's) right edge.
TEST(ViewerLayout, NoLabelIsCutOffAtScales1To2) {
    const fs::path dir = test::scratchDir("viewer_labels_fit");
    for (const auto& [size, scale] : {std::pair<std::string, std::string>{"1280x800", "1"},
                                      {"1920x1200", "1.5"},
                                      {"2560x1600", "2"}})
        for (const char* view : {"answers", "diff"}) {
            SCOPED_TRACE(size + " scale " + scale + " view " + view);
            const fs::path shot = dir / ("shot_" + scale + "_" + view + ".png");
            const std::vector<std::string> args = {
                "screenshot",      test::cornellObj().string(),
                "--size",          size,
                "--ui-scale",      scale,
                "--point",         "278,0,280",
                "--view",          view,
                "--passes",        "1",
                "--light-samples", "1",
                "--out",           shot.string(),
                "--state-out",     (dir / "state.json").string()};
            const test::ProcessResult r = test::runPenumbraGl(args);
            ASSERT_EQ(r.exitCode, 0) << r.err;
            const json state = test::readJson(dir / "state.json");
            ASSERT_TRUE(state.contains("panelOverflow"));
            const json& overflow = state["panelOverflow"];
            for (const std::string& name : kPanels) EXPECT_TRUE(overflow.contains(name)) << name;
            for (const auto& [name, pixels] : overflow.items())
                EXPECT_LE(pixels.get<double>(), 1.0)
                    << name << ": an item reaches " << pixels << " px past the edge";
        }
}

}  // namespace panel_arrangement_test
}  // namespace penumbra
