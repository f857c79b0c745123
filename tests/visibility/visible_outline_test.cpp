// The visible region's outline (visibility/visible_outline.h): hand-derived unions of convex
// pieces (side by side, with a T-junction, around a hole, touching at a corner, with rounded
// chords), and the outline of FPQuery's fragments on random occluder soups against the exact
// CGAL region: the same form factor and visible area, and as many loops as its boundaries.
#include "visibility/visible_outline.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "engine/scene/procedural_scenes.h"
#include "tests/support/closed_forms.h"
#include "tests/support/exact_reference.h"
#include "tests/support/random_points.h"
#include "tests/support/test_scale.h"
#include "visibility/form_factor.h"
#include "visibility/fp_query/from_point_query.h"
#include "visibility/history_tree_builder.h"

// (Its own namespace: in a unity build it shares a file with other tests.)
namespace penumbra::visible_outline_test {
namespace {

using vis::Vec3;
using Polygon = std::vector<Vec3>;

// An axis-aligned rectangle at height z, counter-clockwise seen from above.
Polygon rect(double x0, double y0, double x1, double y1, double z = 1) {
    return {{x0, y0, z}, {x1, y0, z}, {x1, y1, z}, {x0, y1, z}};
}

// Signed area about +z of one loop (positive: counter-clockwise seen from above).
double signedAreaZ(const Polygon& l) {
    double a = 0;
    for (size_t i = 0; i < l.size(); ++i) {
        const Vec3& p = l[i];
        const Vec3& q = l[(i + 1) % l.size()];
        a += p.x * q.y - q.x * p.y;
    }
    return a / 2;
}

const Vec3 kUp{0, 0, 1};

// Four quadrants of the unit square: one loop, its four corners, and the closed form of the
// square's form factor from below its corner (Howell C-11).
TEST(VisibleOutline, SideBySidePiecesMergeIntoOneLoop) {
    const std::vector<Polygon> pieces{rect(0, 0, 0.5, 0.5), rect(0.5, 0, 1, 0.5),
                                      rect(0.5, 0.5, 1, 1), rect(0, 0.5, 0.5, 1)};
    const vis::VisibleOutline outline = vis::visibleOutline(pieces);
    ASSERT_EQ(outline.loops.size(), 1u);
    EXPECT_EQ(outline.edges(), 4u);
    EXPECT_NEAR(signedAreaZ(outline.loops[0]), 1.0, 1e-15);
    const Vec3 x{0, 0, 0};
    EXPECT_NEAR(vis::formFactorOfLoops(x, kUp, outline.loops), test::cornerFormFactor(1, 1, 1),
                1e-15);
}

// The right half cut again (a split of one side only): the left piece's right edge meets two
// edges and a vertex in its middle. Still one loop of four edges.
TEST(VisibleOutline, TJunctionsCancel) {
    const std::vector<Polygon> pieces{rect(0, 0, 1, 2), rect(1, 0, 2, 0.75), rect(1, 0.75, 2, 2)};
    const vis::VisibleOutline outline = vis::visibleOutline(pieces);
    ASSERT_EQ(outline.loops.size(), 1u);
    EXPECT_EQ(outline.edges(), 4u);
    EXPECT_NEAR(outline.area(), 4.0, 1e-14);
}

// A 3 x 3 square less its middle, as four strips: an outer loop turning as the pieces do and a
// hole turning the other way; the form factor is the square's less the hole's (closed forms,
// from below a corner of each by superposition: the hole [1,2]^2 seen from (0,0) is
// F(2,2) - F(1,2) - F(2,1) + F(1,1)).
TEST(VisibleOutline, AHoleIsALoopTurningTheOtherWay) {
    const std::vector<Polygon> pieces{rect(0, 0, 3, 1), rect(0, 2, 3, 3), rect(0, 1, 1, 2),
                                      rect(2, 1, 3, 2)};
    const vis::VisibleOutline outline = vis::visibleOutline(pieces);
    ASSERT_EQ(outline.loops.size(), 2u);
    EXPECT_EQ(outline.edges(), 8u);
    const double a0 = signedAreaZ(outline.loops[0]), a1 = signedAreaZ(outline.loops[1]);
    EXPECT_NEAR(std::max(a0, a1), 9.0, 1e-14);
    EXPECT_NEAR(std::min(a0, a1), -1.0, 1e-14);
    auto f = [](double a, double b) { return test::cornerFormFactor(a, b, 1); };
    const double hole = f(2, 2) - f(1, 2) - f(2, 1) + f(1, 1);
    EXPECT_NEAR(vis::formFactorOfLoops({0, 0, 0}, kUp, outline.loops), f(3, 3) - hole, 1e-14);
}

// Two squares that touch at a corner only stay two loops (each turns left where they touch).
TEST(VisibleOutline, RegionsTouchingAtAVertexStayApart) {
    const std::vector<Polygon> pieces{rect(0, 0, 1, 1), rect(1, 1, 2, 2)};
    const vis::VisibleOutline outline = vis::visibleOutline(pieces);
    ASSERT_EQ(outline.loops.size(), 2u);
    for (const Polygon& l : outline.loops) {
        EXPECT_EQ(l.size(), 4u);
        EXPECT_NEAR(signedAreaZ(l), 1.0, 1e-15);
    }
}

// Pieces cut along chords whose crossing points are rounded, each side of a chord cut again at
// its own rounded points (what FPQuery's splits leave): a fan of eight wedges of a regular
// octagon, each wedge's outer edge split at a rounded point. One loop, the octagon; also far
// from the origin, where the rounding is relatively coarser (1e5: some 2^-36 of the octagon).
TEST(VisibleOutline, RoundedChordsAndSplitsStillCancel) {
    const double pi = std::acos(-1.0);
    for (const Vec3 c : {Vec3{0.1, 0.2, 1}, Vec3{1e5 + 0.1, -1e5 + 0.2, 1}}) {
        SCOPED_TRACE("centre " + vis::toString(c));
        std::vector<Vec3> rim;
        for (int k = 0; k < 8; ++k)
            rim.push_back(c +
                          Vec3{std::cos(2 * pi * k / 8 + 0.3), std::sin(2 * pi * k / 8 + 0.3), 0});
        std::vector<Polygon> pieces;
        for (int k = 0; k < 8; ++k) {
            const Vec3 a = rim[k], b = rim[(k + 1) % 8];
            const Vec3 m = a + (b - a) * (1.0 / 3.0);  // rounded: not on the chord a-b exactly
            // The spoke to the centre, split at a rounded point on either side of it.
            if (k % 2 == 0)
                pieces.push_back({c, c + (a - c) * (1.0 / 3.0), a, m, b});
            else
                pieces.push_back({c, a, m, b, c + (b - c) * (2.0 / 7.0)});
        }
        const vis::VisibleOutline outline = vis::visibleOutline(pieces);
        ASSERT_EQ(outline.loops.size(), 1u);
        EXPECT_EQ(outline.edges(), 8u);
        double fragments = 0;
        const Vec3 x = c + Vec3{0.2, -0.4, -1};
        for (const Polygon& p : pieces) fragments += vis::formFactor(x, kUp, p);
        // (Far from the origin the rounded points lie some 1e-11 off the octagon's sides: the
        // fragments' integral and the outline's, which straightens them, differ by that much.)
        EXPECT_NEAR(vis::formFactorOfLoops(x, kUp, outline.loops), fragments, 1e-9 * fragments);
    }
}

// Lambert's sum is linear in the edges, and the outline only splits edges at vertices and
// cancels opposite pairs: its form factor is the pieces' summed whatever they are, here random
// rectangles on a coarse grid that share, overlap, touch and meet at T-junctions (not the
// disjoint fragments FPQuery gives). Every loop closes, with three vertices or more.
TEST(VisibleOutline, IntegralIsThePiecesSumForAnyPieces) {
    std::mt19937_64 rng(7);
    std::uniform_int_distribution<int> cell(0, 6);
    for (int trial = 0; trial < 200; ++trial) {
        std::vector<Polygon> pieces;
        const int count = 1 + trial % 12;
        for (int k = 0; k < count; ++k) {
            int x0 = cell(rng), x1 = cell(rng), y0 = cell(rng), y1 = cell(rng);
            if (x0 == x1 || y0 == y1) continue;
            if (x0 > x1) std::swap(x0, x1);
            if (y0 > y1) std::swap(y0, y1);
            pieces.push_back(rect(x0 * 0.25, y0 * 0.25, x1 * 0.25, y1 * 0.25));
        }
        const vis::VisibleOutline outline = vis::visibleOutline(pieces);
        const Vec3 x{0.4, 0.7, 0};
        double sum = 0;
        for (const Polygon& p : pieces) sum += vis::formFactor(x, kUp, p);
        SCOPED_TRACE("trial " + std::to_string(trial));
        EXPECT_NEAR(vis::formFactorOfLoops(x, kUp, outline.loops), sum, 1e-12 * (1 + sum));
        for (const Polygon& l : outline.loops) EXPECT_GE(l.size(), 3u);
    }
}

TEST(VisibleOutline, NoFragmentsNoLoops) {
    EXPECT_TRUE(vis::visibleOutline({}).loops.empty());
    const std::vector<Polygon> point{{{1, 1, 1}, {1, 1, 1}, {1, 1, 1}}};
    EXPECT_TRUE(vis::visibleOutline(point).loops.empty());
}

// FPQuery's fragments under random occluder soups (partial trees, so that the per-point clip and
// the boundary chain cut the light too), against the exact region CGAL computes: the outline's
// form factor and area are the region's, it has as many loops as the region has boundaries (outer
// ones and holes), and never more edges than the fragments (fewer in all).
TEST(VisibleOutline, FragmentsOfRandomSoupsMatchTheExactRegion) {
    const int scenes = test::scaled(6);
    int points = 0, severalFragments = 0, withHoles = 0;
    size_t fragmentEdges = 0, outlineEdges = 0;
    for (int seed = 1; seed <= scenes; ++seed) {
        const Scene s = makeRandomSoup(20 + 20 * (seed % 3), static_cast<uint64_t>(seed));
        vis::BuildOptions budget;
        budget.maxLpSolves = seed % 2 == 0 ? 0 : 8;
        const vis::HistoryTree tree = vis::buildHistoryTree(s.mesh, 0, 1, budget, {});
        std::mt19937_64 rng(static_cast<uint64_t>(seed) * 7919);
        const Vec3 n = vis::normalize(s.mesh.faceAreaNormal(0));
        for (int i = 0; i < 12; ++i) {
            const Vec3 x = test::randomPointOn(s.mesh, 0, rng);
            const vis::FromPointResult got = vis::fromPointQuery(s.mesh, tree, x);
            const test::ReferenceResult ref = test::exactReference(s.mesh, 0, 1, x);
            const vis::VisibleOutline outline = vis::visibleOutline(got.fragments);
            ++points;
            SCOPED_TRACE("seed " + std::to_string(seed) + ", x = " + vis::toString(x));
            EXPECT_NEAR(vis::formFactorOfLoops(x, n, outline.loops), ref.formFactor,
                        1e-9 * std::max(ref.formFactor, 1e-6));
            EXPECT_NEAR(outline.area(), ref.visibleArea, 1e-9 * ref.lightArea);
            EXPECT_EQ(static_cast<int>(outline.loops.size()), ref.boundaryLoops);
            size_t edges = 0;
            for (const auto& f : got.fragments) edges += f.size();
            fragmentEdges += edges;
            outlineEdges += outline.edges();
            EXPECT_LE(outline.edges(), edges);
            severalFragments += got.fragments.size() > 1;
            withHoles += ref.boundaryLoops > 1;
        }
    }
    // The soups must have exercised what the outline is for.
    EXPECT_GT(severalFragments, points / 2);
    EXPECT_GT(withHoles, 0);
    EXPECT_LT(outlineEdges, fragmentEdges);
}

}  // namespace
}  // namespace penumbra::visible_outline_test
