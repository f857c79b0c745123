// Corrupted and truncated files of every format the loaders read. Never a crash, a hang or another
// exception type, and corruption is reported, not swallowed:
//   - a truncation that removes data the file declares (a binary header's sizes and counts, an
//     ASCII PLY or OFF header's counts, a GLB's chunk lengths, a JSON document's closing brace, an
//     ASCII STL's endsolid) is a SceneError naming the file, with a reason;
//   - a truncation that removes only trailing white space loads the whole scene;
//   - an OBJ declares no counts: cut after a complete statement it may load, but only a prefix of
//     the original (no more faces or vertices, the faces before the last one unchanged), and a
//     scene that passes validation;
//   - random byte changes: a SceneError naming the file, or a scene that passes validation.
// Every format must reject some of its corruptions (counted), and the uncorrupted file must load:
// the test cannot pass by accepting, or by rejecting, everything.
#include <gtest/gtest.h>

#include <cctype>
#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "engine/io/scene_loader.h"
#include "engine/scene/scene_validation.h"
#include "tests/support/loader_test_support.h"
#include "tests/support/test_scale.h"

namespace penumbra {
namespace {

namespace fs = std::filesystem;

// Where a format stops declaring data: cuts shorter than `complete` bytes must be rejected, cuts
// at or beyond it (trailing white space only) must load the whole scene. npos: the format
// declares nothing (OBJ), a cut may load a prefix of the scene.
struct Declared {
    size_t complete = std::string::npos;
};

// The length without trailing white space: what an ASCII format with counts needs in full.
size_t withoutTrailingSpace(const std::string& s) {
    size_t n = s.size();
    while (n > 0 && std::isspace(static_cast<unsigned char>(s[n - 1]))) --n;
    return n;
}

class LoaderCorruption : public test::LoaderFiles {
  protected:
    // The outcome of one load: the scene, or the error (checked to be a SceneError about the
    // file with a reason).
    struct Outcome {
        bool threw = false;
        Scene scene;
    };

    Outcome load(const fs::path& p, const std::string& what) {
        Outcome o;
        try {
            o.scene = loadScene(p);
        } catch (const SceneError& e) {
            o.threw = true;
            EXPECT_EQ(e.file, p.string()) << what << ": " << e.what();
            EXPECT_NE(e.message.find_first_not_of(" \t\n"), std::string::npos)
                << what << ": no reason given: " << e.what();
            EXPECT_EQ(std::string(e.what()).rfind(p.string(), 0), 0u)
                << what << ": the message does not start with the file: " << e.what();
        } catch (const std::exception& e) {
            o.threw = true;
            ADD_FAILURE() << what << ": not a SceneError: " << e.what();
        }
        return o;
    }

    // A scene that loaded from a corrupted file must still meet the scene contract.
    static void expectValid(const Scene& s, const std::string& what) {
        try {
            validateScene(s);
        } catch (const SceneError& e) {
            ADD_FAILURE() << what << ": loaded a scene that fails validation: " << e.what();
        }
        for (const Vec3& v : s.mesh.vertices)
            EXPECT_TRUE(std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z)) << what;
    }

