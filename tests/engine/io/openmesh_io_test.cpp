// Tests of the PLY, OFF and STL readers (engine/io/openmesh_io.h) on small files written here, with
// counts, coordinates and face vertex lists checked against the values written.
#include "engine/io/openmesh_io.h"

#include <gtest/gtest.h>

#include <array>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include "tests/support/loader_test_support.h"

namespace penumbra {
namespace {

namespace fs = std::filesystem;
using test::expectLoadError;
using test::putF32;
using test::putU32;
using test::putU8;

// The test solid: a unit square at z=0 (face 0, a quad, facing +z) and a triangle standing on its
// edge y=0 (face 1: vertices 0, 1, 4, facing -y).
const std::vector<Vec3> kVertices = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0.5, 0, 1}};
const std::vector<std::vector<uint32_t>> kFaces = {{0, 1, 2, 3}, {0, 1, 4}};

void expectTestSolid(const Scene& scene) {
    ASSERT_EQ(scene.mesh.vertices.size(), kVertices.size());
    for (size_t i = 0; i < kVertices.size(); ++i)
        EXPECT_EQ(scene.mesh.vertices[i], kVertices[i]) << i;
    EXPECT_EQ(scene.mesh.faces, kFaces);
    EXPECT_EQ(scene.faceMaterial, std::vector<int32_t>(2, -1));
    EXPECT_TRUE(scene.lights.empty());
    EXPECT_TRUE(scene.warnings.empty());
    // Face 0 faces +z, face 1 faces -y (counter-clockwise kept).
    EXPECT_GT(scene.mesh.faceAreaNormal(0).z, 0);
    EXPECT_LT(scene.mesh.faceAreaNormal(1).y, 0);
    EXPECT_DOUBLE_EQ(scene.mesh.faceArea(0), 1.0);
    EXPECT_DOUBLE_EQ(scene.mesh.faceArea(1), 0.5);
}

std::string asciiPly(const std::string& vertexLines, const std::string& faceLines, int nv, int nf) {
    return "ply\nformat ascii 1.0\ncomment test\nelement vertex " + std::to_string(nv) +
           "\nproperty float x\nproperty float y\nproperty float z\nelement face " +
           std::to_string(nf) + "\nproperty list uchar int vertex_indices\nend_header\n" +
           vertexLines + faceLines;
}

const std::string kPlyVertices = "0 0 0\n1 0 0\n1 1 0\n0 1 0\n0.5 0 1\n";
const std::string kPlyFaces = "4 0 1 2 3\n3 0 1 4\n";

// A binary little-endian PLY of the test solid; each vertex has an extra uchar property.
std::string binaryPly() {
    std::string s =
        "ply\nformat binary_little_endian 1.0\nelement vertex 5\nproperty float x\n"
        "property float y\nproperty float z\nproperty uchar red\nelement face 2\n"
        "property list uchar int vertex_indices\nend_header\n";
    for (const Vec3& v : kVertices) {
        putF32(s, static_cast<float>(v.x));
        putF32(s, static_cast<float>(v.y));
        putF32(s, static_cast<float>(v.z));
        putU8(s, 200);
    }
    for (const auto& f : kFaces) {
        putU8(s, static_cast<uint8_t>(f.size()));
        for (uint32_t i : f) putU32(s, i);
    }
    return s;
}

class OpenMeshIo : public test::LoaderFiles {};

TEST_F(OpenMeshIo, AsciiPly) {
    expectTestSolid(loadOpenMeshFile(write("solid.ply", asciiPly(kPlyVertices, kPlyFaces, 5, 2))));
}

TEST_F(OpenMeshIo, BinaryPly) {
    expectTestSolid(loadOpenMeshFile(write("solid.PLY", binaryPly())));
}

