// Texture lookup (engine/scene/texture.h) and a face's texture coordinates at a point
// (engine/scene/face_uv.h), against values derived by hand: the sRGB curve's table values,
// bilinear weights between texel centres, the wrap modes' periodic images, KHR_texture_transform's
// own example, and barycentric interpolation on the fan.
#include "engine/scene/texture.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <vector>

#include "engine/scene/face_uv.h"
#include "engine/scene/scene.h"

namespace penumbra {
namespace texture_test {

// width x height texels, each channel the same byte.
TextureImage grey(int width, int height, std::vector<uint8_t> bytes) {
    TextureImage image;
    image.source = "test";
    image.width = width;
    image.height = height;
    for (uint8_t b : bytes) image.srgb.insert(image.srgb.end(), {b, b, b});
    return image;
}

double red(const TextureImage& image, const TextureRef& ref, Uv uv) {
    return sampleTexture(image, ref, uv).x;
}

TEST(Texture, SrgbBytesDecodeToTheStandardsLinearValues) {
    EXPECT_EQ(srgbToLinear(0), 0.0);
    EXPECT_EQ(srgbToLinear(255), 1.0);
    // Below the knee (0.04045 * 255 = 10.3): c / 12.92.
    EXPECT_NEAR(srgbToLinear(10), 10 / 255.0 / 12.92, 1e-15);
    // ((128 / 255 + 0.055) / 1.055)^2.4 = 0.2158605 (IEC 61966-2-1's table).
    EXPECT_NEAR(srgbToLinear(128), 0.2158605, 1e-7);
    EXPECT_NEAR(srgbToLinear(188), 0.5028865, 1e-7);
}

// Two texels in a row, white then black: u = 1/4 and 3/4 are their centres.
TEST(Texture, BilinearBetweenTexelCentresWithEachWrapMode) {
    const TextureImage image = grey(2, 1, {255, 0});
    TextureRef ref;
    ref.image = 0;
    for (const TextureWrap wrap :
         {TextureWrap::Repeat, TextureWrap::ClampToEdge, TextureWrap::MirroredRepeat}) {
        ref.wrapU = ref.wrapV = wrap;
        EXPECT_EQ(red(image, ref, {0.25, 0.5}), 1.0);
        EXPECT_EQ(red(image, ref, {0.75, 0.5}), 0.0);
        EXPECT_NEAR(red(image, ref, {0.5, 0.5}), 0.5, 1e-15);
        EXPECT_NEAR(red(image, ref, {0.375, 0.5}), 0.75, 1e-15);  // a quarter of the way
    }
    // At u = 0 the neighbour across the edge is texel 1 (repeat: black), texel 0 again (clamp,
    // mirror: white); at u = 1.25 repeat reads texel 0's centre again, the mirror's reversed copy
    // of [0, 1] reads 0.75's (texel 1).
    ref.wrapU = TextureWrap::Repeat;
    EXPECT_NEAR(red(image, ref, {0.0, 0.5}), 0.5, 1e-15);
    EXPECT_EQ(red(image, ref, {1.25, 0.5}), 1.0);
    EXPECT_EQ(red(image, ref, {-0.75, 0.5}), 1.0);
    ref.wrapU = TextureWrap::ClampToEdge;
    EXPECT_EQ(red(image, ref, {0.0, 0.5}), 1.0);
    EXPECT_EQ(red(image, ref, {7.0, 0.5}), 0.0);
    EXPECT_EQ(red(image, ref, {-3.0, 0.5}), 1.0);
    ref.wrapU = TextureWrap::MirroredRepeat;
    EXPECT_EQ(red(image, ref, {0.0, 0.5}), 1.0);
    EXPECT_EQ(red(image, ref, {1.25, 0.5}), 0.0);
    EXPECT_EQ(red(image, ref, {1.75, 0.5}), 1.0);
    EXPECT_NEAR(red(image, ref, {-0.375, 0.5}), 0.75, 1e-15);  // mirror of 0.375
    // Mirror of 0.125, whose neighbour across the edge is texel 0 itself; repeat reads texel 1
    // there, a quarter weight.
    EXPECT_EQ(red(image, ref, {-0.125, 0.5}), 1.0);
    ref.wrapU = TextureWrap::Repeat;
    EXPECT_NEAR(red(image, ref, {0.125, 0.5}), 0.75, 1e-15);
}

TEST(Texture, NearestReadsTheTexelThePointIsIn) {
    const TextureImage image = grey(2, 2, {255, 0, 128, 10});
    TextureRef ref;
    ref.image = 0;
    ref.filter = TextureFilter::Nearest;
    EXPECT_EQ(red(image, ref, {0.49, 0.01}), 1.0);
    EXPECT_EQ(red(image, ref, {0.51, 0.49}), 0.0);
    EXPECT_EQ(red(image, ref, {0.01, 0.99}), srgbToLinear(128));
    EXPECT_EQ(red(image, ref, {0.99, 0.51}), srgbToLinear(10));
    EXPECT_EQ(red(image, ref, {1.01, 1.51}), srgbToLinear(128));  // repeat
    // Far outside and non-finite coordinates still read a texel.
    EXPECT_TRUE(std::isfinite(red(image, ref, {1e300, -1e300})));
    EXPECT_TRUE(std::isfinite(red(image, ref, {NAN, INFINITY})));
}

// KHR_texture_transform's example: offset (0, 1), rotation pi/2, scale 1/2 "utilizes only the lower
// left quadrant of the source image, rotated clockwise 90 degrees": [0, 1]^2 goes onto
// [0, 1/2] x [1/2, 1] (v down), u along -v' and v along u'.
TEST(Texture, UvTransformIsTheExtensionsExample) {
    UvTransform t;
    t.offset = {0, 1};
    t.rotation = std::numbers::pi / 2;
    t.scale = {0.5, 0.5};
    const auto near = [](Uv a, Uv b) {
        EXPECT_NEAR(a.u, b.u, 1e-15);
        EXPECT_NEAR(a.v, b.v, 1e-15);
    };
    near(t.apply({0, 0}), {0, 1});
    near(t.apply({1, 0}), {0, 0.5});
    near(t.apply({0, 1}), {0.5, 1});
    near(t.apply({1, 1}), {0.5, 0.5});
    // Offset and scale alone: u s + o.
    UvTransform os;
    os.offset = {0.25, -1};
    os.scale = {2, 3};
    near(os.apply({0.5, 0.5}), {1.25, 0.5});
    EXPECT_TRUE(UvTransform{}.isIdentity());
    EXPECT_FALSE(os.isIdentity());
    // Applied by the lookup: a 2x1 image read through a half-texel offset swaps the texels.
    const TextureImage image = grey(2, 1, {255, 0});
    TextureRef ref;
    ref.image = 0;
    ref.transform.offset = {0.5, 0};
    EXPECT_EQ(red(image, ref, {0.25, 0.5}), 0.0);
    EXPECT_EQ(red(image, ref, {0.75, 0.5}), 1.0);
}

// A quad (not a parallelogram: its UVs are no affine image of it) and a triangle: on the fan
// triangle holding the point, the barycentric mix of its corners' UVs.
TEST(FaceUv, BarycentricOnTheFanTriangleHoldingThePoint) {
    Scene s;
    s.mesh.vertices = {{0, 0, 0},  {4, 0, 0},  {4, 2, 0}, {0, 4, 0},
                       {10, 0, 5}, {12, 0, 5}, {10, 2, 5}};
    s.mesh.faces = {{0, 1, 2, 3}, {4, 5, 6}, {4, 6, 5}};
    s.faceUv = {{{0, 0}, {1, 0}, {1, 1}, {0, 1}}, {{0.5, 0.5}, {1, 0.5}, {0.5, 0}}, {}};
    // Fan triangle (0, 1, 2): (3, 1) = 1/4 v0 + 1/4 v1 + 1/2 v2 -> u = 3/4, v = 1/2.
    auto uv = faceUvAt(s, 0, {3, 1, 0});
    ASSERT_TRUE(uv);
    EXPECT_NEAR(uv->u, 0.75, 1e-15);
    EXPECT_NEAR(uv->v, 0.5, 1e-15);
    // (1, 2) lies outside (0, 1, 2) (its weight on v1 would be -3/4); in fan triangle (0, 2, 3):
    // (1, 2) = 3/8 v0 + 1/4 v2 + 3/8 v3 -> u = 1/4, v = 1/4 + 3/8 = 5/8.
    uv = faceUvAt(s, 0, {1, 2, 0});
    ASSERT_TRUE(uv);
    EXPECT_NEAR(uv->u, 0.25, 1e-15);
    EXPECT_NEAR(uv->v, 0.625, 1e-15);
    // The triangle: (11, 0.5) = 1/4 v4 + 1/2 v5 + 1/4 v6, so
    // u = 0.25 * 0.5 + 0.5 * 1 + 0.25 * 0.5 = 0.75, v = 0.25 * 0.5 + 0.5 * 0.5 + 0 = 0.375.
    uv = faceUvAt(s, 1, {11, 0.5, 5});
    ASSERT_TRUE(uv);
    EXPECT_NEAR(uv->u, 0.75, 1e-15);
    EXPECT_NEAR(uv->v, 0.375, 1e-15);
    EXPECT_FALSE(faceUvAt(s, 2, {11, 0.5, 5}));  // a face without coordinates
    s.faceUv.clear();
    EXPECT_FALSE(faceUvAt(s, 0, {1, 1, 0}));  // a scene without
}

// Scene::kdAt: the factor times the texture at the point; the factor alone where the face has
// no coordinates or the material no map.
TEST(FaceUv, KdAtIsTheFactorTimesTheTexture) {
    Scene s;
    s.mesh.vertices = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
    s.mesh.faces = {{0, 1, 2, 3}, {0, 2, 3}};
    s.textures = {grey(2, 1, {255, 128})};
    Material m;
    m.kd = {0.5, 0.25, 1};
    m.kdMap.image = 0;
    m.kdMap.filter = TextureFilter::Nearest;
    s.materials = {m};
    s.faceMaterial = {0, -1};
    s.faceUv = {{{0, 0}, {1, 0}, {1, 1}, {0, 1}}, {{0, 0}, {1, 1}, {0, 1}}};
    const Vec3 left = s.kdAt(0, {0.2, 0.7, 0}), right = s.kdAt(0, {0.8, 0.3, 0});
    EXPECT_EQ(left.x, 0.5);
    EXPECT_EQ(left.z, 1.0);
    EXPECT_EQ(right.y, 0.25 * srgbToLinear(128));
    EXPECT_EQ(s.kdAt(1, {0.2, 0.7, 0}).x, Material{}.kd.x);  // the default material: no map
    s.faceUv[0].clear();
    EXPECT_EQ(s.kdAt(0, {0.8, 0.3, 0}).y, 0.25);
}

}  // namespace texture_test
}  // namespace penumbra
