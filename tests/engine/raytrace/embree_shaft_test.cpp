// EmbreeScene::shaftCandidates (a query of the hierarchy of face boxes, visibility/box_tree.h,
// with the supporting planes of the hull of receiver and light) against the same test over every
// face: the sets must be identical; and no face with a point strictly inside the hull may be
// missing from them.
#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <vector>

#include "engine/raytrace/embree_scene.h"
#include "engine/scene/procedural_scenes.h"
#include "tests/support/test_scale.h"
#include "visibility/pair_occluders.h"

namespace {

using penumbra::EmbreeScene;
using penumbra::Vec3;
using penumbra::vis::PolygonMesh;

std::vector<Vec3> polygon(const PolygonMesh& m, uint32_t f) {
    std::vector<Vec3> p;
    for (uint32_t v : m.faces[f]) p.push_back(m.vertices[v]);
    return p;
}

// The reference: every face other than receiver and light with at least 3 vertices whose box is
// not certainly outside one of the hull's planes (or, for a degenerate hull, meets the box of
// both). Boxes recomputed here from the mesh.
std::vector<uint32_t> bruteForce(const PolygonMesh& m, uint32_t receiver, uint32_t light) {
    const auto hull = penumbra::vis::hullPlanes(polygon(m, receiver), polygon(m, light));
    penumbra::vis::Bounds3 shaft = m.faceBounds(receiver);
    const penumbra::vis::Bounds3 l = m.faceBounds(light);
    shaft.add(l.lo);
    shaft.add(l.hi);
    const bool degenerate =
        hull.empty() || m.faces[receiver].size() < 3 || m.faces[light].size() < 3;
    std::vector<uint32_t> out;
    for (uint32_t f = 0; f < m.faces.size(); ++f) {
        if (f == receiver || f == light || m.faces[f].size() < 3) continue;
        const penumbra::vis::Bounds3 b = m.faceBounds(f);
        bool keep = true;
        if (degenerate)
            keep = b.overlaps(shaft);
        else
            for (const auto& p : hull) keep = keep && !p.boxNegative(b.lo, b.hi);
        if (keep) out.push_back(f);
    }
    return out;
}

// Faces with a vertex strictly inside every hull plane: they certainly meet the hull.
std::vector<uint32_t> surelyInside(const PolygonMesh& m, uint32_t receiver, uint32_t light) {
    const auto hull = penumbra::vis::hullPlanes(polygon(m, receiver), polygon(m, light));
    std::vector<uint32_t> out;
    if (hull.empty()) return out;
    for (uint32_t f = 0; f < m.faces.size(); ++f) {
        if (f == receiver || f == light || m.faces[f].size() < 3) continue;
        for (uint32_t v : m.faces[f]) {
            bool inside = true;
            for (const auto& p : hull)
                inside = inside && p.sign(m.vertices[v]) == penumbra::vis::Sign::Positive;
            if (inside) {
                out.push_back(f);
                break;
            }
        }
    }
    return out;
}

// Random triangles and quads with corners on a coarse dyadic grid (so boxes often touch exactly),
// sizes from tiny to scene-sized, an offset that makes float rounding matter, and a few faces with
// fewer than 3 vertices.
PolygonMesh randomMesh(std::mt19937_64& rng, int faces, double offset) {
    PolygonMesh m;
    std::uniform_real_distribution<double> unit(0, 1);
    auto grid = [&](double extent) { return std::round(unit(rng) * extent * 64) / 64; };
    for (int i = 0; i < faces; ++i) {
        const double size = std::pow(2.0, -static_cast<int>(rng() % 8));
        const Vec3 base{grid(16) + offset, grid(16) - offset, grid(16) + offset * 0.5};
        const int n = (rng() % 16 == 0) ? 2 : 3 + static_cast<int>(rng() % 2);
        std::vector<uint32_t> idx;
        for (int k = 0; k < n; ++k) {
            idx.push_back(static_cast<uint32_t>(m.vertices.size()));
            m.vertices.push_back(base + Vec3{grid(size), grid(size), grid(size)});
        }
        m.faces.push_back(std::move(idx));
    }
    return m;
}

TEST(EmbreeShaft, MatchesBruteForceOnRandomMeshes) {
    std::mt19937_64 rng(42);
    const int scenes = penumbra::test::scaled(12);
    for (int s = 0; s < scenes; ++s) {
        const double offset = (s % 3 == 0) ? 0.0 : (s % 3 == 1 ? 1000.5 : 3.0e5);
        const PolygonMesh m = randomMesh(rng, 300 + 100 * s, offset);
        const EmbreeScene scene(m);
        size_t nonEmpty = 0;
        for (int p = 0; p < 200; ++p) {
            const auto nf = static_cast<uint32_t>(m.faces.size());
            const uint32_t r = static_cast<uint32_t>(rng() % nf);
            uint32_t l = static_cast<uint32_t>(rng() % nf);
            if (l == r) l = (l + 1) % nf;
            if (m.faces[r].size() < 3 || m.faces[l].size() < 3) continue;
            const std::vector<uint32_t> expected = bruteForce(m, r, l);
            const std::vector<uint32_t> got = scene.shaftCandidates(r, l);
            ASSERT_EQ(got, expected) << "scene " << s << " receiver " << r << " light " << l;
            for (uint32_t f : surelyInside(m, r, l))
                ASSERT_TRUE(std::binary_search(got.begin(), got.end(), f))
                    << "face " << f << " meets the hull but is not a candidate";
            nonEmpty += !expected.empty();
        }
        // The random pairs must exercise the query (most shafts meet some face).
        EXPECT_GT(nonEmpty, 50u) << "scene " << s;
    }
}

// Faces touching the hull (here the box [0,1]^2 x [0,2]) exactly at a face, an edge or a corner
// count; so may faces a hair away (the box test is certain, with a margin: conservative); faces
// clearly away do not.
TEST(EmbreeShaft, TouchingCountsClearlyAwayDoesNot) {
    PolygonMesh m;
    auto quad = [&](Vec3 lo, Vec3 hi) {  // axis-aligned quad in z = lo.z
        const auto b = static_cast<uint32_t>(m.vertices.size());
        m.vertices.insert(
            m.vertices.end(),
            {{lo.x, lo.y, lo.z}, {hi.x, lo.y, lo.z}, {hi.x, hi.y, lo.z}, {lo.x, hi.y, lo.z}});
        m.faces.push_back({b, b + 1, b + 2, b + 3});
    };
    quad({0, 0, 0}, {1, 1, 0});              // receiver
    quad({0, 0, 2}, {1, 1, 2});              // light
    quad({1, 0.5, 1}, {2, 1, 1});            // 2: touches x = 1
    quad({1.01, 0.5, 1}, {2, 1, 1});         // 3: clearly away
    quad({1, 1, 2}, {2, 2, 2});              // 4: corner contact
    quad({-1, -1, 2.01}, {3, 3, 3});         // 5: clearly above
    quad({0.25, 0.25, 1}, {0.75, 0.75, 1});  // 6: inside
    const EmbreeScene scene(m);
    EXPECT_EQ(scene.shaftCandidates(0, 1), (std::vector<uint32_t>{2, 4, 6}));
    EXPECT_EQ(scene.shaftCandidates(0, 1), bruteForce(m, 0, 1));
}

}  // namespace