TEST_F(OpenMeshIo, TruncatedBinaryPlyIsAnError) {
    const std::string full = binaryPly();
    for (size_t cut : {size_t{1}, size_t{5}, size_t{30}}) {
        const fs::path p =
            write("cut" + std::to_string(cut) + ".ply", full.substr(0, full.size() - cut));
        expectLoadError([&] { loadOpenMeshFile(p); }, p, {"truncated"});
    }
    const fs::path header = write("header.ply", full.substr(0, 40));
    expectLoadError([&] { loadOpenMeshFile(header); }, header, {"end_header"});
}

TEST_F(OpenMeshIo, TruncatedAsciiPlyIsAnError) {
    const fs::path p = write("cut.ply", asciiPly(kPlyVertices, "4 0 1 2 3\n", 5, 2));
    expectLoadError([&] { loadOpenMeshFile(p); }, p, {"truncated"});
}

TEST_F(OpenMeshIo, PlyNonFiniteCoordinateIsAnError) {
    const fs::path p =
        write("nan.ply", asciiPly("0 0 0\n1 0 0\n1 1 0\n0 1 0\n0.5 nan 1\n", kPlyFaces, 5, 2));
    expectLoadError([&] { loadOpenMeshFile(p); }, p, {"vertex 4", "non-finite"});
}

// engine/io/text_input.h's sign rule: one '+' is a sign, "+-" is no number (this reader once
// read "+-0.5" as -0.5 and handed the line to OpenMesh, which reads it otherwise).
TEST_F(OpenMeshIo, OnePlusIsASignAndASecondSignIsAnError) {
    expectTestSolid(loadOpenMeshFile(
        write("plus.ply", asciiPly("+0 0 0\n1 0 0\n1 +1 0\n0 1 0\n+0.5 0 +1\n", kPlyFaces, 5, 2))));
    const fs::path ply =
        write("sign.ply", asciiPly("0 0 0\n1 0 0\n1 1 0\n0 1 0\n+-0.5 0 1\n", kPlyFaces, 5, 2));
    expectLoadError([&] { loadOpenMeshFile(ply); }, ply, {"vertex 4", "'+-0.5'"});
    const fs::path off = write("sign.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 +-1 0\n3 0 1 2\n");
    expectLoadError([&] { loadOpenMeshFile(off); }, off, {"vertex 2", "'+-1'"});
}

TEST_F(OpenMeshIo, PlyIndexOutOfRangeNamesTheFace) {
    const fs::path p = write("range.ply", asciiPly(kPlyVertices, "4 0 1 2 3\n3 0 1 7\n", 5, 2));
    expectLoadError([&] { loadOpenMeshFile(p); }, p, {"face 1", "out of range"});
}

TEST_F(OpenMeshIo, PlyNonPlanarFaceNamesTheFace) {
    const fs::path p =
        write("bent.ply", asciiPly("0 0 0\n1 0 0\n1 1 0.1\n0 1 0\n0.5 0 1\n", kPlyFaces, 5, 2));
    expectLoadError([&] { loadOpenMeshFile(p, LoadOptions::strictMode()); }, p,
                    {"face 0", "non-planar"});
}

TEST_F(OpenMeshIo, PlyNonConvexFaceNamesTheFace) {
    // An arrow head: vertex 2 is reflex.
    const fs::path p = write("reflex.ply", asciiPly("0 0 0\n2 0 0\n1 0.5 0\n2 2 0\n0.5 0 1\n",
                                                    "3 0 1 4\n4 0 1 2 3\n", 5, 2));
    expectLoadError([&] { loadOpenMeshFile(p, LoadOptions::strictMode()); }, p,
                    {"face 1", "non-convex"});
}

