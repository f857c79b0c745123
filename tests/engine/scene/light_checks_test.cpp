// Tests of the lights that can light nothing (engine/scene/light_checks.h): a light whose winding
// is flipped is named with its face, material and line, on load too; the decision is exact (a
// receiver vertex on the light's plane does not count as in front, one a rounding in front does);
// a scene of lights alone has no receiver to warn about.
#include "engine/scene/light_checks.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "engine/io/obj_io.h"
#include "engine/io/scene_loader.h"

namespace penumbra {
namespace light_checks_test {

namespace fs = std::filesystem;

// A floor at y = 0 facing up (line 7) and a lamp at y = 2 (line 13), facing down, or up when
// flipped (its vertices in the other order).
std::string obj(bool flipped) {
    std::string s =
        "mtllib m.mtl\nv -1 0 -1\nv -1 0 1\nv 1 0 1\nv 1 0 -1\n"
        "usemtl white\nf 1 2 3 4\nusemtl lamp\n"
        "v -0.2 2 -0.2\nv 0.2 2 -0.2\nv 0.2 2 0.2\nv -0.2 2 0.2\n";
    s += flipped ? "f 5 8 7 6\n" : "f 5 6 7 8\n";
    return s;
}
const char* kMtl = "newmtl white\nKd 0.8 0.8 0.8\nnewmtl lamp\nKd 0 0 0\nKe 5 5 5\n";

TEST(LightChecks, AFlippedLightIsNamedWithItsFaceMaterialAndLine) {
    const Scene good = loadObjFromString(obj(false), kMtl, "lamp.obj");
    ASSERT_EQ(good.lights.size(), 1u);
    EXPECT_TRUE(lightsFacingAway(good).empty());
    EXPECT_FALSE(lightsFacingAwayWarning(good));

    const Scene flipped = loadObjFromString(obj(true), kMtl, "lamp.obj");
    EXPECT_EQ(lightsFacingAway(flipped), std::vector<size_t>{0});
    const auto warning = lightsFacingAwayWarning(flipped);
    ASSERT_TRUE(warning);
    EXPECT_NE(warning->find("lamp.obj: light 0 (face 1, material 'lamp', line 13)"),
              std::string::npos)
        << *warning;
    EXPECT_NE(warning->find("its normal points away from every other face: flipped winding?"),
              std::string::npos)
        << *warning;

    // loadScene says it among the scene's warnings, with or without the default light (the scene
    // has a light: it gets none).
    const fs::path dir =
        fs::temp_directory_path() / ("penumbra_light_checks_" + std::to_string(::getpid()));
    fs::create_directories(dir);
    std::ofstream(dir / "lamp.obj") << obj(true);
    std::ofstream(dir / "m.mtl") << kMtl;
    std::ofstream(dir / "good.obj") << obj(false);
    for (const LoadOptions& options : {LoadOptions{}, LoadOptions::forCommands()}) {
        const Scene loaded = loadScene(dir / "lamp.obj", options);
        EXPECT_FALSE(loaded.defaultLight);
        ASSERT_EQ(loaded.warnings.size(), 1u);
        EXPECT_NE(loaded.warnings[0].find("light 0 (face 1, material 'lamp', line 13)"),
                  std::string::npos)
            << loaded.warnings[0];
        EXPECT_TRUE(loadScene(dir / "good.obj", options).warnings.empty());
    }
    fs::remove_all(dir);
}

// The light faces down at y = 1; the only receiver stands on its plane and rises behind it. On
// the plane is not in front: the light faces away from it. Moved down by one ulp, its lowest edge
// is in front: it does not.
TEST(LightChecks, InFrontOfTheLightIsDecidedExactly) {
    for (const bool touching : {true, false}) {
        SCOPED_TRACE(touching ? "edge on the plane" : "edge one ulp in front");
        Scene scene;
        scene.sourcePath = "exact.obj";
        const double low = touching ? 1.0 : std::nextafter(1.0, 0.0);
        scene.mesh.vertices = {{-0.2, 1, -0.2}, {-0.2, 1, 0.2}, {0.2, 1, 0.2}, {0.2, 1, -0.2},
                               {-1, low, 2},    {1, low, 2},    {1, 3, 2},     {-1, 3, 2}};
        // The light: clockwise seen from above, so facing down.
        scene.mesh.faces = {{0, 3, 2, 1}, {4, 5, 6, 7}};
        ASSERT_LT(normalize(scene.mesh.faceAreaNormal(0)).y, 0);
        Material lamp;
        lamp.name = "lamp";
        lamp.ke = {1, 1, 1};
        scene.materials = {lamp};
        scene.faceMaterial = {0, -1};
        scene.collectLights();
        EXPECT_EQ(lightsFacingAway(scene).size(), touching ? 1u : 0u);
    }
}

TEST(LightChecks, LightsAloneHaveNoReceiverToFaceAwayFrom) {
    const Scene lamps = loadObjFromString(
        "mtllib m.mtl\nusemtl lamp\nv 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 2 3\nf 1 4 2\n", kMtl,
        "lamps.obj");
    ASSERT_EQ(lamps.lights.size(), 2u);
    // Nothing but lights: no receiver to warn about.
    EXPECT_TRUE(lightsFacingAway(lamps).empty());
}

TEST(LightChecks, HiddenLightWarningGivesTheCounts) {
    const Scene scene = loadObjFromString(obj(false), kMtl, "lamp.obj");
    const std::string w = hiddenLightWarning(scene, 0, 3, 5);
    EXPECT_NE(w.find("lamp.obj: light 0 (face 1, material 'lamp', line 13) is hidden from every "
                     "receiver: of its 8 (receiver patch, light) pairs 3 are back-facing and 5 "
                     "hidden"),
              std::string::npos)
        << w;
}

}  // namespace light_checks_test
}  // namespace penumbra
