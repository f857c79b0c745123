// Tests of the independent references (tests/support/exact_reference.h) against hand-derived
// values and against each other.
#include "tests/support/exact_reference.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <utility>
#include <vector>

#include "engine/scene/procedural_scenes.h"
#include "tests/support/closed_forms.h"

namespace {

using penumbra::Vec3;
using penumbra::test::exactReference;
using penumbra::test::monteCarloFraction;
using penumbra::test::ReferenceResult;
using penumbra::vis::PolygonMesh;

constexpr double kPi = std::numbers::pi;

using penumbra::test::cornerFormFactor;  // the closed form (tests/support/closed_forms.h)

// Same, for the rectangle [x0,x1] x [y0,y1] (coordinates relative to the point) at distance c:
// inclusion-exclusion over signed corner rectangles.
double rectFormFactor(double x0, double x1, double y0, double y1, double c) {
    auto g = [c](double x, double y) {
        const double s = (x < 0 ? -1.0 : 1.0) * (y < 0 ? -1.0 : 1.0);
        return s * cornerFormFactor(std::fabs(x), std::fabs(y), c);
    };
    return g(x1, y1) - g(x0, y1) - g(x1, y0) + g(x0, y0);
}

// Builds meshes: face 0 = receiver quad [-4,4]^2 at z = 0 facing up.
struct MeshBuilder {
    PolygonMesh mesh;
    MeshBuilder() { face({{-4, -4, 0}, {4, -4, 0}, {4, 4, 0}, {-4, 4, 0}}); }
    uint32_t face(const std::vector<Vec3>& pts) {
        std::vector<uint32_t> idx;
        for (const Vec3& p : pts) {
            idx.push_back(static_cast<uint32_t>(mesh.vertices.size()));
            mesh.vertices.push_back(p);
        }
        mesh.faces.push_back(idx);
        return static_cast<uint32_t>(mesh.faces.size() - 1);
    }
    // Horizontal quad [x0,x1] x [y0,y1] at height z, facing down (toward the receiver).
    uint32_t quadDown(double x0, double x1, double y0, double y1, double z) {
        return face({{x0, y0, z}, {x0, y1, z}, {x1, y1, z}, {x1, y0, z}});
    }
    uint32_t quadUp(double x0, double x1, double y0, double y1, double z) {
        return face({{x0, y0, z}, {x1, y0, z}, {x1, y1, z}, {x0, y1, z}});
    }
    // Axis-aligned box, six quads.
    void box(Vec3 lo, Vec3 hi) {
        quadDown(lo.x, hi.x, lo.y, hi.y, lo.z);
        quadUp(lo.x, hi.x, lo.y, hi.y, hi.z);
        face({{lo.x, lo.y, lo.z}, {hi.x, lo.y, lo.z}, {hi.x, lo.y, hi.z}, {lo.x, lo.y, hi.z}});
        face({{lo.x, hi.y, lo.z}, {lo.x, hi.y, hi.z}, {hi.x, hi.y, hi.z}, {hi.x, hi.y, lo.z}});
        face({{lo.x, lo.y, lo.z}, {lo.x, lo.y, hi.z}, {lo.x, hi.y, hi.z}, {lo.x, hi.y, lo.z}});
        face({{hi.x, lo.y, lo.z}, {hi.x, hi.y, lo.z}, {hi.x, hi.y, hi.z}, {hi.x, lo.y, hi.z}});
    }
};

// Midpoint-rule form factor of the rectangle {x = px} x [y0,y1] x [z0,z1] (facing -x) seen from
// point p with normal +z: an independent check of Lambert's formula.
double quadratureVertical(double px, double y0, double y1, double z0, double z1, Vec3 p, int n) {
    double sum = 0;
    const double hy = (y1 - y0) / n, hz = (z1 - z0) / n;
    for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j) {
            const Vec3 y{px, y0 + (i + 0.5) * hy, z0 + (j + 0.5) * hz};
            const Vec3 d = y - p;
            const double r2 = penumbra::vis::dot(d, d);
            const double cosR = d.z / std::sqrt(r2), cosL = d.x / std::sqrt(r2);  // L faces -x
            if (cosR > 0 && cosL > 0) sum += cosR * cosL / (kPi * r2);
        }
    return sum * hy * hz;
}