TEST_F(OpenMeshIo, DegenerateFaceIsDroppedByDefaultAndAnErrorWhenStrict) {
    // Face 1 is collinear (zero area), face 2 repeats a vertex.
    const std::string text =
        asciiPly(kPlyVertices + "2 0 0\n", "4 0 1 2 3\n3 0 1 5\n3 0 4 4\n3 0 1 4\n", 6, 4);
    const fs::path p = write("degenerate.ply", text);
    expectLoadError([&] { loadOpenMeshFile(p, LoadOptions::strictMode()); }, p,
                    {"face 1", "degenerate"});
    const Scene scene = loadOpenMeshFile(p);
    EXPECT_EQ(scene.mesh.faces, kFaces);
    ASSERT_EQ(scene.warnings.size(), 1u);
    EXPECT_NE(scene.warnings[0].find(p.string() + ": dropped 2 degenerate"), std::string::npos)
        << scene.warnings[0];
    EXPECT_NE(scene.warnings[0].find("face 1"), std::string::npos) << scene.warnings[0];
}

TEST_F(OpenMeshIo, OffDegenerateFaceIsDroppedByDefaultAndAnErrorWhenStrict) {
    // Face 1 repeats vertex 4.
    const fs::path p = write("degenerate.off",
                             "OFF\n5 3 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n0.5 0 1\n"
                             "4 0 1 2 3\n3 0 4 4\n3 0 1 4\n");
    expectLoadError([&] { loadOpenMeshFile(p, LoadOptions::strictMode()); }, p,
                    {"face 1", "repeated"});
    const Scene scene = loadOpenMeshFile(p);
    EXPECT_EQ(scene.mesh.faces, kFaces);
    ASSERT_EQ(scene.warnings.size(), 1u);
    EXPECT_NE(scene.warnings[0].find(p.string() + ": dropped 1 degenerate"), std::string::npos)
        << scene.warnings[0];
    EXPECT_NE(scene.warnings[0].find("face 1"), std::string::npos) << scene.warnings[0];
}

// Repair mode splits a concave polygon and a non-planar quad into triangles of their own vertices,
// in PLY and OFF alike, with one warning per kind; strict mode refuses them.
TEST_F(OpenMeshIo, ConcaveAndNonPlanarPolygonsAreSplitIntoTriangles) {
    const std::string vertices =
        "0 0 0\n2 0 0\n2 2 0\n1 0.5 0\n0 2 0\n"   // a concave pentagon (a dart at vertex 3)
        "0 0 1\n1 0 1\n1 1 1.00000025\n0 1 1\n";  // a quad planar only to 2.5e-7
    const std::string ply =
        "ply\nformat ascii 1.0\nelement vertex 9\nproperty float x\n"
        "property float y\nproperty float z\nelement face 2\n"
        "property list uchar int vertex_indices\nend_header\n" +
        vertices + "5 0 1 2 3 4\n4 5 6 7 8\n";
    const std::string off = "OFF\n9 2 0\n" + vertices + "5 0 1 2 3 4\n4 5 6 7 8\n";
    for (const auto& [name, text] : {std::pair{"poly.ply", ply}, std::pair{"poly.off", off}}) {
        SCOPED_TRACE(name);
        const fs::path p = write(name, text);
        const Scene scene = loadOpenMeshFile(p);
        // 3 triangles for the pentagon, 2 for the quad, in the faces' order.
        ASSERT_EQ(scene.faceCount(), 5u);
        for (uint32_t f = 0; f < 3; ++f)
            for (uint32_t v : scene.mesh.faces[f]) EXPECT_LT(v, 5u);
        for (uint32_t f = 3; f < 5; ++f)
            for (uint32_t v : scene.mesh.faces[f]) EXPECT_GE(v, 5u);
        // The pentagon's area (the square 4 less the notch 2 x 1.5 / 2) is kept exactly.
        double area = 0;
        for (uint32_t f = 0; f < 3; ++f) area += scene.mesh.faceArea(f);
        EXPECT_NEAR(area, 2.5, 1e-12);
        ASSERT_EQ(scene.warnings.size(), 2u);
        EXPECT_NE(
            scene.warnings[0].find("split 1 non-planar faces into 2 triangles (first: face 1"),
            std::string::npos)
            << scene.warnings[0];
        EXPECT_NE(
            scene.warnings[1].find("split 1 non-convex faces into 3 triangles (first: face 0"),
            std::string::npos)
            << scene.warnings[1];
        expectLoadError([&] { loadOpenMeshFile(p, LoadOptions::strictMode()); }, p,
                        {"face 0", "non-convex", "strict mode refuses them"});
    }
}

