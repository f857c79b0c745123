// Tests of the glTF reader (engine/io/gltf_io.h) on small .gltf (embedded base64 buffer) and .glb
// files built here; positions, materials, lights and the camera are checked against values derived
// by hand from what was written.
#include "engine/io/gltf_io.h"

#include <gtest/gtest.h>
#include <sys/stat.h>

#include <cmath>
#include <limits>
#include <nlohmann/json.hpp>
#include <numbers>
#include <string>
#include <utility>
#include <vector>

#include "tests/support/loader_test_support.h"
#include "tests/support/test_files.h"

namespace penumbra {
namespace {

namespace fs = std::filesystem;
using Json = nlohmann::json;
using test::expectLoadError;
using test::putF32;
using test::putU16;
using test::putU32;

// The buffer: a unit quad at z=0 (4 positions, 6 UNSIGNED_SHORT indices) and a non-indexed
// triangle at z=1 (3 positions).
std::string testBuffer(float nan = 0, uint16_t lastIndex = 3) {
    std::string b;
    const float quad[4][3] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, nan}};
    for (const auto& p : quad)
        for (float x : p) putF32(b, x);
    for (uint16_t i : {0, 1, 2, 0, 2}) putU16(b, i);
    putU16(b, lastIndex);
    const float tri[3][3] = {{0, 0, 1}, {1, 0, 1}, {0, 1, 1}};
    for (const auto& p : tri)
        for (float x : p) putF32(b, x);
    return b;  // 96 bytes
}

Json testGltf() {
    return Json::parse(R"({
      "asset": {"version": "2.0"},
      "extensionsUsed": ["KHR_materials_emissive_strength"],
      "scene": 0,
      "scenes": [{"nodes": [0, 2]}],
      "nodes": [
        {"translation": [10, 0, 0], "children": [1]},
        {"scale": [2, 2, 2], "mesh": 0},
        {"translation": [0, 0, 5], "camera": 0}
      ],
      "cameras": [{"type": "perspective", "perspective": {"yfov": 0.5, "znear": 0.1}}],
      "meshes": [{"primitives": [
        {"attributes": {"POSITION": 0}, "indices": 1, "material": 0},
        {"attributes": {"POSITION": 2}, "material": 1}
      ]}],
      "materials": [
        {"name": "clay", "pbrMetallicRoughness": {"baseColorFactor": [0.8, 0.6, 0.4, 1],
                                                  "metallicFactor": 0.25, "roughnessFactor": 0.5}},
        {"name": "lamp", "emissiveFactor": [1, 0.5, 0.25],
         "pbrMetallicRoughness": {"metallicFactor": 0, "roughnessFactor": 1},
         "extensions": {"KHR_materials_emissive_strength": {"emissiveStrength": 4}}}
      ],
      "accessors": [
        {"bufferView": 0, "componentType": 5126, "type": "VEC3", "count": 4,
         "min": [0, 0, 0], "max": [1, 1, 0]},
        {"bufferView": 1, "componentType": 5123, "type": "SCALAR", "count": 6},
        {"bufferView": 2, "componentType": 5126, "type": "VEC3", "count": 3,
         "min": [0, 0, 1], "max": [1, 1, 1]}
      ],
      "bufferViews": [
        {"buffer": 0, "byteOffset": 0, "byteLength": 48},
        {"buffer": 0, "byteOffset": 48, "byteLength": 12},
        {"buffer": 0, "byteOffset": 60, "byteLength": 36}
      ],
      "buffers": [{"byteLength": 96}]
    })");
}

std::string embedded(Json g, const std::string& buffer) {
    g["buffers"][0]["uri"] = "data:application/octet-stream;base64," + test::base64(buffer);
    return g.dump(1);
}

std::string glb(const Json& g, const std::string& buffer) {
    std::string json = g.dump();
    while (json.size() % 4) json += ' ';
    std::string bin = buffer;
    while (bin.size() % 4) bin += '\0';
    std::string out = "glTF";
    putU32(out, 2);
    putU32(out, static_cast<uint32_t>(12 + 8 + json.size() + 8 + bin.size()));
    putU32(out, static_cast<uint32_t>(json.size()));
    out += "JSON";
    out += json;
    putU32(out, static_cast<uint32_t>(bin.size()));
    out += std::string("BIN\0", 4);
    out += bin;
    return out;
}

using test::expectNear;

