// Corrupted and truncated files of every format the loaders read: each load either succeeds or
// throws SceneError naming the file; never a crash, a hang or another exception type.
#include <gtest/gtest.h>

#include <random>
#include <string>
#include <vector>

#include "engine/io/scene_loader.h"
#include "tests/support/loader_test_support.h"
#include "tests/support/test_scale.h"

namespace penumbra {
namespace {

namespace fs = std::filesystem;

class LoaderCorruption : public test::LoaderFiles {
  protected:
    // Loads `bytes` written as `name`; a failure must be a SceneError about that file.
    void loadSurvives(const std::string& name, const std::string& bytes, const std::string& what) {
        const fs::path p = write(name, bytes);
        try {
            (void)loadScene(p);
        } catch (const SceneError& e) {
            EXPECT_EQ(e.file, p.string()) << what << ": " << e.what();
        } catch (const std::exception& e) {
            ADD_FAILURE() << what << ": not a SceneError: " << e.what();
        }
    }

    // Truncations at every length up to 64 bytes and at random ones, and random byte changes.
    void corrupt(const std::string& name, const std::string& good) {
        std::mt19937 random(12345);
        for (size_t n = 0; n < std::min<size_t>(good.size(), 64); ++n)
            loadSurvives(name, good.substr(0, n), name + " cut to " + std::to_string(n));
        const int rounds = test::scaled(60);
        for (int r = 0; r < rounds; ++r) {
            const size_t n = random() % good.size();
            loadSurvives(name, good.substr(0, n), name + " cut to " + std::to_string(n));
            std::string bad = good;
            const int changes = 1 + static_cast<int>(random() % 4);
            for (int c = 0; c < changes; ++c) {
                const size_t at = random() % bad.size();
                bad[at] = static_cast<char>(random() % 3 == 0 ? bad[at] ^ 0x80 : random() % 256);
            }
            loadSurvives(name, bad, name + " corruption " + std::to_string(r));
        }
    }
};

std::string binaryPly() {
    std::string s =
        "ply\nformat binary_little_endian 1.0\nelement vertex 4\nproperty float x\n"
        "property float y\nproperty float z\nelement face 2\n"
        "property list uchar int vertex_indices\nend_header\n";
    const float v[4][3] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
    for (const auto& p : v)
        for (float x : p) test::putF32(s, x);
    const uint32_t faces[2][3] = {{0, 1, 2}, {0, 2, 3}};
    for (const auto& f : faces) {
        test::putU8(s, 3);
        for (uint32_t i : f) test::putU32(s, i);
    }
    return s;
}

std::string binaryStl() {
    std::string s(80, ' ');
    test::putU32(s, 2);
    const float t[2][9] = {{0, 0, 0, 1, 0, 0, 1, 1, 0}, {0, 0, 0, 1, 1, 0, 0, 1, 0}};
    for (const auto& tri : t) {
        for (int k = 0; k < 3; ++k) test::putF32(s, k == 2 ? 1.0f : 0.0f);
        for (float x : tri) test::putF32(s, x);
        s += std::string(2, '\0');
    }
    return s;
}

std::string glb() {
    std::string bin;
    const float v[3][3] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    for (const auto& p : v)
        for (float x : p) test::putF32(bin, x);
    for (uint16_t i : {0, 1, 2, 0}) test::putU16(bin, i);  // 3 indices + padding
    std::string json =
        R"({"asset":{"version":"2.0"},"scenes":[{"nodes":[0]}],"nodes":[{"mesh":0}],)"
        R"("meshes":[{"primitives":[{"attributes":{"POSITION":0},"indices":1}]}],)"
        R"("accessors":[{"bufferView":0,"componentType":5126,"type":"VEC3","count":3,)"
        R"("min":[0,0,0],"max":[1,1,0]},)"
        R"({"bufferView":1,"componentType":5123,"type":"SCALAR","count":3}],)"
        R"("bufferViews":[{"buffer":0,"byteOffset":0,"byteLength":36},)"
        R"({"buffer":0,"byteOffset":36,"byteLength":6}],"buffers":[{"byteLength":44}]})";
    while (json.size() % 4) json += ' ';
    std::string out = "glTF";
    test::putU32(out, 2);
    test::putU32(out, static_cast<uint32_t>(12 + 8 + json.size() + 8 + bin.size()));
    test::putU32(out, static_cast<uint32_t>(json.size()));
    out += "JSON" + json;
    test::putU32(out, static_cast<uint32_t>(bin.size()));
    out += std::string("BIN\0", 4) + bin;
    return out;
}

TEST_F(LoaderCorruption, BinaryPly) { corrupt("c.ply", binaryPly()); }

TEST_F(LoaderCorruption, AsciiPly) {
    corrupt("c.ply",
            "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\n"
            "property float z\nelement face 2\nproperty list uchar int vertex_indices\n"
            "end_header\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n3 0 1 2\n3 0 2 3\n");
}

TEST_F(LoaderCorruption, Off) {
    corrupt("c.off", "OFF\n4 2 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n3 0 1 2\n3 0 2 3\n");
}

TEST_F(LoaderCorruption, BinaryStl) { corrupt("c.stl", binaryStl()); }

TEST_F(LoaderCorruption, AsciiStl) {
    corrupt("c.stl",
            "solid s\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 1 1 0\n"
            "endloop\nendfacet\nendsolid s\n");
}

TEST_F(LoaderCorruption, Glb) { corrupt("c.glb", glb()); }

TEST_F(LoaderCorruption, Json) {
    write("m.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n");
    corrupt("c.json", R"({"meshes": [{"file": "m.off", "transform": {"scale": [1, 2, 3]}}],)"
                      R"( "area_lights": [{"vertices": [[0,0,1],[0,1,1],[1,0,1]], "emission": 1}],)"
                      R"( "camera": {"eye": [0,0,5], "target": [0,0,0]}})");
}

}  // namespace
}  // namespace penumbra
