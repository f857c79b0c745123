// The headless host's refusals (app/viewer/host/host_error.h) as the commands report them: each
// names the option at fault (or none, for the scene), and `penumbra view` with no display tries
// again without its pixel when nothing lies under the centre of the view.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>
#include <vector>

#include "tests/app/viewer/viewer_test_support.h"

namespace penumbra {
namespace {

namespace fs = std::filesystem;

fs::path cornellObj() { return test::sourceDir() / "assets" / "cornell_box.obj"; }

TEST(HeadlessHost, ScreenshotRefusalsNameTheOptionAtFault) {
    const fs::path dir = test::scratchDir("headless_host_refusals");
    const std::string out = (dir / "x.png").string();
    struct Case {
        std::vector<std::string> args;
        std::string message;  // the start of stderr after "penumbra: error: "
    };
    const std::vector<Case> cases = {
        // (2, 2) lies in the Scene panel, outside the 3D view: no surface under it.
        {{cornellObj().string(), "--pixel", "2,2"}, "--pixel: nothing under pixel (2, 2)"},
        {{cornellObj().string(), "--point", "1e9,0,0"},
         "--point: point (1e+09, 0, 0) lies on no face"},
        {{(dir / "none.obj").string()}, "cannot open " + (dir / "none.obj").string()},
    };
    for (const Case& c : cases) {
        std::vector<std::string> args = {"screenshot", "--no-preview", "--out", out};
        args.insert(args.end(), c.args.begin(), c.args.end());
        const test::ProcessResult r = test::runPenumbraGl(args);
        EXPECT_EQ(r.exitCode, 1) << r.err;
        EXPECT_EQ(r.err.rfind("penumbra: error: " + c.message, 0), 0u) << r.err;
        EXPECT_FALSE(fs::exists(out));
    }
}

TEST(HeadlessHost, ViewWithoutDisplayDropsThePixelWhenNothingIsUnderTheCentre) {
    const fs::path dir = test::scratchDir("headless_host_view");
    // Looking away from the box: nothing under the centre of the view.
    const std::string command =
        "env -u DISPLAY -u WAYLAND_DISPLAY " + test::shellQuote(PENUMBRA_EXE) + " view " +
        test::shellQuote(cornellObj().string()) +
        " --camera 278,273,-800,278,273,-1600,40 --no-preview --size 800x600 --out-dir " +
        test::shellQuote(dir.string()) + " >/dev/null 2>" +
        test::shellQuote((dir / "stderr").string());
    ASSERT_EQ(test::runShell(command), 0);
    const test::Image image = test::readPng(dir / "view.png");
    EXPECT_EQ(image.width, 800);
    const nlohmann::json state = test::readJson(dir / "view_state.json");
    EXPECT_TRUE(state["point"].is_null());
    EXPECT_FALSE(state.value("inspectionPending", true));
}

}  // namespace
}  // namespace penumbra
