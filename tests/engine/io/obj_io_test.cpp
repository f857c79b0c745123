// Tests of the OBJ/MTL reader and writer (engine/io/obj_io.h) and of scene validation
// (engine/scene/scene_validation.h).
#include "engine/io/obj_io.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>
#include <vector>

#include "engine/scene/scene_error.h"
#include "engine/scene/scene_validation.h"
#include "tests/support/obj_reference.h"
#include "tests/support/test_scale.h"

namespace penumbra {
namespace {

namespace fs = std::filesystem;

uint64_t bits(double x) {
    uint64_t b;
    std::memcpy(&b, &x, sizeof b);
    return b;
}

// Loads from memory and expects a SceneError at `line` of `file` whose message contains `keyword`.
// Repair mode by default (the loaders' default); the repairs' own errors need strict mode.
void expectError(const std::string& obj, const std::string& mtl, int64_t line,
                 const std::string& keyword, const std::string& file = "bad.obj",
                 const LoadOptions& options = {}) {
    SCOPED_TRACE("OBJ text:\n" + obj);
    try {
        loadObjFromString(obj, mtl, "bad.obj", options);
        ADD_FAILURE() << "no SceneError; expected line " << line << " '" << keyword << "'";
    } catch (const SceneError& e) {
        const std::string what = e.what();
        EXPECT_EQ(e.line, line) << what;
        EXPECT_EQ(e.file, file) << what;
        const std::string location =
            line > 0 ? file + ":" + std::to_string(line) + ": " : file + ": ";
        EXPECT_EQ(what.rfind(location, 0), 0u) << what;
        EXPECT_NE(what.find(keyword), std::string::npos) << what;
    }
}

const char* kMtl =
    "# materials\n"
    "newmtl white\n"
    "Ka 0.1 0.1 0.1\n"
    "Kd 0.75 0.7 0.65\n"
    "Ks 0.01 0.02 0.03\n"
    "Ns 12.5\n"
    "illum 2\n"
    "map_Kd white.png\n"
    "\n"
    "newmtl lamp\n"
    "Kd 0 0 0\n"
    "Ke 10 9 8\n"
    "d 1.0\n"
    "Ni 1.5\n"
    "newmtl grey\n"
    "Kd 0.5\n";

const char* kObj =
    "# a floor, a wall, a lamp and a second lamp\n"  // 1
    "mtllib scene.mtl\n"                             // 2
    "o room\n"                                       // 3
    "v 0 0 0\n"                                      // 4
    "v 4 0 0\n"                                      // 5
    "v 4 4 0\n"                                      // 6
    "v 0 4 0\n"                                      // 7
    "v 1 1 3\n"                                      // 8
    "v 1 2 3\n"                                      // 9
    "v 2 2 3\n"                                      // 10
    "usemtl white\n"                                 // 11
    "f 1 2 3 4\n"                                    // 12 face 0 floor
    "usemtl lamp\n"                                  // 13
    "f 5 6 7\n"                                      // 14 face 1 light 0
    "usemtl grey\n"                                  // 15
    "f 1 5 2\n"                                      // 16 face 2
    "usemtl lamp\n"                                  // 17
    "s off\n"                                        // 18
    "f 2 5 3\n";                                     // 19 face 3 light 1

TEST(ObjIo, LoadsSceneWithLightsMaterialsAndFaceOrder) {
    const Scene s = loadObjFromString(kObj, kMtl, "dir/room.obj");
    EXPECT_EQ(s.sourcePath, "dir/room.obj");
    ASSERT_EQ(s.mesh.vertices.size(), 7u);
    EXPECT_EQ(s.mesh.vertices[4], (Vec3{1, 1, 3}));
    ASSERT_EQ(s.faceCount(), 4u);
    EXPECT_EQ(s.mesh.faces[0], (std::vector<uint32_t>{0, 1, 2, 3}));
    EXPECT_EQ(s.mesh.faces[1], (std::vector<uint32_t>{4, 5, 6}));
    EXPECT_EQ(s.mesh.faces[2], (std::vector<uint32_t>{0, 4, 1}));
    EXPECT_EQ(s.mesh.faces[3], (std::vector<uint32_t>{1, 4, 2}));
    EXPECT_EQ(s.faceSourceLine, (std::vector<int32_t>{12, 14, 16, 19}));

    ASSERT_EQ(s.materials.size(), 3u);
    EXPECT_EQ(s.materials[0].name, "white");
    EXPECT_EQ(s.materials[0].kd, (Vec3{0.75, 0.7, 0.65}));
    EXPECT_EQ(s.materials[0].ks, (Vec3{0.01, 0.02, 0.03}));
    EXPECT_EQ(s.materials[0].ke, (Vec3{0, 0, 0}));
    EXPECT_EQ(s.materials[0].ns, 12.5);
    EXPECT_EQ(s.materials[1].name, "lamp");
    EXPECT_EQ(s.materials[1].ke, (Vec3{10, 9, 8}));
    EXPECT_TRUE(s.materials[1].isEmissive());
    EXPECT_EQ(s.materials[2].name, "grey");
    EXPECT_EQ(s.materials[2].kd, (Vec3{0.5, 0.5, 0.5}));  // one number: grey

    EXPECT_EQ(s.faceMaterial, (std::vector<int32_t>{0, 1, 2, 1}));
    EXPECT_EQ(s.lights, (std::vector<uint32_t>{1, 3}));
    EXPECT_EQ(s.material(3).name, "lamp");
}

TEST(ObjIo, FacesBeforeUsemtlHaveTheDefaultMaterial) {
    const Scene s = loadObjFromString("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", "", "t.obj");
    ASSERT_EQ(s.faceCount(), 1u);
    EXPECT_EQ(s.faceMaterial, (std::vector<int32_t>{-1}));
    EXPECT_TRUE(s.materials.empty());
    EXPECT_TRUE(s.lights.empty());
    EXPECT_EQ(s.material(0).kd, (Vec3{0.8, 0.8, 0.8}));
}

TEST(ObjIo, NegativeIndicesAreRelativeToTheVerticesSoFar) {
    const Scene s = loadObjFromString(
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nf -3 -2 -1\n"
        "v 5 0 0\nv 6 0 0\nv 6 1 0\nv 5 1 0\nf -4 -3 -2 -1\nf 1 -3 -2\n",
        "", "neg.obj");
    ASSERT_EQ(s.faceCount(), 3u);
    EXPECT_EQ(s.mesh.faces[0], (std::vector<uint32_t>{0, 1, 2}));
    EXPECT_EQ(s.mesh.faces[1], (std::vector<uint32_t>{3, 4, 5, 6}));
    EXPECT_EQ(s.mesh.faces[2], (std::vector<uint32_t>{0, 4, 5}));
}

TEST(ObjIo, ReadsTextureAndNormalForms) {
    const std::string obj =
        "# exported\r\n"
        "mtllib m.mtl\r\n"
        "g group one\r\n"
        "s 1\r\n"
        "v 0 0 0\r\n"
        "v 1 0 0 1.0\r\n"          // w
        "v 1 1 0 0.5 0.5 0.5\r\n"  // vertex colours
        "v 0 1 0\r\n"
        "vt 0 0\r\nvt 1 0\r\nvt 1 1\r\nvt 0 1\r\n"
        "vn 0 0 1\r\n"
        "\r\n"
        "   \t \r\n"
        "usemtl m\r\n"
        "f 1/1/1 2/2/1 3/3/1 4/4/1\r\n"  // line 17
        "f 1//1 2//1 3//1\r\n"           // line 18
        "f 1/1 3/3 4/4   # trailing comment\r\n"
        "f -4/-4/-1 -3/-3/-1 -2/-2/-1\r\n"
        "l 1 2\r\n"
        "p 3\r\n"
        "o other\r\n"
        "f +1 +2 +3";  // no newline at the end
    const Scene s = loadObjFromString(obj, "newmtl m\r\nKd 1 1 1\r\n", "forms.obj");
    ASSERT_EQ(s.faceCount(), 5u);
    EXPECT_EQ(s.mesh.faces[0], (std::vector<uint32_t>{0, 1, 2, 3}));
    EXPECT_EQ(s.mesh.faces[1], (std::vector<uint32_t>{0, 1, 2}));
    EXPECT_EQ(s.mesh.faces[2], (std::vector<uint32_t>{0, 2, 3}));
    EXPECT_EQ(s.mesh.faces[3], (std::vector<uint32_t>{0, 1, 2}));
    EXPECT_EQ(s.mesh.faces[4], (std::vector<uint32_t>{0, 1, 2}));
    EXPECT_EQ(s.mesh.vertices[1], (Vec3{1, 0, 0}));
    EXPECT_EQ(s.mesh.vertices[2], (Vec3{1, 1, 0}));
    EXPECT_EQ(s.faceSourceLine[0], 17);
    EXPECT_EQ(s.faceSourceLine[1], 18);
    EXPECT_EQ(s.faceSourceLine[4], 24);
}

TEST(ObjIo, LineContinuationAndByteOrderMark) {
    const Scene s = loadObjFromString(
        "\xEF\xBB\xBFv 0 0 0\nv 1 0 \\\n 0\nv 1 1 0\n"
        "# c:\\dir\\\nv 0 1 0 # c:\\\nf 1 2 \\\n3 4\nf 1 2 3\n",
        "", "cont.obj");
    ASSERT_EQ(s.faceCount(), 2u);
    EXPECT_EQ(s.mesh.vertices.size(), 4u);
    EXPECT_EQ(s.mesh.vertices[1], (Vec3{1, 0, 0}));
    EXPECT_EQ(s.mesh.faces[0].size(), 4u);
    EXPECT_EQ(s.faceSourceLine[0], 7);
    EXPECT_EQ(s.faceSourceLine[1], 9);
}

TEST(ObjIo, QuadsAndConvexPolygons) {
    // A unit quad, a regular hexagon in a tilted plane, and a clockwise quad (seen from +z).
    std::string obj = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n";
    for (int i = 0; i < 6; ++i) {
        const double a = i * 3.14159265358979323846 / 3;
        const double x = std::cos(a), y = std::sin(a);
        // Plane z = x: exactly representable once x is.
        obj += "v " + std::to_string(x) + " " + std::to_string(y) + " " + std::to_string(x) + "\n";
    }
    obj += "f 5 6 7 8 9 10\n";
    obj += "f 4 3 2 1\n";
    const Scene s = loadObjFromString(obj, "", "quads.obj");
    ASSERT_EQ(s.faceCount(), 3u);
    EXPECT_EQ(s.mesh.faces[1].size(), 6u);
}

TEST(ObjIo, ConvexQuadInAnInexactPlaneIsAccepted) {
    // Points of the plane x + 2y + 3z = 1 rounded to doubles: not exactly coplanar.
    std::string obj;
    const double uv[4][2] = {{0.1, 0.1}, {0.9, 0.13}, {0.7, 0.8}, {0.15, 0.7}};
    for (const auto& p : uv) {
        const double z = (1 - p[0] - 2 * p[1]) / 3;
        char line[128];
        std::snprintf(line, sizeof line, "v %.17g %.17g %.17g\n", p[0], p[1], z);
        obj += line;
    }
    obj += "f 1 2 3 4\n";
    // Strict: refused as non-planar (exactly: no tolerance); repaired: split into two triangles
    // of its own vertices, with a warning.
    expectError(obj, "", 5, "face 0: non-planar", "bad.obj", LoadOptions::strictMode());
    const Scene s = loadObjFromString(obj, "", "tilted.obj");
    ASSERT_EQ(s.faceCount(), 2u);
    EXPECT_EQ(s.faceSourceLine, (std::vector<int32_t>{5, 5}));
    ASSERT_EQ(s.warnings.size(), 1u);
    EXPECT_NE(s.warnings[0].find("tilted.obj: split 1 non-planar faces into 2 triangles (first: "
                                 "face 0, line 5: non-planar"),
              std::string::npos)
        << s.warnings[0];
}

// ---- errors -------------------------------------------------------------------------------------

const std::string kTri = "v 0 0 0\nv 1 0 0\nv 0 1 0\n";  // lines 1-3

TEST(ObjErrors, MalformedNumbers) {
    expectError(kTri + "v 1.0 abc 2\nf 1 2 3\n", "", 4, "malformed number 'abc'");
    expectError(kTri + "v 1 2\nf 1 2 3\n", "", 4, "too few coordinates");
    expectError(kTri + "v\nf 1 2 3\n", "", 4, "too few coordinates");
    expectError(kTri + "v 1 nan 2\nf 1 2 3\n", "", 4, "non-finite");
    expectError(kTri + "v 1 2 inf\nf 1 2 3\n", "", 4, "non-finite");
    expectError(kTri + "v 1 2 -Infinity\nf 1 2 3\n", "", 4, "non-finite");
    expectError(kTri + "v 1 2 1e999\nf 1 2 3\n", "", 4, "out of range");
    expectError(kTri + "v 1 2 3 4 5 6 7 8\nf 1 2 3\n", "", 4, "too many numbers");
    expectError(kTri + "v 1.5e 2 3\nf 1 2 3\n", "", 4, "malformed");
    expectError(kTri + "v 0x10 2 3\nf 1 2 3\n", "", 4, "malformed");
    expectError(kTri + "v 1,5 2 3\nf 1 2 3\n", "", 4, "malformed");
    // One sign: "+-1" is no number (engine/io/text_input.h).
    expectError(kTri + "v +-1 2 3\nf 1 2 3\n", "", 4, "malformed number '+-1'");
    expectError(kTri + "v 1 ++2 3\nf 1 2 3\n", "", 4, "malformed number '++2'");
}

TEST(ObjErrors, BadIndices) {
    expectError(kTri + "f 0 1 2\n", "", 4, "face 0: vertex index 0");
    expectError(kTri + "f 1 2 3\nf 1 2 4\n", "", 5,
                "face 1: vertex index 4 out of range (file has 3 vertices)");
    expectError(kTri + "f 1 2 3\nf 1 2 -4\n", "", 5, "face 1: vertex index -4 out of range");
    expectError(kTri + "f 1 2 99999999999999999999999\n", "", 4, "out of range");
    expectError(kTri + "f 1 2 +-3\n", "", 4, "malformed vertex reference '+-3'");
    expectError(kTri + "f 1 2 -9223372036854775808\n", "", 4, "out of range");
    expectError(kTri + "f 1 2 9223372036854775807\n", "", 4, "out of range");
    expectError(kTri + "f 1 2 x\n", "", 4, "malformed vertex reference 'x'");
    expectError(kTri + "f 1 2 3/0\n", "", 4, "texture index 0");
    expectError(kTri + "f 1 2 3//0\n", "", 4, "normal index 0");
    expectError(kTri + "f 1 2 3/1/1/1\n", "", 4, "malformed vertex reference");
    expectError(kTri + "f 1 2 /3\n", "", 4, "malformed vertex reference");
    // Forward references are fine, but only up to the file's vertex count.
    expectError("f 1 2 3\nv 0 0 0\nv 1 0 0\n", "", 1, "face 0: vertex index 3 out of range");
}

TEST(ObjErrors, TooFewOrRepeatedVertices) {
    expectError(kTri + "f 1 2\n", "", 4, "face 0: too few vertices");
    expectError(kTri + "f\n", "", 4, "too few vertices");
    // A repeated vertex is a degenerate face: refused while parsing in strict mode.
    const LoadOptions strict = LoadOptions::strictMode();
    expectError(kTri + "f 1 2 3\nf 1 2 1\n", "", 5, "face 1: vertex 1 repeated", "bad.obj", strict);
    expectError(kTri + "f 1 2 3\nf 3 2 -1\n", "", 5, "face 1: vertex 3 repeated", "bad.obj",
                strict);
}

TEST(ObjRepairs, RepeatedVertexIsDroppedWithOneWarning) {
    // Faces 1 and 3 repeat a vertex (line 5 and 7); faces 0 and 2 stay, renumbered 0 and 1.
    const Scene s =
        loadObjFromString(kTri + "v 0 0 1\nf 1 2 3\nf 1 2 1\nf 3 2 4\nf 3 2 -2\n", "", "rep.obj");
    ASSERT_EQ(s.faceCount(), 2u);
    EXPECT_EQ(s.mesh.faces[0], (std::vector<uint32_t>{0, 1, 2}));
    EXPECT_EQ(s.mesh.faces[1], (std::vector<uint32_t>{2, 1, 3}));
    EXPECT_EQ(s.faceSourceLine, (std::vector<int32_t>{5, 7}));
    ASSERT_EQ(s.warnings.size(), 1u);
    EXPECT_NE(s.warnings[0].find("rep.obj: dropped 2 degenerate"), std::string::npos)
        << s.warnings[0];
    EXPECT_NE(s.warnings[0].find("face 1"), std::string::npos) << s.warnings[0];
    EXPECT_NE(s.warnings[0].find("line 6"), std::string::npos) << s.warnings[0];
}

TEST(ObjErrors, TruncatedFiles) {
    // Cut mid-number: "2." is a number, but then a coordinate is missing.
    expectError(kTri + "f 1 2 3\nv 1.0 2.", "", 5, "too few coordinates");
    expectError(kTri + "f 1 2", "", 4, "too few vertices");
    expectError(kTri + "f 1/", "", 4, "malformed vertex reference '1/'");
    expectError(kTri + "f 1 2 3/", "", 4, "malformed vertex reference");
    expectError(kTri + "f 1 2 3\nf 1 2 3/-", "", 5, "malformed");
    expectError(kTri + "f 1 2 3\nv 1.0e", "", 5, "malformed");
    expectError(kTri + "f 1 2 3\nusemtl", "", 5, "usemtl without");
}

TEST(ObjErrors, EmptyFilesHaveNoFaces) {
    expectError("", "", 0, "no faces");
    expectError("\n\n# only a comment\n   \n", "", 0, "no faces");
    expectError(kTri, "", 0, "no faces");
}

TEST(ObjErrors, BinaryGarbage) {
    std::string garbage = kTri + "f 1 2 3\n";
    garbage += std::string(
        "\x7f"
        "ELF\x02\x01\x01\x00\x00\x00",
        10);
    expectError(garbage, "", 5, "binary data (byte 0x7f at column 1)");
    expectError(std::string("v 0 0 0\x00 1\n", 11), "", 1, "binary data (byte 0x00 at column 8)");
    expectError("\x89PNG\r\n\x1a\n", "", 2, "binary data");
    expectError("\xff\xfe\xfd\xfc ab\n", "", 1, "unknown statement");
}

TEST(ObjErrors, UnsupportedStatements) {
    expectError(kTri + "curv 0 1 1 2\nf 1 2 3\n", "", 4, "free-form");
    expectError(kTri + "call other.obj\nf 1 2 3\n", "", 4, "'call'");
    expectError(kTri + "vertex 1 2 3\nf 1 2 3\n", "", 4, "unknown statement 'vertex'");
}

TEST(ObjErrors, LineNumbersCountCrLfAndCrOnlyEndings) {
    expectError("v 0 0 0\r\nv 1 0 0\r\nv 0 1 0\r\n\r\nf 1 2 7\r\n", "", 5, "out of range");
    expectError("v 0 0 0\rv 1 0 0\rv 0 1 0\r\rf 1 2 7\r", "", 5, "out of range");
    expectError("v 0 0 0\nv 1 0 \\\n0\nv 0 1 0\nv x 1 0\n", "", 5, "malformed");
}

TEST(ObjErrors, Materials) {
    // Strict mode: an unknown usemtl names the OBJ line of the usemtl.
    const LoadOptions strict = LoadOptions::strictMode();
    expectError(kTri + "usemtl nothere\nf 1 2 3\n", "", 4,
                "usemtl: unknown material 'nothere' (0 materials defined, no mtllib)", "bad.obj",
                strict);
    expectError("mtllib m.mtl\n" + kTri + "f 1 2 3\nusemtl Lamp\nf 1 2 3\n",
                "newmtl lamp\nKe 1 1 1\n", 6,
                "usemtl: unknown material 'Lamp' (1 materials defined)", "bad.obj", strict);
    // MTL errors name the MTL (relative to the OBJ's directory) and its line.
    const std::string obj = "mtllib lib/m.mtl\n" + kTri + "f 1 2 3\n";
    try {
        loadObjFromString(obj, "newmtl a\nKd 1 x 2\n", "scenes/bad.obj");
        ADD_FAILURE() << "no SceneError";
    } catch (const SceneError& e) {
        EXPECT_EQ(e.file, "scenes/lib/m.mtl");
        EXPECT_EQ(e.line, 2);
        EXPECT_NE(std::string(e.what()).find("scenes/lib/m.mtl:2: Kd: malformed number 'x'"),
                  std::string::npos)
            << e.what();
    }
    const auto mtlError = [&](const std::string& mtl, int64_t line, const std::string& keyword) {
        expectError("mtllib m.mtl\n" + kTri + "f 1 2 3\n", mtl, line, keyword, "m.mtl");
    };
    mtlError("Kd 1 1 1\n", 1, "before any newmtl");
    mtlError("newmtl a\nKe 1 -1 1\n", 2, "negative");
    mtlError("newmtl a\nKe 1 1\n", 2, "expected 1 or 3 numbers");
    mtlError("newmtl a\nKd spectral x.rfl\n", 2, "not supported");
    mtlError("newmtl a\nNs\n", 2, "Ns: missing");
    mtlError("newmtl a\nNs 1 2\n", 2, "Ns: unexpected");
    mtlError("newmtl a\nNs nan\n", 2, "non-finite");
    mtlError("newmtl a\nnewmtl b\n\nnewmtl a\n", 4, "defined twice");
    mtlError("newmtl a\n\x01\x02\n", 2, "binary");
    expectError("mtllib m.mtl\n" + kTri + "f 1 2 3\n", "newmtl a\nnewmtl  \nKd 1 1 1\n", 2,
                "newmtl without a material name", "m.mtl", strict);
}

// ---- repairs of missing materials (issue 41): a default material and one warning per kind
// --------

TEST(ObjRepairs, UsemtlWithoutMtllibGetsADefaultMaterial) {
    const std::string obj = kTri + "f 1 2 3\nusemtl Default\nf 1 2 3\nf 3 2 1\n";  // 5-7
    const Scene s = loadObjFromString(obj, "", "model.obj");
    ASSERT_EQ(s.faceCount(), 3u);
    ASSERT_EQ(s.materials.size(), 1u);
    EXPECT_EQ(s.materials[0].name, "Default");
    EXPECT_EQ(s.materials[0].kd, Material{}.kd);
    EXPECT_FALSE(s.materials[0].isEmissive());
    EXPECT_FALSE(s.materials[0].isGlossy());
    EXPECT_EQ(s.faceMaterial, (std::vector<int32_t>{-1, 0, 0}));
    EXPECT_TRUE(s.lights.empty());
    ASSERT_EQ(s.warnings.size(), 1u);
    EXPECT_EQ(s.warnings[0],
              "model.obj: usemtl 'Default' on line 5 names no material (no mtllib): 2 faces use a "
              "default diffuse material");
}

TEST(ObjRepairs, UsemtlNamesAMaterialTheMtlDoesNotDefine) {
    // 'Lamp' is not 'lamp'; 'x' twice: one material for both, one warning line for all three.
    const std::string obj = "mtllib m.mtl\n" + kTri +
                            "usemtl lamp\nf 1 2 3\nusemtl Lamp\nf 1 2 3\nusemtl x\nf 1 2 3\n"
                            "usemtl lamp\nf 3 2 1\nusemtl x\nf 3 2 1\n";  // usemtl: 5 7 9 11 13
    const Scene s = loadObjFromString(obj, "newmtl lamp\nKe 1 1 1\n", "model.obj");
    ASSERT_EQ(s.faceCount(), 5u);
    ASSERT_EQ(s.materials.size(), 3u);
    EXPECT_EQ(s.materials[0].name, "lamp");
    EXPECT_EQ(s.materials[1].name, "Lamp");
    EXPECT_EQ(s.materials[2].name, "x");
    EXPECT_FALSE(s.materials[1].isEmissive());
    EXPECT_EQ(s.faceMaterial, (std::vector<int32_t>{0, 1, 2, 0, 2}));
    EXPECT_EQ(s.lights, (std::vector<uint32_t>{0, 3}));  // only the defined lamp emits
    ASSERT_EQ(s.warnings.size(), 1u);
    EXPECT_EQ(s.warnings[0],
              "model.obj: 3 usemtl lines name no material (first: 'Lamp' on line 7; 1 materials "
              "defined): 3 faces use a default diffuse material");
}

TEST(ObjRepairs, NewmtlWithoutANameIsIgnoredWithItsStatements) {
    // The unnamed material's Ke would make it a light: its statements go with it.
    const std::string mtl =
        "newmtl a\nKd 0.5 0.5 0.5\nnewmtl\nKe 9 9 9\nKd 2 x 2\nnewmtl b\n"
        "Kd 0.1 0.1 0.1\nnewmtl \n";
    const Scene s = loadObjFromString("mtllib m.mtl\n" + kTri +
                                          "usemtl a\nf 1 2 3\n"
                                          "usemtl b\nf 3 2 1\n",
                                      mtl, "dir/model.obj");
    ASSERT_EQ(s.materials.size(), 2u);
    EXPECT_EQ(s.materials[1].kd, (Vec3{0.1, 0.1, 0.1}));
    EXPECT_EQ(s.faceMaterial, (std::vector<int32_t>{0, 1}));
    EXPECT_TRUE(s.lights.empty());
    ASSERT_EQ(s.warnings.size(), 1u);
    EXPECT_EQ(s.warnings[0],
              "dir/m.mtl: newmtl without a material name on line 3 (and 1 more): those materials "
              "are ignored, with their statements");
}

// ---- validation ---------------------------------------------------------------------------------

const std::string kQuadBase = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n";  // lines 1-5

// These polygons are errors in strict mode (in repair mode they are split into triangles).
const LoadOptions kStrict = LoadOptions::strictMode();

TEST(ObjValidation, PlanarConvexQuadIsAccepted) {
    EXPECT_NO_THROW(loadObjFromString(kQuadBase, "", "ok.obj"));
    // Off the plane by 1e-12 of the diameter: planarity is exact, so this one is not planar.
    expectError(kQuadBase + "v 0 0 1\nv 1 0 1\nv 1 1 1.000000000001\nv 0 1 1\nf 5 6 7 8\n", "", 10,
                "face 1: non-planar", "bad.obj", kStrict);
}

TEST(ObjValidation, NonPlanarQuadIsRejected) {
    expectError(kQuadBase + "v 0 0 1\nv 1 0 1\nv 1 1 1.001\nv 0 1 1\nf 5 6 7 8\n", "", 10,
                "face 1: non-planar", "bad.obj", kStrict);
    try {
        loadObjFromString(kQuadBase + "v 0 0 1\nv 1 0 1\nv 1 1 1.001\nv 0 1 1\nf 5 6 7 8\n", "",
                          "np.obj", kStrict);
    } catch (const SceneError& e) {
        // The measured deviation: a quarter of the lift (0.001 / 4) from the centroid plane.
        EXPECT_NE(std::string(e.what()).find("0.00025"), std::string::npos) << e.what();
    }
    // Just beyond the tolerance.
    expectError(kQuadBase + "v 0 0 1\nv 1 0 1\nv 1 1 1.00000001\nv 0 1 1\nf 5 6 7 8\n", "", 10,
                "non-planar", "bad.obj", kStrict);
}

TEST(ObjValidation, NonConvexQuadIsRejected) {
    // A dart: vertex 7 (0-based 6) is reflex.
    expectError(kQuadBase + "v 0 0 1\nv 2 0 1\nv 0.5 0.5 1\nv 0 2 1\nf 5 6 7 8\n", "", 10,
                "face 1: non-convex: reflex vertex 6", "bad.obj", kStrict);
    // The same dart clockwise.
    expectError(kQuadBase + "v 0 0 1\nv 2 0 1\nv 0.5 0.5 1\nv 0 2 1\nf 8 7 6 5\n", "", 10,
                "face 1: non-convex: reflex vertex 6", "bad.obj", kStrict);
    // A bow tie (self-intersecting, zero net area).
    expectError(kQuadBase + "v 0 0 1\nv 1 1 1\nv 1 0 1\nv 0 1 1\nf 5 6 7 8\n", "", 10,
                "face 1: non-convex", "bad.obj", kStrict);
    // A pentagram: every turn agrees but the boundary winds twice.
    std::string star = kQuadBase;
    for (int i = 0; i < 5; ++i) {
        const int j = (2 * i) % 5;
        const double a = j * 2 * 3.14159265358979323846 / 5;
        star += "v " + std::to_string(std::cos(a)) + " " + std::to_string(std::sin(a)) + " 3\n";
    }
    star += "f 5 6 7 8 9\n";  // line 11
    expectError(star, "", 11, "face 1: non-convex: self-intersecting", "bad.obj", kStrict);
}

TEST(ObjValidation, DegenerateFacesAreRejected) {
    expectError(kQuadBase + "v 2 0 0\nv 3 0 0\nf 2 5 6\n", "", 8, "face 1: degenerate (zero area)",
                "bad.obj", kStrict);
    expectError(kQuadBase + "v 2 2 2\nv 3 3 3\nf 1 5 6\n", "", 8, "degenerate (zero area)",
                "bad.obj", kStrict);
    // Distinct indices at the same position.
    expectError(kQuadBase + "v 0 0 0\nf 1 5 2\n", "", 7,
                "face 1: degenerate (zero area): zero-length edge", "bad.obj", kStrict);
    // A sliver: the third vertex is one ulp off the line through the others. Not degenerate.
    EXPECT_NO_THROW(loadObjFromString(
        "v 0 0 0\nv 1e8 1e8 1e8\nv 1e8 1e8 100000000.00000001490116119384765625\nf 1 2 3\n"
        "v 0 0 0.5\nv 1 0 0.5\nv 0 1 0.5\nf 4 5 6\n",
        "", "thin.obj"));
}

TEST(ObjRepairs, DegenerateFacesAreDroppedByDefault) {
    // Face 1 (line 8) is three collinear points, face 2 (line 10) has a zero-length edge.
    const Scene s = loadObjFromString(
        kQuadBase + "v 2 0 0\nv 3 0 0\nf 2 5 6\nv 0 0 0\nf 1 7 2\nf 1 2 3\n", "", "deg.obj");
    ASSERT_EQ(s.faceCount(), 2u);
    EXPECT_EQ(s.mesh.faces[0], (std::vector<uint32_t>{0, 1, 2, 3}));
    EXPECT_EQ(s.mesh.faces[1], (std::vector<uint32_t>{0, 1, 2}));
    EXPECT_EQ(s.faceSourceLine, (std::vector<int32_t>{5, 11}));
    ASSERT_EQ(s.warnings.size(), 1u);
    EXPECT_NE(s.warnings[0].find("deg.obj: dropped 2 degenerate"), std::string::npos)
        << s.warnings[0];
    EXPECT_NE(s.warnings[0].find("(first: face 1, line 8: degenerate (zero area)"),
              std::string::npos)
        << s.warnings[0];
}

TEST(ObjValidation, CollinearVerticesAreRejected) {
    // A triangle with an extra vertex in the middle of an edge.
    expectError(kQuadBase + "v 0 0 1\nv 1 0 1\nv 2 0 1\nv 0 1 1\nf 5 6 7 8\n", "", 10,
                "face 1: collinear vertices: vertex 5", "bad.obj", kStrict);
    // Exactly collinear with non-representable-looking coordinates: 0.25 steps are exact.
    expectError("v 0 0 0\nv 0.25 0.5 0.75\nv 0.5 1 1.5\nv 0 1 0\nf 1 2 3 4\n", "", 5,
                "collinear vertices", "bad.obj", kStrict);
}

TEST(ObjValidation, ValidateSceneChecksProgrammaticScenes) {
    Scene s;
    s.sourcePath = "made.obj";
    s.mesh.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    s.mesh.faces = {{0, 1, 2}};
    EXPECT_NO_THROW(validateScene(s));
    s.mesh.faces = {{0, 1, 2}, {0, 1, 3}};
    s.faceSourceLine = {10, 11};
    try {
        validateScene(s);
        ADD_FAILURE();
    } catch (const SceneError& e) {
        EXPECT_EQ(e.line, 11);
        EXPECT_NE(std::string(e.what()).find("made.obj:11: face 1: vertex index 3 out of range"),
                  std::string::npos)
            << e.what();
    }
    s.mesh.faces = {{0, 1, 2}};
    s.faceSourceLine = {};
    s.faceMaterial = {2};
    EXPECT_THROW(validateScene(s), SceneError);
    s.faceMaterial = {-1};
    s.mesh.vertices[2].z = std::nan("");
    EXPECT_THROW(validateScene(s), SceneError);
}

// ---- robustness ---------------------------------------------------------------------------------

// Physical lines: 1 comment, 2 mtllib, 3-7 v, 8 vt, 9 vn, 10 g, 11 usemtl, 12 f, 13 usemtl, 14-15 f
// continued, 16 f, 17-18 v (LF from here on), 19 f, 20 f naming vertex 8, defined on line 21.
const std::string kRobustObj =
    "# robustness sample\r\n"
    "mtllib r.mtl\r\n"
    "v 0 0 0\r\nv 1.5 0 0\r\nv 1.5 1.25 0\r\nv 0 1.25 0\r\n"
    "v -1e-3 2.000001 3.25e+2 1.0\r\n"
    "vt 0.5 0.5\r\nvn 0 0 1\r\n"
    "g floor\r\n"
    "usemtl white\r\n"
    "f 1/1/1 2/1/1 3/1/1 4/1/1\r\n"
    "usemtl lamp\r\n"
    "f -5//1 -4//1 \\\r\n -1//1\r\n"
    "f 2/1 3/1 5/1 # end\r\n"
    "v 3 0 0\nv 3 1 0\nf -2 -1 3\n"
    "f 3 4 8\nv 2 2 1\n";

const std::string kRobustMtl =
    "newmtl white\r\nKd 0.7 0.7 0.7\r\nKs 0.1 0.1 0.1\r\nNs 20\r\n"
    "newmtl lamp\r\nKe 5 5 5\r\nmap_Kd x.png\r\n";

TEST(ObjRobustness, TheSampleLoads) {
    const Scene s = loadObjFromString(kRobustObj, kRobustMtl, "r.obj");
    EXPECT_EQ(s.faceCount(), 5u);
    EXPECT_EQ(s.mesh.vertices.size(), 8u);
    EXPECT_EQ(s.lights, (std::vector<uint32_t>{1, 2, 3, 4}));
    EXPECT_EQ(s.mesh.faces[4], (std::vector<uint32_t>{2, 3, 7}));
    // The lamp's map_Kd names an image that is not there (the texts come from memory): its one
    // warning, naming the file.
    ASSERT_EQ(s.warnings.size(), 1u);
    EXPECT_NE(s.warnings[0].find("x.png"), std::string::npos) << s.warnings[0];
}

// The sample cut after the first `n` bytes of the line that starts with `line`.
std::string cutInside(const std::string& text, const std::string& line, size_t n) {
    return text.substr(0, text.find(line) + n);
}

// What one load gave, against the reference reading (tests/support/obj_reference.h).
enum class Loaded { kRefused, kAsRead, kRepaired };

// Loads `obj` with `mtl` (as r.obj) and expects what readObjReference says: a SceneError naming the
// file and line it names, or the vertices, faces and lights it reads. With `mayRepair` (the
// geometry was changed, so faces may have become degenerate, non-planar or non-convex) the loader
// may also repair faces, with a warning, or refuse one it cannot split.
Loaded expectAsTheReferenceReads(const std::string& obj, const std::string& mtl,
                                 const std::string& what, bool mayRepair) {
    const test::ObjReading ref = test::readObjReference(obj, mtl, "r.obj");
    const std::string expected =
        ref.refused() ? "refused at " + ref.errorFile + ":" + std::to_string(ref.errorLine)
                      : "loaded with " + std::to_string(ref.faces.size()) + " faces";
    try {
        const Scene s = loadObjFromString(obj, mtl, "r.obj");
        if (ref.refused()) {
            ADD_FAILURE() << what << ": loaded " << s.faceCount() << " faces, but must be "
                          << expected;
            return Loaded::kAsRead;
        }
        const bool repaired = std::any_of(s.warnings.begin(), s.warnings.end(), [](auto& w) {
            return w.find("degenerate") != std::string::npos ||
                   w.find(" split ") != std::string::npos;
        });
        EXPECT_TRUE(s.mesh.vertices == ref.vertices) << what;
        if (repaired) {
            EXPECT_TRUE(mayRepair) << what << ": repaired an unchanged face: " << s.warnings[0];
            try {
                validateScene(s);
            } catch (const SceneError& e) {
                ADD_FAILURE() << what << ": the repaired scene fails validation: " << e.what();
            }
            return Loaded::kRepaired;
        }
        EXPECT_EQ(s.mesh.faces, ref.faces) << what;
        EXPECT_EQ(s.lights, ref.lights) << what;
        return Loaded::kAsRead;
    } catch (const SceneError& e) {
        const std::string message = e.what();
        if (!ref.refused()) {
            const bool unsplittable = message.find("cannot be split") != std::string::npos ||
                                      message.find("no faces") != std::string::npos;
            EXPECT_TRUE(mayRepair && unsplittable)
                << what << ": refused (" << message << "), but must be " << expected;
            return Loaded::kRefused;
        }
        EXPECT_EQ(e.file, ref.errorFile) << what << ": " << message;
        EXPECT_EQ(e.line, ref.errorLine) << what << ": " << message;
        const std::string location =
            e.line > 0 ? e.file + ":" + std::to_string(e.line) + ": " : e.file + ": ";
        EXPECT_EQ(message.rfind(location, 0), 0u) << what << ": " << message;
        return Loaded::kRefused;
    } catch (const std::exception& e) {
        ADD_FAILURE() << what << ": not a SceneError: " << e.what();
        return Loaded::kRefused;
    }
}

// A few cuts worked out by hand: they pin down the reference reading the next test relies on.
TEST(ObjRobustness, TruncationsWorkedOutByHand) {
    const auto refusedAt = [](const std::string& obj, const std::string& mtl,
                              const std::string& file, int64_t line) {
        try {
            loadObjFromString(obj, mtl, "r.obj");
            ADD_FAILURE() << "loaded; must be refused at " << file << ":" << line << "\n" << obj;
        } catch (const SceneError& e) {
            EXPECT_EQ(e.file, file) << e.what();
            EXPECT_EQ(e.line, line) << e.what();
        }
        const test::ObjReading ref = test::readObjReference(obj, mtl, "r.obj");
        EXPECT_EQ(ref.errorFile, file);
        EXPECT_EQ(ref.errorLine, line);
    };
    // Inside a face's index list: a reference cut after its slash, then a face of two vertices.
    refusedAt(cutInside(kRobustObj, "f 1/1/1", 10), kRobustMtl, "r.obj", 12);
    refusedAt(cutInside(kRobustObj, "f 1/1/1", 14), kRobustMtl, "r.obj", 12);
    // A continued face cut after its backslash (two vertices), or after the sign of its third.
    refusedAt(cutInside(kRobustObj, "f -5//1", 15), kRobustMtl, "r.obj", 14);
    refusedAt(cutInside(kRobustObj, " -1//1", 2), kRobustMtl, "r.obj", 14);
    // A vertex cut inside an exponent, and one left with two coordinates.
    refusedAt(cutInside(kRobustObj, "v -1e-3", 23), kRobustMtl, "r.obj", 7);
    refusedAt(cutInside(kRobustObj, "v 2 2 1", 5), kRobustMtl, "r.obj", 21);
    // Face 4 names vertex 8, which the cut removed.
    refusedAt(cutInside(kRobustObj, "v 2 2 1", 0), kRobustMtl, "r.obj", 20);
    // Before the first face: nothing to render.
    refusedAt(cutInside(kRobustObj, "usemtl white", 12), kRobustMtl, "r.obj", 0);
    // The material library: a colour of two numbers.
    refusedAt(kRobustObj, cutInside(kRobustMtl, "Kd 0.7 0.7", 10), "r.mtl", 2);

    // Cut after a whole statement: a shorter file.
    Scene s = loadObjFromString(cutInside(kRobustObj, "f 3 4 8", 0), kRobustMtl, "r.obj");
    EXPECT_EQ(s.faceCount(), 4u);
    EXPECT_EQ(s.mesh.vertices.size(), 7u);
    EXPECT_EQ(s.lights, (std::vector<uint32_t>{1, 2, 3}));
    // A face cut after its third vertex is a triangle.
    s = loadObjFromString(cutInside(kRobustObj, "f 1/1/1", 19), kRobustMtl, "r.obj");
    EXPECT_EQ(s.mesh.faces, (std::vector<std::vector<uint32_t>>{{0, 1, 2}}));
    // The lamp's Ke cut away: no light.
    s = loadObjFromString(kRobustObj, cutInside(kRobustMtl, "Ke 5", 0), "r.obj");
    EXPECT_EQ(s.faceCount(), 5u);
    EXPECT_TRUE(s.lights.empty());
}

// Every cut of the OBJ and of the MTL: refused at the file and line the reference reading names,
// or loaded with the vertices, faces and lights it reads (a cut removes data, it never makes a
// face degenerate: no repair either). Both outcomes must occur many times.
TEST(ObjRobustness, TruncationAtEveryByteIsRefusedOrLoadsWhatRemains) {
    int refused = 0, loaded = 0;
    for (size_t n = 0; n <= kRobustObj.size(); ++n) {
        const Loaded o = expectAsTheReferenceReads(kRobustObj.substr(0, n), kRobustMtl,
                                                   "OBJ cut at " + std::to_string(n), false);
        (o == Loaded::kRefused ? refused : loaded) += 1;
    }
    for (size_t n = 0; n <= kRobustMtl.size(); ++n) {
        const Loaded o = expectAsTheReferenceReads(kRobustObj, kRobustMtl.substr(0, n),
                                                   "MTL cut at " + std::to_string(n), false);
        (o == Loaded::kRefused ? refused : loaded) += 1;
    }
    EXPECT_GT(refused, 100);
    EXPECT_GT(loaded, 100);
}

// Random byte changes, deletions and insertions (3000, scaled): refused at the file and line the
// reference reading names, or loaded as it reads them (faces the change made degenerate, non-planar
// or non-convex may be repaired, with a warning). Each kind of outcome must occur.
TEST(ObjRobustness, RandomByteCorruptionIsRefusedOrLoadsWhatIsLeft) {
    const test::ObjReading sample = test::readObjReference(kRobustObj, kRobustMtl, "r.obj");
    ASSERT_FALSE(sample.refused());
    std::mt19937 rng(12345);
    const int iterations = test::scaled(3000);
    int refused = 0, unchanged = 0, changed = 0;
    for (int iter = 0; iter < iterations; ++iter) {
        std::string obj = kRobustObj, mtl = kRobustMtl;
        std::string& target = iter % 4 == 3 ? mtl : obj;
        const int edits = 1 + static_cast<int>(rng() % 4);
        for (int e = 0; e < edits && !target.empty(); ++e) {
            const size_t at = rng() % target.size();
            switch (rng() % 3) {
                case 0:
                    target[at] = static_cast<char>(rng() % 256);
                    break;
                case 1:
                    target.erase(at, 1 + rng() % 8);
                    break;
                default:
                    target.insert(at, 1, "0123456789/-+.e #\\\n\rvfx"[rng() % 24]);
                    break;
            }
        }
        const test::ObjReading ref = test::readObjReference(obj, mtl, "r.obj");
        const bool sameGeometry =
            !ref.refused() && ref.vertices == sample.vertices && ref.faces == sample.faces;
        const Loaded o = expectAsTheReferenceReads(obj, mtl, "corruption " + std::to_string(iter),
                                                   !sameGeometry);
        refused += o == Loaded::kRefused;
        unchanged += o != Loaded::kRefused && sameGeometry;
        changed += o != Loaded::kRefused && !sameGeometry;
    }
    std::printf("%d corruptions: %d refused, %d loaded the sample's geometry, %d another\n",
                iterations, refused, unchanged, changed);
    EXPECT_GT(refused, iterations / 4);
    EXPECT_GT(unchanged, iterations / 20);
    EXPECT_GT(changed, iterations / 50);
}

// ---- files --------------------------------------------------------------------------------------

class ObjFiles : public ::testing::Test {
  protected:
    void SetUp() override {
        std::random_device random;
        dir_ = fs::temp_directory_path() /
               ("penumbra_obj_test_" + std::to_string(random()) + std::to_string(random()));
        fs::create_directories(dir_);
    }
    void TearDown() override {
        std::error_code ec;
        fs::remove_all(dir_, ec);
    }
    void write(const fs::path& p, const std::string& text) {
        fs::create_directories(p.parent_path());
        std::ofstream(p, std::ios::binary) << text;
    }
    std::string read(const fs::path& p) {
        std::ifstream in(p, std::ios::binary);
        return std::string(std::istreambuf_iterator<char>(in), {});
    }
    size_t filesIn(const fs::path& d) {
        size_t n = 0;
        for ([[maybe_unused]] const auto& e : fs::directory_iterator(d)) ++n;
        return n;
    }
    fs::path dir_;
};

TEST_F(ObjFiles, LoadsFromDiskWithMtllibRelativeToTheObj) {
    write(dir_ / "scenes" / "mats" / "scene.mtl", kMtl);
    std::string obj = kObj;
    obj.replace(obj.find("mtllib scene.mtl"), 16, "mtllib mats/scene.mtl");
    write(dir_ / "scenes" / "room.obj", obj);
    const Scene s = loadObj(dir_ / "scenes" / "room.obj");
    EXPECT_EQ(s.sourcePath, (dir_ / "scenes" / "room.obj").string());
    EXPECT_EQ(s.faceCount(), 4u);
    EXPECT_EQ(s.lights, (std::vector<uint32_t>{1, 3}));
    EXPECT_EQ(s.materials[1].ke, (Vec3{10, 9, 8}));
}

TEST_F(ObjFiles, MtllibNamesWithSpacesAndSeveralLibraries) {
    write(dir_ / "my mats.mtl", "newmtl a\nKd 0.1 0.2 0.3\n");
    write(dir_ / "b.mtl", "newmtl b\nKe 1 1 1\n");
    write(dir_ / "c.mtl", "newmtl c\n");
    write(dir_ / "x.obj", "mtllib my mats.mtl\nmtllib b.mtl c.mtl b.mtl\n" + kTri +
                              "usemtl a\nf 1 2 3\nusemtl b\nf 1 2 3\n");
    const Scene s = loadObj(dir_ / "x.obj");
    ASSERT_EQ(s.materials.size(), 3u);
    EXPECT_EQ(s.materials[0].kd, (Vec3{0.1, 0.2, 0.3}));
    EXPECT_EQ(s.lights, (std::vector<uint32_t>{1}));
}

TEST_F(ObjFiles, MissingOrUnreadableFiles) {
    try {
        loadObj(dir_ / "none.obj");
        ADD_FAILURE();
    } catch (const SceneError& e) {
        EXPECT_EQ(e.file, (dir_ / "none.obj").string());
        EXPECT_NE(std::string(e.what()).find("none.obj: cannot read file"), std::string::npos)
            << e.what();
    }
    EXPECT_THROW(loadObj(dir_), SceneError);  // a directory
    write(dir_ / "a.obj", "# x\nmtllib missing.mtl\n" + kTri + "f 1 2 3\n");
    try {
        loadObj(dir_ / "a.obj", LoadOptions::strictMode());
        ADD_FAILURE();
    } catch (const SceneError& e) {
        EXPECT_EQ(e.line, 2);
        EXPECT_NE(std::string(e.what()).find("a.obj:2: mtllib: cannot read material library "
                                             "'missing.mtl'"),
                  std::string::npos)
            << e.what();
    }
}

TEST_F(ObjFiles, UnreadableMtllibIsSkippedWithAWarning) {
    // One library missing, one read: the missing one's material is a default one, its faces
    // counted in the usemtl warning.
    write(dir_ / "b.mtl", "newmtl lamp\nKe 2 2 2\n");
    write(dir_ / "a.obj", "mtllib missing.mtl\nmtllib b.mtl\n" + kTri +
                              "usemtl wood\nf 1 2 3\nusemtl lamp\nf 3 2 1\n");  // usemtl: 6, 8
    const Scene s = loadObj(dir_ / "a.obj");
    ASSERT_EQ(s.faceCount(), 2u);
    ASSERT_EQ(s.materials.size(), 2u);
    EXPECT_EQ(s.materials[0].name, "lamp");
    EXPECT_EQ(s.materials[1].name, "wood");
    EXPECT_EQ(s.materials[1].kd, Material{}.kd);
    EXPECT_EQ(s.faceMaterial, (std::vector<int32_t>{1, 0}));
    EXPECT_EQ(s.lights, (std::vector<uint32_t>{1}));
    const std::string file = (dir_ / "a.obj").string();
    ASSERT_EQ(s.warnings.size(), 2u);
    EXPECT_EQ(s.warnings[0], file + ":1: mtllib: cannot read material library 'missing.mtl' (" +
                                 (dir_ / "missing.mtl").string() +
                                 "): No such file or directory; its materials are missing");
    EXPECT_EQ(s.warnings[1], file +
                                 ": usemtl 'wood' on line 6 names no material (1 materials "
                                 "defined, a material library unreadable): 1 face uses a default "
                                 "diffuse material");
}

TEST_F(ObjFiles, WriteThenReadIsBitIdentical) {
    std::mt19937_64 rng(7);
    std::uniform_real_distribution<double> coord(-1e3, 1e3);
    Scene s;
    s.sourcePath = "generated";
    s.materials = {Material{"white", {0.1, 1.0 / 3, 0.7}, {0.01, 0, 0}, {0, 0, 0}, 1.0 / 7, {}},
                   Material{"lamp light", {0, 0, 0}, {0, 0, 0}, {17.3, 1e-3, 2.0 / 3}, 0, {}}};
    for (int t = 0; t < 200; ++t) {
        const auto base = static_cast<uint32_t>(s.mesh.vertices.size());
        for (int k = 0; k < 3; ++k) s.mesh.vertices.push_back({coord(rng), coord(rng), coord(rng)});
        s.mesh.faces.push_back({base, base + 1, base + 2});
        // No lamp among them: beside the quad below (1.9e17 across), triangles a thousand units
        // wide are lights too small for doubles to resolve in this scene (the light-area rule,
        // scene_validation.h), and so is the quad, 0.2 wide. The lamp is a triangle as large.
        s.faceMaterial.push_back(t % 2 == 0 ? -1 : 0);
    }
    // A quad in the plane z = -0.0 with awkward coordinates, and subnormal magnitudes and huge
    // ones (as large as the coordinate contract allows: engine/scene/scene_validation.h).
    const auto base = static_cast<uint32_t>(s.mesh.vertices.size());
    s.mesh.vertices.push_back({0.1, 0.2, -0.0});
    s.mesh.vertices.push_back({0x1p59 / 3, 0.2, -0.0});
    s.mesh.vertices.push_back({0x1p59 / 3, 1e-310, -0.0});
    s.mesh.vertices.push_back({0.1, 5e-324, -0.0});
    s.mesh.faces.push_back({base, base + 3, base + 2, base + 1});
    s.faceMaterial.push_back(0);
    s.mesh.vertices.push_back({0, 0, 1e17});
    s.mesh.vertices.push_back({0, 1e17, 1e17});
    s.mesh.vertices.push_back({1e17, 0, 1e17});
    s.mesh.faces.push_back({base + 4, base + 5, base + 6});
    s.faceMaterial.push_back(1);
    s.collectLights();
    ASSERT_NO_THROW(validateScene(s));

    writeObj(s, dir_ / "out.obj");
    EXPECT_EQ(filesIn(dir_), 2u);  // out.obj and out.mtl, no temporaries left
    const std::string objText = read(dir_ / "out.obj");
    const std::string mtlText = read(dir_ / "out.mtl");
    EXPECT_EQ(objText.rfind("# penumbra scene v1\n", 0), 0u);
    EXPECT_EQ(mtlText.rfind("# penumbra scene v1\n", 0), 0u);
    EXPECT_NE(objText.find("mtllib out.mtl\n"), std::string::npos);

    const Scene r = loadObj(dir_ / "out.obj");
    ASSERT_EQ(r.mesh.vertices.size(), s.mesh.vertices.size());
    for (size_t i = 0; i < s.mesh.vertices.size(); ++i) {
        for (int c = 0; c < 3; ++c) {
            ASSERT_EQ(bits(r.mesh.vertices[i][c]), bits(s.mesh.vertices[i][c])) << i << " " << c;
        }
    }
    EXPECT_EQ(r.mesh.faces, s.mesh.faces);
    EXPECT_EQ(r.lights, s.lights);
    // -1 faces after material faces come back with the written default material.
    ASSERT_EQ(r.materials.size(), 3u);
    EXPECT_EQ(r.materials[2].name, "penumbra_default");
    EXPECT_EQ(r.materials[2].kd, Material{}.kd);
    for (size_t m = 0; m < 2; ++m) {
        EXPECT_EQ(r.materials[m].name, s.materials[m].name);
        EXPECT_EQ(r.materials[m].kd, s.materials[m].kd);
        EXPECT_EQ(r.materials[m].ks, s.materials[m].ks);
        EXPECT_EQ(r.materials[m].ke, s.materials[m].ke);
        EXPECT_EQ(r.materials[m].ns, s.materials[m].ns);
    }
    for (size_t f = 0; f < s.faceMaterial.size(); ++f) {
        const int32_t expected = f == 0 ? -1 : s.faceMaterial[f] < 0 ? 2 : s.faceMaterial[f];
        EXPECT_EQ(r.faceMaterial[f], expected) << f;
    }

    // Writing again over the same files replaces them atomically.
    writeObj(r, dir_ / "out.obj");
    EXPECT_EQ(filesIn(dir_), 2u);
    const Scene again = loadObj(dir_ / "out.obj");
    EXPECT_EQ(again.faceMaterial, r.faceMaterial);
    EXPECT_EQ(again.materials.size(), 3u);
}

TEST_F(ObjFiles, WriteFailuresThrowAndLeaveNothingBehind) {
    const Scene s = loadObjFromString(kObj, kMtl, "room.obj");
    EXPECT_THROW(writeObj(s, dir_ / "no" / "such" / "dir" / "x.obj"), SceneError);
    // The target is a directory: the rename fails, the temporary is removed.
    fs::create_directories(dir_ / "blocked.obj" / "inside");
    try {
        writeObj(s, dir_ / "blocked.obj");
        ADD_FAILURE();
    } catch (const SceneError& e) {
        EXPECT_NE(std::string(e.what()).find("cannot write"), std::string::npos) << e.what();
    }
    for (const auto& e : fs::directory_iterator(dir_)) {
        EXPECT_EQ(e.path().filename().string().find(".tmp"), std::string::npos) << e.path();
    }
    EXPECT_THROW(writeObj(s, dir_ / "x.mtl"), SceneError);
    Scene bad = s;
    bad.materials[0].name = "two\nlines";
    EXPECT_THROW(writeObj(bad, dir_ / "bad.obj"), SceneError);
    bad = s;
    bad.mesh.vertices[6] = {1, 1.5, 3};  // face 1 becomes degenerate: not written
    EXPECT_THROW(writeObj(bad, dir_ / "bad.obj"), SceneError);
    EXPECT_FALSE(fs::exists(dir_ / "bad.obj"));
}

}  // namespace
}  // namespace penumbra