// A tool's line between the header lines, outside a comment: skipped with a warning in repair
// mode, in ASCII and binary files alike; strict mode refuses it.
TEST_F(OpenMeshIo, PlyUnknownHeaderLineIsSkippedWithAWarning) {
    std::string ascii = asciiPly(kPlyVertices, kPlyFaces, 5, 2);
    ascii.insert(ascii.find("comment test"), "Created by Blender 2.93\n");  // line 3
    std::string binary = binaryPly();
    binary.insert(binary.find("element face"), "\tgenerated by scanner\nobj_extra 7\n");  // 8, 9
    for (const bool isBinary : {false, true}) {
        const fs::path p = write(isBinary ? "tool_bin.ply" : "tool.ply", isBinary ? binary : ascii);
        Scene scene = loadOpenMeshFile(p);
        ASSERT_EQ(scene.warnings.size(), 1u);
        EXPECT_EQ(scene.warnings[0],
                  isBinary ? p.string() +
                                 ":8: PLY header: line 'generated by scanner' is no header "
                                 "keyword (not a comment): skipped with 1 more such lines"
                           : p.string() +
                                 ":3: PLY header: line 'Created by Blender 2.93' is no header "
                                 "keyword (not a comment): skipped");
        scene.warnings.clear();
        expectTestSolid(scene);
        expectLoadError([&] { loadOpenMeshFile(p, LoadOptions::strictMode()); }, p,
                        {isBinary ? ":8: PLY header: unknown keyword 'generated'"
                                  : ":3: PLY header: unknown keyword 'Created'"});
    }
    // The rest of the header must still be consistent: a count beyond the body is refused.
    std::string bad = asciiPly(kPlyVertices, kPlyFaces, 5, 9);
    bad.insert(bad.find("comment test"), "Created by Blender 2.93\n");
    const fs::path q = write("tool_bad.ply", bad);
    expectLoadError([&] { loadOpenMeshFile(q); }, q, {"face", "9"});
}

TEST_F(OpenMeshIo, PlyMalformedHeaderIsAnError) {
    const fs::path p = write("bad.ply", "ply\nformat ascii 1.0\nelement vertex x\nend_header\n");
    expectLoadError([&] { loadOpenMeshFile(p); }, p, {"bad count"});
    const fs::path q = write("notply.ply", "hello\n");
    expectLoadError([&] { loadOpenMeshFile(q); }, q, {"ply"});
    const fs::path e = write("empty.ply", "");
    expectLoadError([&] { loadOpenMeshFile(e); }, e, {"empty"});
}

const std::string kOff =
    "OFF\n# the test solid\n5 2 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n0.5 0 1\n4 0 1 2 3\n3 0 1 4\n";

TEST_F(OpenMeshIo, Off) { expectTestSolid(loadOpenMeshFile(write("solid.off", kOff))); }

TEST_F(OpenMeshIo, TruncatedOffIsAnError) {
    const fs::path p = write("cut.off", kOff.substr(0, kOff.size() - 8));
    expectLoadError([&] { loadOpenMeshFile(p); }, p, {"2 faces"});
    const fs::path q = write("short.off", "OFF\n5 2 0\n0 0 0\n1 0 0\n");
    expectLoadError([&] { loadOpenMeshFile(q); }, q, {});
    const fs::path r = write("noheader.off", "5 2 0\n");
    expectLoadError([&] { loadOpenMeshFile(r); }, r, {"OFF"});
}

// Two triangles of the unit square at z = 0, facing +z; 4 distinct corners.
const float kStlTriangles[2][9] = {{0, 0, 0, 1, 0, 0, 1, 1, 0}, {0, 0, 0, 1, 1, 0, 0, 1, 0}};