TEST(ExactReference, UnoccludedSquareMatchesClosedForm) {
    MeshBuilder b;
    const uint32_t light = b.quadDown(-0.5, 0.5, -0.5, 0.5, 1);
    const ReferenceResult r = exactReference(b.mesh, 0, light, {0, 0, 0});
    EXPECT_EQ(r.fraction, 1.0);
    EXPECT_DOUBLE_EQ(r.lightArea, 1.0);
    EXPECT_DOUBLE_EQ(r.visibleArea, 1.0);
    const double analytic = 4 * cornerFormFactor(0.5, 0.5, 1);
    EXPECT_NEAR(r.formFactor, analytic, 1e-14);
    EXPECT_NEAR(r.unoccludedFormFactor, analytic, 1e-14);
    EXPECT_GT(r.formFactor, 0.2);  // sign convention: positive for a light in front

    // below a corner of the light, and off-center
    const ReferenceResult c = exactReference(b.mesh, 0, light, {0.5, 0.5, 0});
    EXPECT_NEAR(c.formFactor, cornerFormFactor(1, 1, 1), 1e-14);
    const ReferenceResult o = exactReference(b.mesh, 0, light, {0.25, -1.5, 0});
    EXPECT_NEAR(o.formFactor, rectFormFactor(-0.75, 0.25, 1, 2, 1), 1e-14);
    EXPECT_EQ(o.fraction, 1.0);
}

TEST(ExactReference, HalfCoveringOccluder) {
    MeshBuilder b;
    const uint32_t light = b.quadDown(-0.5, 0.5, -0.5, 0.5, 1);
    // at height 0.5 the projection from the origin doubles: [0,1] x [-1,1] covers x >= 0 of L
    b.quadDown(0, 0.5, -0.5, 0.5, 0.5);
    // occluders above the light and below the point change nothing
    b.quadDown(-2, 2, -2, 2, 2);
    b.quadDown(-2, 2, -2, 2, -1);
    const ReferenceResult r = exactReference(b.mesh, 0, light, {0, 0, 0});
    EXPECT_EQ(r.fraction, 0.5);
    EXPECT_DOUBLE_EQ(r.visibleArea, 0.5);
    EXPECT_NEAR(r.formFactor, 2 * cornerFormFactor(0.5, 0.5, 1), 1e-14);
    EXPECT_NEAR(r.unoccludedFormFactor, 4 * cornerFormFactor(0.5, 0.5, 1), 1e-14);
}

TEST(ExactReference, CentralOccluderMakesAHole) {
    MeshBuilder b;
    const uint32_t light = b.quadDown(-0.5, 0.5, -0.5, 0.5, 1);
    b.quadUp(-0.125, 0.125, -0.125, 0.125, 0.5);  // projects to [-0.25,0.25]^2
    const ReferenceResult r = exactReference(b.mesh, 0, light, {0, 0, 0});
    EXPECT_EQ(r.fraction, 0.75);
    EXPECT_NEAR(r.formFactor,
                4 * cornerFormFactor(0.5, 0.5, 1) - 4 * cornerFormFactor(0.25, 0.25, 1), 1e-14);
}

TEST(ExactReference, OccluderTouchingTheLight) {
    {
        // a box hanging from the light: top face in L's plane (ignored), bottom face projects
        // to [-0.25,0.25]^2, the sides project inside that
        MeshBuilder b;
        const uint32_t light = b.quadDown(-0.5, 0.5, -0.5, 0.5, 1);
        b.box({-0.125, -0.125, 0.5}, {0.125, 0.125, 1});
        const ReferenceResult r = exactReference(b.mesh, 0, light, {0, 0, 0});
        EXPECT_EQ(r.fraction, 0.75);
        EXPECT_NEAR(r.formFactor,
                    4 * cornerFormFactor(0.5, 0.5, 1) - 4 * cornerFormFactor(0.25, 0.25, 1), 1e-14);
    }
    {
        // a vertical wall x = 0, z in [0.5,1], touching L along its midline, seen from
        // (0.25,0,0): (0,y,z) projects to (0.25 - 0.25/z, y/z), covering [-0.25,0] x [-0.5,0.5]
        MeshBuilder b;
        const uint32_t light = b.quadDown(-0.5, 0.5, -0.5, 0.5, 1);
        b.face({{0, -0.5, 0.5}, {0, 0.5, 0.5}, {0, 0.5, 1}, {0, -0.5, 1}});
        const ReferenceResult r = exactReference(b.mesh, 0, light, {0.25, 0, 0});
        EXPECT_EQ(r.fraction, 0.75);
        const double expected =
            rectFormFactor(-0.75, -0.5, -0.5, 0.5, 1) + rectFormFactor(-0.25, 0.25, -0.5, 0.5, 1);
        EXPECT_NEAR(r.formFactor, expected, 1e-14);
    }
    {
        // a quad in L's plane overlapping L does not occlude (open segments)
        MeshBuilder b;
        const uint32_t light = b.quadDown(-0.5, 0.5, -0.5, 0.5, 1);
        b.quadDown(-0.25, 1, -0.25, 1, 1);
        EXPECT_EQ(exactReference(b.mesh, 0, light, {0, 0, 0}).fraction, 1.0);
    }
}

