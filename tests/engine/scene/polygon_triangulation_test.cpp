// PolygonTriangulation against exact references: the triangles of a polygon cover exactly its
// area (GMP shoelace sums, no rounding anywhere), each turns the polygon's way, none overlaps
// another (their exact areas add up to the polygon's, and each is strictly positive), and the
// split is the same for every rotation of the vertex list.
#include "engine/scene/polygon_triangulation.h"

#include <gmpxx.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <set>

namespace penumbra {
namespace {

using vis::Vec3;

// Twice the signed area of the polygon projected along z, exactly.
mpq_class twiceArea(const std::vector<Vec3>& p) {
    mpq_class sum = 0;
    for (size_t i = 0; i < p.size(); ++i) {
        const Vec3& a = p[i];
        const Vec3& b = p[(i + 1) % p.size()];
        sum += mpq_class(a.x) * mpq_class(b.y) - mpq_class(b.x) * mpq_class(a.y);
    }
    return sum;
}

// The triangles as sets of positions (rotation-independent comparison).
std::set<std::vector<double>> asPositions(const std::vector<Vec3>& p,
                                          const PolygonTriangulation& t) {
    std::set<std::vector<double>> out;
    for (const auto& tri : t.triangles()) {
        // Each triangle's cycle from its least corner, so that the same triangle compares equal.
        std::vector<Vec3> c = {p[tri[0]], p[tri[1]], p[tri[2]]};
        const auto lexLess = [](const Vec3& a, const Vec3& b) {
            return std::tie(a.x, a.y, a.z) < std::tie(b.x, b.y, b.z);
        };
        std::rotate(c.begin(), std::min_element(c.begin(), c.end(), lexLess), c.end());
        out.insert({c[0].x, c[0].y, c[0].z, c[1].x, c[1].y, c[1].z, c[2].x, c[2].y, c[2].z});
    }
    return out;
}

// Splits `polygon` and checks the exact covering; returns the triangles as positions.
std::set<std::vector<double>> checkSplit(const std::vector<Vec3>& polygon) {
    PolygonTriangulation t;
    const auto problem = t.run(polygon);
    EXPECT_FALSE(problem) << *problem;
    const mpq_class whole = twiceArea(polygon);
    mpq_class sum = 0;
    for (const auto& tri : t.triangles()) {
        const mpq_class a = twiceArea({polygon[tri[0]], polygon[tri[1]], polygon[tri[2]]});
        EXPECT_EQ(sgn(a), sgn(whole)) << "a triangle turns the other way, or has zero area";
        sum += a;
    }
    EXPECT_EQ(sum, whole) << "the triangles do not cover the polygon exactly";
    return asPositions(polygon, t);
}

// Every rotation of the vertex list gives the same triangles.
void checkRotations(std::vector<Vec3> polygon) {
    const auto first = checkSplit(polygon);
    for (size_t r = 1; r < polygon.size(); ++r) {
        std::rotate(polygon.begin(), polygon.begin() + 1, polygon.end());
        EXPECT_EQ(checkSplit(polygon), first) << "rotation " << r;
    }
}

TEST(PolygonTriangulation, ConcavePolygonsAllRotations) {
    // An L, an arrow head, a comb.
    checkRotations({{0, 0, 0}, {2, 0, 0}, {2, 1, 0}, {1, 1, 0}, {1, 2, 0}, {0, 2, 0}});
    checkRotations({{0, 0, 0}, {2, 1, 0}, {0, 2, 0}, {0.5, 1, 0}});
    std::vector<Vec3> comb;
    for (int i = 0; i < 6; ++i) {
        comb.push_back({2.0 * i, 0, 0});
        comb.push_back({2.0 * i + 1, 3, 0});
    }
    comb.push_back({11, -1, 0});
    comb.push_back({0, -1, 0});
    std::reverse(comb.begin(), comb.end());  // counter-clockwise
    if (twiceArea(comb) < 0) std::reverse(comb.begin(), comb.end());
    checkRotations(comb);
}

TEST(PolygonTriangulation, CollinearVerticesAndDecimalCoordinates) {
    // Vertices in the middle of edges (a T-junction written into the polygon), with decimals.
    checkRotations({{0, 0, 0},
                    {0.1, 0, 0},
                    {0.3, 0, 0},
                    {0.3, 0.1, 0},
                    {0.3, 0.7, 0},
                    {0.2, 0.7, 0},
                    {0.2, 0.2, 0},
                    {0, 0.2, 0}});
    // Clockwise polygons turn the other way and stay so.
    checkRotations({{0, 0, 0}, {0, 1, 0}, {0.5, 0.5, 0}, {1, 1, 0}, {1, 0, 0}});
}

TEST(PolygonTriangulation, SpiralsOfManyVertices) {
    // A thick spiral: an inner and an outer arm joined at both ends, 2 x 40 vertices.
    std::vector<Vec3> outer, inner;
    for (int i = 0; i < 40; ++i) {
        const double a = 0.25 * i, r = 1 + 0.3 * a;
        outer.push_back({r * std::cos(a), r * std::sin(a), 0});
        inner.push_back({(r - 0.35) * std::cos(a), (r - 0.35) * std::sin(a), 0});
    }
    std::vector<Vec3> spiral(inner.begin(), inner.end());
    spiral.insert(spiral.end(), outer.rbegin(), outer.rend());
    if (twiceArea(spiral) < 0) std::reverse(spiral.begin(), spiral.end());
    checkRotations(spiral);
}

TEST(PolygonTriangulation, WeaklySimplePolygonWithAHoleThroughABridge) {
    // A square with a square hole, one loop: out along the bridge (0,0)->(1,1), round the hole
    // clockwise, back along the same bridge.
    const std::vector<Vec3> polygon = {{0, 0, 0}, {4, 0, 0}, {4, 4, 0}, {0, 4, 0}, {0, 0, 0},
                                       {1, 1, 0}, {1, 3, 0}, {3, 3, 0}, {3, 1, 0}, {1, 1, 0}};
    // Consecutive repeats aside the loop is (0,0) ... (0,4), (0,0)->(1,1) hole (1,1)->(0,0).
    PolygonTriangulation t;
    ASSERT_FALSE(t.run(polygon));
    mpq_class sum = 0;
    for (const auto& tri : t.triangles()) {
        const mpq_class a = twiceArea({polygon[tri[0]], polygon[tri[1]], polygon[tri[2]]});
        EXPECT_GT(sgn(a), 0);
        sum += a;
    }
    EXPECT_EQ(sum, mpq_class(2 * (16 - 4)));  // the square less the hole
}

TEST(PolygonTriangulation, NonPlanarPolygonsAreSplitAlongTheirOwnVertices) {
    // A quad whose fourth corner lies off the plane of the others by 1e-8 .. 1e-15 of its size:
    // two triangles of its vertices, the same pair whatever vertex the list starts at.
    std::mt19937_64 rng(3);
    std::uniform_real_distribution<double> u(-1, 1);
    for (int i = 0; i < 200; ++i) {
        const double off = std::pow(10.0, -8 - 7 * (0.5 + 0.5 * u(rng)));
        std::vector<Vec3> quad = {{0.1 * u(rng), 0.1 * u(rng), 0},
                                  {1 + 0.1 * u(rng), 0.1 * u(rng), 0},
                                  {1 + 0.1 * u(rng), 1 + 0.1 * u(rng), off},
                                  {0.1 * u(rng), 1 + 0.1 * u(rng), 0}};
        PolygonTriangulation t;
        ASSERT_FALSE(t.run(quad));
        ASSERT_EQ(t.triangles().size(), 2u);
        const auto first = asPositions(quad, t);
        for (int r = 1; r < 4; ++r) {
            std::rotate(quad.begin(), quad.begin() + 1, quad.end());
            ASSERT_FALSE(t.run(quad));
            EXPECT_EQ(asPositions(quad, t), first) << "rotation " << r;
        }
        checkSplit(quad);  // (projected along z: the exact cover)
    }
}

TEST(PolygonTriangulation, SelfIntersectingAndCollinearPolygonsAreRefused) {
    PolygonTriangulation t;
    // A bow tie and a pentagram: no projection is simple.
    EXPECT_TRUE(t.run(std::vector<Vec3>{{0, 0, 0}, {1, 1, 0}, {1, 0, 0}, {0, 1, 0}}));
    std::vector<Vec3> star;
    for (int i = 0; i < 5; ++i) {
        const double a = 4 * M_PI * i / 5;
        star.push_back({std::cos(a), std::sin(a), 0});
    }
    const auto problem = t.run(star);
    ASSERT_TRUE(problem);
    EXPECT_NE(problem->find("self-intersecting"), std::string::npos) << *problem;
    // A vertex on another edge's interior (touching, not a bridge).
    EXPECT_TRUE(t.run(std::vector<Vec3>{{0, 0, 0}, {4, 0, 0}, {4, 4, 0}, {2, 0, 0}, {0, 4, 0}}));
    // Fewer than three distinct positions.
    EXPECT_TRUE(t.run(std::vector<Vec3>{{0, 0, 0}, {0, 0, 0}, {1, 0, 0}}));
}

}  // namespace
}  // namespace penumbra
