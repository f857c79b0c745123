// Base-colour textures as the loaders read them (engine/io/texture_io.h, gltf_io.h, obj_io.h,
// scene_file.h): a 2x2 checker PNG whose texels are known bytes, mapped onto a quad, read back
// through Scene::kdAt at points of each quadrant and compared with the texel a hand derivation
// puts there (glTF's UVs as they are, with KHR_texture_transform applied; OBJ's vt flipped to the
// image's rows; map_Kd's -o/-s). A texture that cannot be used is a warning naming the file (the
// factor alone is used), an error in strict mode.
#include "engine/io/texture_io.h"

#include <gtest/gtest.h>

#include <cmath>
#include <nlohmann/json.hpp>
#include <numbers>
#include <string>
#include <vector>

#include "engine/io/gltf_io.h"
#include "engine/io/image_io.h"
#include "engine/io/obj_io.h"
#include "engine/io/scene_file.h"
#include "engine/scene/face_uv.h"
#include "tests/support/loader_test_support.h"

namespace penumbra {
namespace texture_io_test {

namespace fs = std::filesystem;
using Json = nlohmann::json;
using test::expectLoadError;
using test::putF32;
using test::putU16;

// The checker's texels, rows from the top: red, green / blue, grey 128.
const Vec3 kRed{1, 0, 0}, kGreen{0, 1, 0}, kBlue{0, 0, 1};
const double kGrey = 0.2158605;  // the linear value of sRGB byte 128 (IEC 61966-2-1's table)
const Vec3 kGreyTexel{kGrey, kGrey, kGrey};

std::string checkerPng() {
    const uint8_t texels[] = {255, 0, 0, 0, 255, 0, 0, 0, 255, 128, 128, 128};
    return encodePng(2, 2, 3, texels);
}

Vec3 times(const Vec3& a, const Vec3& b) { return {a.x * b.x, a.y * b.y, a.z * b.z}; }

void expectColour(const Vec3& got, const Vec3& want, const char* what) {
    EXPECT_NEAR(got.x, want.x, 1e-6) << what;
    EXPECT_NEAR(got.y, want.y, 1e-6) << what;
    EXPECT_NEAR(got.z, want.z, 1e-6) << what;
}

bool hasWarning(const Scene& s, std::initializer_list<std::string> keywords) {
    for (const std::string& w : s.warnings) {
        bool all = true;
        for (const std::string& k : keywords) all = all && w.find(k) != std::string::npos;
        if (all) return true;
    }
    return false;
}

std::string warnings(const Scene& s) {
    std::string all;
    for (const std::string& w : s.warnings) all += w + "\n";
    return all;
}

class TextureLoading : public test::LoaderFiles {};

TEST_F(TextureLoading, DecodesImagesAndSaysWhyNot) {
    const std::string png = checkerPng();
    const TextureRead ok = decodeTexture(
        std::span(reinterpret_cast<const unsigned char*>(png.data()), png.size()), "checker");
    ASSERT_TRUE(ok.image) << ok.problem;
    EXPECT_EQ(ok.image->width, 2);
    EXPECT_EQ(ok.image->height, 2);
    EXPECT_EQ(ok.image->srgb,
              (std::vector<uint8_t>{255, 0, 0, 0, 255, 0, 0, 0, 255, 128, 128, 128}));
    const TextureRead missing = readTextureFile(dir_ / "none.png");
    EXPECT_FALSE(missing.image);
    EXPECT_NE(missing.problem.find("No such file"), std::string::npos) << missing.problem;
    const TextureRead junk = readTextureFile(write("junk.png", "not an image at all"));
    EXPECT_FALSE(junk.image);
    EXPECT_NE(junk.problem.find("cannot decode"), std::string::npos) << junk.problem;
}

// ---- glTF ---------------------------------------------------------------------------------------

// A quad [0, 2]^2 at z = 0 (two triangles) with TEXCOORD_0 = (x, y) / 2.
std::string quadBuffer() {
    std::string b;
    for (const auto& p : {std::array<float, 3>{0, 0, 0}, {2, 0, 0}, {2, 2, 0}, {0, 2, 0}})
        for (float x : p) putF32(b, x);
    for (const auto& t : {std::array<float, 2>{0, 0}, {1, 0}, {1, 1}, {0, 1}})
        for (float x : t) putF32(b, x);
    for (uint16_t i : {0, 1, 2, 0, 2, 3}) putU16(b, i);
    return b;  // 48 + 32 + 12 = 92 bytes
}

Json quadGltf(const std::string& imageUri, bool texCoords = true) {
    Json g = Json::parse(R"({
      "asset": {"version": "2.0"},
      "extensionsUsed": ["KHR_texture_transform"],
      "scenes": [{"nodes": [0]}],
      "nodes": [{"mesh": 0}],
      "meshes": [{"primitives": [
        {"attributes": {"POSITION": 0, "TEXCOORD_0": 1}, "indices": 2, "material": 0}]}],
      "materials": [{"name": "checker", "pbrMetallicRoughness": {
        "baseColorFactor": [0.5, 0.6, 0.7, 1], "metallicFactor": 0,
        "baseColorTexture": {"index": 0}}}],
      "textures": [{"source": 0, "sampler": 0}],
      "samplers": [{"magFilter": 9728, "wrapS": 33071, "wrapT": 33648}],
      "accessors": [
        {"bufferView": 0, "componentType": 5126, "type": "VEC3", "count": 4,
         "min": [0, 0, 0], "max": [2, 2, 0]},
        {"bufferView": 1, "componentType": 5126, "type": "VEC2", "count": 4},
        {"bufferView": 2, "componentType": 5123, "type": "SCALAR", "count": 6}
      ],
      "bufferViews": [
        {"buffer": 0, "byteOffset": 0, "byteLength": 48},
        {"buffer": 0, "byteOffset": 48, "byteLength": 32},
        {"buffer": 0, "byteOffset": 80, "byteLength": 12}
      ],
      "buffers": [{"byteLength": 92}]
    })");
    g["images"] = Json::array({Json{{"uri", imageUri}}});
    g["buffers"][0]["uri"] = "data:application/octet-stream;base64," + test::base64(quadBuffer());
    if (!texCoords) g["meshes"][0]["primitives"][0]["attributes"].erase("TEXCOORD_0");
    return g;
}

const Vec3 kBase{0.5, 0.6, 0.7};

// Each quadrant of the quad shows one texel (magFilter NEAREST): points anywhere in it, not only
// at its centre. UV = (x, y) / 2 with v down the image: the quadrant at small x, small y shows
// texel (0, 0).
TEST_F(TextureLoading, GltfBaseColorTextureOverEachQuadrant) {
    write("checker.png", checkerPng());
    const Scene s = loadGltf(write("quad.gltf", quadGltf("checker.png").dump()));
    ASSERT_EQ(s.textures.size(), 1u) << warnings(s);
    EXPECT_TRUE(s.warnings.empty()) << warnings(s);
    const TextureRef& map = s.materials[0].kdMap;
    EXPECT_EQ(map.image, 0);
    EXPECT_EQ(map.filter, TextureFilter::Nearest);
    EXPECT_EQ(map.wrapU, TextureWrap::ClampToEdge);
    EXPECT_EQ(map.wrapV, TextureWrap::MirroredRepeat);
    ASSERT_EQ(s.faceUv.size(), 2u);
    // Face 0 is the triangle below the diagonal (y < x), face 1 the one above.
    expectColour(s.kdAt(1, {0.3, 0.8, 0}), times(kBase, kRed), "x < 1, y < 1");
    expectColour(s.kdAt(0, {0.9, 0.1, 0}), times(kBase, kRed), "x < 1, y < 1");
    expectColour(s.kdAt(0, {1.7, 0.2, 0}), times(kBase, kGreen), "x > 1, y < 1");
    expectColour(s.kdAt(1, {0.2, 1.9, 0}), times(kBase, kBlue), "x < 1, y > 1");
    expectColour(s.kdAt(1, {1.2, 1.6, 0}), times(kBase, kGreyTexel), "x > 1, y > 1");
}

// KHR_texture_transform offset (0, 1), rotation pi/2: u' = v, v' = 1 - u (texture.h), so the
// quadrant (x, y) < 1 reads uv (x, y) / 2 -> (y / 2, 1 - x / 2): texel (0, 1), blue; the pattern
// turns a quarter. From a data URI this time.
TEST_F(TextureLoading, GltfTextureTransformTurnsThePattern) {
    Json g = quadGltf("data:image/png;base64," + test::base64(checkerPng()));
    g["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"]["extensions"] = {
        {"KHR_texture_transform", {{"offset", {0, 1}}, {"rotation", std::numbers::pi / 2}}}};
    const Scene s = loadGltf(write("turned.gltf", g.dump()));
    ASSERT_EQ(s.textures.size(), 1u) << warnings(s);
    expectColour(s.kdAt(1, {0.3, 0.8, 0}), times(kBase, kBlue), "x < 1, y < 1");
    expectColour(s.kdAt(0, {1.7, 0.2, 0}), times(kBase, kRed), "x > 1, y < 1");
    expectColour(s.kdAt(1, {0.2, 1.9, 0}), times(kBase, kGreyTexel), "x < 1, y > 1");
    expectColour(s.kdAt(1, {1.2, 1.6, 0}), times(kBase, kGreen), "x > 1, y > 1");
    // A transform field of the wrong type is a broken file.
    g["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"]["extensions"]
     ["KHR_texture_transform"]["offset"] = "left";
    const fs::path bad = write("bad_transform.gltf", g.dump());
    expectLoadError([&] { loadGltf(bad); }, bad, {"KHR_texture_transform", "offset"});
}

TEST_F(TextureLoading, GltfTextureThatCannotBeUsedWarnsOrFailsStrict) {
    // The image file is missing: the factor alone, one warning naming the file.
    const fs::path missing = write("missing.gltf", quadGltf("absent.png").dump());
    const Scene s = loadGltf(missing);
    EXPECT_TRUE(s.textures.empty());
    EXPECT_FALSE(s.materials[0].kdMap.present());
    EXPECT_TRUE(hasWarning(s, {"absent.png", "No such file", "baseColorFactor alone"}))
        << warnings(s);
    expectColour(s.kdAt(1, {0.3, 0.8, 0}), kBase, "the factor");
    expectLoadError([&] { loadGltf(missing, LoadOptions::strictMode()); }, missing,
                    {"absent.png", "No such file", "strict mode refuses"});
    // Not an image.
    write("junk.png", "junk");
    const Scene junk = loadGltf(write("junk.gltf", quadGltf("junk.png").dump()));
    EXPECT_TRUE(hasWarning(junk, {"junk.png", "cannot decode"})) << warnings(junk);
    // No TEXCOORD_0 on the primitive.
    write("checker.png", checkerPng());
    const fs::path bare = write("bare.gltf", quadGltf("checker.png", false).dump());
    const Scene noUv = loadGltf(bare);
    EXPECT_TRUE(hasWarning(noUv, {"TEXCOORD_0", "baseColorFactor alone"})) << warnings(noUv);
    expectColour(noUv.kdAt(1, {0.3, 0.8, 0}), kBase, "the factor");
    expectLoadError([&] { loadGltf(bare, LoadOptions::strictMode()); }, bare, {"TEXCOORD_0"});
}

// ---- OBJ ----------------------------------------------------------------------------------------

// The quad [0, 2]^2 at z = 0 with vt = (x, y) / 2 (v up, as OBJ's), material "checker".
std::string quadObj() {
    return "mtllib quad.mtl\n"
           "v 0 0 0\nv 2 0 0\nv 2 2 0\nv 0 2 0\n"
           "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n"
           "usemtl checker\n"
           "f 1/1 2/2 3/3 4/4\n";
}

const Vec3 kKd{0.9, 0.8, 0.7};

// OBJ's v runs up: stored v = 1 - y / 2, so the quadrant at small x, large y shows the image's top
// left texel (red): the image upright. Bilinear, read at the texel centres, the quadrants' centres.
TEST_F(TextureLoading, ObjMapKdOverEachQuadrant) {
    write("tex/checker.png", checkerPng());
    write("quad.mtl", "newmtl checker\nKd 0.9 0.8 0.7\nmap_Kd tex/checker.png\n");
    const Scene s = loadObj(write("quad.obj", quadObj()));
    EXPECT_TRUE(s.warnings.empty()) << warnings(s);
    ASSERT_EQ(s.textures.size(), 1u);
    ASSERT_EQ(s.faceUv.size(), 1u);
    EXPECT_EQ(s.faceUv[0], (std::vector<Uv>{{0, 1}, {1, 1}, {1, 0}, {0, 0}}));
    EXPECT_EQ(s.materials[0].kdMap.filter, TextureFilter::Linear);
    expectColour(s.kdAt(0, {0.5, 1.5, 0}), times(kKd, kRed), "top left");
    expectColour(s.kdAt(0, {1.5, 1.5, 0}), times(kKd, kGreen), "top right");
    expectColour(s.kdAt(0, {0.5, 0.5, 0}), times(kKd, kBlue), "bottom left");
    expectColour(s.kdAt(0, {1.5, 0.5, 0}), times(kKd, kGreyTexel), "bottom right");
    // Between two texel centres (x = 1.5, y = 1: image v = 1/2, halfway down column 1): the mean
    // of green and grey.
    expectColour(s.kdAt(0, {1.5, 1.0, 0}), times(kKd, {kGrey / 2, (1 + kGrey) / 2, kGrey / 2}),
                 "between");
}

// map_Kd -s 0.5 0.5 -o 0.5 0: OBJ's (u, v) -> (u / 2 + 1/2, v / 2), so (1, 1) reads (3/4, 1/4 up
// = 3/4 down): the grey texel's centre; (1, 2) reads (3/4, 1/2): halfway between green and grey.
TEST_F(TextureLoading, ObjMapKdOffsetAndScale) {
    write("checker.png", checkerPng());
    write("quad.mtl",
          "newmtl checker\nKd 0.9 0.8 0.7\nmap_Kd -blendu off -s 0.5 0.5 -o 0.5 0 checker.png\n");
    const Scene s = loadObj(write("quad.obj", quadObj()));
    EXPECT_TRUE(s.warnings.empty()) << warnings(s);
    expectColour(s.kdAt(0, {1, 1, 0}), times(kKd, kGreyTexel), "(1, 1)");
    expectColour(s.kdAt(0, {1, 2, 0}), times(kKd, {kGrey / 2, (1 + kGrey) / 2, kGrey / 2}),
                 "(1, 2)");
}

TEST_F(TextureLoading, ObjMapKdThatCannotBeUsedWarnsOrFailsStrict) {
    const fs::path mtl = write("quad.mtl", "newmtl checker\nKd 0.9 0.8 0.7\nmap_Kd gone.png\n");
    const fs::path obj = write("quad.obj", quadObj());
    const Scene s = loadObj(obj);
    EXPECT_TRUE(s.textures.empty());
    EXPECT_TRUE(hasWarning(s, {"quad.mtl:3", "gone.png", "No such file", "Kd alone"}))
        << warnings(s);
    expectColour(s.kdAt(0, {0.5, 1.5, 0}), kKd, "the factor");
    expectLoadError([&] { loadObj(obj, LoadOptions::strictMode()); }, mtl, {"gone.png"});
    // A face of the textured material without vt: the factor, with a warning.
    write("checker.png", checkerPng());
    write("quad.mtl", "newmtl checker\nKd 0.9 0.8 0.7\nmap_Kd checker.png\n");
    const fs::path plain =
        write("plain.obj", "mtllib quad.mtl\nv 0 0 0\nv 2 0 0\nv 2 2 0\nusemtl checker\nf 1 2 3\n");
    const Scene noVt = loadObj(plain);
    EXPECT_TRUE(hasWarning(noVt, {"no texture coordinates", "line 6"})) << warnings(noVt);
    expectLoadError([&] { loadObj(plain, LoadOptions::strictMode()); }, plain,
                    {"no texture coordinates"});
    // A vt index beyond the file's: an error at the face's line.
    const fs::path beyond =
        write("beyond.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nf 1/1 2/2 3/1\n");
    expectLoadError([&] { loadObj(beyond); }, beyond, {"texture index 2 out of range"});
}

// A non-convex textured face is split into triangles of its own vertices: each corner keeps its
// vertex's texture coordinates.
TEST_F(TextureLoading, SplitFacesKeepTheirCornersCoordinates) {
    write("checker.png", checkerPng());
    write("l.mtl", "newmtl checker\nmap_Kd checker.png\n");
    const Scene s =
        loadObj(write("l.obj",
                      "mtllib l.mtl\nv 0 0 0\nv 2 0 0\nv 2 1 0\nv 1 1 0\nv 1 2 0\nv 0 2 0\n"
                      "vt 0 0\nvt 1 0\nvt 1 0.5\nvt 0.5 0.5\nvt 0.5 1\nvt 0 1\nusemtl checker\n"
                      "f 1/1 2/2 3/3 4/4 5/5 6/6\n"));
    ASSERT_EQ(s.faceCount(), 4u);  // the hexagon in 4 triangles
    ASSERT_EQ(s.faceUv.size(), 4u);
    for (uint32_t f = 0; f < s.faceCount(); ++f) {
        ASSERT_EQ(s.faceUv[f].size(), 3u);
        for (size_t k = 0; k < 3; ++k) {
            const Vec3 p = s.mesh.vertices[s.mesh.faces[f][k]];
            EXPECT_EQ(s.faceUv[f][k], (Uv{p.x / 2, 1 - p.y / 2}))
                << "face " << f << " corner " << k;
        }
    }
}

// ---- JSON scenes --------------------------------------------------------------------------------

// A mirrored mesh keeps its texture where it was on each face (its corners' coordinates reversed
// with its vertices); the textures of two meshes are both kept, each material pointing at its own.
TEST_F(TextureLoading, JsonSceneComposesAndMirrorsTexturedMeshes) {
    write("checker.png", checkerPng());
    write("quad.mtl", "newmtl checker\nKd 0.9 0.8 0.7\nmap_Kd checker.png\n");
    write("quad.obj", quadObj());
    const Scene s = loadJsonScene(write("scene.json", R"({"meshes": [
        {"file": "quad.obj"},
        {"file": "quad.obj", "transform": [{"scale": [-1, 1, 1]}, {"translate": [0, 0, 1]}]}],
      "polygons": [{"vertices": [[5, 0, 0], [6, 0, 0], [6, 1, 0]]}]})"));
    EXPECT_TRUE(s.warnings.empty()) << warnings(s);
    ASSERT_EQ(s.faceCount(), 3u);
    ASSERT_EQ(s.textures.size(), 2u);
    EXPECT_EQ(s.materials[0].kdMap.image, 0);
    EXPECT_EQ(s.materials[1].kdMap.image, 1);
    ASSERT_EQ(s.faceUv.size(), 3u);
    EXPECT_TRUE(s.faceUv[2].empty());
    for (uint32_t f = 0; f < 2; ++f) {
        for (size_t k = 0; k < 4; ++k) {
            const Vec3 p = s.mesh.vertices[s.mesh.faces[f][k]];
            EXPECT_EQ(s.faceUv[f][k], (Uv{std::fabs(p.x) / 2, 1 - p.y / 2}));
        }
    }
    expectColour(s.kdAt(1, {-0.5, 1.5, 1}), times(kKd, kRed), "mirrored top left");
    expectColour(s.kdAt(1, {-1.5, 0.5, 1}), times(kKd, kGreyTexel), "mirrored bottom right");
}

}  // namespace texture_io_test
}  // namespace penumbra