// Node 0 translates by (10,0,0), its child node 1 scales by 2: p -> (10,0,0) + 2p.
void expectTestScene(const Scene& scene) {
    const std::vector<Vec3> vertices = {{10, 0, 0}, {12, 0, 0}, {12, 2, 0}, {10, 2, 0},
                                        {10, 0, 2}, {12, 0, 2}, {10, 2, 2}};
    EXPECT_EQ(scene.mesh.vertices, vertices);
    const std::vector<std::vector<uint32_t>> faces = {{0, 1, 2}, {0, 2, 3}, {4, 5, 6}};
    EXPECT_EQ(scene.mesh.faces, faces);
    EXPECT_EQ(scene.faceMaterial, (std::vector<int32_t>{0, 0, 1}));
    EXPECT_EQ(scene.lights, (std::vector<uint32_t>{2}));
    ASSERT_EQ(scene.materials.size(), 2u);
    // kd = base (1 - metallic), ks = mix(0.04, base, metallic), ns = 2 / roughness^4 - 2.
    const Material& clay = scene.materials[0];
    EXPECT_EQ(clay.name, "clay");
    expectNear(clay.kd, {0.6, 0.45, 0.3});
    expectNear(clay.ks, {0.23, 0.18, 0.13});
    EXPECT_NEAR(clay.ns, 30, 1e-9);
    EXPECT_FALSE(clay.isEmissive());
    const Material& lamp = scene.materials[1];
    expectNear(lamp.ke, {4, 2, 1});
    expectNear(lamp.kd, {1, 1, 1});
    expectNear(lamp.ks, {0.04, 0.04, 0.04});
    EXPECT_NEAR(lamp.ns, 0, 1e-12);
    ASSERT_TRUE(scene.camera.has_value());
    expectNear(scene.camera->eye, {0, 0, 5});
    expectNear(scene.camera->target, {0, 0, 4});
    expectNear(scene.camera->up, {0, 1, 0});
    EXPECT_NEAR(scene.camera->fovYDegrees, 0.5 * 180 / std::numbers::pi, 1e-12);
}

class GltfIo : public test::LoaderFiles {};

TEST_F(GltfIo, EmbeddedBuffer) {
    expectTestScene(loadGltf(write("scene.gltf", embedded(testGltf(), testBuffer()))));
}

TEST_F(GltfIo, Glb) {
    expectTestScene(loadGltf(write("scene.glb", glb(testGltf(), testBuffer()))));
}

TEST_F(GltfIo, ExternalBuffer) {
    write("data/scene.bin", testBuffer());
    Json g = testGltf();
    g["buffers"][0]["uri"] = "scene.bin";
    expectTestScene(loadGltf(write("data/scene.gltf", g.dump())));
}

TEST_F(GltfIo, MatrixTransform) {
    Json g = testGltf();
    // Column-major: scale 2 and translation (1, 2, 3); the parent adds (10, 0, 0).
    g["nodes"][1] = Json::parse(R"({"mesh": 0, "matrix": [2,0,0,0, 0,2,0,0, 0,0,2,0, 1,2,3,1]})");
    const Scene scene = loadGltf(write("m.gltf", embedded(g, testBuffer())));
    EXPECT_EQ(scene.mesh.vertices[0], Vec3(11, 2, 3));
    EXPECT_EQ(scene.mesh.vertices[2], Vec3(13, 4, 3));
    EXPECT_EQ(scene.mesh.vertices[6], Vec3(11, 4, 5));
}

TEST_F(GltfIo, MirrorReversesWinding) {
    Json g = testGltf();
    g["nodes"][1]["scale"] = {-2, 2, 2};
    const Scene scene = loadGltf(write("mirror.gltf", embedded(g, testBuffer())));
    EXPECT_EQ(scene.mesh.vertices[1], Vec3(8, 0, 0));
    const std::vector<std::vector<uint32_t>> faces = {{0, 2, 1}, {0, 3, 2}, {4, 6, 5}};
    EXPECT_EQ(scene.mesh.faces, faces);
    // The quad faced +z before the mirror x -> -x and still does.
    EXPECT_GT(scene.mesh.faceAreaNormal(0).z, 0);
    EXPECT_GT(scene.mesh.faceAreaNormal(1).z, 0);
}

TEST_F(GltfIo, RotationQuaternion) {
    Json g = testGltf();
    // 90 degrees about +z: (x, y, z) -> (-y, x, z); then the parent's translation.
    const double h = std::sqrt(0.5);
    g["nodes"][1] = Json{{"mesh", 0}, {"rotation", {0, 0, h, h}}};
    const Scene scene = loadGltf(write("rot.gltf", embedded(g, testBuffer())));
    expectNear(scene.mesh.vertices[1], {10, 1, 0});
    expectNear(scene.mesh.vertices[2], {9, 1, 0});
}