TEST(ExactReference, LightStraddlingTheHorizon) {
    MeshBuilder b;
    // light in the plane x = 1, facing -x, z in [-0.5,1.5]: 3/4 of it above the receiver plane
    const uint32_t light = b.face({{1, -0.5, -0.5}, {1, -0.5, 1.5}, {1, 0.5, 1.5}, {1, 0.5, -0.5}});
    const ReferenceResult r = exactReference(b.mesh, 0, light, {0, 0, 0});
    EXPECT_DOUBLE_EQ(r.lightArea, 2.0);
    EXPECT_EQ(r.fraction, 0.75);
    EXPECT_DOUBLE_EQ(r.visibleArea, 1.5);
    const double quad = quadratureVertical(1, -0.5, 0.5, 0, 1.5, {0, 0, 0}, 1000);
    EXPECT_NEAR(r.unoccludedFormFactor, quad, 1e-6);
    EXPECT_NEAR(r.formFactor, r.unoccludedFormFactor, 1e-15);
    EXPECT_GT(r.formFactor, 0);

    // an occluder below the horizon changes nothing; one above it hides its share
    MeshBuilder c;
    const uint32_t light2 =
        c.face({{1, -0.5, -0.5}, {1, -0.5, 1.5}, {1, 0.5, 1.5}, {1, 0.5, -0.5}});
    c.face({{0.5, -1, -0.5}, {0.5, 1, -0.5}, {0.5, 1, -0.125}, {0.5, -1, -0.125}});
    // x = 0.5 plane, z in [0, 0.25] projects (scale 2) to z in [0, 0.5]: a quarter of the
    // visible part, so fraction 0.75 - 0.25 = 0.5
    c.face({{0.5, -1, 0}, {0.5, 1, 0}, {0.5, 1, 0.25}, {0.5, -1, 0.25}});
    const ReferenceResult s = exactReference(c.mesh, 0, light2, {0, 0, 0});
    EXPECT_EQ(s.fraction, 0.5);
    EXPECT_NEAR(s.formFactor, quadratureVertical(1, -0.5, 0.5, 0.5, 1.5, {0, 0, 0}, 1000), 1e-6);
}

TEST(ExactReference, PointBehindTheLightSeesNothing) {
    MeshBuilder b;
    const uint32_t light = b.quadDown(-0.5, 0.5, -0.5, 0.5, 1);
    for (Vec3 x : {Vec3{0, 0, 2}, Vec3{3, 0, 1}, Vec3{0.25, 0.25, 1}}) {
        const ReferenceResult r = exactReference(b.mesh, 0, light, x);
        EXPECT_EQ(r.fraction, 0.0);
        EXPECT_EQ(r.visibleArea, 0.0);
        EXPECT_EQ(r.formFactor, 0.0);
        EXPECT_EQ(r.unoccludedFormFactor, 0.0);
        EXPECT_EQ(monteCarloFraction(b.mesh, 0, light, x, 1000, 1, nullptr), 0.0);
    }
    // the light entirely behind the receiver's plane
    MeshBuilder c;
    const uint32_t below = c.quadUp(-0.5, 0.5, -0.5, 0.5, -1);
    const ReferenceResult r = exactReference(c.mesh, 0, below, {0, 0, 0});
    EXPECT_EQ(r.fraction, 0.0);
    EXPECT_EQ(r.formFactor, 0.0);
}

TEST(ExactReference, MonteCarloAgreesOnRandomScenes) {
    for (uint64_t seed : {1u, 2u, 3u}) {
        const penumbra::Scene scene = penumbra::makeRandomSoup(40, seed);
        const uint32_t light = scene.lights.at(0);
        for (Vec3 x : {Vec3{0.5, 0.5, 0}, Vec3{0.25, 0.75, 0}, Vec3{0.875, 0.125, 0}}) {
            const ReferenceResult r = exactReference(scene.mesh, 0, light, x);
            double sigma = 0;
            const double mc =
                monteCarloFraction(scene.mesh, 0, light, x, 40000, seed * 7 + 1, &sigma);
            EXPECT_GE(r.fraction, 0.0);
            EXPECT_LE(r.fraction, 1.0);
            EXPECT_LE(r.formFactor, r.unoccludedFormFactor + 1e-15);
            EXPECT_NEAR(mc, r.fraction, 4 * sigma + 1e-9)
                << "seed " << seed << " x " << x.x << "," << x.y;
        }
    }
}

