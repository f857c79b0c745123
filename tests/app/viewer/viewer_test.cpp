// Tests of the viewer (app/viewer/): the path sides of the point inspection against the
// from-point query, and the headless screenshots (`penumbra screenshot`, OSMesa) checked for
// content against independent queries: the fragment overlay is where the camera projects the
// exact fragments, the path panel's state lists the query's path, picking a pixel inspects the
// surface an independent ray hits, bad arguments are refused. The Scene panel's list holds every
// format the loader reads, from assets/ and assets/scenes/.
#include "app/viewer/viewer.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <iterator>
#include <set>
#include <vector>

#include "engine/io/image_io.h"
#include "engine/io/obj_io.h"
#include "engine/io/scene_loader.h"
#include "engine/precompute/point_inspection.h"
#include "engine/raytrace/embree_scene.h"
#include "tests/app/viewer/viewer_test_support.h"
#include "tests/support/exact_reference.h"
#include "tests/support/read_exr.h"
#include "tests/support/read_pfm.h"
#include "tests/support/test_files.h"
#include "tests/support/two_light_scene.h"

namespace penumbra {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

// Below the ceiling in front of the open side of the Cornell box, looking up at the light: its
// fragments are seen from the front, nothing in between.
const char* kCameraFlag = "278,150,-350,278,548,280,45";
Camera lightCamera() {
    Camera c;
    c.eye = {278, 150, -350};
    c.target = {278, 548, 280};
    c.fovYDegrees = 45;
    return c;
}

// At every window size from 1280x720 to 3840x2160, content scale 1 to 2 (HiDPI) and dragged
// column widths (none, narrow, too wide for the window), the docked panels and the 3D view tile
// the window: each inside it, no two overlapping, their areas summing to the window's; the view
// keeps its minimum width.
TEST(ViewerLayout, PanelsTileTheWindowAtEverySizeAndScale) {
    int layouts = 0;
    for (int w = 1280; w <= 3840; w += 160)
        for (int h = 720; h <= 2160; h += 144)
            for (float scale : {1.0f, 1.25f, 1.5f, 2.0f})
                for (const auto& [left, right] :
                     {std::pair{0, 0}, std::pair{200, 150}, std::pair{2000, 1900}}) {
                    const viewer::LayoutSettings settings{scale, left, right};
                    const viewer::Layout l = viewer::computeLayout(w, h, settings);
                    SCOPED_TRACE(std::to_string(w) + "x" + std::to_string(h) + " scale " +
                                 std::to_string(scale) + " columns " + std::to_string(left) + "/" +
                                 std::to_string(right));
                    const viewer::PanelRect view{
                        static_cast<float>(l.view.x), static_cast<float>(l.view.y),
                        static_cast<float>(l.view.width), static_cast<float>(l.view.height)};
                    const std::vector<viewer::PanelRect> rects = {
                        view,      l.scene, l.precompute, l.tree,
                        l.preview, l.point, l.lightPlane, l.path};
                    double area = 0;
                    for (size_t i = 0; i < rects.size(); ++i) {
                        const viewer::PanelRect& a = rects[i];
                        EXPECT_GE(a.x, 0);
                        EXPECT_GE(a.y, 0);
                        EXPECT_LE(a.x + a.width, w + 1e-3);
                        EXPECT_LE(a.y + a.height, h + 1e-3);
                        EXPECT_GT(a.width, 0);
                        EXPECT_GT(a.height, 0);
                        area += double(a.width) * a.height;
                        for (size_t j = i + 1; j < rects.size(); ++j) {
                            const viewer::PanelRect& b = rects[j];
                            const double ox =
                                std::min(a.x + a.width, b.x + b.width) - std::max(a.x, b.x);
                            const double oy =
                                std::min(a.y + a.height, b.y + b.height) - std::max(a.y, b.y);
                            EXPECT_FALSE(ox > 1e-3 && oy > 1e-3) << "rects " << i << ", " << j;
                        }
                    }
                    EXPECT_NEAR(area, double(w) * h, 1e-3 * w * h);
                    EXPECT_GE(l.view.width, static_cast<int>(viewer::kMinViewWidth * scale));
                    if (left == 200) {
                        EXPECT_EQ(l.leftWidth, 200);
                    }
                    if (::testing::Test::HasFailure()) return;
                    ++layouts;
                }
    EXPECT_EQ(layouts, 17 * 11 * 4 * 3);
}

// The real windows, drawn by ImGui, at a HiDPI scale and the largest size, and at the smallest
// size: no panel in its default place over another or over the 3D view, the status line inside
// the view, Help over the Path panel.
TEST(ViewerLayout, WindowsStayApartAtHiDpiScale) {
    const fs::path dir = test::scratchDir("viewer_hidpi");
    auto shoot = [&](const std::string& size, const std::string& scale) {
        return test::shootCornell(dir, {"--ui-scale", scale, "--point", "278,0,280"}, size);
    };
    for (const auto& [size, scale] :
         {std::pair<std::string, std::string>{"3840x2160", "2"}, {"1280x720", "1"}}) {
        SCOPED_TRACE(size + " scale " + scale);
        const json state = shoot(size, scale);
        const json& rects = state["panelRects"];
        const json& view = rects["3D view"];
        std::vector<std::pair<std::string, std::array<double, 4>>> docked;
        for (const auto& [name, r] : rects.items()) {
            const std::array<double, 4> a = {r[0], r[1], r[2], r[3]};
            if (name == "Help") {
                // Over the Path panel (empty until a click), beside the view, never over it.
                const json& path = rects["Path"];
                for (int k = 0; k < 4; ++k)
                    EXPECT_NEAR(a[k], path[k].get<double>(), 1) << "Help " << k;
                continue;
            }
            if (name == "Status") {
                EXPECT_GE(a[0], view[0].get<double>()) << name;
                EXPECT_LE(a[0] + a[2], view[0].get<double>() + view[2].get<double>()) << name;
                EXPECT_LE(a[1] + a[3], view[1].get<double>() + view[3].get<double>()) << name;
                continue;
            }
            docked.emplace_back(name, a);
        }
        EXPECT_GE(docked.size(), 8u);  // the 3D view and the seven docked panels
        for (size_t i = 0; i < docked.size(); ++i)
            for (size_t j = i + 1; j < docked.size(); ++j) {
                const auto& a = docked[i].second;
                const auto& b = docked[j].second;
                const double ox = std::min(a[0] + a[2], b[0] + b[2]) - std::max(a[0], b[0]);
                const double oy = std::min(a[1] + a[3], b[1] + b[3]) - std::max(a[1], b[1]);
                EXPECT_FALSE(ox > 0.5 && oy > 0.5) << docked[i].first << " / " << docked[j].first;
            }
    }
}

// The settings that shape the answer, as the UI holds them (the Preview panel edits them): the
// command line's defaults (engine/render/exact_options.h, the renderer's) when no flag is given,
// the flags' values otherwise.
TEST(ViewerScreenshot, ExactOptionsInTheUiAreTheCommandLines) {
    const fs::path dir = test::scratchDir("viewer_exact_options");
    auto shoot = [&](const std::vector<std::string>& extra) {
        return test::shootCornell(dir, extra, "640x400")["exact"];
    };
    const ExactOptions defaults;
    const json d = shoot({});
    EXPECT_EQ(d["maxLpSolves"], defaults.maxLpSolves);
    EXPECT_EQ(d["minTreeSamples"], defaults.minTreeSamples);
    EXPECT_EQ(d["exactWorkLimit"], defaults.exactWorkLimit);
    EXPECT_EQ(d["minTreeSamples"], RenderSettings{}.minTreeSamples);
    EXPECT_EQ(d["exactWorkLimit"], RenderSettings{}.exactWorkLimit);
    EXPECT_EQ(d["lightEdgeWorkLimit"], RenderSettings{}.lightEdgeWorkLimit);
    EXPECT_EQ(d["refineLevels"], RenderSettings{}.refineLevels);
    const json g = shoot({"--max-lp-solves", "77", "--min-tree-samples", "5", "--exact-work-limit",
                          "999", "--light-edge-work-limit", "4321", "--passes", "3",
                          "--light-samples", "9", "--refine-levels", "1"});
    EXPECT_EQ(g["maxLpSolves"], 77);
    EXPECT_EQ(g["minTreeSamples"], 5);
    EXPECT_EQ(g["exactWorkLimit"], 999);
    EXPECT_EQ(g["lightEdgeWorkLimit"], 4321);
    EXPECT_EQ(g["refineLevels"], 1);
    EXPECT_EQ(g["passes"], 3);
    EXPECT_EQ(g["lightSamples"], 9);
}

// A scene the loader repairs: its warnings are on stderr, in the status line and in the Scene
// panel (the state JSON's "sceneWarnings"); --strict refuses it with the loader's error.
TEST(ViewerScreenshot, LoaderWarningsReachTheSceneStatusAndStderr) {
    const fs::path dir = test::scratchDir("viewer_loader_warnings");
    std::ofstream(dir / "lamp.mtl") << "newmtl lamp\nKe 5 5 5\n";
    std::ofstream(dir / "repair.obj")
        << "mtllib lamp.mtl\nv -2 0 -2\nv -2 0 2\nv 2 0 2\nv 2 0 -2\n"    // lines 1-5
           "v -1 2 -1\nv 1 2 -1\nv 1 2 1\nv -1 2 1\n"                     // 6-9
           "usemtl floor\nf 1 2 3 4\nf 1 2 2\nusemtl lamp\nf 5 6 7 8\n";  // 10-14
    const std::string scene = (dir / "repair.obj").string();
    const std::vector<std::string> args = {"screenshot",
                                           scene,
                                           "--size",
                                           "640x400",
                                           "--no-preview",
                                           "--out",
                                           (dir / "shot.png").string(),
                                           "--state-out",
                                           (dir / "state.json").string()};
    const test::ProcessResult r = test::runPenumbraGl(args);
    ASSERT_EQ(r.exitCode, 0) << r.err;
    const std::string usemtl = scene +
                               ": usemtl 'floor' on line 10 names no material (1 materials "
                               "defined): 1 face uses a default diffuse material";
    EXPECT_NE(r.err.find("penumbra: warning: " + usemtl + "\n"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("penumbra: warning: " + scene + ": dropped 1 degenerate"),
              std::string::npos)
        << r.err;
    const json state = test::readJson(dir / "state.json");
    ASSERT_EQ(state["sceneWarnings"].size(), 2u) << state["sceneWarnings"].dump();
    EXPECT_EQ(state["sceneWarnings"][0], usemtl);
    EXPECT_NE(state["sceneWarnings"][1].get<std::string>().find("line 12"), std::string::npos)
        << state["sceneWarnings"][1];
    EXPECT_NE(state["status"].get<std::string>().find("2 faces, 1 area lights; 2 warnings, the "
                                                      "first: " +
                                                      usemtl),
              std::string::npos)
        << state["status"];
    std::vector<std::string> strict = args;
    strict.push_back("--strict");
    const test::ProcessResult s = test::runPenumbraGl(strict);
    EXPECT_EQ(s.exitCode, 1) << s.err;
    EXPECT_NE(s.err.find(scene + ":12: face 1: vertex 2 repeated"), std::string::npos) << s.err;
}

// Below a menu bar the panels and the view tile what is left of the window; with the history tree
// hidden (T) the Preview panel takes its place and leaves no hole; the enlarged rectangle covers
// most of the window below the menu bar.
TEST(ViewerLayout, MenuBarAndHiddenTreeLeaveNoHole) {
    for (const bool tree : {true, false}) {
        SCOPED_TRACE(tree ? "tree shown" : "tree hidden");
        viewer::LayoutSettings settings;
        settings.top = 19;
        settings.tree = tree;
        const viewer::Layout l = viewer::computeLayout(1280, 800, settings);
        EXPECT_EQ(l.view.y, 19);
        EXPECT_EQ(l.view.height, 800 - 19);
        std::vector<viewer::PanelRect> rects = {l.scene, l.precompute, l.preview,
                                                l.point, l.lightPlane, l.path};
        if (tree) rects.push_back(l.tree);
        double area = double(l.view.width) * l.view.height;
        for (const viewer::PanelRect& r : rects) {
            EXPECT_GE(r.y, 19);
            EXPECT_LE(r.y + r.height, 800 + 1e-3);
            area += double(r.width) * r.height;
        }
        EXPECT_NEAR(area, 1280.0 * (800 - 19), 1);
        if (!tree) {
            EXPECT_FLOAT_EQ(l.preview.y, l.precompute.y + l.precompute.height);
        }
        EXPECT_GT(l.enlarged.width * l.enlarged.height, 0.8 * 1280 * (800 - 19));
        EXPECT_GE(l.enlarged.y, 19);
    }
}

TEST(ViewerLayout, ViewBetweenTheColumns) {
    const viewer::Layout l = viewer::computeLayout(1280, 800);
    EXPECT_EQ(l.view.x, l.leftWidth);
    EXPECT_EQ(l.view.x + l.view.width + l.rightWidth, 1280);
    EXPECT_EQ(l.view.height, 800);
    EXPECT_GT(l.view.width, 400);
}

TEST(ViewerSceneList, EveryLoadableFormatInAssetsAndScenes) {
    const fs::path dir = test::scratchDir("viewer_scene_list");
    fs::create_directories(dir / "scenes");
    fs::create_directories(dir / "external");    // not listed: the fetched raw meshes go there
    fs::create_directories(dir / "folder.obj");  // a directory, not a scene
    for (const char* name :
         {"b.obj", "a.PLY", "c.off", "d.stl", "e.gltf", "f.Glb", "g.json", "b.mtl", "notes.txt",
          "noext", "scenes/z.json", "scenes/y.obj", "scenes/readme.md", "external/mesh.ply"})
        std::ofstream(dir / name) << "x";
    const std::vector<fs::path> want = {
        dir / "a.PLY", dir / "b.obj",  dir / "c.off",        dir / "d.stl",        dir / "e.gltf",
        dir / "f.Glb", dir / "g.json", dir / "scenes/y.obj", dir / "scenes/z.json"};
    EXPECT_EQ(viewer::listSceneFiles(dir), want);
    EXPECT_TRUE(viewer::listSceneFiles(dir / "none").empty());

    // The committed assets: the OBJ scenes and the JSON scenes under assets/scenes/.
    const fs::path assets = test::sourceDir() / "assets";
    const std::vector<fs::path> listed = viewer::listSceneFiles(assets);
    const auto lists = [&](const fs::path& p) {
        return std::find(listed.begin(), listed.end(), p) != listed.end();
    };
    EXPECT_TRUE(lists(assets / "cornell_box.obj"));
    EXPECT_TRUE(lists(assets / "scenes" / "cornell_box.json"));
    EXPECT_FALSE(lists(assets / "cornell_box.mtl"));
}

TEST(ViewerScreenshot, FragmentOverlayAndPathMatchAnIndependentQuery) {
    const fs::path dir = test::scratchDir("viewer_screenshot");
    const Vec3 x{278, 0, 280};
    test::ProcessResult r;
    const json state =
        test::shootCornell(dir, {"--point", "278,0,280", "--camera", kCameraFlag}, "1280x800", &r);
    ASSERT_EQ(r.exitCode, 0) << r.err;
    const test::Image image = test::readPng(dir / "shot.png");
    ASSERT_EQ(image.width, 1280);
    ASSERT_EQ(image.height, 800);

    // The path panel's state against an independent query.
    const Scene scene = loadObj(test::cornellObj());
    VisibilityStore store(scene);
    const uint32_t face = *findFaceContaining(scene, x).face;
    const std::vector<LightAtPoint> q = queryPoint(store, face, x, std::nullopt);
    ASSERT_EQ(state["point"]["face"], face);
    ASSERT_EQ(state["point"]["lights"].size(), q.size());
    const json& light = state["point"]["lights"][0];
    // The answer in the schema of `penumbra query` (the path as node ids and sides), and the
    // path panel's rows beside it.
    ASSERT_EQ(light["path"].size(), q[0].trace.size());
    ASSERT_EQ(light["path_sides"].size(), q[0].trace.size());
    ASSERT_EQ(light["path_steps"].size(), q[0].trace.size());
    for (size_t i = 0; i < q[0].trace.size(); ++i) {
        EXPECT_EQ(light["path"][i], q[0].trace[i].node);
        EXPECT_EQ(light["path_sides"][i], vis::toString(q[0].trace[i].side));
        EXPECT_EQ(light["path_steps"][i]["node"], q[0].trace[i].node);
        EXPECT_EQ(light["path_steps"][i]["depth"], q[0].trace[i].depth);
        EXPECT_EQ(light["path_steps"][i]["side"], vis::toString(q[0].trace[i].side));
    }
    EXPECT_EQ(light["pair"], std::string(vis::toString(q[0].kind)));
    EXPECT_EQ(light["fragments"].size(), q[0].fragments.size());
    EXPECT_EQ(light["fragment_colours"].size(), q[0].fragments.size());
    EXPECT_NEAR(light["fraction"].get<double>(), q[0].fraction, 1e-12);
    EXPECT_GT(q[0].fragments.size(), 2u);  // a penumbra point: several fragments to look for
    // The visible region's outline against the exact region (CGAL): one loop per boundary, and
    // its contour integral the region's form factor.
    const test::ReferenceResult exact = test::exactReference(scene.mesh, face, q[0].lightFace, x);
    EXPECT_EQ(static_cast<int>(light["outline"]["loops"].size()), exact.boundaryLoops);
    EXPECT_LT(light["outline"]["edges"].get<size_t>(), [&] {
        size_t edges = 0;
        for (const vis::Polygon3& f : q[0].fragments) edges += f.size();
        return edges;
    }());
    EXPECT_NEAR(light["outline"]["form_factor"].get<double>(), exact.formFactor,
                1e-9 * exact.formFactor);

    // One schema for a point's answer: `penumbra query` at the same point prints every key the
    // state's point has from it (the viewer adds its own: the normal, the colours, the path
    // panel's rows, the times), with the same values.
    const test::ProcessResult qr =
        test::runPenumbra({"query", test::cornellObj().string(), "--point", "278,0,280"});
    ASSERT_EQ(qr.exitCode, 0) << qr.err;
    const json answer = json::parse(qr.out);
    for (const auto& [key, value] : answer.items()) {
        if (key == "lights") continue;
        EXPECT_EQ(state["point"][key], value) << key;
    }
    ASSERT_EQ(answer["lights"].size(), state["point"]["lights"].size());
    for (size_t k = 0; k < answer["lights"].size(); ++k) {
        for (const auto& [key, value] : answer["lights"][k].items())
            EXPECT_EQ(state["point"]["lights"][k][key], value) << "light " << k << ": " << key;
    }

    // The fragment overlay where the camera projects the exact fragments.
    const int viewport[4] = {state["viewport"]["x"], state["viewport"]["y"],
                             state["viewport"]["width"], state["viewport"]["height"]};
    const int checked =
        test::checkFragmentOverlay(image, lightCamera(), viewport, test::cornellObj(), face, x, 0);
    EXPECT_GE(checked, 2);
}

TEST(ViewerScreenshot, PickingAPixelInspectsTheSurfaceAnIndependentRayHits) {
    const fs::path dir = test::scratchDir("viewer_pick");
    // The view lies below the menu bar: its height as a screenshot of the same size draws it.
    const test::ProcessResult probe = test::runPenumbraGl(
        {"screenshot", test::cornellObj().string(), "--size", "640x400", "--no-preview", "--out",
         (dir / "probe.png").string(), "--state-out", (dir / "probe.json").string()});
    ASSERT_EQ(probe.exitCode, 0) << probe.err;
    viewer::LayoutSettings settings;
    settings.top = test::readJson(dir / "probe.json")["layout"]["menuBarHeight"].get<int>();
    const viewer::Layout layout = viewer::computeLayout(640, 400, settings);
    // A floor point seen from the default-like camera: the pixel where it projects.
    Camera c;
    c.eye = {278, 273, -800};
    c.target = {278, 273, 0};
    c.fovYDegrees = 39;
    double px = 0, py = 0;
    ASSERT_TRUE(c.project({400, 0, 120}, layout.view.width, layout.view.height, px, py));
    px += layout.view.x;
    py += layout.view.y;
    test::ProcessResult r;
    const json state = test::shootCornell(dir,
                                          {"--pixel", std::to_string(px) + "," + std::to_string(py),
                                           "--camera", "278,273,-800,278,273,0,39"},
                                          "640x400", &r);
    ASSERT_EQ(r.exitCode, 0) << r.err;
    ASSERT_FALSE(state["point"].is_null());
    const json& p = state["point"]["point"];
    // The ray through the pixel centre meets the floor (face 0 of the Cornell box) near the
    // projected point (within a pixel's footprint, a few scene units here).
    EXPECT_EQ(state["point"]["face"], 0);
    EXPECT_NEAR(p[1].get<double>(), 0.0, 1e-9);
    EXPECT_NEAR(p[0].get<double>(), 400, 5);
    EXPECT_NEAR(p[2].get<double>(), 120, 5);
}

// The raster view draws a base-colour texture on the faces that have one: a quad [0, 2]^2 seen from
// straight above, textured with a checker (OBJ map_Kd) of 4x4 texels, 2x2 of each colour: red,
// green / blue, grey from the image's top, OBJ's v up so the top row lies at large y. Over the
// middle half of each quadrant (between the centres of its own texels, where bilinear filtering
// mixes in no other colour), wherever the view's overlays leave it visible, the pixels have that
// colour (times Kd and the headlight's shade, near 1 seen head on): the dominant channel where
// the texel has one, three similar dark ones for grey.
TEST(ViewerScreenshot, RasterViewShowsBaseColourTextures) {
    const fs::path dir = test::scratchDir("viewer_texture");
    const uint8_t colours[4][3] = {{255, 0, 0}, {0, 255, 0}, {0, 0, 255}, {128, 128, 128}};
    std::vector<uint8_t> texels;
    for (int y = 0; y < 4; ++y)
        for (int x = 0; x < 4; ++x)
            texels.insert(texels.end(), colours[(y / 2) * 2 + x / 2],
                          colours[(y / 2) * 2 + x / 2] + 3);
    std::ofstream(dir / "checker.png", std::ios::binary) << encodePng(4, 4, 3, texels.data());
    std::ofstream(dir / "quad.mtl") << "newmtl checker\nKd 0.9 0.9 0.9\nmap_Kd checker.png\n";
    std::ofstream(dir / "quad.obj") << "mtllib quad.mtl\nv 0 0 0\nv 2 0 0\nv 2 2 0\nv 0 2 0\n"
                                       "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nusemtl checker\n"
                                       "f 1/1 2/2 3/3 4/4\n";
    Camera c;
    c.eye = {1, 1, 2.5};
    c.target = {1, 1, 0};
    c.up = {0, 1, 0};
    c.fovYDegrees = 60;
    const test::ProcessResult r = test::runPenumbraGl(
        {"screenshot", (dir / "quad.obj").string(), "--camera", "1,1,2.5,1,1,0,60", "--size",
         "1280x800", "--no-preview", "--out", (dir / "shot.png").string(), "--state-out",
         (dir / "state.json").string()});
    ASSERT_EQ(r.exitCode, 0) << r.err;
    const test::Image image = test::readPng(dir / "shot.png");
    const json state = test::readJson(dir / "state.json");
    const json& v = state["panelRects"]["3D view"];
    const int vx = v[0], vy = v[1], vw = v[2], vh = v[3];
    std::vector<std::array<double, 4>> overlays;
    for (const char* name : {"Help", "Status"}) {
        const json& o = state["panelRects"][name];
        overlays.push_back({o[0], o[1], o[2], o[3]});
    }
    auto covered = [&](int x, int y) {
        for (const auto& o : overlays)
            if (x >= o[0] - 2 && y >= o[1] - 2 && x <= o[0] + o[2] + 2 && y <= o[1] + o[3] + 2)
                return true;
        return false;
    };
    struct Quadrant {
        double x0, y0;  // its lower corner
        int dominant;   // channel, or -1 for grey
        const char* name;
    };
    for (const Quadrant& q : {Quadrant{0, 1, 0, "red"}, Quadrant{1, 1, 1, "green"},
                              Quadrant{0, 0, 2, "blue"}, Quadrant{1, 0, -1, "grey"}}) {
        SCOPED_TRACE(q.name);
        int seen = 0;
        for (int i = 0; i <= 8; ++i) {
            for (int j = 0; j <= 8; ++j) {
                const Vec3 p{q.x0 + 0.27 + 0.46 * i / 8, q.y0 + 0.27 + 0.46 * j / 8, 0};
                double px = 0, py = 0;
                ASSERT_TRUE(c.project(p, vw, vh, px, py));
                const int x = vx + static_cast<int>(px), y = vy + static_cast<int>(py);
                if (covered(x, y)) continue;
                ++seen;
                const unsigned char* rgb = image.at(x, y);
                const std::string at = std::to_string(x) + "," + std::to_string(y) + ": " +
                                       std::to_string(rgb[0]) + " " + std::to_string(rgb[1]) + " " +
                                       std::to_string(rgb[2]);
                if (q.dominant >= 0) {
                    EXPECT_GT(rgb[q.dominant], 150) << at;
                    for (int k = 0; k < 3; ++k) {
                        if (k != q.dominant) {
                            EXPECT_LT(rgb[k], 40) << at;
                        }
                    }
                } else {
                    // 0.9 x 0.216 (sRGB 128, linear) x the shade: about 48 of 255 each.
                    for (int k = 0; k < 3; ++k) {
                        EXPECT_GT(rgb[k], 30) << at;
                        EXPECT_LT(rgb[k], 70) << at;
                    }
                }
            }
        }
        EXPECT_GT(seen, 8);
    }
}

// The sampled preview (N shadow rays per light) is an unbiased estimate of the exact one and both
// share the primary-ray jitter (RenderSettings::seed), so their relative RMS difference falls as
// passes accumulate (about 1/sqrt(passes): 1/4 after 16) and with more light samples.
TEST(ViewerScreenshot, SampledPreviewConvergesToTheExactOne) {
    const fs::path dir = test::scratchDir("viewer_preview");
    auto run = [&](int lightSamples, int passes) {
        const test::ProcessResult r = test::runPenumbraGl(
            {"screenshot", test::cornellObj().string(), "--size", "640x400", "--preview-mode",
             "diff", "--light-samples", std::to_string(lightSamples), "--passes",
             std::to_string(passes), "--out", (dir / "shot.png").string(), "--state-out",
             (dir / "state.json").string(), "--preview-out", (dir / "preview.png").string()});
        EXPECT_EQ(r.exitCode, 0) << r.err;
        return test::readJson(dir / "state.json");
    };
    const json few = run(2, 16);
    // The preview panel is drawn (the viewer records the rectangle of every panel it places).
    ASSERT_TRUE(few["panelRects"].contains("Preview")) << few["panelRects"];
    EXPECT_GT(few["panelRects"]["Preview"][2].get<double>(), 0.0);
    EXPECT_GT(few["panelRects"]["Preview"][3].get<double>(), 0.0);
    const json& p = few["preview"];
    ASSERT_EQ(p["error"], "");
    ASSERT_EQ(p["passes"], 16);
    ASSERT_TRUE(p["finished"].get<bool>());
    const std::vector<double> history = p["errorHistory"].get<std::vector<double>>();
    ASSERT_EQ(history.size(), 16u);
    EXPECT_GT(history.front(), 0.0);
    EXPECT_LT(history.back(), 0.5 * history.front());
    for (size_t i = 1; i < history.size(); ++i) EXPECT_LT(history[i], 1.15 * history[i - 1]);
    const json many = run(64, 1);
    EXPECT_LT(many["preview"]["relativeRmsError"].get<double>(), 0.5 * history.front());
    EXPECT_TRUE(fs::exists(dir / "preview.png"));
}

// The rendered view (--view) shows, pixel for pixel, what `penumbra render` writes for the same
// camera, size (the view's), samples and tone map: exact, and exact and sampled side by side split
// at the middle (exact left, sampled right), wherever the view's overlays (status line, help,
// which must stay inside the view) leave it visible. The raster view of the same camera is far
// from that image (the test can tell).
TEST(ViewerScreenshot, RenderedViewIsTheImagePenumbraRenderWrites) {
    const fs::path dir = test::scratchDir("viewer_rendered");
    const std::string scene =
        (test::sourceDir() / "assets" / "scenes" / "cornell_box.json").string();
    const std::string camera = "278,273,-800,278,273,0,39.3";
    auto shoot = [&](const std::string& view, const std::string& name) {
        const test::ProcessResult r = test::runPenumbraGl(
            {"screenshot", scene, "--view", view, "--camera", camera, "--size", "800x500",
             "--passes", "1", "--light-samples", "4", "--out", (dir / (name + ".png")).string(),
             "--state-out", (dir / (name + ".json")).string()});
        EXPECT_EQ(r.exitCode, 0) << r.err;
        return test::readJson(dir / (name + ".json"));
    };
    const json state = shoot("rendered", "exact");
    const json& v = state["panelRects"]["3D view"];
    const int vx = v[0], vy = v[1], vw = v[2], vh = v[3];
    EXPECT_EQ(state["view"]["mode"], "rendered");
    EXPECT_TRUE(state["view"]["showsImage"].get<bool>());
    EXPECT_EQ(state["preview"]["width"], vw);
    EXPECT_EQ(state["preview"]["height"], vh);
    const std::string size = std::to_string(vw) + "x" + std::to_string(vh);
    auto render = [&](const std::string& method, const std::string& name) {
        const test::ProcessResult r = test::runPenumbra(
            {"render", scene, "--camera", camera, "--up", "0,1,0", "--size", size, "--spp", "1",
             "--method", method, "--light-samples", "4", "--out", (dir / name).string()});
        EXPECT_EQ(r.exitCode, 0) << r.err;
        return test::readPng(dir / name);
    };
    const test::Image exact = render("exact", "exact_render.png");
    const test::Image sampled = render("sampled", "sampled_render.png");
    ASSERT_EQ(exact.width, vw);
    // The view's overlays (the status line; the colour scale of the answers, below) stay inside
    // it, and their pixels are not compared. Help is beside the view, over the Path panel.
    std::vector<std::array<double, 4>> overlays;
    const auto overlay = [&](const json& state, const char* name) {
        ASSERT_TRUE(state["panelRects"].contains(name)) << name;
        const json& r = state["panelRects"][name];
        const std::array<double, 4> rect = {r[0], r[1], r[2], r[3]};
        EXPECT_GE(rect[0], vx) << name;
        EXPECT_GE(rect[1], vy) << name;
        EXPECT_LE(rect[0] + rect[2], vx + vw) << name;
        EXPECT_LE(rect[1] + rect[3], vy + vh) << name;
        overlays.push_back(rect);
    };
    overlay(state, "Status");
    {
        const json& help = state["panelRects"]["Help"];
        EXPECT_GE(help[0].get<double>(), vx + vw - 1) << "Help over the view";
    }
    auto covered = [&](int x, int y) {
        for (const auto& r : overlays)
            if (x >= r[0] - 1 && y >= r[1] - 1 && x <= r[0] + r[2] + 1 && y <= r[1] + r[3] + 1)
                return true;
        return false;
    };
    // Mean absolute difference (in [0, 1]) between the view's pixels and `reference(x)`'s, over
    // the pixels no overlay covers.
    auto meanDifference = [&](const test::Image& shot, auto reference) {
        double sum = 0;
        long n = 0;
        for (int y = 0; y < vh; ++y)
            for (int x = 0; x < vw; ++x) {
                const test::Image* ref = reference(x, y);
                if (ref == nullptr || covered(vx + x, vy + y)) continue;
                const unsigned char* a = shot.at(vx + x, vy + y);
                const unsigned char* b = ref->at(x, y);
                for (int k = 0; k < 3; ++k) sum += std::abs(int(a[k]) - int(b[k])) / 255.0;
                n += 3;
            }
        EXPECT_GT(n, 3 * 50000);
        return sum / std::max<long>(n, 1);
    };
    const test::Image shotExact = test::readPng(dir / "exact.png");
    EXPECT_LT(meanDifference(shotExact, [&](int, int) { return &exact; }), 1e-3);
    const json side = shoot("side", "side");
    EXPECT_EQ(side["preview"]["width"], 2 * vw);
    const int split = static_cast<int>(side["view"]["split"].get<double>() * vw);
    EXPECT_LT(meanDifference(test::readPng(dir / "side.png"),
                             [&](int x, int y) -> const test::Image* {
                                 // The drawn line, and its two labels at mid-height.
                                 if (std::abs(x - split) <= 2) return nullptr;
                                 if (std::abs(x - split) <= 90 && std::abs(y - vh / 2) <= 24)
                                     return nullptr;
                                 return x < split ? &exact : &sampled;
                             }),
              1e-3);
    // The answers view: how the exact render answered each pixel, as `render --out-answers`
    // writes it for the same camera and size.
    const test::ProcessResult r =
        test::runPenumbra({"render", scene, "--camera", camera, "--up", "0,1,0", "--size", size,
                           "--spp", "1", "--out", (dir / "exact_again.png").string(),
                           "--out-answers", (dir / "answers_render.png").string()});
    ASSERT_EQ(r.exitCode, 0) << r.err;
    const test::Image answers = test::readPng(dir / "answers_render.png");
    const json answered = shoot("answers", "answers");
    EXPECT_EQ(answered["preview"]["mode"], "answers");
    overlay(answered, "Colour scale");
    EXPECT_LT(
        meanDifference(test::readPng(dir / "answers.png"), [&](int, int) { return &answers; }),
        1e-3);
    // Its totals: the Cornell box is answered without sampling, its walls mostly by trees.
    const json& totals = answered["preview"]["answers"];
    ASSERT_TRUE(totals.is_object()) << answered["preview"];
    EXPECT_EQ(totals["sampled"], 0) << totals;
    EXPECT_GT(totals["tree walk"].get<uint64_t>(), 0u) << totals;
    EXPECT_GT(totals["fully visible"].get<uint64_t>(), 0u) << totals;
    // Not a coincidence: the raster view of this camera is another picture.
    shoot("raster", "raster");
    EXPECT_GT(meanDifference(test::readPng(dir / "raster.png"), [&](int, int) { return &exact; }),
              0.03);
}

// The pixel inspector of the rendered view (--hover): the pixel's exact and sampled radiance are
// the linear values `penumbra render` writes to its PFM for that pixel, and the per-light visible
// fraction at the surface point under it is the one the history tree's query gives there (an
// independent exact evaluation). The pixel lies in the tall box's penumbra on the floor.
TEST(ViewerScreenshot, PixelInspectorReportsTheRenderedPixelAndTheExactFraction) {
    const fs::path dir = test::scratchDir("viewer_hover");
    const fs::path scene = test::sourceDir() / "assets" / "scenes" / "cornell_box.json";
    const std::string camera = "278,273,-800,278,273,0,39.3";
    const test::ProcessResult r = test::runPenumbraGl(
        {"screenshot", scene.string(), "--view", "side", "--camera", camera, "--size", "960x600",
         "--passes", "1", "--light-samples", "4", "--hover", "300,400", "--out",
         (dir / "shot.png").string(), "--state-out", (dir / "state.json").string()});
    ASSERT_EQ(r.exitCode, 0) << r.err;
    const json state = test::readJson(dir / "state.json");
    ASSERT_TRUE(state.contains("pixel")) << "no pixel report";
    const json& p = state["pixel"];
    const json& v = state["panelRects"]["3D view"];
    const int vw = v[2], vh = v[3];
    EXPECT_EQ(p["x"], 300 - v[0].get<int>());
    EXPECT_EQ(p["y"], 400 - v[1].get<int>());
    const std::string size = std::to_string(vw) + "x" + std::to_string(vh);
    for (const char* method : {"exact", "sampled"}) {
        SCOPED_TRACE(method);
        const fs::path pfm = dir / (std::string(method) + ".pfm");
        const test::ProcessResult rr = test::runPenumbra(
            {"render", scene.string(), "--camera", camera, "--up", "0,1,0", "--size", size, "--spp",
             "1", "--method", method, "--light-samples", "4", "--out", pfm.string()});
        ASSERT_EQ(rr.exitCode, 0) << rr.err;
        int w = 0, h = 0;
        const std::vector<float> image = test::readPfm(pfm.string(), w, h);
        ASSERT_EQ(w, vw);
        const size_t at = (static_cast<size_t>(p["y"].get<int>()) * w + p["x"].get<int>()) * 3;
        ASSERT_TRUE(p[method].is_array());
        for (int k = 0; k < 3; ++k)
            EXPECT_FLOAT_EQ(p[method][k].get<float>(), image[at + k]) << "channel " << k;
    }
    // The fraction under the pixel against the tree's answer at the same point.
    const Scene s = loadScene(scene);
    VisibilityStore store(s);
    const Vec3 x{p["point"][0], p["point"][1], p["point"][2]};
    const std::vector<LightAtPoint> tree = queryPoint(store, p["face"], x, std::nullopt);
    ASSERT_EQ(p["lights"].size(), tree.size());
    EXPECT_FALSE(p["lights"][0].contains("complete"));  // (written only when false)
    EXPECT_NEAR(p["lights"][0]["fraction"].get<double>(), tree[0].fraction, 1e-9);
    EXPECT_NEAR(p["lights"][0]["form_factor"].get<double>(), tree[0].formFactor, 1e-12);
    EXPECT_GT(tree[0].fraction, 0.05);  // a penumbra: the test can tell a wrong point
    EXPECT_LT(tree[0].fraction, 0.95);
    // How the exact render answered the pixel: one evaluation (one pass, one light), by a query
    // (a point in a penumbra is neither fully visible nor unlit), exact (no sampling).
    const json& answers = p["answers"];
    ASSERT_TRUE(answers.is_object()) << p;
    uint64_t all = 0;
    for (const auto& [name, n] : answers.items()) all += n.get<uint64_t>();
    EXPECT_EQ(all, 1u) << answers;
    for (const char* none : {"fully visible", "no light", "sampled"})
        EXPECT_EQ(answers[none], 0) << answers;
}

// Keep what you see (--save-view, the Preview panel's button): the rendered view saved as PNG,
// linear PFM and OpenEXR and a JSON scene with the view's camera, in another directory than the
// scene; that scene reopened by `penumbra render` at the view's size gives the same radiance,
// pixel for pixel, and by `penumbra screenshot` the same camera. Also from a mesh file (no JSON
// scene). --preview-out FILE.exr writes the same radiance.
TEST(ViewerScreenshot, SavedViewReopensAsTheSameView) {
    const fs::path dir = test::scratchDir("viewer_save_view");
    const std::string camera = "300,250,-700,270,280,0,42";
    for (const fs::path& scene : {test::sourceDir() / "assets" / "scenes" / "cornell_box.json",
                                  test::sourceDir() / "assets" / "cornell_box.obj"}) {
        SCOPED_TRACE(scene.string());
        const fs::path stem = dir / scene.extension().string().substr(1) / "saved";
        const test::ProcessResult r = test::runPenumbraGl(
            {"screenshot", scene.string(), "--view", "rendered", "--camera", camera, "--size",
             "640x400", "--passes", "1", "--save-view", stem.string(), "--out",
             (dir / "shot.png").string(), "--state-out", (dir / "state.json").string(),
             "--preview-out", (dir / "preview.exr").string()});
        ASSERT_EQ(r.exitCode, 0) << r.err;
        const json state = test::readJson(dir / "state.json");
        const int vw = state["panelRects"]["3D view"][2], vh = state["panelRects"]["3D view"][3];
        for (const char* ext : {".png", ".pfm", ".exr", ".json"})
            EXPECT_TRUE(fs::exists(fs::path(stem.string() + ext))) << ext;
        const test::Image png = test::readPng(stem.string() + ".png");
        EXPECT_EQ(png.width, vw);
        EXPECT_EQ(png.height, vh);
        // The saved scene, rendered at the view's size with the same samples.
        const fs::path rendered = dir / "rendered.pfm";
        const test::ProcessResult rr =
            test::runPenumbra({"render", stem.string() + ".json", "--size",
                               std::to_string(vw) + "x" + std::to_string(vh), "--spp", "1",
                               "--method", "exact", "--out", rendered.string()});
        ASSERT_EQ(rr.exitCode, 0) << rr.err;
        int w1 = 0, h1 = 0, w2 = 0, h2 = 0;
        const std::vector<float> saved = test::readPfm(stem.string() + ".pfm", w1, h1);
        const std::vector<float> again = test::readPfm(rendered.string(), w2, h2);
        ASSERT_EQ(w1, w2);
        ASSERT_EQ(h1, h2);
        size_t differ = 0, lit = 0;
        for (size_t i = 0; i < saved.size(); ++i) {
            differ += saved[i] != again[i];
            lit += saved[i] > 0;
        }
        EXPECT_EQ(differ, 0u);
        EXPECT_GT(lit, saved.size() / 2);
        // The OpenEXR files hold the PFM's floats.
        for (const fs::path& exrPath : {fs::path(stem.string() + ".exr"), dir / "preview.exr"}) {
            const test::ExrImage exr = test::readExr(exrPath.string());
            EXPECT_EQ(exr.width, w1);
            EXPECT_EQ(exr.height, h1);
            EXPECT_EQ(exr.rgb, saved) << exrPath;
        }
        // And the viewer opens it with the saved camera.
        const test::ProcessResult rs = test::runPenumbraGl(
            {"screenshot", stem.string() + ".json", "--size", "400x300", "--no-preview", "--out",
             (dir / "again.png").string(), "--state-out", (dir / "again.json").string()});
        ASSERT_EQ(rs.exitCode, 0) << rs.err;
        const json again_state = test::readJson(dir / "again.json");
        EXPECT_EQ(again_state["camera"]["eye"], json({300.0, 250.0, -700.0}));
        EXPECT_EQ(again_state["camera"]["target"], json({270.0, 280.0, 0.0}));
        EXPECT_EQ(again_state["camera"]["fovY"], 42.0);
    }
}

// `penumbra render` of `scene` with the camera `camera` (+y up) at the size of the 3D view of a
// screenshot's `state`, exact, one sample a pixel (as the preview's single pass): its linear image,
// written to `out` (.pfm).
std::vector<float> renderLikeThe3DView(const fs::path& scene, const std::string& camera,
                                       const json& state, const fs::path& out) {
    const int vw = state["panelRects"]["3D view"][2], vh = state["panelRects"]["3D view"][3];
    const test::ProcessResult r =
        test::runPenumbra({"render", scene.string(), "--camera", camera, "--up", "0,1,0", "--size",
                           std::to_string(vw) + "x" + std::to_string(vh), "--spp", "1", "--method",
                           "exact", "--out", out.string()});
    EXPECT_EQ(r.exitCode, 0) << r.err;
    int w = 0, h = 0;
    std::vector<float> image = test::readPfm(out.string(), w, h);
    EXPECT_EQ(w, vw);
    EXPECT_EQ(h, vh);
    return image;
}

// How many values of two images differ beyond 1e-4 relative (the same exact answer, whichever
// path answered each point, gives 0).
size_t differingValues(const std::vector<float>& a, const std::vector<float>& b) {
    size_t n = 0;
    for (size_t i = 0; i < a.size() && i < b.size(); ++i)
        n += std::abs(a[i] - b[i]) > 1e-4f * std::max(1.0f, std::abs(b[i]));
    return n + (a.size() > b.size() ? a.size() - b.size() : b.size() - a.size());
}

// Moving a light (`screenshot --move-light`, what the Move light window does): the rendered view
// is the image `penumbra render` gives of the Cornell box whose OBJ file has the lamp's coordinates
// moved by hand, the state lists those coordinates, the trees of the position before are dropped
// and rebuilt, and the saved view reopens with the light moved (and renders the same image).
TEST(ViewerScreenshot, MovedLightIsTheSceneWithTheLightMovedByHand) {
    const fs::path dir = test::scratchDir("viewer_move_light");
    const std::string scene =
        (test::sourceDir() / "assets" / "scenes" / "cornell_box.json").string();
    const std::string camera = "278,273,-800,278,273,0,39.3";
    const fs::path stem = dir / "saved";
    // Translate (-60, -150, 40), scale (1.5, 1, 0.5) about the lamp's centre (278, 548, 279.5):
    // x 278 -+ 1.5 * 65 - 60, y 548 - 150, z 279.5 -+ 0.5 * 52.5 + 40.
    const test::ProcessResult r =
        test::runPenumbraGl({"screenshot",    scene,
                             "--view",        "rendered",
                             "--camera",      camera,
                             "--size",        "640x400",
                             "--passes",      "1",
                             "--move-light",  "0",
                             "--translate",   "-60,-150,40",
                             "--scale",       "1.5,1,0.5",
                             "--out",         (dir / "moved.png").string(),
                             "--state-out",   (dir / "moved.json").string(),
                             "--preview-out", (dir / "moved.pfm").string(),
                             "--save-view",   stem.string()});
    ASSERT_EQ(r.exitCode, 0) << r.err;
    const json state = test::readJson(dir / "moved.json");
    const json hand = {{315.5, 398.0, 293.25},
                       {315.5, 398.0, 345.75},
                       {120.5, 398.0, 345.75},
                       {120.5, 398.0, 293.25}};
    ASSERT_EQ(state["lights"].size(), 1u);
    EXPECT_EQ(state["lights"][0]["vertices"], hand);
    EXPECT_TRUE(state["lights"][0]["moved"].get<bool>());
    const json& moves = state["lightMoves"];
    EXPECT_GE(moves["sceneVersion"].get<uint64_t>(), 1u);
    EXPECT_EQ(state["preview"]["sceneVersion"], moves["sceneVersion"]);  // the moved scene's image
    EXPECT_FALSE(moves["rebuilding"].get<bool>());
    EXPECT_FALSE(moves["building"].get<bool>());
    EXPECT_TRUE(moves["windowShown"].get<bool>());
    EXPECT_TRUE(state["panelRects"].contains("Move light"));
    // The render of the moved scene built its own trees; none came from the store before.
    EXPECT_GT(moves["treesInStore"].get<uint64_t>(), 0u);

    // The reference: the OBJ with the lamp's four vertex lines written by hand.
    std::ifstream in(test::sourceDir() / "assets" / "cornell_box.obj");
    std::string obj((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    const std::array<std::pair<std::string, std::string>, 4> lamp = {
        std::pair{"v 343 548 227\n", "v 315.5 398 293.25\n"},
        {"v 343 548 332\n", "v 315.5 398 345.75\n"},
        {"v 213 548 332\n", "v 120.5 398 345.75\n"},
        {"v 213 548 227\n", "v 120.5 398 293.25\n"}};
    for (const auto& [from, to] : lamp) {
        const size_t at = obj.find(from);
        ASSERT_NE(at, std::string::npos) << from;
        obj.replace(at, from.size(), to);
    }
    std::ofstream(dir / "by_hand.obj") << obj;
    fs::copy_file(test::sourceDir() / "assets" / "cornell_box.mtl", dir / "cornell_box.mtl",
                  fs::copy_options::overwrite_existing);
    auto render = [&](const fs::path& file, const std::string& name) {
        return renderLikeThe3DView(file, camera, state, dir / name);
    };
    const std::vector<float> byHand = render(dir / "by_hand.obj", "by_hand.pfm");
    const std::vector<float> unmoved =
        render(test::sourceDir() / "assets" / "cornell_box.obj", "unmoved.pfm");
    int w = 0, h = 0;
    const std::vector<float> shown = test::readPfm((dir / "moved.pfm").string(), w, h);
    ASSERT_EQ(shown.size(), byHand.size());
    const auto differing = differingValues;
    EXPECT_EQ(differing(shown, byHand), 0u);
    EXPECT_GT(differing(unmoved, byHand), byHand.size() / 10);  // the move shows

    // The saved view: its scene has the light moved, and renders the same image.
    const test::ProcessResult rs = test::runPenumbraGl(
        {"screenshot", stem.string() + ".json", "--size", "400x300", "--no-preview", "--out",
         (dir / "again.png").string(), "--state-out", (dir / "again.json").string()});
    ASSERT_EQ(rs.exitCode, 0) << rs.err;
    const json again = test::readJson(dir / "again.json");
    EXPECT_EQ(again["lights"][0]["vertices"], hand);
    EXPECT_FALSE(again["lights"][0]["moved"].get<bool>());  // where its file puts it now
    EXPECT_EQ(differing(render(stem.string() + ".json", "saved_render.pfm"), byHand), 0u);

    // Refusals name the option and the reason.
    const test::ProcessResult zero =
        test::runPenumbraGl({"screenshot", scene, "--no-preview", "--move-light", "0", "--scale",
                             "1,0,1", "--out", (dir / "zero.png").string()});
    EXPECT_NE(zero.exitCode, 0);
    EXPECT_NE(zero.err.find("--move-light 0: scale: every factor must be positive"),
              std::string::npos)
        << zero.err;
    const test::ProcessResult missing =
        test::runPenumbraGl({"screenshot", scene, "--no-preview", "--move-light", "3",
                             "--translate", "0,1,0", "--out", (dir / "missing.png").string()});
    EXPECT_NE(missing.exitCode, 0);
    EXPECT_NE(missing.err.find("--move-light: move light: no light 3 (the scene has 1)"),
              std::string::npos)
        << missing.err;
    const test::ProcessResult alone =
        test::runPenumbraGl({"screenshot", scene, "--no-preview", "--translate", "0,1,0", "--out",
                             (dir / "alone.png").string()});
    EXPECT_NE(alone.exitCode, 0);
    EXPECT_NE(alone.err.find("give --move-light N"), std::string::npos) << alone.err;
}

// Moving light 1 of a two-light scene after every pair was precomputed (`screenshot --precompute
// --move-light`): light 1 stays outside every shaft of light 0 (tests/support/two_light_scene.h),
// so light 0's trees are kept but the one whose receiver is light 1, and only the rest is rebuilt.
// Counted by hand: with P receiver patches in all (one per light), each light has P - 1 trees;
// light 0 keeps P - 2, light 1's P - 1 and that one go; once rebuilt the store holds 2 (P - 1)
// again, so kept = stored / 2 - 1 and dropped = stored / 2 + 1. The image is `penumbra render` of
// the scene whose file has light 1 moved by hand. `view` takes the same options (its no-display
// screenshot) and keeps as many.
TEST(ViewerScreenshot, MovingOneLightKeepsTheOtherLightsTrees) {
    const fs::path dir = test::scratchDir("viewer_move_one_of_two");
    const fs::path byHandDir = dir / "by_hand";
    fs::create_directories(byHandDir);
    const std::string scene = test::writeTwoLightScene(dir).string();
    // x in [3, 3.5], y = 0.875, z in [-0.25, 0.25]: light 1's corners plus (0.25, -0.125, 0).
    const fs::path byHand = test::writeTwoLightScene(byHandDir, {0.25, -0.125, 0});
    const std::string camera = "1.5,3,4.5,1.5,0,0,50";
    const std::vector<std::string> move = {
        "--move-light",    "1", "--translate", "0.25,-0.125,0", "--precompute",
        "--refine-levels", "0", "--camera",    camera,          "--size",
        "640x400"};
    std::vector<std::string> args = {"screenshot",    scene,
                                     "--passes",      "1",
                                     "--out",         (dir / "moved.png").string(),
                                     "--state-out",   (dir / "moved.json").string(),
                                     "--preview-out", (dir / "moved.pfm").string()};
    args.insert(args.end(), move.begin(), move.end());
    const test::ProcessResult r = test::runPenumbraGl(args);
    ASSERT_EQ(r.exitCode, 0) << r.err;
    const json state = test::readJson(dir / "moved.json");
    const json& moves = state["lightMoves"];
    EXPECT_FALSE(moves["rebuilding"].get<bool>());
    EXPECT_EQ(moves["treesNotKeptBecause"], "");
    const size_t stored = moves["treesInStore"], kept = moves["treesKept"],
                 dropped = moves["treesDropped"];
    ASSERT_EQ(stored % 2, 0u);
    EXPECT_GT(stored, 8u);  // the floor is split into patches
    EXPECT_EQ(kept, stored / 2 - 1);
    EXPECT_EQ(dropped, stored / 2 + 1);
    ASSERT_EQ(state["lights"].size(), 2u);
    EXPECT_FALSE(state["lights"][0]["moved"].get<bool>());
    EXPECT_TRUE(state["lights"][1]["moved"].get<bool>());
    EXPECT_EQ(
        state["lights"][1]["vertices"],
        json({{3.0, 0.875, -0.25}, {3.5, 0.875, -0.25}, {3.5, 0.875, 0.25}, {3.0, 0.875, 0.25}}));

    const std::vector<float> expected =
        renderLikeThe3DView(byHand, camera, state, dir / "by_hand.pfm");
    const std::vector<float> unmoved =
        renderLikeThe3DView(scene, camera, state, dir / "unmoved.pfm");
    int w = 0, h = 0;
    const std::vector<float> shown = test::readPfm((dir / "moved.pfm").string(), w, h);
    EXPECT_EQ(differingValues(shown, expected), 0u);
    EXPECT_GT(differingValues(unmoved, expected), expected.size() / 100);  // the move shows

    // `view` with the same options, no display: its headless screenshot keeps as many trees.
    const fs::path viewDir = dir / "view";
    std::string command = "env -u DISPLAY -u WAYLAND_DISPLAY " + test::shellQuote(PENUMBRA_EXE) +
                          " view " + test::shellQuote(scene) + " --no-preview --out-dir " +
                          test::shellQuote(viewDir.string());
    for (const std::string& a : move) command += " " + test::shellQuote(a);
    command += " >" + test::shellQuote((dir / "view_stdout").string()) + " 2>" +
               test::shellQuote((dir / "view_stderr").string());
    ASSERT_EQ(test::runShell(command), 0) << test::readFile(dir / "view_stderr");
    const json viewState = test::readJson(viewDir / "view_state.json");
    EXPECT_EQ(viewState["lightMoves"]["treesKept"], kept);
    EXPECT_EQ(viewState["lights"][1]["vertices"], state["lights"][1]["vertices"]);
    EXPECT_TRUE(viewState["lightMoves"]["windowShown"].get<bool>());
    // And refuses what screenshot refuses, naming the option.
    const test::ProcessResult bad = test::runPenumbra(
        {"view", scene, "--no-preview", "--out-dir", viewDir.string(), "--translate", "1,0,0"});
    EXPECT_NE(bad.exitCode, 0);
    EXPECT_NE(bad.err.find("view: --translate, --rotate and --scale move a light: give "
                           "--move-light N"),
              std::string::npos)
        << bad.err;
    const test::ProcessResult missing = test::runPenumbra(
        {"view", scene, "--no-preview", "--out-dir", viewDir.string(), "--move-light", "2"});
    EXPECT_NE(missing.exitCode, 0);
    EXPECT_NE(missing.err.find("--move-light: no light 2"), std::string::npos) << missing.err;
}

// A scene without lights opens with the default light (engine/scene/default_light.h): the status
// line and stderr say so, the state records it, and a saved view keeps it as an area light of its
// own: the saved scene renders to the same image with the default light turned off.
TEST(ViewerScreenshot, DefaultLightIsAnnouncedRecordedAndSaved) {
    const fs::path dir = test::scratchDir("viewer_default_light");
    std::ofstream(dir / "unlit.obj")
        << "v -1 0 -1\nv -1 0 1\nv 1 0 1\nv 1 0 -1\n"
           "v 0.5 0.4 0.5\nv 0.5 0.4 0.9\nv 0.9 0.4 0.9\nv 0.9 0.4 0.5\n"
           "f 1 2 3 4\nf 5 6 7 8\n";
    const std::string scene = (dir / "unlit.obj").string();
    const fs::path stem = dir / "saved";
    const test::ProcessResult r = test::runPenumbraGl(
        {"screenshot", scene, "--view", "rendered", "--camera", "0,2,2.5,0,0,0,40", "--size",
         "640x400", "--passes", "1", "--save-view", stem.string(), "--out",
         (dir / "shot.png").string(), "--state-out", (dir / "state.json").string()});
    ASSERT_EQ(r.exitCode, 0) << r.err;
    EXPECT_NE(r.err.find("penumbra: warning: " + scene +
                         " has no lights: added a default area "
                         "light"),
              std::string::npos)
        << r.err;
    const json state = test::readJson(dir / "state.json");
    const std::string status = state["status"].get<std::string>();
    EXPECT_NE(status.find("3 faces, 1 area lights; unlit.obj has no lights: added a default"),
              std::string::npos)
        << status;
    EXPECT_NE(status.find("--no-default-light turns it off"), std::string::npos) << status;
    const json& d = state["defaultLight"];
    ASSERT_TRUE(d.is_object()) << state.dump();
    EXPECT_EQ(d["face"], 2);
    EXPECT_EQ(d["light"], 0);
    EXPECT_EQ(d["up"], "+y");
    ASSERT_EQ(d["corners"].size(), 4u);
    // The rule's numbers for these bounds, by hand: side 2 / 4, D / 2 above y = 0.4.
    EXPECT_DOUBLE_EQ(d["side"].get<double>(), 0.5);
    EXPECT_DOUBLE_EQ(d["corners"][0][1].get<double>(), 0.4 + std::sqrt(8.16) / 2);

    const json saved = test::readJson(stem.string() + ".json");
    ASSERT_EQ(saved["area_lights"].size(), 1u) << saved.dump();
    EXPECT_EQ(saved["area_lights"][0]["vertices"], d["corners"]);
    EXPECT_EQ(saved["area_lights"][0]["emission"], d["emission"]);
    const int vw = state["panelRects"]["3D view"][2], vh = state["panelRects"]["3D view"][3];
    const fs::path rendered = dir / "rendered.pfm";
    const test::ProcessResult rr = test::runPenumbra(
        {"render", stem.string() + ".json", "--size", std::to_string(vw) + "x" + std::to_string(vh),
         "--spp", "1", "--method", "exact", "--no-default-light", "--out", rendered.string()});
    ASSERT_EQ(rr.exitCode, 0) << rr.err;
    EXPECT_EQ(rr.err.find("default"), std::string::npos) << "the light is the file's: " << rr.err;
    int w1 = 0, h1 = 0, w2 = 0, h2 = 0;
    const std::vector<float> shown = test::readPfm(stem.string() + ".pfm", w1, h1);
    const std::vector<float> again = test::readPfm(rendered.string(), w2, h2);
    ASSERT_EQ(w1, w2);
    ASSERT_EQ(h1, h2);
    size_t differ = 0, lit = 0;
    for (size_t i = 0; i < shown.size(); ++i) {
        differ += shown[i] != again[i];
        lit += shown[i] > 0;
    }
    EXPECT_EQ(differ, 0u);
    EXPECT_GT(lit, shown.size() / 4);
}

// The raster view draws a light as the renderer does, one-sided: its own colour seen from the
// front, dark from behind (a flipped light reads as one). A lamp facing down at y = 1, seen from
// above and from below (right of the view's centre, clear of the help window).
TEST(ViewerScreenshot, RasterViewDrawsLightsOneSided) {
    const fs::path dir = test::scratchDir("viewer_one_sided_light");
    std::ofstream(dir / "lamp.mtl")
        << "newmtl white\nKd 0.8 0.8 0.8\nnewmtl lamp\nKd 0 0 0\nKe 5 5 5\n";
    std::ofstream(dir / "lamp.obj") << "mtllib lamp.mtl\nv -1 0 -1\nv -1 0 1\nv 1 0 1\nv 1 0 -1\n"
                                       "v -0.2 1 -0.2\nv 0.2 1 -0.2\nv 0.2 1 0.2\nv -0.2 1 0.2\n"
                                       "usemtl white\nf 1 2 3 4\nusemtl lamp\nf 5 6 7 8\n";
    for (const bool fromAbove : {true, false}) {
        SCOPED_TRACE(fromAbove ? "from above: its back" : "from below: its front");
        const fs::path png = dir / (fromAbove ? "above.png" : "below.png");
        const fs::path stateFile = dir / "state.json";
        const test::ProcessResult r = test::runPenumbraGl(
            {"screenshot", (dir / "lamp.obj").string(), "--camera",
             fromAbove ? "0,3,1.5,-0.1,1,0,30" : "0,0.3,1.5,-0.1,1,0,30", "--size", "1280x800",
             "--no-preview", "--out", png.string(), "--state-out", stateFile.string()});
        ASSERT_EQ(r.exitCode, 0) << r.err;
        const json state = test::readJson(stateFile);
        const json& rects = state["panelRects"];
        const int vx = rects["3D view"][0], vy = rects["3D view"][1], vw = rects["3D view"][2],
                  vh = rects["3D view"][3];
        Camera camera;
        camera.eye = {0, fromAbove ? 3.0 : 0.3, 1.5};
        camera.target = {-0.1, 1, 0};
        camera.fovYDegrees = 30;
        const test::Image image = test::readPng(png);
        ASSERT_GT(image.width, 0);
        // Points of the lamp (inset from its edges) where they show in the view, not under the
        // windows drawn over it (help, status).
        auto covered = [&](double x, double y) {
            for (const char* name : {"Help", "Status"}) {
                if (!rects.contains(name)) continue;
                const json& r = rects[name];
                if (x >= r[0].get<double>() && x < r[0].get<double>() + r[2].get<double>() &&
                    y >= r[1].get<double>() && y < r[1].get<double>() + r[3].get<double>())
                    return true;
            }
            return false;
        };
        int checked = 0;
        for (int i = -3; i <= 3; ++i)
            for (int j = -3; j <= 3; ++j) {
                double px = 0, py = 0;
                if (!camera.project({0.05 * i, 1, 0.05 * j}, vw, vh, px, py)) continue;
                px += vx;
                py += vy;
                if (covered(px, py)) continue;
                const unsigned char* p = image.at(static_cast<int>(px), static_cast<int>(py));
                const int brightest = std::max({p[0], p[1], p[2]});
                ++checked;
                if (fromAbove)
                    EXPECT_LT(brightest, 40) << "the lamp's back, dark: " << px << ", " << py;
                else
                    EXPECT_GT(brightest, 240) << "its front, its own colour: " << px << ", " << py;
            }
        EXPECT_GT(checked, 10);
    }
}

// The "Accuracy vs time" panel of the view, run as the viewer runs it (in the background, frames
// drawn meanwhile): the study's curve behaves as Monte Carlo must (the error of the sampled image
// falls with every doubling of the rays, by about 1/sqrt(2) or faster with stratification), the
// exact image agrees with the converged two-seed reference to within that reference's own noise,
// and the panel draws the curve across the plot.
TEST(ViewerScreenshot, AccuracyPanelPlotsTheStudyOfThisView) {
    const fs::path dir = test::scratchDir("viewer_accuracy");
    const fs::path scene = test::sourceDir() / "assets" / "scenes" / "cornell_box.json";
    const test::ProcessResult r = test::runPenumbraGl(
        {"screenshot", scene.string(), "--accuracy", "--no-preview", "--size", "1280x800", "--out",
         (dir / "shot.png").string(), "--state-out", (dir / "state.json").string()});
    ASSERT_EQ(r.exitCode, 0) << r.err;
    const json state = test::readJson(dir / "state.json");
    const json& a = state["accuracy"];
    ASSERT_TRUE(a["shown"].get<bool>());
    ASSERT_FALSE(a["running"].get<bool>());
    ASSERT_FALSE(a["study"].is_null());
    const json& st = a["study"];
    ASSERT_TRUE(st["complete"].get<bool>());
    const json& sampled = st["sampled"];
    ASSERT_EQ(sampled.size(), 11u);  // 1, 2, 4 ... 1024 rays
    for (size_t i = 0; i < sampled.size(); ++i) {
        EXPECT_EQ(sampled[i]["rays"], 1 << i);
        if (i == 0) continue;
        EXPECT_LT(sampled[i]["rmse"].get<double>(), 0.9 * sampled[i - 1]["rmse"].get<double>())
            << "rays " << sampled[i]["rays"];
    }
    const double exactRmse = st["exact"]["rmse"].get<double>();
    const double noise = st["referenceNoise"].get<double>();
    EXPECT_GT(noise, 0.0);
    EXPECT_LT(exactRmse, 1.3 * noise);
    EXPECT_LT(exactRmse, sampled.back()["rmse"].get<double>());
    EXPECT_EQ(st["pointsDrawn"], 12);  // 11 sampled + the exact point

    // The curve's colour (app/viewer/panels/accuracy_panel.cpp kSampled) across the panel, not only
    // in its legend: the points span three decades of time on the plot's log axis.
    ASSERT_TRUE(state["panelRects"].contains("Accuracy vs time"));
    const json& rect = state["panelRects"]["Accuracy vs time"];
    const int x0 = rect[0], y0 = rect[1], w = rect[2], h = rect[3];
    const test::Image image = test::readPng(dir / "shot.png");
    ASSERT_GE(image.width, x0 + w);
    ASSERT_GE(image.height, y0 + h);
    int count = 0, minX = image.width, maxX = -1;
    for (int y = y0; y < y0 + h; ++y)
        for (int x = x0; x < x0 + w; ++x) {
            const unsigned char* p = image.at(x, y);
            if (std::abs(p[0] - 90) <= 12 && std::abs(p[1] - 160) <= 12 &&
                std::abs(p[2] - 255) <= 12) {
                ++count;
                minX = std::min(minX, x);
                maxX = std::max(maxX, x);
            }
        }
    EXPECT_GT(count, 300);
    // A third of the plot at least: the x axis is measured wall time, and the sampled curve's
    // share of it shrinks when the exact and reference times grow on a loaded machine (311 of 640
    // px once under ASan beside a fuzzer).
    EXPECT_GT(maxX - minX, w / 3) << "sampled-colour pixels from x " << minX << " to " << maxX;
}

// `penumbra view` with no display says so and writes the headless screenshot and its state
// (with the surface point at the centre of the 3D view inspected) instead of failing.
TEST(ViewerFallback, NoDisplayWritesTheHeadlessScreenshot) {
    const fs::path dir = test::scratchDir("viewer_fallback");
    const std::string command =
        "env -u DISPLAY -u WAYLAND_DISPLAY " + test::shellQuote(PENUMBRA_EXE) + " view " +
        test::shellQuote(test::cornellObj().string()) + " --no-preview --out-dir " +
        test::shellQuote(dir.string()) + " >" + test::shellQuote((dir / "stdout").string()) +
        " 2>" + test::shellQuote((dir / "stderr").string());
    ASSERT_EQ(test::runShell(command), 0);
    std::ifstream err(dir / "stderr");
    const std::string message((std::istreambuf_iterator<char>(err)), {});
    EXPECT_NE(message.find("cannot open a window"), std::string::npos) << message;
    EXPECT_NE(message.find("DISPLAY"), std::string::npos) << message;
    const test::Image image = test::readPng(dir / "view.png");
    EXPECT_EQ(image.width, 1280);
    const json state = test::readJson(dir / "view_state.json");
    ASSERT_FALSE(state["point"].is_null());
    EXPECT_FALSE(state["point"]["lights"].empty());
}

TEST(ViewerScreenshot, BadArgumentsAreRefusedWithTheReason) {
    const fs::path dir = test::scratchDir("viewer_bad");
    const std::string out = (dir / "x.png").string();
    struct Case {
        std::vector<std::string> args;
        int code;
        std::string message;
    };
    const std::vector<Case> cases = {
        {{"--size", "12x4"}, 2, "--size"},
        {{"--size", "wide"}, 2, "expected WxH"},
        {{"--point", "1,2"}, 2, "--point"},
        {{"--camera", "0,0,0,0,0,0"}, 2, "same point"},
        {{"--backend", "vulkan"}, 2, "osmesa or egl"},
        {{"--pixel", "5000,5"}, 2, "outside"},
        {{"--point", "1,2,3"}, 1, "lies on no face"},
        {{"--preview-out", (dir / "p.jpg").string()}, 2, ".png, .pfm or .exr"},
    };
    for (const Case& c : cases) {
        std::vector<std::string> args = {"screenshot", test::cornellObj().string(), "--out", out};
        args.insert(args.end(), c.args.begin(), c.args.end());
        const test::ProcessResult r = test::runPenumbraGl(args);
        EXPECT_EQ(r.exitCode, c.code) << c.args.front() << ": " << r.err;
        EXPECT_NE(r.err.find(c.message), std::string::npos) << r.err;
        EXPECT_FALSE(fs::exists(out));
    }
    const test::ProcessResult missing =
        test::runPenumbraGl({"screenshot", (dir / "none.obj").string(), "--out", out});
    EXPECT_EQ(missing.exitCode, 1);
    EXPECT_NE(missing.err.find("no such file"), std::string::npos) << missing.err;
}

TEST(ViewerScreenshot, EglBackendRendersTheSameOverlayOrSaysWhy) {
    const fs::path dir = test::scratchDir("viewer_egl");
    // Under the sanitizer build: libglvnd unloads the EGL vendor library before exit, so what it
    // keeps allocated is reported from "<unknown module>" frames that no suppression can name.
    // Leak checking is off for this one child (its other sanitizers stay on); the OSMesa tests
    // keep it, with tests/app/viewer/lsan_gl.supp.
    const char* previous = std::getenv("ASAN_OPTIONS");
    const std::string saved = previous != nullptr ? previous : "";
    setenv("ASAN_OPTIONS", (saved.empty() ? "detect_leaks=0" : saved + ":detect_leaks=0").c_str(),
           1);
    const test::ProcessResult r = test::runPenumbraGl(
        {"screenshot", test::cornellObj().string(), "--point", "278,0,280", "--camera", kCameraFlag,
         "--no-preview", "--backend", "egl", "--out", (dir / "shot.png").string(), "--state-out",
         (dir / "state.json").string()});
    if (previous != nullptr)
        setenv("ASAN_OPTIONS", saved.c_str(), 1);
    else
        unsetenv("ASAN_OPTIONS");
    if (r.exitCode != 0) {
        // No surfaceless EGL here: the message must name the backend and the reason.
        EXPECT_NE(r.err.find("egl backend"), std::string::npos) << r.err;
        GTEST_SKIP() << "EGL surfaceless unavailable: " << r.err;
    }
    const json state = test::readJson(dir / "state.json");
    const test::Image image = test::readPng(dir / "shot.png");
    const int viewport[4] = {state["viewport"]["x"], state["viewport"]["y"],
                             state["viewport"]["width"], state["viewport"]["height"]};
    EXPECT_GE(test::checkFragmentOverlay(image, lightCamera(), viewport, test::cornellObj(), 0,
                                         {278, 0, 280}, 0),
              2);
}

}  // namespace
}  // namespace penumbra