// A URI naming a directory (seeking to its end reports 2^63 - 1 bytes: tinygltf's own reader asked
// for that much memory, a fuzzing finding), a pipe, a missing or an empty file is an error naming
// the file and why; an image's URI is only ignored, since images are not used.
TEST_F(GltfIo, ExternalBufferThatIsNotARegularFileIsAnError) {
    write("data/empty.bin", "");
    const fs::path fifo = dir_ / "data" / "fifo";
    ASSERT_EQ(mkfifo(fifo.c_str(), 0600), 0);
    const std::vector<std::pair<std::string, std::string>> cases = {
        {".", "data/. : not a regular file"},
        {"..", "data/.. : not a regular file"},
        {"fifo", "data/fifo : not a regular file"},
        {"empty.bin", "data/empty.bin : empty file"},
        {"missing.bin", "not found : missing.bin"}};
    for (const auto& [uri, why] : cases) {
        SCOPED_TRACE(uri);
        Json g = testGltf();
        g["buffers"][0]["uri"] = uri;
        const fs::path p = write("data/uri.gltf", g.dump());
        expectLoadError([&] { loadGltf(p); }, p, {why});
    }
    Json g = testGltf();
    g["images"] = Json::array({Json{{"uri", "."}}, Json{{"uri", "fifo"}}});
    expectTestScene(loadGltf(write("data/images.gltf", embedded(g, testBuffer()))));
}

TEST_F(GltfIo, IndexOutOfRangeIsAnError) {
    const fs::path p = write("range.gltf", embedded(testGltf(), testBuffer(0, 9)));
    expectLoadError([&] { loadGltf(p); }, p, {"mesh 0 primitive 0", "index 5", "out of range"});
}

TEST_F(GltfIo, AccessorPastItsBufferViewIsAnError) {
    Json g = testGltf();
    g["accessors"][0]["count"] = 5;
    const fs::path p = write("count.gltf", embedded(g, testBuffer()));
    expectLoadError([&] { loadGltf(p); }, p, {"accessor 0", "past the end"});
    Json h = testGltf();
    h["bufferViews"][2]["byteLength"] = 400;
    const fs::path q = write("view.gltf", embedded(h, testBuffer()));
    expectLoadError([&] { loadGltf(q); }, q, {});
    Json k = testGltf();
    k["accessors"][1]["componentType"] = 5126;
    const fs::path r = write("type.gltf", embedded(k, testBuffer()));
    expectLoadError([&] { loadGltf(r); }, r, {"indices"});
}

TEST_F(GltfIo, NonFinitePositionIsAnError) {
    const fs::path p = write(
        "nan.gltf", embedded(testGltf(), testBuffer(std::numeric_limits<float>::quiet_NaN())));
    expectLoadError([&] { loadGltf(p); }, p, {"POSITION 3", "non-finite"});
}

TEST_F(GltfIo, MalformedAndTruncatedFilesAreErrors) {
    const std::string text = embedded(testGltf(), testBuffer());
    const fs::path p = write("cut.gltf", text.substr(0, text.size() / 2));
    expectLoadError([&] { loadGltf(p); }, p, {"glTF"});
    const std::string bin = glb(testGltf(), testBuffer());
    for (size_t cut : {size_t{20}, bin.size() / 2, bin.size() - 12}) {
        const fs::path q = write("cut" + std::to_string(cut) + ".glb", bin.substr(0, cut));
        expectLoadError([&] { loadGltf(q); }, q, {});
    }
    const fs::path e = write("empty.gltf", "");
    expectLoadError([&] { loadGltf(e); }, e, {"empty"});
    Json g = testGltf();
    g["nodes"][1]["children"] = {0};  // a cycle
    const fs::path c = write("cycle.gltf", embedded(g, testBuffer()));
    expectLoadError([&] { loadGltf(c); }, c, {"reached twice"});
    Json m = testGltf();
    m["nodes"][1]["mesh"] = 7;
    const fs::path n = write("mesh.gltf", embedded(m, testBuffer()));
    expectLoadError([&] { loadGltf(n); }, n, {});
}

TEST_F(GltfIo, DegenerateTriangleIsDroppedByDefaultAndNamedWhenStrict) {
    Json g = testGltf();
    // The second quad triangle (0, 2, 2) repeats a vertex.
    for (const bool binary : {false, true}) {
        const fs::path p = binary ? write("deg.glb", glb(g, testBuffer(0, 2)))
                                  : write("deg.gltf", embedded(g, testBuffer(0, 2)));
        expectLoadError([&] { loadGltf(p, LoadOptions::strictMode()); }, p,
                        {"node 1 mesh 0 primitive 0 triangle 1", "repeated"});
        const Scene scene = loadGltf(p);
        EXPECT_EQ(scene.mesh.faces, (std::vector<std::vector<uint32_t>>{{0, 1, 2}, {4, 5, 6}}));
        EXPECT_EQ(scene.faceMaterial, (std::vector<int32_t>{0, 1}));
        EXPECT_EQ(scene.lights, (std::vector<uint32_t>{1}));
        ASSERT_EQ(scene.warnings.size(), 1u);
        EXPECT_NE(scene.warnings[0].find(p.string() + ": dropped 1 degenerate"), std::string::npos)
            << scene.warnings[0];
        EXPECT_NE(scene.warnings[0].find("node 1 mesh 0 primitive 0 triangle 1"), std::string::npos)
            << scene.warnings[0];
    }
}