std::string binaryStl(const std::vector<std::array<float, 9>>& triangles) {
    std::string s(80, ' ');
    putU32(s, static_cast<uint32_t>(triangles.size()));
    for (const auto& t : triangles) {
        for (int k = 0; k < 3; ++k) putF32(s, k == 2 ? 1.0f : 0.0f);  // normal
        for (float x : t) putF32(s, x);
        s += std::string(2, '\0');
    }
    return s;
}

std::vector<std::array<float, 9>> stlSquare() {
    std::vector<std::array<float, 9>> t(2);
    for (int i = 0; i < 2; ++i)
        for (int k = 0; k < 9; ++k) t[i][k] = kStlTriangles[i][k];
    return t;
}

std::string asciiStl(const std::vector<std::array<float, 9>>& triangles, bool end = true) {
    std::string s = "solid square\n";
    for (const auto& t : triangles) {
        s += "  facet normal 0 0 1\n    outer loop\n";
        for (int k = 0; k < 3; ++k) {
            s += "      vertex " + std::to_string(t[3 * k]) + " " + std::to_string(t[3 * k + 1]) +
                 " " + std::to_string(t[3 * k + 2]) + "\n";
        }
        s += "    endloop\n  endfacet\n";
    }
    if (end) s += "endsolid square\n";
    return s;
}

// `extraVertices`: the corners of dropped facets that no other facet has.
void expectStlSquare(const Scene& scene, size_t extraVertices = 0) {
    ASSERT_EQ(scene.mesh.faces.size(), 2u);
    EXPECT_EQ(scene.mesh.vertices.size(), 4u + extraVertices);  // corners are merged
    for (size_t f = 0; f < 2; ++f) {
        ASSERT_EQ(scene.mesh.faces[f].size(), 3u);
        for (size_t k = 0; k < 3; ++k) {
            const Vec3 v = scene.mesh.vertices[scene.mesh.faces[f][k]];
            EXPECT_EQ(v, Vec3(kStlTriangles[f][3 * k], kStlTriangles[f][3 * k + 1],
                              kStlTriangles[f][3 * k + 2]))
                << f << " " << k;
        }
        EXPECT_GT(scene.mesh.faceAreaNormal(static_cast<uint32_t>(f)).z, 0);
    }
    EXPECT_TRUE(scene.lights.empty());
}

TEST_F(OpenMeshIo, AsciiStl) {
    expectStlSquare(loadOpenMeshFile(write("square.stl", asciiStl(stlSquare()))));
}

TEST_F(OpenMeshIo, BinaryStl) {
    expectStlSquare(loadOpenMeshFile(write("square.stl", binaryStl(stlSquare()))));
}

TEST_F(OpenMeshIo, TruncatedStlIsAnError) {
    const std::string bin = binaryStl(stlSquare());
    const fs::path p = write("cut.stl", bin.substr(0, bin.size() - 10));
    expectLoadError([&] { loadOpenMeshFile(p); }, p, {"truncated", "2 triangles"});
    const fs::path tiny = write("tiny.stl", bin.substr(0, 50));
    expectLoadError([&] { loadOpenMeshFile(tiny); }, tiny, {"truncated"});
    const fs::path a = write("cut_ascii.stl", asciiStl(stlSquare(), false));
    expectLoadError([&] { loadOpenMeshFile(a); }, a, {"endsolid"});
}

TEST_F(OpenMeshIo, StlNonFiniteIsAnError) {
    auto t = stlSquare();
    t[1][4] = std::numeric_limits<float>::quiet_NaN();
    const fs::path p = write("nan.stl", binaryStl(t));
    expectLoadError([&] { loadOpenMeshFile(p); }, p, {"facet 1", "non-finite"});
    const fs::path a = write("nan_ascii.stl",
                             "solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 "
                             "nan\nvertex 0 1 0\nendloop\nendfacet\nendsolid x\n");
    expectLoadError([&] { loadOpenMeshFile(a); }, a, {"facet 0"});
}

