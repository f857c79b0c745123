// Tests of S_L (light_silhouette_edges.h) and the edge table under it: hand-counted sets on a cube
// under lights placed so that each kind of edge occurs (silhouette, hidden, coplanar, open), and
// soundness on random closed meshes: no edge left out is a silhouette seen from any point of L,
// tested with exact signs at L's vertices and at points inside L near them (sub-ulp offsets).
#include "visibility/light_silhouette_edges.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <span>
#include <vector>

#include "tests/support/test_scale.h"
#include "visibility/face_plane.h"
#include "visibility/light_edge_index.h"
#include "visibility/mesh_edges.h"

namespace penumbra::vis {
namespace {

// The unit cube [0,1]^3 as six outward quads (counter-clockwise seen from outside), then a
// square light of half-side `h` centred over the cube at height z, facing down.
PolygonMesh cubeUnderLight(double z, double h) {
    PolygonMesh m;
    for (int i = 0; i < 8; ++i)
        m.vertices.push_back({double(i & 1), double((i >> 1) & 1), double(i >> 2)});
    m.faces = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
    const uint32_t b = 8;
    m.vertices.push_back({0.5 - h, 0.5 - h, z});
    m.vertices.push_back({0.5 - h, 0.5 + h, z});
    m.vertices.push_back({0.5 + h, 0.5 + h, z});
    m.vertices.push_back({0.5 + h, 0.5 - h, z});
    m.faces.push_back({b, b + 1, b + 2, b + 3});  // normal -z
    return m;
}

TEST(MeshEdges, EachEdgeOnceWithItsUsesAndTheirDirections) {
    const PolygonMesh m = cubeUnderLight(3, 0.1);
    const MeshEdges edges(m);
    ASSERT_EQ(edges.size(), 12u + 4u);  // the cube's 12, the light's 4
    size_t manifold = 0;
    for (size_t e = 0; e < edges.size(); ++e) {
        EXPECT_LT(edges.edge(e).lo, edges.edge(e).hi);
        manifold += edges.manifold(e);
        for (const MeshEdges::Use& u : edges.uses(e)) {
            // The face really has the edge, in the direction the use says.
            const auto& f = m.faces[u.face];
            bool found = false;
            for (size_t i = 0; i < f.size(); ++i) {
                const uint32_t a = f[i], b = f[(i + 1) % f.size()];
                if (std::min(a, b) == edges.edge(e).lo && std::max(a, b) == edges.edge(e).hi) {
                    found = true;
                    EXPECT_EQ(u.forward, a < b);
                }
            }
            EXPECT_TRUE(found);
        }
    }
    EXPECT_EQ(manifold, 12u);
}

TEST(LightSilhouetteEdges, CubeUnderANarrowLightKeepsItsTopRimAndTheOpenEdges) {
    // The light (x, y in [0.4, 0.6], z = 3) is in front of the top face's plane and behind every
    // other face's: the top face's four edges are silhouettes from L (top faces L, sides face
    // away), the four vertical and four bottom edges join two faces that both face away. The
    // light's own four edges are borders: kept.
    const PolygonMesh m = cubeUnderLight(3, 0.1);
    const MeshEdges edges(m);
    const LightSilhouetteEdges s(m, edges, 6);
    EXPECT_EQ(s.size(), 8u);
    EXPECT_EQ(s.open(), 4u);
    EXPECT_DOUBLE_EQ(s.share(), 0.5);
    for (size_t e = 0; e < edges.size(); ++e) {
        const auto& ed = edges.edge(e);
        const bool top = ed.lo >= 4 && ed.hi < 8, light = ed.lo >= 8;
        EXPECT_EQ(s.contains(e), top || light) << ed.lo << "-" << ed.hi;
    }
}

TEST(LightSilhouetteEdges, AWideLightSeesEverySideFromBothSides) {
    // x, y in [-0.5, 1.5]: every side face's plane cuts L (mixed signs): all 12 edges kept.
    const PolygonMesh m = cubeUnderLight(3, 1.0);
    const MeshEdges edges(m);
    const LightSilhouetteEdges s(m, edges, 6);
    EXPECT_EQ(s.size(), 16u);
}

TEST(LightSilhouetteEdges, ALightInAFacesPlaneKeepsThatFacesEdges) {
    // z = 1: L lies in the top face's plane (zero signs, lines grazing it): the top edges stay;
    // the vertical and bottom edges still join two faces that L sees from behind.
    const PolygonMesh m = cubeUnderLight(1, 0.1);
    const MeshEdges edges(m);
    const LightSilhouetteEdges s(m, edges, 6);
    EXPECT_EQ(s.size(), 8u);
}

TEST(LightSilhouetteEdges, InconsistentlyOrientedFacesKeepTheirEdges) {
    // The bottom face flipped: its four edges are used twice in the same direction (open).
    PolygonMesh m = cubeUnderLight(3, 0.1);
    m.faces[0] = {0, 1, 3, 2};
    const MeshEdges edges(m);
    const LightSilhouetteEdges s(m, edges, 6);
    EXPECT_EQ(s.open(), 8u);
    EXPECT_EQ(s.size(), 12u);
}

// A closed, consistently oriented triangle mesh: an octahedron subdivided `levels` times, its
// vertices pushed to random radii in [0.6, 1.4] about c (star-shaped, planar triangles).
PolygonMesh randomBlob(std::mt19937_64& rng, const Vec3& c, int levels) {
    PolygonMesh m;
    m.vertices = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
    m.faces = {{0, 2, 4}, {2, 1, 4}, {1, 3, 4}, {3, 0, 4},
               {2, 0, 5}, {1, 2, 5}, {3, 1, 5}, {0, 3, 5}};
    for (int l = 0; l < levels; ++l) {
        std::vector<std::vector<uint32_t>> faces;
        std::vector<std::pair<std::pair<uint32_t, uint32_t>, uint32_t>> mids;
        auto mid = [&](uint32_t a, uint32_t b) {
            const auto key = std::make_pair(std::min(a, b), std::max(a, b));
            for (const auto& [k, v] : mids)
                if (k == key) return v;
            const Vec3 p = (m.vertices[a] + m.vertices[b]) * 0.5;
            m.vertices.push_back(p / std::sqrt(dot(p, p)));
            mids.push_back({key, uint32_t(m.vertices.size() - 1)});
            return uint32_t(m.vertices.size() - 1);
        };
        for (const auto& f : m.faces) {
            const uint32_t a = f[0], b = f[1], cc = f[2];
            const uint32_t ab = mid(a, b), bc = mid(b, cc), ca = mid(cc, a);
            faces.push_back({a, ab, ca});
            faces.push_back({ab, b, bc});
            faces.push_back({ca, bc, cc});
            faces.push_back({ab, bc, ca});
        }
        m.faces = std::move(faces);
    }
    std::uniform_real_distribution<double> r(0.6, 1.4);
    for (Vec3& v : m.vertices) v = c + v * r(rng);
    return m;
}

TEST(LightSilhouetteEdges, NoEdgeLeftOutIsASilhouetteFromAnyPointOfTheLight) {
    std::mt19937_64 rng(7);
    std::uniform_real_distribution<double> u(-1, 1);
    size_t left = 0, kept = 0;
    const int trials = test::scaled(40);
    for (int t = 0; t < trials; ++t) {
        PolygonMesh m = randomBlob(rng, {u(rng), u(rng), u(rng)}, 2);
        // A random light triangle around the blob (its plane may cut the blob).
        const uint32_t b = uint32_t(m.vertices.size());
        for (int i = 0; i < 3; ++i) m.vertices.push_back({3 * u(rng), 3 * u(rng), 2.5 + u(rng)});
        m.faces.push_back({b, b + 1, b + 2});
        const uint32_t light = uint32_t(m.faces.size() - 1);
        const MeshEdges edges(m);
        const LightSilhouetteEdges s(m, edges, light);
        // Points of L: its vertices, and points inside it near each vertex, a few ulps in.
        std::vector<Vec3> ys;
        const Vec3 a = m.vertices[b], bb = m.vertices[b + 1], c = m.vertices[b + 2];
        const Vec3 centre = (a + bb + c) / 3.0;
        for (const Vec3& v : {a, bb, c}) {
            ys.push_back(v);
            for (double k : {1e-15, 1e-12, 1e-6, 0.3}) ys.push_back(v + (centre - v) * k);
        }
        for (int i = 0; i < 20; ++i) {
            double p = std::abs(u(rng)), q = std::abs(u(rng));
            if (p + q > 1) p = 1 - p, q = 1 - q;
            ys.push_back(a + (bb - a) * p + (c - a) * q);
        }
        for (size_t e = 0; e < edges.size(); ++e) {
            if (s.contains(e)) {
                ++kept;
                continue;
            }
            ++left;
            ASSERT_TRUE(edges.manifold(e));
            const auto uses = edges.uses(e);
            const FacePlane p0 = facePlane(m, uses[0].face), p1 = facePlane(m, uses[1].face);
            for (const Vec3& y : ys) {
                const Sign s0 = p0.side(y), s1 = p1.side(y);
                EXPECT_TRUE(s0 == s1 && s0 != Sign::Zero)
                    << "trial " << t << " edge " << e << ": a silhouette seen from a point of L";
            }
        }
    }
    // Both outcomes occur (a set that kept everything would pass the loop above).
    EXPECT_GT(left, 0u);
    EXPECT_GT(kept, 0u);
}

}  // namespace
}  // namespace penumbra::vis

