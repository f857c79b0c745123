// Tests of EmbreeScene: ray casting, filtered shadow segments, the sampled visibility baseline.
#include "engine/raytrace/embree_scene.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <initializer_list>
#include <random>
#include <stdexcept>
#include <type_traits>
#include <utility>
#include <vector>

#include "tests/support/test_scale.h"

namespace {

using penumbra::EmbreeScene;
using penumbra::Vec3;
using penumbra::vis::PolygonMesh;

uint32_t addFace(PolygonMesh& m, std::initializer_list<Vec3> ccwFromFront) {
    std::vector<uint32_t> idx;
    for (const Vec3& p : ccwFromFront) {
        idx.push_back(static_cast<uint32_t>(m.vertices.size()));
        m.vertices.push_back(p);
    }
    m.faces.push_back(std::move(idx));
    return static_cast<uint32_t>(m.faces.size() - 1);
}

// An axis-aligned rectangle at height z over [x0,x1] x [y0,y1], facing up (+z) or down (-z).
uint32_t addRect(PolygonMesh& m, double x0, double x1, double y0, double y1, double z, bool up) {
    if (up) return addFace(m, {{x0, y0, z}, {x1, y0, z}, {x1, y1, z}, {x0, y1, z}});
    return addFace(m, {{x0, y0, z}, {x0, y1, z}, {x1, y1, z}, {x1, y0, z}});
}

constexpr uint32_t kFloor = 0, kLight = 1, kBlocker = 2, kCeiling = 3;

// Floor z=0 facing up; light [-0.5,0.5]^2 at z=2 facing down; blocker x in [-1,0], y in [-1,1]
// at z=1 (seen from the origin it covers exactly the x<0 half of the light); ceiling at z=3.
PolygonMesh halfBlockedScene() {
    PolygonMesh m;
    EXPECT_EQ(addRect(m, -2, 2, -2, 2, 0, true), kFloor);
    EXPECT_EQ(addRect(m, -0.5, 0.5, -0.5, 0.5, 2, false), kLight);
    EXPECT_EQ(addRect(m, -1, 0, -1, 1, 1, false), kBlocker);
    EXPECT_EQ(addRect(m, -2, 2, -2, 2, 3, false), kCeiling);
    return m;
}

TEST(EmbreeScene, FanTriangulationKeepsFaceMap) {
    PolygonMesh m = halfBlockedScene();
    // A hexagon (4 fan triangles) and a degenerate 2-vertex face (no triangles).
    addFace(m, {{5, 0, 0}, {6, 0, 0}, {6.5, 1, 0}, {6, 2, 0}, {5, 2, 0}, {4.5, 1, 0}});
    m.faces.push_back({0, 1});
    EmbreeScene s(m);
    EXPECT_EQ(s.faceCount(), 6u);
    EXPECT_EQ(s.triangleCount(), 4u * 2u + 4u);
    EXPECT_EQ(s.faceOfPrimitive(0), 0u);
    EXPECT_EQ(s.faceOfPrimitive(7), kCeiling);
    for (uint32_t p = 8; p < 12; ++p) EXPECT_EQ(s.faceOfPrimitive(p), 4u);
    EXPECT_NEAR(s.faceArea(4), 3.0, 1e-12);
    EXPECT_NEAR(s.faceArea(kLight), 1.0, 1e-12);
    EXPECT_EQ(s.faceArea(5), 0.0);
}

TEST(EmbreeScene, IntersectHitsRightFaceAtRightT) {
    EmbreeScene s(halfBlockedScene());
    auto h = s.intersect({-0.5, 0.5, 0.5}, {0, 0, 1}, 0, 100);
    ASSERT_TRUE(h);
    EXPECT_EQ(h->face, kBlocker);
    EXPECT_NEAR(h->t, 0.5, 1e-6);
    EXPECT_NEAR(h->point.z, 1.0, 1e-6);

    h = s.intersect({0.25, 0.25, 0.5}, {0, 0, 1});
    ASSERT_TRUE(h);
    EXPECT_EQ(h->face, kLight);
    EXPECT_NEAR(h->t, 1.5, 1e-6);
    EXPECT_NEAR(h->point.x, 0.25, 1e-6);
    EXPECT_NEAR(h->point.y, 0.25, 1e-6);
    EXPECT_NEAR(h->point.z, 2.0, 1e-6);

    // t is in units of the (unnormalised) direction.
    h = s.intersect({0.25, 0.25, 0.5}, {0, 0, 2});
    ASSERT_TRUE(h);
    EXPECT_EQ(h->face, kLight);
    EXPECT_NEAR(h->t, 0.75, 1e-6);

    h = s.intersect({0.5, 0.5, 0.5}, {0, 0, -1});
    ASSERT_TRUE(h);
    EXPECT_EQ(h->face, kFloor);
    EXPECT_NEAR(h->t, 0.5, 1e-6);

    // tnear skips the light, tfar stops short of it.
    h = s.intersect({0.25, 0.25, 0.5}, {0, 0, 1}, 2.0);
    ASSERT_TRUE(h);
    EXPECT_EQ(h->face, kCeiling);
    EXPECT_NEAR(h->t, 2.5, 1e-6);
    EXPECT_FALSE(s.intersect({0.25, 0.25, 0.5}, {0, 0, 1}, 0, 1.0));
    EXPECT_FALSE(s.intersect({0, 0, 3.5}, {0, 0, 1}));
    EXPECT_FALSE(s.intersect({10, 10, 1}, {1, 0, 0}));
}

TEST(EmbreeScene, OccludedIgnoresReceiverAndLight) {
    EmbreeScene s(halfBlockedScene());
    const Vec3 x{0, 0, 0};
    EXPECT_TRUE(s.occluded(x, {-0.25, 0, 2}, kFloor, kLight));  // through the blocker
    EXPECT_FALSE(s.occluded(x, {0.25, 0, 2}, kFloor, kLight));  // clear
    EXPECT_FALSE(s.occluded({0.5, 0.5, 0}, {0.3, 0.3, 2}, kFloor, kLight));
    // Open segment ends: touching faces at the end points do not count even if not ignored.
    EXPECT_FALSE(s.occluded({0.5, 0.5, 0}, {0.3, 0.3, 2}));

    // A segment crossing the light: blocked unless the light is ignored.
    EXPECT_TRUE(s.occluded({0.1, 0.1, 0.5}, {0.1, 0.1, 2.5}, kFloor, kBlocker));
    EXPECT_FALSE(s.occluded({0.1, 0.1, 0.5}, {0.1, 0.1, 2.5}, kFloor, kLight));
    EXPECT_FALSE(s.occluded({0.1, 0.1, 0.5}, {0.1, 0.1, 2.5}, kLight, kFloor));
    // A segment crossing the floor: blocked unless the floor is ignored.
    EXPECT_TRUE(s.occluded({0.5, 0.5, -1}, {0.5, 0.5, 1.5}, kBlocker, kLight));
    EXPECT_FALSE(s.occluded({0.5, 0.5, -1}, {0.5, 0.5, 1.5}, kFloor, kLight));
    // Crossing blocker and light: ignoring the light alone is not enough.
    EXPECT_TRUE(s.occluded({-0.25, 0, 0.5}, {-0.25, 0, 2.5}, kFloor, kLight));
    EXPECT_FALSE(s.occluded({-0.25, 0, 0.5}, {-0.25, 0, 2.5}, kBlocker, kLight));
    EXPECT_FALSE(s.occluded(x, x, kFloor, kLight));  // empty segment
}

TEST(EmbreeScene, SampledFractionHalfBlocked) {
    EmbreeScene s(halfBlockedScene());
    const double f = s.sampledFraction(kFloor, kLight, {0, 0, 0}, 1024, 1);
    EXPECT_NEAR(f, 0.5, 0.02);
    // Other seeds and sample counts (square, non-square, prime).
    EXPECT_NEAR(s.sampledFraction(kFloor, kLight, {0, 0, 0}, 1024, 12345), 0.5, 0.02);
    EXPECT_NEAR(s.sampledFraction(kFloor, kLight, {0, 0, 0}, 128, 7), 0.5, 0.05);
    EXPECT_NEAR(s.sampledFraction(kFloor, kLight, {0, 0, 0}, 1021, 7), 0.5, 0.03);
    // Deterministic per seed.
    EXPECT_EQ(s.sampledFraction(kFloor, kLight, {0, 0, 0}, 100, 3),
              s.sampledFraction(kFloor, kLight, {0, 0, 0}, 100, 3));
    // Fully visible and fully blocked points.
    EXPECT_EQ(s.sampledFraction(kFloor, kLight, {1.5, 1.5, 0}, 64, 1), 1.0);
    EXPECT_EQ(s.sampledFraction(kFloor, kLight, {-1.5, 0, 0}, 64, 1), 0.0);
    EXPECT_EQ(s.sampledFraction(kFloor, kLight, {0.7, 0.2, 0}, 1, 1),
              s.sampledFraction(kFloor, kLight, {0.7, 0.2, 0}, 1, 1));
}

TEST(EmbreeScene, SampledFractionBehindLightIsZero) {
    EmbreeScene s(halfBlockedScene());
    // On the ceiling (facing down, towards the light's back): behind the light.
    EXPECT_EQ(s.sampledFraction(kCeiling, kLight, {0, 0, 3}, 256, 1), 0.0);
    // In the light's plane.
    EXPECT_EQ(s.sampledFraction(kCeiling, kLight, {1, 0, 2}, 256, 1), 0.0);
    // In front of the light, but the receiver (facing down) turns away from it: nothing counts.
    EXPECT_EQ(s.sampledFraction(kCeiling, kLight, {1.5, 1.5, 0}, 64, 1), 0.0);
}

TEST(EmbreeScene, SampledFractionReceiverHemisphere) {
    // A wall facing +x whose plane cuts the light in half: only the light's x>0 half counts.
    PolygonMesh m;
    addRect(m, -0.5, 0.5, -0.5, 0.5, 2, false);  // light, face 0
    const uint32_t wall = addFace(m, {{0, -1, 0.5}, {0, 1, 0.5}, {0, 1, 1.5}, {0, -1, 1.5}});
    EmbreeScene s(m);
    EXPECT_GT(s.faceAreaNormal(wall).x, 0);
    EXPECT_NEAR(s.sampledFraction(wall, 0, {0, 0, 1}, 1024, 5), 0.5, 0.02);
    // The hemisphere is the open half-space in front of the receiver's plane through x.
    EXPECT_EQ(s.sampledFraction(wall, 0, {-0.6, 0, 1}, 64, 5), 1.0);
    EXPECT_EQ(s.sampledFraction(wall, 0, {0.6, 0, 1}, 64, 5), 0.0);
}

// Area of the part of a convex polygon (xy) with x < 0 (Sutherland-Hodgman + shoelace).
double areaLeftOfYAxis(const std::vector<Vec3>& poly) {
    std::vector<Vec3> out;
    for (size_t i = 0; i < poly.size(); ++i) {
        const Vec3 a = poly[i], b = poly[(i + 1) % poly.size()];
        if (a.x < 0) out.push_back(a);
        if ((a.x < 0) != (b.x < 0)) {
            const double t = a.x / (a.x - b.x);
            out.push_back(a + (b - a) * t);
        }
    }
    double area2 = 0;
    for (size_t i = 0; i < out.size(); ++i) {
        const Vec3 a = out[i], b = out[(i + 1) % out.size()];
        area2 += a.x * b.y - b.x * a.y;
    }
    return 0.5 * std::abs(area2);
}

TEST(EmbreeScene, SampledFractionIsAreaUniformOnPolygons) {
    // An irregular convex pentagon light (fan triangles of unequal area), half-plane blocker.
    const std::vector<Vec3> pent{
        {-0.6, -0.4, 0}, {0.5, -0.5, 0}, {0.7, 0.2, 0}, {0.1, 0.6, 0}, {-0.5, 0.3, 0}};
    PolygonMesh m;
    addRect(m, -2, 2, -2, 2, 0, true);  // floor, face 0
    // Light at z=2 facing down: reverse the (ccw from above) order.
    const uint32_t light = addFace(m, {{pent[0].x, pent[0].y, 2},
                                       {pent[4].x, pent[4].y, 2},
                                       {pent[3].x, pent[3].y, 2},
                                       {pent[2].x, pent[2].y, 2},
                                       {pent[1].x, pent[1].y, 2}});
    addRect(m, -5, 0, -5, 5, 1, false);  // blocker: hides exactly the x<0 part from the origin
    EmbreeScene s(m);
    double total = 0;
    for (size_t i = 0; i < pent.size(); ++i) {
        const Vec3 a = pent[i], b = pent[(i + 1) % pent.size()];
        total += 0.5 * (a.x * b.y - b.x * a.y);
    }
    EXPECT_NEAR(s.faceArea(light), total, 1e-12);
    const double expected = 1.0 - areaLeftOfYAxis(pent) / total;
    EXPECT_NEAR(s.sampledFraction(0, light, {0, 0, 0}, 4096, 9), expected, 0.01);
    EXPECT_NEAR(s.sampledFraction(0, light, {0, 0, 0}, 1000, 9), expected, 0.02);
}

// The candidates are the faces whose box meets the hull of receiver and light (a frustum here:
// the floor [-2,2]^2 at z 0, the light [-0.5,0.5]^2 at z 2; at z 0.5 it reaches x = 1.625), not
// their common bounding box.
TEST(EmbreeScene, ShaftCandidatesAreTheFacesNearTheHull) {
    PolygonMesh m = halfBlockedScene();
    addRect(m, 5, 6, 5, 6, 1, true);         // face 4: far away
    addRect(m, 1.9, 3, 1.9, 3, 2.5, true);   // face 5: above the light, outside the hull
    addRect(m, 1.5, 3, -1, 1, 0.5, true);    // face 6: reaches into the hull
    addRect(m, 1.75, 3, -1, 1, 0.5, true);   // face 7: in the bounding box, outside the hull
    addRect(m, 1.625, 3, -1, 1, 0.5, true);  // face 8: touches the hull
    EmbreeScene s(m);
    EXPECT_EQ(s.shaftCandidates(kFloor, kLight), (std::vector<uint32_t>{kBlocker, 6, 8}));
    // A part of the floor (a patch): its own hull with the light.
    const std::vector<Vec3> corner = {{1, 1, 0}, {2, 1, 0}, {2, 2, 0}, {1, 2, 0}};
    EXPECT_EQ(s.shaftCandidates(kFloor, corner, kLight), (std::vector<uint32_t>{6, 8}));
}

TEST(EmbreeScene, BadArgumentsThrow) {
    EmbreeScene s(halfBlockedScene());
    EXPECT_THROW(s.sampledFraction(kFloor, 99, {0, 0, 0}, 16, 1), std::out_of_range);
    EXPECT_THROW(s.sampledFraction(99, kLight, {0, 0, 0}, 16, 1), std::out_of_range);
    EXPECT_THROW(s.sampledFraction(kFloor, kLight, {0, 0, 0}, 0, 1), std::invalid_argument);
    EXPECT_THROW(s.shaftCandidates(kFloor, 4), std::out_of_range);
    PolygonMesh bad;
    bad.vertices = {{0, 0, 0}, {1, 0, 0}};
    bad.faces = {{0, 1, 2}};
    EXPECT_THROW(EmbreeScene{bad}, std::invalid_argument);
}

TEST(EmbreeScene, EmbreeErrorsBecomeExceptions) {
    // A malformed device config makes rtcNewDevice fail; the error surfaces as std::runtime_error.
    EmbreeScene::Options options;
    options.deviceConfig = "threads=abc";
    EXPECT_THROW(EmbreeScene(halfBlockedScene(), options), std::runtime_error);
}

TEST(EmbreeScene, MoveOnly) {
    static_assert(!std::is_copy_constructible_v<EmbreeScene>);
    static_assert(std::is_nothrow_move_constructible_v<EmbreeScene>);
    EmbreeScene::Options options;
    options.deviceConfig = "threads=1";
    options.robust = false;
    EmbreeScene a(halfBlockedScene(), options);
    EmbreeScene b(std::move(a));
    EXPECT_NEAR(b.sampledFraction(kFloor, kLight, {0, 0, 0}, 1024, 1), 0.5, 0.02);
    PolygonMesh other;
    addRect(other, -1, 1, -1, 1, 0, true);
    EmbreeScene c(other);
    c = std::move(b);
    EXPECT_EQ(c.faceCount(), 4u);
    auto h = c.intersect({-0.5, 0.5, 0.5}, {0, 0, 1});
    ASSERT_TRUE(h);
    EXPECT_EQ(h->face, kBlocker);
    EmbreeScene empty(PolygonMesh{});
    EXPECT_FALSE(empty.intersect({0, 0, 0}, {0, 0, 1}));
    EXPECT_FALSE(empty.occluded({0, 0, 0}, {0, 0, 1}));
}

// ~1000 random triangles between a floor and a quad light: Embree's robust mode (no ray slips
// between two triangles that share an edge) and its fast one must see the same mean visible
// fraction at 128 samples per point, the same seeds for both (only rays through shared edges may
// differ), strictly between 0 and 1. (Their throughput is measured by `penumbra bench`.)
TEST(EmbreeScene, RobustAndFastModesAgreeOnARandomScene) {
    std::mt19937_64 rng(42);
    std::uniform_real_distribution<double> U(0, 1);
    PolygonMesh m;
    addRect(m, -5, 5, -5, 5, 0, true);   // receiver, face 0
    addRect(m, -1, 1, -1, 1, 4, false);  // light, face 1
    for (int i = 0; i < 1000; ++i) {
        const Vec3 c{-3 + 6 * U(rng), -3 + 6 * U(rng), 0.5 + 3 * U(rng)};
        auto jitter = [&] { return Vec3{U(rng) - 0.5, U(rng) - 0.5, U(rng) - 0.5} * 0.6; };
        addFace(m, {c + jitter(), c + jitter(), c + jitter()});
    }
    const int points = std::max(50, penumbra::test::scaled(2000));
    std::vector<Vec3> xs;
    for (int i = 0; i < points; ++i) xs.push_back({-4 + 8 * U(rng), -4 + 8 * U(rng), 0});
    double means[2] = {0, 0};
    for (const bool robust : {true, false}) {
        EmbreeScene::Options options;
        options.robust = robust;
        EmbreeScene s(m, options);
        ASSERT_EQ(s.triangleCount(), 1004u);
        double sum = 0;
        for (int i = 0; i < points; ++i) sum += s.sampledFraction(0, 1, xs[i], 128, i);
        means[robust ? 0 : 1] = sum / points;
        EXPECT_GT(sum / points, 0.0);
        EXPECT_LT(sum / points, 1.0);
    }
    EXPECT_NEAR(means[0], means[1], 0.01);
}

}  // namespace