TEST_F(OpenMeshIo, StlDegenerateFacetIsDroppedByDefaultAndAnErrorWhenStrict) {
    // Facet 1: corners 1 and 2 coincide (OpenMesh skips it); facet 3: three distinct collinear
    // corners (validation finds it). One warning counts both, facets numbered as in the file.
    auto t = stlSquare();
    t.insert(t.begin() + 1, std::array<float, 9>{0, 0, 0, 1, 0, 0, 1, 0, 0});
    t.push_back({0, 0, 0, 0.5f, 0.5f, 0, 1, 1, 0});
    for (const bool binary : {true, false}) {
        const fs::path p =
            write(binary ? "deg.stl" : "deg_ascii.stl", binary ? binaryStl(t) : asciiStl(t));
        // Strict: the first facet, with its line in ASCII (7 lines a facet: facet 1 on line 9).
        expectLoadError([&] { loadOpenMeshFile(p, LoadOptions::strictMode()); }, p,
                        {binary ? ": face 1" : ":9: face 1", "degenerate", "corners coincide"});
        const Scene scene = loadOpenMeshFile(p);
        expectStlSquare(scene, 1);  // (0.5, 0.5, 0), the collinear facet's middle corner
        ASSERT_EQ(scene.warnings.size(), 1u);
        EXPECT_NE(scene.warnings[0].find(p.string() + ": dropped 2 degenerate"), std::string::npos)
            << scene.warnings[0];
        EXPECT_NE(scene.warnings[0].find(binary ? "(first: face 1: " : "(first: face 1, line 9: "),
                  std::string::npos)
            << scene.warnings[0];
        if (!binary) {
            EXPECT_EQ(scene.faceSourceLine, (std::vector<int32_t>{2, 16}));
        }
    }
    // A collinear facet with distinct corners is found by validation, named by its facet index.
    auto c = stlSquare();
    c.push_back({0, 0, 0, 1, 1, 0, 2, 2, 0});
    const fs::path q = write("collinear.stl", binaryStl(c));
    expectLoadError([&] { loadOpenMeshFile(q, LoadOptions::strictMode()); }, q,
                    {"face 2", "degenerate"});
}

// Solids one after the other in one ASCII file (as tools concatenate them): every facet is read,
// as one mesh whose equal corners are merged across the solids.
TEST_F(OpenMeshIo, MultiSolidAsciiStlLoadsEverySolid) {
    const auto t = stlSquare();
    const std::string first = asciiStl({t[0]});
    std::string second = asciiStl({t[1]});
    second.replace(0, std::string("solid square").size(), "SOLID other part");
    second.replace(second.find("endsolid square"), 15, "endsolid other part");
    // The second solid starts on line 10, after two blank lines on 12.
    const std::pair<std::string, int32_t> files[] = {
        {first + second, 11}, {first + "\n\n" + second + "trailing junk\n", 13}};
    for (const auto& [text, secondFacetLine] : files) {
        const fs::path p = write("two.stl", text);
        const Scene scene = loadOpenMeshFile(p);
        expectStlSquare(scene);
        EXPECT_TRUE(scene.warnings.empty());
        EXPECT_EQ(scene.faceSourceLine, (std::vector<int32_t>{2, secondFacetLine}));
    }
    // A solid left open is still a truncated file.
    const fs::path p = write("open.stl", first + asciiStl({t[1]}, false));
    expectLoadError([&] { loadOpenMeshFile(p); }, p, {"no endsolid"});
    // A facet cut short by endsolid too.
    std::string cut = first;
    cut.insert(cut.find("endloop"), "endsolid square\n");
    const fs::path q = write("cut_facet.stl", cut);
    expectLoadError([&] { loadOpenMeshFile(q); }, q, {"facet 0", "no endfacet"});
}

}  // namespace
}  // namespace penumbra
