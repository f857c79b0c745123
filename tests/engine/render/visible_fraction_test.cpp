// The exact renderer's visible fractions (RenderSettings::recordVisibleFraction,
// engine/render/visible_fraction.h) against a closed form: a square occluder under a square
// light casts a penumbra on the floor that is, in closed form, an open square; the pixels whose
// whole footprint on the floor lies inside it must be penumbra pixels, those wholly outside it
// not.
#include "engine/render/visible_fraction.h"

#include <gtest/gtest.h>

#include <cmath>
#include <optional>

#include "engine/precompute/visibility_store.h"
#include "engine/raytrace/embree_scene.h"
#include "engine/render/renderer.h"

namespace penumbra {
namespace visible_fraction_test {

uint32_t addRect(Scene& s, double x0, double x1, double y0, double y1, double z, bool up,
                 int32_t material) {
    const uint32_t first = static_cast<uint32_t>(s.mesh.vertices.size());
    if (up)
        s.mesh.vertices.insert(s.mesh.vertices.end(),
                               {{x0, y0, z}, {x1, y0, z}, {x1, y1, z}, {x0, y1, z}});
    else
        s.mesh.vertices.insert(s.mesh.vertices.end(),
                               {{x0, y0, z}, {x0, y1, z}, {x1, y1, z}, {x1, y0, z}});
    s.mesh.faces.push_back({first, first + 1, first + 2, first + 3});
    s.faceMaterial.push_back(material);
    s.faceSourceLine.push_back(0);
    return s.faceCount() - 1;
}

// A floor [-2,2]^2 at z=0, a light [-0.5,0.5]^2 at z=2 facing down and an occluder
// [-0.15,0.15]^2 at z=1. Seen from floor point p, the occluder covers the square of half-size
// 0.3 centred on -p in the light's plane (scaled by 2 about p): it overlaps the light exactly when
// |p.x| < 0.8 and |p.y| < 0.8, and never covers it. So the penumbra is the open square
// (-0.8, 0.8)^2, every other floor point sees all of the light, and no point none of it.
Scene occludedFloor() {
    Scene s;
    Material grey;
    grey.kd = {0.6, 0.6, 0.6};
    Material light;
    light.kd = {0.2, 0.2, 0.2};
    light.ke = {5, 5, 5};
    s.materials = {grey, light};
    addRect(s, -2, 2, -2, 2, 0, true, 0);
    addRect(s, -0.5, 0.5, -0.5, 0.5, 2, false, 1);
    addRect(s, -0.15, 0.15, -0.15, 0.15, 1, true, 0);
    s.collectLights();
    return s;
}

// Where the ray through continuous pixel position (px, py) meets the floor, if it goes down
// and meets it within the floor.
std::optional<Vec3> onFloor(const Camera& camera, double px, double py, int w, int h) {
    const Ray r = camera.ray(px, py, w, h);
    if (!(r.direction.z < 0)) return std::nullopt;
    const Vec3 p = r.origin + r.direction * (-r.origin.z / r.direction.z);
    if (std::abs(p.x) > 1.9 || std::abs(p.y) > 1.9) return std::nullopt;
    return p;
}

TEST(VisibleFraction, PenumbraPixelsAreThoseOfTheClosedFormPenumbra) {
    const Scene scene = occludedFloor();
    const EmbreeScene bvh(scene.mesh);
    VisibilityStore store(scene, &bvh);
    ProgressiveRenderer renderer(scene, bvh, store);
    // Below the occluder's height, looking down at the floor: every hit is on the floor.
    Camera camera;
    camera.eye = {0.1, -3.5, 0.8};
    camera.target = {0, 0, 0};
    camera.up = {0, 0, 1};
    camera.fovYDegrees = 50;
    RenderSettings s;
    s.width = s.height = 48;
    s.spp = 2;
    s.exactWorkLimit = 0;
    s.recordVisibleFraction = true;
    const Film film = renderer.render(camera, s);
    ASSERT_EQ(film.seen.size(), static_cast<size_t>(s.width * s.height));
    int inside = 0, outside = 0;
    for (int y = 0; y < s.height; ++y)
        for (int x = 0; x < s.width; ++x) {
            // The footprint's corners on the floor: the footprint is a convex quadrilateral, so
            // it lies in the (convex) penumbra square when its corners do, and outside it when
            // its corners all lie beyond one of the square's sides.
            bool all = true, anyMissing = false;
            int beyond[4] = {0, 0, 0, 0};  // corners with x >= 0.8, x <= -0.8, y >= 0.8, <= -0.8
            for (int c = 0; c < 4; ++c) {
                const std::optional<Vec3> p =
                    onFloor(camera, x + (c & 1), y + (c >> 1), s.width, s.height);
                if (!p) {
                    anyMissing = true;
                    break;
                }
                const double m = 1e-6;  // away from the boundary by more than rounding
                all = all && std::abs(p->x) < 0.8 - m && std::abs(p->y) < 0.8 - m;
                beyond[0] += p->x >= 0.8 + m;
                beyond[1] += p->x <= -0.8 - m;
                beyond[2] += p->y >= 0.8 + m;
                beyond[3] += p->y <= -0.8 - m;
            }
            if (anyMissing) continue;
            const SeenCounts& c = film.seen[static_cast<size_t>(y) * s.width + x];
            EXPECT_EQ(c[0] + c[1] + c[2], static_cast<uint32_t>(s.spp)) << x << "," << y;
            EXPECT_EQ(c[static_cast<size_t>(LightSeen::None)], 0u) << x << "," << y;
            if (all) {
                ++inside;
                EXPECT_TRUE(penumbraPixel(c)) << x << "," << y;
            } else if (beyond[0] == 4 || beyond[1] == 4 || beyond[2] == 4 || beyond[3] == 4) {
                ++outside;
                EXPECT_FALSE(penumbraPixel(c)) << x << "," << y;
            }
        }
    // Both kinds are there to check.
    EXPECT_GT(inside, 50);
    EXPECT_GT(outside, 50);
}

TEST(VisibleFraction, NotRecordedUnlessAsked) {
    const Scene scene = occludedFloor();
    const EmbreeScene bvh(scene.mesh);
    VisibilityStore store(scene, &bvh);
    ProgressiveRenderer renderer(scene, bvh, store);
    RenderSettings s;
    s.width = s.height = 8;
    s.spp = 1;
    Camera camera;
    camera.eye = {0, -3, 0.8};
    camera.up = {0, 0, 1};
    EXPECT_TRUE(renderer.render(camera, s).seen.empty());
    s.method = DirectMethod::Sampled;
    s.recordVisibleFraction = true;  // (the exact method's only)
    EXPECT_TRUE(renderer.render(camera, s).seen.empty());
}

}  // namespace visible_fraction_test
}  // namespace penumbra
