// Moving an area light (engine/scene/light_move.h): the moved vertices against coordinates worked
// out by hand for the Cornell box's lamp, exact planarity after a rotation that doubles cannot do
// exactly, refusals (a zero or negative scale, a light that does not exist), a lamp that shares
// its vertices with its neighbour, and the JSON scene's "moved_lights" that a saved view writes.
#include "engine/scene/light_move.h"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include "engine/io/scene_file.h"
#include "engine/io/scene_loader.h"
#include "engine/scene/scene_validation.h"

namespace penumbra {
namespace {

namespace fs = std::filesystem;

Scene cornellBox() {
    return loadScene(fs::path(PENUMBRA_SOURCE_DIR) / "assets" / "cornell_box.obj");
}

std::vector<Vec3> lightVertices(const Scene& scene, uint32_t light) {
    std::vector<Vec3> out;
    for (uint32_t v : scene.mesh.faces[scene.lights[light]]) out.push_back(scene.mesh.vertices[v]);
    return out;
}

// The lamp of assets/cornell_box.obj: y = 548, x in [213, 343], z in [227, 332], centre
// (278, 548, 279.5); half extents 65 (x) and 52.5 (z).
const std::vector<Vec3> kLamp = {
    {343, 548, 227}, {343, 548, 332}, {213, 548, 332}, {213, 548, 227}};

TEST(LightMove, TranslationScaleAndQuarterTurnAsWorkedOutByHand) {
    const Scene original = cornellBox();
    ASSERT_EQ(original.lights.size(), 1u);
    ASSERT_EQ(lightVertices(original, 0), kLamp);
    {
        Scene s = original;
        moveLight(s, 0, LightMove{.translate = {10, -100, 20}});
        EXPECT_EQ(lightVertices(s, 0),
                  (std::vector<Vec3>{
                      {353, 448, 247}, {353, 448, 352}, {223, 448, 352}, {223, 448, 247}}));
    }
    {
        // Scaled about the centre: x 278 -+ 2 * 65, z 279.5 -+ 0.5 * 52.5.
        Scene s = original;
        moveLight(s, 0, LightMove{.scale = {2, 1, 0.5}});
        EXPECT_EQ(
            lightVertices(s, 0),
            (std::vector<Vec3>{
                {408, 548, 253.25}, {408, 548, 305.75}, {148, 548, 305.75}, {148, 548, 253.25}}));
    }
    {
        // A quarter turn about y (right-hand rule: x -> -z, z -> x of the offsets from the centre):
        // the offset (65, 0, -52.5) becomes (-52.5, 0, -65), exactly, cos 90 degrees taken as 0.
        Scene s = original;
        moveLight(s, 0, LightMove{.rotateDegrees = {0, 90, 0}});
        EXPECT_EQ(lightVertices(s, 0), (std::vector<Vec3>{{225.5, 548, 214.5},
                                                          {330.5, 548, 214.5},
                                                          {330.5, 548, 344.5},
                                                          {225.5, 548, 344.5}}));
    }
    // The other faces did not move.
    Scene s = original;
    moveLight(s, 0, LightMove{.translate = {1, 2, 3}});
    for (uint32_t f = 0; f < s.faceCount(); ++f) {
        if (f == s.lights[0]) continue;
        for (uint32_t v : s.mesh.faces[f]) {
            EXPECT_EQ(s.mesh.vertices[v], original.mesh.vertices[v]);
        }
    }
}

TEST(LightMove, TiltedLightIsExactlyPlanarAndWhereTheRotationPutsIt) {
    const Scene original = cornellBox();
    Scene s = original;
    // 30 degrees about x, then 20 about z: no double rotation keeps the quad exactly planar.
    moveLight(s, 0, LightMove{.translate = {0, -50, 0}, .rotateDegrees = {30, 0, 20}});
    EXPECT_NO_THROW(validateScene(s));  // exactly planar, strictly convex: the contract
    // By hand: offset d from the centre (278, 548, 279.5), rotated about x by 30 degrees
    // (y' = c y - s z, z' = s y + c z), then about z by 20 degrees (x' = c x - s y, y' = s x + c
    // y).
    const double c30 = std::sqrt(3.0) / 2, s30 = 0.5;
    const double c20 = std::cos(20 * std::numbers::pi / 180),
                 s20 = std::sin(20 * std::numbers::pi / 180);
    const std::vector<Vec3> moved = lightVertices(s, 0);
    for (size_t i = 0; i < kLamp.size(); ++i) {
        const Vec3 d = kLamp[i] - Vec3{278, 548, 279.5};
        const Vec3 rx{d.x, c30 * d.y - s30 * d.z, s30 * d.y + c30 * d.z};
        const Vec3 rz{c20 * rx.x - s20 * rx.y, s20 * rx.x + c20 * rx.y, rx.z};
        const Vec3 expected = Vec3{278, 498, 279.5} + rz;
        // The exact-planar construction moves a vertex by ~1e-7 of the light's size (130).
        EXPECT_LT(vis::length(moved[i] - expected), 1e-4) << i;
    }
}

TEST(LightMove, ZeroOrNegativeScaleAndMissingLightsAreRefused) {
    Scene s = cornellBox();
    const std::vector<Vec3> before = lightVertices(s, 0);
    for (const Vec3& scale : {Vec3{1, 0, 1}, Vec3{-1, 1, 1}, Vec3{1, 1, std::nan("")}}) {
        try {
            moveLight(s, 0, LightMove{.scale = scale});
            ADD_FAILURE() << "scale " << scale.x << "," << scale.y << "," << scale.z << " accepted";
        } catch (const SceneError& e) {
            EXPECT_NE(e.message.find("light 0: scale"), std::string::npos) << e.what();
        }
    }
    EXPECT_TRUE(lightMoveProblem(LightMove{.scale = {1, 0, 1}}).has_value());
    EXPECT_NE(lightMoveProblem(LightMove{.scale = {1, 0, 1}})->find("along y"), std::string::npos);
    EXPECT_FALSE(lightMoveProblem(LightMove{.scale = {0.01, 3, 1}}).has_value());
    try {
        moveLight(s, 1, LightMove{.translate = {1, 0, 0}});
        ADD_FAILURE() << "light 1 of a scene with one";
    } catch (const SceneError& e) {
        EXPECT_NE(e.message.find("light 1: no such light (the scene has 1)"), std::string::npos)
            << e.what();
    }
    EXPECT_EQ(lightVertices(s, 0), before);  // nothing moved
}

TEST(LightMove, SharedVerticesAreSplitOffSoThatTheNeighbourStays) {
    // A wall triangle and a lamp triangle sharing the edge (0, 2).
    Scene s;
    s.sourcePath = "shared.obj";
    s.mesh.vertices = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
    s.mesh.faces = {{0, 1, 2}, {0, 2, 3}};
    Material wall, lamp;
    wall.name = "wall";
    lamp.name = "lamp";
    lamp.ke = {5, 5, 5};
    s.materials = {wall, lamp};
    s.faceMaterial = {0, 1};
    s.collectLights();
    ASSERT_EQ(s.lights, (std::vector<uint32_t>{1}));
    moveLight(s, 0, LightMove{.translate = {0, 0, 0.5}});
    EXPECT_EQ(s.mesh.faces[0], (std::vector<uint32_t>{0, 1, 2}));
    EXPECT_EQ(s.mesh.vertices[0], (Vec3{0, 0, 0}));
    EXPECT_EQ(s.mesh.vertices[2], (Vec3{1, 1, 0}));
    EXPECT_EQ(lightVertices(s, 0), (std::vector<Vec3>{{0, 0, 0.5}, {1, 1, 0.5}, {0, 1, 0.5}}));
    EXPECT_EQ(s.mesh.faces[1], (std::vector<uint32_t>{4, 5, 6}));
}

TEST(LightMove, SavedMovedLightsReadBackAndBadEntriesNameTheirPath) {
    const fs::path source =
        fs::path(PENUMBRA_SOURCE_DIR) / "assets" / "scenes" / "cornell_box.json";
    const fs::path target = fs::path(PENUMBRA_SOURCE_DIR) / "assets" / "scenes" / "saved.json";
    const std::vector<Vec3> hand = {
        {315.5, 398, 293.25}, {315.5, 398, 345.75}, {120.5, 398, 345.75}, {120.5, 398, 293.25}};
    const std::vector<PlacedLight> moved = {{0, hand}};
    const std::string text = jsonSceneWithCamera(source, Camera{}, target, nullptr, moved);
    const Scene s = loadJsonSceneFromString(text, target.parent_path(), "saved.json");
    EXPECT_EQ(lightVertices(s, 0), hand);
    EXPECT_NO_THROW(validateScene(s));
    // Saving again replaces the entry of the same light.
    const std::string again = jsonSceneWithCamera(source, Camera{}, target, nullptr, moved);
    EXPECT_EQ(again, text);

    const auto error = [&](const std::string& entry) -> std::string {
        const std::string json =
            R"({"meshes": [{"file": "../cornell_box.obj"}], "moved_lights": [)" + entry + "]}";
        try {
            loadJsonSceneFromString(json, target.parent_path(), "bad.json");
        } catch (const SceneError& e) {
            return e.what();
        }
        return "(accepted)";
    };
    EXPECT_NE(error(R"({"light": 1, "vertices": []})")
                  .find("bad.json: moved_lights[0].light: no light 1 (the scene has 1)"),
              std::string::npos)
        << error(R"({"light": 1, "vertices": []})");
    EXPECT_NE(error(R"({"light": 0, "vertices": [[0,0,0],[1,0,0],[1,1,0]]})")
                  .find("moved_lights[0]: expected 4 vertices"),
              std::string::npos);
    const std::string bent =
        error(R"({"light": 0, "vertices": [[0,0,0],[1,0,0],[1,1,0.001],[0,1,0]]})");
    EXPECT_NE(bent.find("moved_lights[0]: the moved light is not a face the scene contract "
                        "accepts: non-planar"),
              std::string::npos)
        << bent;
    EXPECT_NE(error(R"({"light": 0, "vertices": [[0,0,0],[1,0,0],[1,1,0],[0,1,0]], "spin": 1})")
                  .find("unknown key \"spin\""),
              std::string::npos);
}

}  // namespace
}  // namespace penumbra
