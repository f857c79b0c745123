// A textured quad under an area light, rendered: each quadrant of the quad shows one texel of a
// 2x2 checker (OBJ map_Kd), and the exact render's pixel there is kd(x) Le F with kd(x) = Kd x
// that texel (sRGB-decoded by hand) and F the closed-form form factor of the light from that point
// (tests/support/closed_forms.h), no occluder: computed here by hand, not by the renderer. The
// sampled estimator and a point light read the same kd(x).
#include <gtest/gtest.h>
#include <unistd.h>

#include <array>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <string>

#include "engine/io/image_io.h"
#include "engine/io/obj_io.h"
#include "engine/precompute/visibility_store.h"
#include "engine/raytrace/embree_scene.h"
#include "engine/render/renderer.h"
#include "tests/support/closed_forms.h"

namespace penumbra {
namespace textured_render_test {

namespace fs = std::filesystem;

// The floor quad [0, 2]^2 at z = 0 (facing up, vt = (x, y) / 2) textured with the checker, and a
// light [0, 3] x [0, 2.5] at z = 1.2 facing down, Ke (3, 4, 5): off-centre over the quad, so that
// each quadrant's centre sees it with another form factor.
constexpr double kHeight = 1.2, kLightX = 3, kLightY = 2.5;
const Vec3 kKd{0.9, 0.8, 0.7}, kKe{3, 4, 5};

Scene texturedQuadScene(const fs::path& dir) {
    fs::create_directories(dir);
    // Texels, rows from the top: red, green / blue, grey 128.
    const uint8_t texels[] = {255, 0, 0, 0, 255, 0, 0, 0, 255, 128, 128, 128};
    std::ofstream(dir / "checker.png", std::ios::binary) << encodePng(2, 2, 3, texels);
    std::ofstream(dir / "quad.mtl") << "newmtl checker\nKd 0.9 0.8 0.7\nmap_Kd checker.png\n"
                                       "newmtl lamp\nKd 0 0 0\nKe 3 4 5\n";
    std::ofstream(dir / "quad.obj") << "mtllib quad.mtl\n"
                                       "v 0 0 0\nv 2 0 0\nv 2 2 0\nv 0 2 0\n"
                                       "v 0 0 1.2\nv 0 2.5 1.2\nv 3 2.5 1.2\nv 3 0 1.2\n"
                                       "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n"
                                       "usemtl checker\nf 1/1 2/2 3/3 4/4\n"
                                       "usemtl lamp\nf 5 6 7 8\n";
    return loadObj(dir / "quad.obj");
}

// The light's form factor from (px, py, 0): the four rectangles with a corner above the point.
double formFactor(double px, double py) {
    using test::cornerFormFactor;
    return cornerFormFactor(px, py, kHeight) + cornerFormFactor(kLightX - px, py, kHeight) +
           cornerFormFactor(px, kLightY - py, kHeight) +
           cornerFormFactor(kLightX - px, kLightY - py, kHeight);
}

struct Quadrant {
    double x, y;
    Vec3 texel;  // linear
    const char* name;
};

// OBJ's vt runs up: the image's top row lies at large y (its top-left texel at x < 1, y > 1).
const double kGrey = 0.2158605;  // sRGB byte 128, linear (IEC 61966-2-1's table)
const Quadrant kQuadrants[] = {{0.5, 1.5, {1, 0, 0}, "top left, red"},
                               {1.5, 1.5, {0, 1, 0}, "top right, green"},
                               {0.5, 0.5, {0, 0, 1}, "bottom left, blue"},
                               {1.5, 0.5, {kGrey, kGrey, kGrey}, "bottom right, grey"}};

// One pixel with a tiny field of view looking at (x, y, 0) from below the light.
Film renderPoint(ProgressiveRenderer& renderer, double x, double y, DirectMethod method) {
    Camera camera;
    camera.eye = {x + 0.2, y - 0.3, 0.6};
    camera.target = {x, y, 0};
    camera.fovYDegrees = 1e-4;
    RenderSettings s;
    s.width = s.height = 1;
    s.spp = 2;
    s.method = method;
    s.lightSamples = 4096;
    return renderer.render(camera, s);
}

TEST(TexturedRender, EachQuadrantIsItsTexelTimesTheClosedFormIrradiance) {
    const fs::path dir =
        fs::temp_directory_path() / ("penumbra_textured_render_" + std::to_string(::getpid()));
    Scene scene = texturedQuadScene(dir);
    ASSERT_TRUE(scene.warnings.empty()) << scene.warnings.front();
    ASSERT_EQ(scene.textures.size(), 1u);
    EmbreeScene bvh(scene.mesh);
    VisibilityStore store(scene, &bvh);
    ProgressiveRenderer renderer(scene, bvh, store);
    for (const Quadrant& q : kQuadrants) {
        SCOPED_TRACE(q.name);
        const double f = formFactor(q.x, q.y);
        const Vec3 want{kKd.x * q.texel.x * kKe.x * f, kKd.y * q.texel.y * kKe.y * f,
                        kKd.z * q.texel.z * kKe.z * f};
        const Vec3 exact = renderPoint(renderer, q.x, q.y, DirectMethod::Exact).mean(0, 0);
        EXPECT_NEAR(exact.x, want.x, 1e-5);
        EXPECT_NEAR(exact.y, want.y, 1e-5);
        EXPECT_NEAR(exact.z, want.z, 1e-5);
        // Shadow rays over the same light (4096 stratified samples): within 1% of the largest
        // channel.
        const Vec3 sampled = renderPoint(renderer, q.x, q.y, DirectMethod::Sampled).mean(0, 0);
        const double scale = std::max({want.x, want.y, want.z});
        EXPECT_NEAR(sampled.x, want.x, 0.01 * scale);
        EXPECT_NEAR(sampled.y, want.y, 0.01 * scale);
        EXPECT_NEAR(sampled.z, want.z, 0.01 * scale);
    }
    // The quadrants' form factors differ (the light is off-centre): the test can tell them apart.
    EXPECT_GT(std::fabs(formFactor(0.5, 0.5) - formFactor(1.5, 1.5)), 0.01);

    // A point light straight above the grey quadrant's centre at height 1/2 adds
    // kd(x) I cos / r^2 / pi = kd(x) I 4 / pi.
    const Vec3 before = renderPoint(renderer, 1.5, 0.5, DirectMethod::Exact).mean(0, 0);
    scene.pointLights.push_back({{1.5, 0.5, 0.5}, {2, 2, 2}});  // the renderer reads them live
    const Vec3 after = renderPoint(renderer, 1.5, 0.5, DirectMethod::Exact).mean(0, 0);
    EXPECT_NEAR(after.y - before.y, kKd.y * kGrey * 2 * 4 / std::numbers::pi, 1e-5);
    fs::remove_all(dir);
}

}  // namespace textured_render_test
}  // namespace penumbra
