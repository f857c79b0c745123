// shadingPoint: the hit's projection onto the face's plane where cheap tests certify it on or in
// front of it (never one behind it, by the exact test), else a point strictly in front by the
// exact test within a few ulps of it; the input is always the projection (where the contact rule
// is decided).
#include "engine/render/shading_point.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "visibility/face_plane.h"

namespace penumbra {
namespace {

TEST(ShadingPoint, LiesStrictlyInFrontWithinAHairOfTheProjection) {
    std::mt19937_64 rng(5);
    std::uniform_real_distribution<double> u(-1, 1);
    int moved = 0, kept = 0;
    for (int i = 0; i < 2000; ++i) {
        // A triangle far from the origin at some scale (its sides at least 2^27 ulps of its
        // coordinates: a plane the normal can leave), and a hit a hair off its plane.
        const double scale = std::exp2(std::floor(16 * u(rng)));  // 2^-16 to 2^15
        const vis::Vec3 at{1e4 * u(rng), 1e4 * u(rng), 1e4 * u(rng)};
        vis::PolygonMesh mesh;
        for (int k = 0; k < 3; ++k)
            mesh.vertices.push_back(at + vis::Vec3{u(rng), u(rng), u(rng)} * scale);
        mesh.faces.push_back({0, 1, 2});
        const vis::Vec3 n = normalize(mesh.faceAreaNormal(0));
        const double w0 = 0.5 * (1 + u(rng)), w1 = 0.5 * (1 - w0) * (1 + u(rng));
        const vis::Vec3 inside =
            mesh.vertices[0] * w0 + mesh.vertices[1] * w1 + mesh.vertices[2] * (1 - w0 - w1);
        const vis::Vec3 hit = inside + n * (1e-7 * scale * u(rng));
        const vis::Vec3 projected = hit - n * dot(n, hit - mesh.vertices[0]);
        const vis::AnsweredPoint answered = shadingPoint(mesh, 0, hit);
        const vis::Vec3 x = answered.at;
        EXPECT_EQ(answered.input, projected);
        const vis::PlaneOrient plane = vis::facePlane(mesh, 0).orient();
        // On or in front by the exact test.
        ASSERT_NE(plane.sign(x), vis::Sign::Negative) << vis::toString(x) << " scale " << scale;
        if (x == projected) {
            EXPECT_NE(plane.sign(projected), vis::Sign::Negative);  // never a point behind
            ++kept;
        } else {
            // Strictly in front (the filter certified it).
            ASSERT_EQ(plane.sign(x), vis::Sign::Positive) << vis::toString(x);
            // Moved off the projection by a hair: the filter's error bound at the face's size
            // (larger on a thin face, whose plane is less certain), twice, doubled at most a few
            // times; within 2^-40 of its coordinates' magnitude whatever the face.
            ++moved;
            const double size = std::max({std::fabs(x.x), std::fabs(x.y), std::fabs(x.z)});
            EXPECT_LE(length(x - projected), size * 0x1p-40) << vis::toString(x);
        }
    }
    // The hits a hair off the plane: some projections certainly in front, most within the
    // filter's error of the tilted plane (moved).
    EXPECT_GT(kept, 20);
    EXPECT_GT(moved, 1000);
}

// A face of constant coordinate (a floor): the exact sign decides, so a projection exactly on the
// plane or in front is kept and one behind is moved, without the exact stage.
TEST(ShadingPoint, FloorKeepsItsProjectionExactlyWhereItIsNotBehind) {
    vis::PolygonMesh mesh;
    mesh.vertices = {{0.1, 0.3, 0.7}, {2.9, 0.3, 0.2}, {1.3, 0.3, 2.9}};  // y = 0.3, facing -y
    mesh.faces.push_back({0, 1, 2});
    const vis::PlaneOrient plane = vis::facePlane(mesh, 0).orient();
    for (double dy : {0.0, 0x1p-54, -0x1p-54, 1e-9, -1e-9}) {
        const vis::Vec3 x{1.1, 0.3 + dy, 1.2};
        const vis::AnsweredPoint a = vis::answeredPoint(plane, x);
        if (plane.sign(x) == vis::Sign::Positive || plane.sign(x) == vis::Sign::Zero)
            EXPECT_EQ(a.at, x) << dy;
        else
            EXPECT_EQ(plane.sign(a.at), vis::Sign::Positive) << dy;
    }
}

}  // namespace
}  // namespace penumbra
