// ClosedSurfaces (visibility/closed_surfaces.h): components and open edges of small meshes whose
// answers are derived by hand.
#include "visibility/closed_surfaces.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <set>
#include <utility>
#include <vector>

namespace penumbra::vis {
namespace {

// A tetrahedron on vertices base..base+3, outward.
void addTetrahedron(PolygonMesh& m, uint32_t base) {
    const uint32_t a = base, b = base + 1, c = base + 2, d = base + 3;
    m.faces.push_back({a, c, b});
    m.faces.push_back({a, b, d});
    m.faces.push_back({b, c, d});
    m.faces.push_back({c, a, d});
}

PolygonMesh twoTetrahedra() {
    PolygonMesh m;
    m.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1},
                  {3, 0, 0}, {4, 0, 0}, {3, 1, 0}, {3, 0, 1}};
    addTetrahedron(m, 0);
    addTetrahedron(m, 4);
    return m;
}

std::set<std::pair<uint32_t, uint32_t>> openPairs(const ClosedSurfaces& s) {
    std::set<std::pair<uint32_t, uint32_t>> out;
    for (const ClosedSurfaces::OpenEdge& e : s.openEdges()) out.insert({e.lo, e.hi});
    return out;
}

TEST(ClosedSurfaces, TwoTetrahedraAreTwoClosedComponents) {
    const PolygonMesh m = twoTetrahedra();
    const ClosedSurfaces s(m);
    EXPECT_EQ(s.componentCount(), 2u);
    EXPECT_EQ(s.closedCount(), 2u);
    EXPECT_TRUE(s.openEdges().empty());
    for (uint32_t f = 0; f < 4; ++f) EXPECT_EQ(s.componentOf(f), s.componentOf(0));
    for (uint32_t f = 4; f < 8; ++f) EXPECT_EQ(s.componentOf(f), s.componentOf(4));
    EXPECT_NE(s.componentOf(0), s.componentOf(4));
}

TEST(ClosedSurfaces, AMissingFaceLeavesItsThreeEdgesOpen) {
    PolygonMesh m = twoTetrahedra();
    m.faces.erase(m.faces.begin() + 2);  // {1, 2, 3}
    const ClosedSurfaces s(m);
    EXPECT_EQ(s.componentCount(), 2u);
    EXPECT_EQ(s.closedCount(), 1u);
    const std::set<std::pair<uint32_t, uint32_t>> expected{{1, 2}, {2, 3}, {1, 3}};
    EXPECT_EQ(openPairs(s), expected);
    for (const ClosedSurfaces::OpenEdge& e : s.openEdges())
        EXPECT_EQ(e.component, s.componentOf(0));
    // The hierarchy holds the open edges' boxes: a box around the hole finds all three.
    std::vector<uint32_t> found;
    Bounds3 around;
    around.add({0, 0, 0});
    around.add({1, 1, 1});
    s.openEdgeTree().overlapping(around, found);
    EXPECT_EQ(found.size(), 3u);
}

TEST(ClosedSurfaces, AReversedFaceOpensItsEdges) {
    PolygonMesh m = twoTetrahedra();
    std::reverse(m.faces[5].begin(), m.faces[5].end());  // {4, 5, 7} turned inwards
    const ClosedSurfaces s(m);
    EXPECT_EQ(s.componentCount(), 2u);  // still joined by its edges
    EXPECT_EQ(s.closedCount(), 1u);
    const std::set<std::pair<uint32_t, uint32_t>> expected{{4, 5}, {5, 7}, {4, 7}};
    EXPECT_EQ(openPairs(s), expected);
}

// Two tetrahedra glued along an edge (vertex ids shared): four uses of it, two each way, sum to
// zero: one component, closed (non-manifold).
TEST(ClosedSurfaces, TetrahedraSharingAnEdgeAreOneClosedComponent) {
    PolygonMesh m;
    m.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {-1, 0, 0}, {0, -1, 0}};
    // The second shares the edge 0-3 (vertices 0, 3 and its own 4, 5), outward.
    addTetrahedron(m, 0);
    m.faces.push_back({0, 5, 4});
    m.faces.push_back({0, 4, 3});
    m.faces.push_back({4, 5, 3});
    m.faces.push_back({5, 0, 3});
    const ClosedSurfaces s(m);
    EXPECT_EQ(s.componentCount(), 1u);
    EXPECT_EQ(s.closedCount(), 1u);
    EXPECT_TRUE(s.openEdges().empty());
}

// Sharing a vertex only does not join two surfaces; a single triangle is an open component.
TEST(ClosedSurfaces, AVertexJoinsNothingAndASheetIsOpen) {
    PolygonMesh m = twoTetrahedra();
    m.vertices.push_back({0, 0, 5});
    m.vertices.push_back({1, 0, 5});
    m.faces.push_back({0, 8, 9});  // touches the first tetrahedron at vertex 0 only
    const ClosedSurfaces s(m);
    EXPECT_EQ(s.componentCount(), 3u);
    EXPECT_EQ(s.closedCount(), 2u);
    EXPECT_NE(s.componentOf(8), s.componentOf(0));
    EXPECT_EQ(s.openEdges().size(), 3u);
}

}  // namespace
}  // namespace penumbra::vis