    // Every truncation, then random byte changes; some of each must be rejected.
    void corrupt(const std::string& name, const std::string& good, Declared declared) {
        const Outcome original = load(write(name, good), name + " uncorrupted");
        ASSERT_FALSE(original.threw) << name << ": the uncorrupted file must load";
        const vis::PolygonMesh& full = original.scene.mesh;
        ASSERT_GT(full.faces.size(), 0u);

        // Truncations: every length in the first and the last 64 bytes (the headers, and where
        // the declared data ends), and random lengths between.
        std::mt19937 random(12345);
        std::vector<size_t> lengths;
        for (size_t n = 0; n < good.size(); ++n)
            if (n < 64 || n + 64 >= good.size()) lengths.push_back(n);
        for (int r = 0; r < test::scaled(50); ++r) lengths.push_back(random() % good.size());
        int cutsRejected = 0;
        for (size_t n : lengths) {
            const std::string what = name + " cut to " + std::to_string(n) + " of " +
                                     std::to_string(good.size()) + " bytes";
            const Outcome o = load(write(name, good.substr(0, n)), what);
            cutsRejected += o.threw;
            if (declared.complete != std::string::npos) {
                if (n < declared.complete) {
                    EXPECT_TRUE(o.threw) << what << ": data the file declares is missing, yet it "
                                         << "loaded " << o.scene.faceCount() << " faces";
                } else {
                    EXPECT_FALSE(o.threw) << what << ": only trailing white space is missing";
                    if (!o.threw) {
                        EXPECT_EQ(o.scene.mesh.faces, full.faces) << what;
                        EXPECT_TRUE(o.scene.mesh.vertices == full.vertices) << what;
                    }
                }
                continue;
            }
            if (o.threw) continue;
            // No declared counts: what loads is a prefix of the original.
            const vis::PolygonMesh& m = o.scene.mesh;
            EXPECT_LE(m.faces.size(), full.faces.size()) << what;
            EXPECT_LE(m.vertices.size(), full.vertices.size()) << what;
            for (size_t f = 0; f + 1 < std::min(m.faces.size(), full.faces.size()); ++f)
                EXPECT_EQ(m.faces[f], full.faces[f]) << what << ": face " << f;
            expectValid(o.scene, what);
        }
        EXPECT_GT(cutsRejected, 0) << name << ": no truncation was rejected";

        // Random byte changes: reported, or a valid scene.
        int changesRejected = 0;
        const int rounds = test::scaled(100);
        for (int r = 0; r < rounds; ++r) {
            std::string bad = good;
            const int changes = 1 + static_cast<int>(random() % 4);
            for (int c = 0; c < changes; ++c) {
                const size_t at = random() % bad.size();
                bad[at] = static_cast<char>(random() % 3 == 0 ? bad[at] ^ 0x80 : random() % 256);
            }
            const std::string what = name + " corruption " + std::to_string(r);
            const Outcome o = load(write(name, bad), what);
            changesRejected += o.threw;
            if (!o.threw) expectValid(o.scene, what);
        }
        EXPECT_GT(changesRejected, 0) << name << ": no byte change was rejected";
    }
};

std::string intactBinaryPly() {
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

std::string intactBinaryStl() {
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

std::string intactGlb() {
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

// Binary formats: the header declares every byte (PLY: counts and types; STL: the triangle count;
// GLB: the total and chunk lengths), so every cut is missing declared data.
TEST_F(LoaderCorruption, BinaryPly) {
    const std::string s = intactBinaryPly();
    corrupt("c.ply", s, {s.size()});
}

TEST_F(LoaderCorruption, BinaryStl) {
    const std::string s = intactBinaryStl();
    corrupt("c.stl", s, {s.size()});
}

TEST_F(LoaderCorruption, Glb) {
    const std::string s = intactGlb();
    corrupt("c.glb", s, {s.size()});
}

// ASCII formats with counts: the header's vertex and face counts declare the body to its last
// value.
TEST_F(LoaderCorruption, AsciiPly) {
    const std::string s =
        "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\n"
        "property float z\nelement face 2\nproperty list uchar int vertex_indices\n"
        "end_header\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n3 0 1 2\n3 0 2 3\n";
    corrupt("c.ply", s, {withoutTrailingSpace(s)});
}

TEST_F(LoaderCorruption, Off) {
    const std::string s = "OFF\n4 2 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n3 0 1 2\n3 0 2 3\n";
    corrupt("c.off", s, {withoutTrailingSpace(s)});
}

// ASCII STL ends with the keyword endsolid (its name after it is optional).
TEST_F(LoaderCorruption, AsciiStl) {
    const std::string s =
        "solid s\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 1 1 0\n"
        "endloop\nendfacet\nendsolid s\n";
    corrupt("c.stl", s, {s.find("endsolid") + std::string("endsolid").size()});
}

// A JSON document is complete only with its closing brace.
TEST_F(LoaderCorruption, Json) {
    write("m.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n");
    const std::string s =
        R"({"meshes": [{"file": "m.off", "transform": {"scale": [1, 2, 3]}}],)"
        R"( "area_lights": [{"vertices": [[0,0,1],[0,1,1],[1,0,1]], "emission": 1}],)"
        R"( "camera": {"eye": [0,0,5], "target": [0,0,0]}})";
    corrupt("c.json", s, {s.size()});
}

// OBJ declares no counts: a cut after a complete statement is a shorter, valid file.
TEST_F(LoaderCorruption, Obj) {
    corrupt("c.obj",
            "# a square and a triangle\nv 0.25 0 0\nv 1.5 0 0\nv 1.5 1.25 0\nv 0.25 1.25 0\n"
            "v 3 0 0\nv 4 0 0\nv 3 1 0\nf 1 2 3 4\nf 5 6 7\n",
            {});
}

}  // namespace
}  // namespace penumbra
