// Tests of the default light (engine/scene/default_light.h): where the rule puts it, checked
// against the numbers derived by hand for a small scene, that it touches no geometry (exact side
// tests against its plane), that its emission gives E F = 1 at the top of the scene with F from
// the closed form of a square seen from a point below its centre (not the code's contour
// integral), which up it takes, and when a scene gets one.
#include "engine/scene/default_light.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "engine/io/obj_io.h"
#include "engine/io/scene_loader.h"
#include "tests/support/closed_forms.h"
#include "visibility/face_plane.h"

namespace penumbra {
namespace default_light_test {

namespace fs = std::filesystem;

// A 2 x 2 floor at y = 0 facing up, and a 0.4 x 0.4 tile at y = 0.4 over its corner, no material
// (kd 0.8): the scene's bounds are [-1, 1] x [0, 0.4] x [-1, 1].
const char* kUnlit =
    "v -1 0 -1\nv -1 0 1\nv 1 0 1\nv 1 0 -1\n"
    "v 0.5 0.4 0.5\nv 0.5 0.4 0.9\nv 0.9 0.4 0.9\nv 0.9 0.4 0.5\n"
    "f 1 2 3 4\nf 5 6 7 8\n";

Scene unlit() { return loadObjFromString(kUnlit, "", "unlit.obj"); }

TEST(DefaultLight, SquareCentredOverTheSceneHalfItsDiagonalAboveFacingDown) {
    Scene scene = unlit();
    ASSERT_TRUE(needsDefaultLight(scene));
    addDefaultLight(scene);
    ASSERT_TRUE(scene.defaultLight);
    const DefaultLight& d = *scene.defaultLight;
    // By hand: D = sqrt(2^2 + 0.4^2 + 2^2); the plane D / 2 above y = 0.4; side 2 / 4.
    const double diagonal = std::sqrt(8.16);
    EXPECT_EQ(d.axis, 1);
    EXPECT_EQ(d.sign, 1);
    EXPECT_FALSE(d.upFromCamera);
    EXPECT_DOUBLE_EQ(d.side, 0.5);
    EXPECT_DOUBLE_EQ(d.height, diagonal / 2);
    ASSERT_EQ(scene.faceCount(), 3u);
    EXPECT_EQ(d.face, 2u);
    ASSERT_EQ(scene.lights, std::vector<uint32_t>{2});
    EXPECT_EQ(scene.material(2).name, kDefaultLightMaterial);
    EXPECT_TRUE(scene.material(2).isEmissive());
    for (const Vec3& c : d.corners) {
        EXPECT_DOUBLE_EQ(c.y, 0.4 + diagonal / 2);
        EXPECT_DOUBLE_EQ(std::fabs(c.x), 0.25);
        EXPECT_DOUBLE_EQ(std::fabs(c.z), 0.25);
    }
    const Vec3 n = normalize(scene.mesh.faceAreaNormal(2));
    EXPECT_NEAR(n.y, -1, 1e-15) << "faces down";
    // It touches nothing: every other vertex strictly in front of its plane (exact), its box
    // apart from the scene's.
    const vis::FacePlane plane = vis::facePlane(scene.mesh, 2);
    for (uint32_t v = 0; v < d.firstVertex; ++v)
        EXPECT_EQ(plane.side(scene.mesh.vertices[v]), vis::Sign::Positive) << v;
    EXPECT_FALSE(scene.mesh.faceBounds(2).overlaps(scene.fileBounds()));
    EXPECT_DOUBLE_EQ(scene.fileBounds().hi.y, 0.4);
    // E F = 1 at the centre of the scene's top, F by the closed form (four corner rectangles).
    const double f = 4 * test::cornerFormFactor(0.25, 0.25, diagonal / 2);
    EXPECT_NEAR(d.emission * f, 1.0, 1e-12);
    EXPECT_EQ(scene.material(2).ke, (Vec3{d.emission, d.emission, d.emission}));
}

TEST(DefaultLight, UpIsTheCamerasSnappedToAnAxisElsePlusY) {
    for (const Vec3 up : {Vec3{0.1, 0.2, 0.97}, Vec3{0.1, -0.9, 0.3}, Vec3{-2, 0, 0}}) {
        SCOPED_TRACE(vis::toString(up));
        Scene scene = unlit();
        scene.camera = Camera{};
        scene.camera->up = up;
        addDefaultLight(scene);
        const DefaultLight& d = *scene.defaultLight;
        EXPECT_TRUE(d.upFromCamera);
        const int axis = up.z == 0.97 ? 2 : (up.y == -0.9 ? 1 : 0);
        const int sign = axis == 2 ? 1 : -1;
        EXPECT_EQ(d.axis, axis);
        EXPECT_EQ(d.sign, sign);
        const vis::Bounds3 box = scene.fileBounds();
        // Beyond the scene's top along that up, facing back toward it.
        for (const Vec3& c : d.corners) {
            if (sign > 0)
                EXPECT_GT(c[axis], box.hi[axis]);
            else
                EXPECT_LT(c[axis], box.lo[axis]);
        }
        const Vec3 n = normalize(scene.mesh.faceAreaNormal(d.face));
        EXPECT_NEAR(n[axis], -sign, 1e-15);
        const vis::FacePlane plane = vis::facePlane(scene.mesh, d.face);
        for (uint32_t v = 0; v < d.firstVertex; ++v)
            EXPECT_EQ(plane.side(scene.mesh.vertices[v]), vis::Sign::Positive) << v;
    }
}

TEST(DefaultLight, OnlyAScenesWithNoLightAtAllGetsOne) {
    Scene scene = unlit();
    EXPECT_TRUE(needsDefaultLight(scene));
    scene.pointLights.push_back(PointLight{});
    EXPECT_FALSE(needsDefaultLight(scene)) << "point lights light it";
    Scene lit = loadObjFromString(
        "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 0 0 1\nv 0 1 0\nv 0 1 1\nv 1 1 0\n"
        "usemtl white\nf 1 3 2\nusemtl lamp\nf 4 6 5\n",
        "newmtl white\nKd 0.8 0.8 0.8\nnewmtl lamp\nKe 1 1 1\n", "lit.obj");
    EXPECT_FALSE(needsDefaultLight(lit));
    EXPECT_FALSE(needsDefaultLight(Scene{})) << "no faces, nothing to light";

    // loadScene adds it only when asked (the commands ask; a library caller gets the file).
    const fs::path dir =
        fs::temp_directory_path() / ("penumbra_default_light_" + std::to_string(::getpid()));
    fs::create_directories(dir);
    std::ofstream(dir / "unlit.obj") << kUnlit;
    const Scene plain = loadScene(dir / "unlit.obj");
    EXPECT_FALSE(plain.defaultLight);
    EXPECT_TRUE(plain.lights.empty());
    const Scene withLight = loadScene(dir / "unlit.obj", LoadOptions::forCommands());
    ASSERT_TRUE(withLight.defaultLight);
    EXPECT_EQ(withLight.lights.size(), 1u);
    const std::string said = withLight.defaultLight->announcement("unlit.obj");
    EXPECT_NE(said.find("unlit.obj has no lights: added a default area light"), std::string::npos)
        << said;
    EXPECT_NE(said.find("--no-default-light"), std::string::npos) << said;
    EXPECT_NE(said.find("up +y"), std::string::npos) << said;
    fs::remove_all(dir);
}

}  // namespace default_light_test
}  // namespace penumbra