// glTF 1.0, unsupported versions and required extensions are refused with a message that says what
// is unsupported, before tinygltf misreports them.
TEST_F(GltfIo, GltfOneIsRefusedSayingSo) {
    // asset.version "1.0" with 1.0's dictionaries.
    const Json v1 = Json::parse(R"({
      "asset": {"version": "1.0"},
      "meshes": {"mesh0": {"primitives": [{"attributes": {"POSITION": "acc0"}, "mode": 4}]}},
      "accessors": {"acc0": {"bufferView": "bv0", "componentType": 5126, "type": "VEC3",
                             "count": 3}}
    })");
    const fs::path a = write("v1.gltf", v1.dump());
    expectLoadError([&] { loadGltf(a); }, a,
                    {"glTF 1.0 is not supported (asset.version \"1.0\"); only glTF 2.0 is"});
    // No asset object: the dictionaries say 1.0.
    Json noAsset = v1;
    noAsset.erase("asset");
    const fs::path b = write("v1_noasset.gltf", noAsset.dump());
    expectLoadError([&] { loadGltf(b); }, b,
                    {"glTF 1.0 is not supported (\"meshes\" is a dictionary", "only glTF 2.0 is"});
    // A binary glTF 1.0 (GLB version 1).
    std::string glb1 = "glTF";
    putU32(glb1, 1);
    putU32(glb1, 20);
    putU32(glb1, 0);
    putU32(glb1, 0);
    const fs::path c = write("v1.glb", glb1);
    expectLoadError([&] { loadGltf(c); }, c, {"GLB version 1", "glTF 1.0", "only glTF 2.0 is"});
    // A version from the future.
    Json v3 = testGltf();
    v3["asset"]["version"] = "3.0";
    const fs::path d = write("v3.gltf", embedded(v3, testBuffer()));
    expectLoadError([&] { loadGltf(d); }, d, {"glTF version \"3.0\" is not supported"});
    // 2.x minor versions are 2.0's.
    Json v21 = testGltf();
    v21["asset"]["version"] = "2.1";
    expectTestScene(loadGltf(write("v21.gltf", embedded(v21, testBuffer()))));
}

TEST_F(GltfIo, DracoAndUnknownRequiredExtensionsAreRefusedByName) {
    // Draco required: the primitive's accessors have no buffer view (the data is compressed).
    Json draco = testGltf();
    draco["extensionsUsed"].push_back("KHR_draco_mesh_compression");
    draco["extensionsRequired"] = {"KHR_draco_mesh_compression"};
    draco["meshes"][0]["primitives"][0]["extensions"] = {
        {"KHR_draco_mesh_compression", {{"bufferView", 0}, {"attributes", {{"POSITION", 0}}}}}};
    draco["accessors"][0].erase("bufferView");
    for (const bool binary : {false, true}) {
        const fs::path p = binary ? write("draco.glb", glb(draco, testBuffer()))
                                  : write("draco.gltf", embedded(draco, testBuffer()));
        expectLoadError([&] { loadGltf(p); }, p,
                        {"required extension KHR_draco_mesh_compression",
                         "Draco-compressed meshes are not supported"});
    }
    // Draco used, not required, without the uncompressed fallback: refused naming the primitive.
    Json optional = draco;
    optional.erase("extensionsRequired");
    const fs::path q = write("draco_used.gltf", embedded(optional, testBuffer()));
    expectLoadError([&] { loadGltf(q); }, q,
                    {"mesh 0 primitive 0: compressed with KHR_draco_mesh_compression"});
    // With the fallback (POSITION keeps its buffer view), the uncompressed data loads.
    Json fallback = optional;
    fallback["accessors"][0]["bufferView"] = 0;
    expectTestScene(loadGltf(write("draco_fallback.gltf", embedded(fallback, testBuffer()))));
    // Any other required extension the loader does not implement is named.
    Json quantized = testGltf();
    quantized["extensionsRequired"] = {"KHR_materials_emissive_strength", "KHR_mesh_quantization"};
    const fs::path r = write("quantized.gltf", embedded(quantized, testBuffer()));
    expectLoadError([&] { loadGltf(r); }, r,
                    {"required extension \"KHR_mesh_quantization\" is not supported (supported: "
                     "KHR_materials_emissive_strength"});
    // Required extensions it implements or whose content it never reads are fine.
    Json fine = testGltf();
    fine["extensionsRequired"] = {"KHR_materials_emissive_strength", "KHR_texture_transform"};
    expectTestScene(loadGltf(write("fine.gltf", embedded(fine, testBuffer()))));
}

}  // namespace
}  // namespace penumbra
