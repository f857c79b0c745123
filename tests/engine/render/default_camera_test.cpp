// Tests of the default camera (engine/render/default_camera.h) and lights: it never looks at the
// back of a light (black in every render) when another view shows the scene. Each case also
// checks that the view the rule would take without that care does see the back, so that the
// test can fail. And the Cornell box keeps its traditional view.
#include "engine/render/default_camera.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "engine/io/obj_io.h"
#include "engine/io/scene_loader.h"
#include "visibility/face_plane.h"

namespace penumbra {
namespace default_camera_test {

const Vec3 kYUp{0, 1, 0};

// The first candidate of the rule before lights were considered: 20 degrees up from -z, y up
// (the view every scene below would have got: they all score highest there or tie with it).
Camera firstCandidate(const vis::Bounds3& bounds) {
    return Camera::fitting(bounds, {0, std::tan(20 * std::numbers::pi / 180), -1}, 45, kYUp);
}

// Some ray of a 24 x 24 grid over the image hits the front of a face that is not `light`.
bool showsAReceiver(const Scene& scene, const EmbreeScene& bvh, const Camera& c, uint32_t light) {
    for (int y = 0; y < 24; ++y)
        for (int x = 0; x < 24; ++x) {
            const Ray r = c.ray(x + 0.5, y + 0.5, 24, 24);
            const auto hit = bvh.intersect(r.origin, r.direction);
            if (hit && hit->face != light &&
                dot(scene.mesh.faceAreaNormal(hit->face), r.direction) < 0)
                return true;
        }
    return false;
}

// A 2 x 2 floor at y = 0 and a tile at y = 0.4 over its corner, no light.
const char* kUnlit =
    "v -1 0 -1\nv -1 0 1\nv 1 0 1\nv 1 0 -1\n"
    "v 0.5 0.4 0.5\nv 0.5 0.4 0.9\nv 0.9 0.4 0.9\nv 0.9 0.4 0.5\n"
    "f 1 2 3 4\nf 5 6 7 8\n";

TEST(DefaultCamera, SeesTheDefaultLightFromItsEmittingSide) {
    Scene scene = loadObjFromString(kUnlit, "", "unlit.obj");
    addDefaultLight(scene);
    const uint32_t light = scene.defaultLight->face;
    const EmbreeScene bvh(scene.mesh);
    const Camera c = defaultCamera(scene, bvh);
    const vis::FacePlane plane = vis::facePlane(scene.mesh, light);
    EXPECT_EQ(plane.side(c.eye), vis::Sign::Positive) << "the eye below the light";
    EXPECT_TRUE(showsAReceiver(scene, bvh, c, light));
    // Fitted to the mesh with the light in it, that view's eye is above the light, looking at its
    // back: the rule fits the file's geometry.
    EXPECT_EQ(plane.side(firstCandidate(scene.mesh.bounds()).eye), vis::Sign::Negative);
}

// A lamp hanging over the floor, facing down: from 20 degrees up with y up, every direction looks
// down on its back.
TEST(DefaultCamera, HangingLampIsSeenFromBelowNotFromBehind) {
    const Scene scene = loadObjFromString(
        "mtllib m.mtl\nv -1 0 -1\nv -1 0 1\nv 1 0 1\nv 1 0 -1\n"
        "v -0.2 1 -0.2\nv 0.2 1 -0.2\nv 0.2 1 0.2\nv -0.2 1 0.2\n"
        "usemtl white\nf 1 2 3 4\nusemtl lamp\nf 5 6 7 8\n",
        "newmtl white\nKd 0.8 0.8 0.8\nnewmtl lamp\nKd 0 0 0\nKe 5 5 5\n", "lamp.obj");
    ASSERT_EQ(scene.lights, std::vector<uint32_t>{1});
    const vis::FacePlane plane = vis::facePlane(scene.mesh, 1);
    ASSERT_EQ(plane.side({0, 0, 0}), vis::Sign::Positive) << "the lamp faces the floor";
    const EmbreeScene bvh(scene.mesh);
    const Camera c = defaultCamera(scene, bvh);
    EXPECT_EQ(plane.side(c.eye), vis::Sign::Positive);
    EXPECT_TRUE(showsAReceiver(scene, bvh, c, 1));
    EXPECT_EQ(plane.side(firstCandidate(scene.fileBounds()).eye), vis::Sign::Negative);
}

// The lamp of the Cornell box hangs under the ceiling; from outside, the ceiling hides its back:
// the traditional view from -z stays.
TEST(DefaultCamera, CornellBoxKeepsItsView) {
    const Scene scene =
        loadScene(std::filesystem::path(PENUMBRA_SOURCE_DIR) / "assets" / "cornell_box.obj");
    const EmbreeScene bvh(scene.mesh);
    const Camera c = defaultCamera(scene, bvh);
    const Camera expected = firstCandidate(scene.mesh.bounds());
    EXPECT_EQ(c.eye, expected.eye);
    EXPECT_EQ(c.target, expected.target);
    EXPECT_EQ(c.up, kYUp);
}

}  // namespace default_camera_test
}  // namespace penumbra
