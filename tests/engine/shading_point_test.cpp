// shadingPoint: on the face's plane or in front of it by the exact test, within a few ulps of the
// hit's projection, and the projection itself wherever that is already on the front side.
#include "engine/render/shading_point.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "visibility/face_plane.h"

namespace penumbra {
namespace {

TEST(ShadingPoint, LiesOnTheClosedFrontSideWithinUlpsOfTheProjection) {
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
        const vis::Vec3 x = shadingPoint(mesh, 0, hit);
        const vis::PlaneOrient plane = vis::facePlane(mesh, 0).orient();
        ASSERT_NE(plane.sign(x), vis::Sign::Negative) << vis::toString(x) << " scale " << scale;
        if (plane.sign(projected) != vis::Sign::Negative) {
            EXPECT_EQ(x, projected);
            ++kept;
        } else {
            ++moved;
            // Moved along the normal only, by at most some thousand ulps of its coordinates.
            const double ulp = std::max({std::fabs(x.x), std::fabs(x.y), std::fabs(x.z)}) * 0x1p-52;
            EXPECT_LE(length(x - projected), 1024 * ulp) << vis::toString(x);
        }
    }
    // The projection's rounding falls on either side about equally: both branches ran.
    EXPECT_GT(moved, 500);
    EXPECT_GT(kept, 500);
}

}  // namespace
}  // namespace penumbra
