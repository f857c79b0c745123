// The viewer in a real window: `penumbra view` under Xvfb (xvfb-run), a click with xdotool on the
// pixel where a known floor point projects, a screenshot of the X root window with ImageMagick's
// `import`; the state the window writes must show that floor point inspected, and the screenshot
// the fragment overlay where the camera projects the independent query's fragments. Skipped
// when xvfb-run, xdotool or import is missing.
//
// Also: frame times of the offscreen UI while a precompute runs.
#include <gtest/gtest.h>

#include <fstream>
#include <iterator>
#include <string>

#include "app/viewer/viewer.h"
#include "engine/io/obj_io.h"
#include "engine/scene/procedural_scenes.h"
#include "tests/app/viewer/viewer_test_support.h"
#include "tests/support/test_scale.h"

namespace penumbra {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

TEST(ViewerWindow, ClickUnderXvfbInspectsThePointAndDrawsItsFragments) {
    for (const char* program : {"xvfb-run", "xdotool", "import"})
        if (!test::haveProgram(program)) GTEST_SKIP() << program << " is not installed";
    const fs::path dir = test::scratchDir("viewer_window");
    const fs::path scene = test::sourceDir() / "assets" / "cornell_box.obj";
    // A camera that sees both the floor and the light from below.
    Camera camera;
    camera.eye = {278, 300, -500};
    camera.target = {278, 300, 280};
    camera.fovYDegrees = 60;
    // The view lies below the menu bar: its height as the offscreen UI of the same size draws it.
    const test::ProcessResult probe = test::runPenumbraGl(
        {"screenshot", scene.string(), "--size", "1280x800", "--no-preview", "--out",
         (dir / "probe.png").string(), "--state-out", (dir / "probe.json").string()});
    ASSERT_EQ(probe.exitCode, 0) << probe.err;
    viewer::LayoutSettings layoutSettings;
    layoutSettings.top = test::readJson(dir / "probe.json")["layout"]["menuBarHeight"].get<int>();
    const viewer::Layout layout = viewer::computeLayout(1280, 800, layoutSettings);
    // In front of the boxes.
    const Vec3 floorPoint{400, 0, 150};
    double px = 0, py = 0;
    ASSERT_TRUE(camera.project(floorPoint, layout.view.width, layout.view.height, px, py));
    const int clickX = layout.view.x + static_cast<int>(px);
    const int clickY = layout.view.y + static_cast<int>(py);
    ASSERT_TRUE(layout.view.contains(clickX, clickY));

    const fs::path state = dir / "state.json", shot = dir / "root.png", script = dir / "run.sh";
    {
        std::ofstream s(script);
        // xvfb-run returns once Xvfb says it is ready, but a loaded machine has been seen to
        // refuse the first connection: wait until a client gets the display.
        s << "set -u\n"
          << "for i in $(seq 100); do xdotool getdisplaygeometry >/dev/null 2>&1 && break; "
          << "sleep 0.1; done\n"
          << test::shellQuote(PENUMBRA_EXE) << " view " << test::shellQuote(scene.string())
          << " --camera 278,300,-500,278,300,280,60 --size 1280x800 --no-preview --quit-after 120"
          // A settings file of its own (a first run: Help open), not the user's.
          << " --settings " << test::shellQuote((dir / "viewer.json").string()) << " --state-out "
          << test::shellQuote(state.string()) << " &\n"
          << "pid=$!\n"
          << "for i in $(seq 300); do [ -f " << test::shellQuote(state.string())
          << " ] && break; sleep 0.1; done\n"
          << "sleep 0.5\n"
          << "xdotool mousemove " << layout.view.x + 20 << " 300 keydown h sleep 0.2 keyup h\n"
          << "sleep 0.3\n"
          << "xdotool mousemove " << clickX << " " << clickY << " click 1\n"
          << "for i in $(seq 300); do grep -q '\"lights\"' " << test::shellQuote(state.string())
          << " && break; sleep 0.1; done\n"
          << "sleep 0.5\n"
          << "import -window root " << test::shellQuote(shot.string()) << "\n"
          << "kill $pid; wait $pid\n";
    }
    const fs::path log = dir / "log.txt";
    auto readLog = [&] {
        std::ifstream in(log);
        return std::string((std::istreambuf_iterator<char>(in)), {});
    };
    // The viewer is killed: its status is not the test's outcome. An X server that never let a
    // client in is the machine's failure, not the viewer's: tried again once, and then reported.
    for (int attempt = 0; attempt < 2; ++attempt) {
        fs::remove(state);
        (void)test::runShell("xvfb-run -a -s '-screen 0 1280x800x24' bash " +
                             test::shellQuote(script.string()) + " >" +
                             test::shellQuote(log.string()) + " 2>&1");
        if (readLog().find("Failed to open display") == std::string::npos) break;
    }
    ASSERT_TRUE(fs::exists(state)) << "the viewer wrote no state; its log:\n" << readLog();
    const json s = test::readJson(state);
    ASSERT_TRUE(s.contains("point") && !s["point"].is_null()) << s.dump();
    EXPECT_EQ(s["panels"]["help"], false);  // the H shortcut reached the viewer
    EXPECT_EQ(s["point"]["face"], 0);       // the floor
    const json& x = s["point"]["point"];
    // The click lands on the pixel containing the projection: within a pixel's footprint.
    EXPECT_NEAR(x[0].get<double>(), floorPoint.x, 6);
    EXPECT_NEAR(x[2].get<double>(), floorPoint.z, 6);
    const test::Image image = test::readPng(shot);
    ASSERT_EQ(image.width, 1280);
    const int viewport[4] = {layout.view.x, layout.view.y, layout.view.width, layout.view.height};
    const Vec3 picked{x[0].get<double>(), x[1].get<double>(), x[2].get<double>()};
    EXPECT_GE(test::checkFragmentOverlay(image, camera, viewport, scene, 0, picked, 0), 1);
}

TEST(ViewerFrames, UiThreadNeverWaitsForThePrecompute) {
    const fs::path dir = test::scratchDir("viewer_frames");
    // 500 random triangles under a light: 508 pairs, about 6 s of precompute on 2 cores, long
    // against any frame (grids.obj, once 10 s, now takes 1 s: not long against the 0.3-0.4 s
    // that a loaded 2-core machine has been seen to stall single frames while all cores build).
    // The sanitizer run (PENUMBRA_TEST_SCALE 0.25) takes 300: its precompute, instrumented, is
    // still some 7 s (28 s with 500), its longest frame 0.12 s (GL is not instrumented).
    const fs::path scene = dir / "soup.obj";
    writeObj(makeRandomSoup(std::max(300, test::scaled(500)), 1), scene);
    const test::ProcessResult r = test::runPenumbraGl(
        {"screenshot", scene.string(), "--no-preview", "--precompute", "--size", "640x400", "--out",
         (dir / "shot.png").string(), "--state-out", (dir / "state.json").string()});
    ASSERT_EQ(r.exitCode, 0) << r.err;
    const json s = test::readJson(dir / "state.json");
    ASSERT_TRUE(s.contains("precomputeFrames")) << "no precompute ran";
    const json& f = s["precomputeFrames"];
    const double precompute = f["precomputeSeconds"].get<double>();
    const double maxFrame = f["maxSeconds"].get<double>();
    const size_t frames = f["frames"].get<size_t>();
    // Frames keep coming while the trees build: the UI thread only polls. A UI thread that waited
    // for the precompute would draw one frame about as long as the precompute, on any machine:
    // the bounds are relative to the precompute's own length, never absolute, so nothing is
    // skipped on a fast machine (a faster one builds the trees and draws the frames faster
    // alike). Here about 230 frames are drawn, the longest 0.4 s. Half the precompute, not a
    // quarter: on a machine loaded by other builds the precompute once took 1.67 s and one frame
    // stalled 0.42 s, while a waiting UI thread would show a frame of about the whole 1.67 s.
    EXPECT_GE(frames, 10u) << "max frame " << maxFrame << " s of " << precompute << " s";
    EXPECT_LT(maxFrame, 0.5 * precompute) << "max frame " << maxFrame << " s of " << precompute;
    EXPECT_EQ(s["precompute"]["done"], s["precompute"]["total"]);
    EXPECT_GT(s["precompute"]["nodes"].get<size_t>(), 0u);
}

}  // namespace
}  // namespace penumbra