TEST(ExactReference, MonteCarloAgreesOnHardCases) {
    for (const auto& [name, scene] : penumbra::makeHardCases()) {
        const uint32_t light = scene.lights.at(0);
        Vec3 lo = scene.mesh.vertex(scene.mesh.faces[0][0]), hi = lo;
        for (uint32_t i : scene.mesh.faces[0]) {
            const Vec3 p = scene.mesh.vertex(i);
            lo = {std::min(lo.x, p.x), std::min(lo.y, p.y), lo.z};
            hi = {std::max(hi.x, p.x), std::max(hi.y, p.y), hi.z};
        }
        for (Vec3 t : {Vec3{0.5, 0.5, 0}, Vec3{0.3125, 0.625, 0}, Vec3{0.8, 0.2, 0}}) {
            const Vec3 x{lo.x + t.x * (hi.x - lo.x), lo.y + t.y * (hi.y - lo.y), lo.z};
            const ReferenceResult r = exactReference(scene.mesh, 0, light, x);
            double sigma = 0;
            const double mc = monteCarloFraction(scene.mesh, 0, light, x, 20000, 11, &sigma);
            EXPECT_GE(r.fraction, 0.0) << name;
            EXPECT_LE(r.fraction, 1.0) << name;
            EXPECT_NEAR(mc, r.fraction, 4 * sigma + 2e-4) << name << " at " << t.x << "," << t.y;
        }
    }
}

TEST(ExactReference, ExactImagesGiveIdenticalFractions) {
    const auto cases = penumbra::makeHardCases();
    const penumbra::Scene* base = nullptr;
    const penumbra::Scene* moved = nullptr;
    const penumbra::Scene* big = nullptr;
    for (const auto& [name, scene] : cases) {
        if (name == "shared_vertices") base = &scene;
        if (name == "translated_1e5") moved = &scene;
        if (name == "scaled_1e3") big = &scene;
    }
    ASSERT_TRUE(base && moved && big);
    const uint32_t light = base->lights.at(0);
    for (Vec3 x : {Vec3{0, 0, 0}, Vec3{-1.25, 0.75, 0}, Vec3{0.5, -0.375, 0}}) {
        const ReferenceResult a = exactReference(base->mesh, 0, light, x);
        const ReferenceResult b = exactReference(moved->mesh, 0, light, x + Vec3{1e5, 1e5, 1e5});
        const ReferenceResult c = exactReference(big->mesh, 0, light, x * 1e3);
        EXPECT_EQ(a.fraction, b.fraction);
        EXPECT_EQ(a.fraction, c.fraction);
        EXPECT_NEAR(a.formFactor, c.formFactor, 1e-12);
        EXPECT_NEAR(a.formFactor, b.formFactor, 1e-9);
    }
}

TEST(ExactReference, MonteCarloAgreesOnPaperScenes) {
    const std::pair<penumbra::Scene, std::vector<Vec3>> scenes[] = {
        {penumbra::makeStairs(), {{3.5, 2.5, 0}, {1, -0.5, 0}}},
        {penumbra::makeGrids(), {{0.1, 0.2, 0}, {-0.6875, 0.3, 0}}},
        {penumbra::makeCornellBox(), {{150, 0, 400}, {400, 0, 150}, {278, 0, 50}}},
    };
    for (const auto& [scene, points] : scenes) {
        const uint32_t light = scene.lights.at(0);
        for (const Vec3& x : points) {
            const ReferenceResult r = exactReference(scene.mesh, 0, light, x);
            double sigma = 0;
            const double mc = monteCarloFraction(scene.mesh, 0, light, x, 20000, 3, &sigma);
            EXPECT_GT(r.unoccludedFormFactor, 0.0);
            EXPECT_NEAR(mc, r.fraction, 4 * sigma + 2e-4) << x.x << "," << x.y << "," << x.z;
        }
    }
}

// The exact reference on the paper's table scene (1348 faces: foliage, chairs) against a Monte
// Carlo estimate of 20000 rays per point, at eight floor points in and around its shadows.
TEST(ExactReference, TableMatchesMonteCarlo) {
    const penumbra::Scene scene = penumbra::makeTable();
    const uint32_t light = scene.lights.at(0);
    const Vec3 points[] = {{0.1, 0.2, 0},   {0.9, 0.3, 0},  {1.5, 1.5, 0},  {-0.5, -1.0, 0},
                           {0.25, 0.75, 0}, {-1.0, 0.1, 0}, {0.6, -0.9, 0}, {1.25, 0.0, 0}};
    for (const Vec3& x : points) {
        const ReferenceResult r = exactReference(scene.mesh, 0, light, x);
        EXPECT_GE(r.fraction, 0.0);
        EXPECT_LE(r.fraction, 1.0);
        double sigma = 0;
        const double mc = monteCarloFraction(scene.mesh, 0, light, x, 20000, 5, &sigma);
        EXPECT_NEAR(mc, r.fraction, 4 * sigma + 2e-4) << "x = " << x.x << ", " << x.y;
    }
}

}  // namespace