namespace penumbra::vis {
namespace {

// The per-light index (light_edge_index.h) over the same cube: S_L's edges with their uses and
// boxes, and each face's side of L's plane, hand-derived.
TEST(LightEdgeIndex, KeepsSLWithItsUsesAndSortsTheFacesByLightsPlane) {
    {
        // L at z = 3 facing down (its front is z < 3): the cube is wholly in front, L's own face
        // lies in its plane (no vertex strictly in front: Behind, as the clip leaves nothing).
        const PolygonMesh m = cubeUnderLight(3, 0.1);
        const MeshEdges edges(m);
        const LightEdgeIndex index(m, edges, 6);
        EXPECT_EQ(index.size(), 8u);  // the top rim and the light's border, as S_L
        EXPECT_DOUBLE_EQ(index.share(), 0.5);
        EXPECT_EQ(index.open(), 4u);
        for (uint32_t i = 0; i < index.size(); ++i) {
            const MeshEdges::Edge& e = index.edge(i);
            const bool top = e.lo >= 4 && e.hi < 8, light = e.lo >= 8;
            EXPECT_TRUE(top || light) << e.lo << "-" << e.hi;
            EXPECT_EQ(index.uses(i).size(), top ? 2u : 1u);
        }
        for (uint32_t f = 0; f < 6; ++f) EXPECT_EQ(index.side(f), LightEdgeIndex::Side::Front);
        EXPECT_EQ(index.side(6), LightEdgeIndex::Side::Behind);
        EXPECT_EQ(index.acrossCount(), 0u);
        EXPECT_TRUE(index.acrossFaces().empty());
        // Every edge's box is found by a query around it, none by one far away.
        std::vector<uint32_t> found;
        const std::vector<PlaneOrient> aboveTop = {
            PlaneOrient({0, 0, 0.99}, {1, 0, 0.99}, {0, 1, 0.99})};
        index.edgeBoxes().notOutside(aboveTop, found);
        EXPECT_EQ(found.size(), 8u);  // all lie at z >= 1
        found.clear();
        const std::vector<PlaneOrient> below = {PlaneOrient({0, 0, 0.5}, {0, 1, 0.5}, {1, 0, 0.5})};
        index.edgeBoxes().notOutside(below, found);
        EXPECT_EQ(found.size(), 0u);  // none reaches below z = 0.5
    }
    {
        // L at z = 0.5, through the cube: the four sides cross its plane (Across), the top lies
        // behind it, the bottom in front.
        const PolygonMesh m = cubeUnderLight(0.5, 0.1);
        const LightEdgeIndex index(m, MeshEdges(m), 6);
        EXPECT_EQ(index.side(0), LightEdgeIndex::Side::Front);   // z = 0
        EXPECT_EQ(index.side(1), LightEdgeIndex::Side::Behind);  // z = 1
        for (uint32_t f = 2; f < 6; ++f) EXPECT_EQ(index.side(f), LightEdgeIndex::Side::Across);
        EXPECT_EQ(index.acrossCount(), 4u);
        std::vector<uint32_t> found;
        const std::vector<PlaneOrient> none;
        index.acrossFaces().notOutside(none, found);
        for (uint32_t& item : found) item = index.acrossFace(item);
        std::sort(found.begin(), found.end());
        EXPECT_EQ(found, (std::vector<uint32_t>{2, 3, 4, 5}));
    }
}

// The copies the weights read (LightEdgeIndex::localFace): every use of a Front face names that
// face, and its corners are the face's first three input vertices, bit for bit; a use by any
// other face names none. Each Front face and each vertex is copied once. The mesh itself is the
// reference; both of the cube's placements (all Front, then Front, Behind and Across).
TEST(LightEdgeIndex, CopiesEachFrontFacesCornersOnceForItsUses) {
    for (const double lightZ : {3.0, 0.5}) {
        const PolygonMesh m = cubeUnderLight(lightZ, 0.1);
        const LightEdgeIndex index(m, MeshEdges(m), 6);
        std::vector<int> copies(m.faces.size(), 0);
        for (uint32_t l = 0; l < index.localFaceCount(); ++l) ++copies[index.localFace(l)];
        size_t frontUses = 0, otherUses = 0;
        for (uint32_t i = 0; i < index.size(); ++i) {
            const std::span<const MeshEdges::Use> uses = index.uses(i);
            const std::span<const uint32_t> locals = index.useLocalFaces(i);
            ASSERT_EQ(locals.size(), uses.size());
            for (size_t k = 0; k < uses.size(); ++k) {
                const uint32_t face = uses[k].face;
                if (index.side(face) != LightEdgeIndex::Side::Front) {
                    EXPECT_EQ(locals[k], LightEdgeIndex::kNotFront) << "face " << face;
                    ++otherUses;
                    continue;
                }
                ++frontUses;
                ASSERT_LT(locals[k], index.localFaceCount());
                EXPECT_EQ(index.localFace(locals[k]), face);
                EXPECT_EQ(copies[face], 1) << "face " << face;
                for (size_t c = 0; c < 3; ++c) {
                    const Vec3& copy = index.localVertices()[index.localCorners(locals[k])[c]];
                    const Vec3& input = m.vertices[m.faces[face][c]];
                    EXPECT_TRUE(copy.x == input.x && copy.y == input.y && copy.z == input.z)
                        << "face " << face << " corner " << c;
                }
            }
        }
        // Above the cube every use is by a Front face but the light's own; through it, S_L's edges
        // lie on the sides (Across) and the top (Behind).
        EXPECT_GT(lightZ == 3.0 ? frontUses : otherUses, 0u);
        EXPECT_LE(index.localVertices().size(), m.vertices.size());
    }
}

}  // namespace
}  // namespace penumbra::vis
