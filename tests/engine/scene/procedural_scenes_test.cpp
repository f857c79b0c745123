// Structural checks of the procedural test scenes: triangle counts, exact planarity, strict
// convexity, orientation of receivers and lights, one light each.
#include "engine/scene/procedural_scenes.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <set>
#include <string>
#include <vector>

#include "visibility/predicates.h"

namespace {

using penumbra::Scene;
using penumbra::Vec3;
using penumbra::vis::orientSign;
using penumbra::vis::Sign;

Vec3 faceCentroid(const Scene& s, uint32_t f) {
    Vec3 c{};
    for (uint32_t i : s.mesh.faces[f]) c += s.mesh.vertex(i);
    return c / static_cast<double>(s.mesh.faces[f].size());
}

// Every face: valid distinct indices, exactly planar (orient3d of its first three vertices with
// each other vertex is exactly zero), strictly convex (every consecutive triple turns the same
// way as the face normal, exactly: orient3d against a point well off the face's front), nonzero
// area. Materials and source lines consistent; exactly one light, facing the floor (face 0).
void checkScene(const Scene& s, const std::string& name) {
    SCOPED_TRACE(name);
    const auto& m = s.mesh;
    ASSERT_EQ(s.faceMaterial.size(), m.faces.size());
    ASSERT_EQ(s.faceSourceLine.size(), m.faces.size());
    for (int32_t line : s.faceSourceLine) EXPECT_EQ(line, 0);
    for (uint32_t f = 0; f < m.faces.size(); ++f) {
        SCOPED_TRACE("face " + std::to_string(f));
        const auto& idx = m.faces[f];
        ASSERT_GE(idx.size(), 3u);
        const std::set<uint32_t> distinct(idx.begin(), idx.end());
        EXPECT_EQ(distinct.size(), idx.size());
        for (uint32_t i : idx) ASSERT_LT(i, m.vertices.size());
        ASSERT_GE(s.faceMaterial[f], 0);
        ASSERT_LT(static_cast<size_t>(s.faceMaterial[f]), s.materials.size());

        const Vec3 a = m.vertex(idx[0]), b = m.vertex(idx[1]), c = m.vertex(idx[2]);
        for (size_t k = 3; k < idx.size(); ++k)
            EXPECT_EQ(orientSign(a, b, c, m.vertex(idx[k])), Sign::Zero) << "not planar";

        const Vec3 n = m.faceAreaNormal(f);
        ASSERT_GT(penumbra::vis::length(n), 0.0);
        double size = 0;
        for (size_t k = 0; k < idx.size(); ++k)
            size = std::max(size, penumbra::vis::length(m.vertex(idx[k]) -
                                                        m.vertex(idx[(k + 1) % idx.size()])));
        const Vec3 front = faceCentroid(s, f) + penumbra::vis::normalize(n) * size;
        for (size_t k = 0; k < idx.size(); ++k) {
            const Vec3 p = m.vertex(idx[k]), q = m.vertex(idx[(k + 1) % idx.size()]),
                       r = m.vertex(idx[(k + 2) % idx.size()]);
            EXPECT_EQ(orientSign(p, q, r, front), Sign::Positive) << "not strictly convex at " << k;
        }
    }
    ASSERT_EQ(s.lights.size(), 1u);
    const uint32_t light = s.lights[0];
    EXPECT_NE(light, 0u);
    EXPECT_TRUE(s.material(light).isEmissive());
    EXPECT_EQ(m.faces[light].size(), 4u);
    // the light faces the floor, and some of the light is in front of the floor
    const Vec3 toFloor = faceCentroid(s, 0) - faceCentroid(s, light);
    EXPECT_GT(penumbra::vis::dot(m.faceAreaNormal(light), toFloor), 0);
    const auto& fl = m.faces[0];
    bool someInFront = false;
    for (uint32_t i : m.faces[light])
        someInFront = someInFront || orientSign(m.vertex(fl[0]), m.vertex(fl[1]), m.vertex(fl[2]),
                                                m.vertex(i)) == Sign::Positive;
    EXPECT_TRUE(someInFront);
}

TEST(ProceduralScenes, Stairs) {
    const Scene s = penumbra::makeStairs();
    checkScene(s, "stairs");
    EXPECT_GE(penumbra::triangleCount(s), 240u);
    EXPECT_LE(penumbra::triangleCount(s), 250u);
}

TEST(ProceduralScenes, Table) {
    const Scene s = penumbra::makeTable();
    checkScene(s, "table");
    EXPECT_GE(penumbra::triangleCount(s), 1340u);
    EXPECT_LE(penumbra::triangleCount(s), 1360u);
}

TEST(ProceduralScenes, Grids) {
    const Scene s = penumbra::makeGrids();
    checkScene(s, "grids");
    EXPECT_EQ(penumbra::triangleCount(s), 154u);
    for (uint32_t f = 0; f < 4; ++f) EXPECT_GT(s.mesh.faceAreaNormal(f).z, 0);
}

TEST(ProceduralScenes, CornellBox) {
    const Scene s = penumbra::makeCornellBox();
    checkScene(s, "cornell");
    EXPECT_GE(penumbra::triangleCount(s), 30u);
    EXPECT_LE(penumbra::triangleCount(s), 40u);
    // walls face the inside of the box
    const Vec3 center{278, 274.4, 279.6};
    for (uint32_t f = 0; f < s.faceCount(); ++f) {
        const std::string& mat = s.materials[static_cast<size_t>(s.faceMaterial[f])].name;
        if (mat == "red" || mat == "green") {
            EXPECT_GT(penumbra::vis::dot(s.mesh.faceAreaNormal(f), center - faceCentroid(s, f)), 0);
        }
    }
}

TEST(ProceduralScenes, HardCases) {
    const auto cases = penumbra::makeHardCases();
    EXPECT_GE(cases.size(), 12u);
    std::set<std::string> names;
    for (const auto& [name, scene] : cases) {
        names.insert(name);
        checkScene(scene, name);
        EXPECT_LE(penumbra::triangleCount(scene), 60u) << name;
        EXPECT_GE(scene.faceCount(), 3u) << name;
    }
    EXPECT_EQ(names.size(), cases.size());
}

TEST(ProceduralScenes, RandomSoup) {
    for (uint64_t seed : {1u, 2u, 99u}) {
        const Scene s = penumbra::makeRandomSoup(200, seed);
        checkScene(s, "soup");
        EXPECT_EQ(penumbra::triangleCount(s), 204u);
        for (const Vec3& v : s.mesh.vertices) {
            EXPECT_GE(v.z, 0.0);
            EXPECT_LE(v.z, 2.0);
        }
    }
    // deterministic
    EXPECT_EQ(penumbra::makeRandomSoup(50, 7).mesh.vertices,
              penumbra::makeRandomSoup(50, 7).mesh.vertices);
}

TEST(ProceduralScenes, Transformed) {
    const Scene s = penumbra::makeGrids();
    const Scene t = penumbra::transformed(s, 2, {1, -2, 3});
    ASSERT_EQ(t.mesh.vertices.size(), s.mesh.vertices.size());
    for (size_t i = 0; i < s.mesh.vertices.size(); ++i)
        EXPECT_EQ(t.mesh.vertices[i], s.mesh.vertices[i] * 2 + Vec3(1, -2, 3));
    EXPECT_EQ(t.mesh.faces, s.mesh.faces);
    EXPECT_EQ(t.lights, s.lights);
    checkScene(t, "grids transformed");
}

}  // namespace
