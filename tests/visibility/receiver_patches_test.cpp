// Receiver patches: how many a face gets, counted by hand, and receiverPatchCount (which counts
// them without making them) against subdivideReceiver.
#include "visibility/receiver_patches.h"

#include <gtest/gtest.h>

#include <vector>

namespace penumbra::vis {
namespace {

TEST(ReceiverPatches, CountsMatchTheSubdivisionByHand) {
    // A right triangle with legs 1: diameter sqrt(2). Against 0.3: log2(4.71) = 2.24, so 3
    // levels, k = 8 cells per side, 64 triangles; against 1e-9 the levels stop at 8: k = 256,
    // 65536 triangles. A unit square (two fan triangles, diameter sqrt(2)) against 0.8:
    // log2(1.77) = 0.82, 1 level, k = 2, 2 * 4 = 8 triangles; against 1.5, itself.
    const std::vector<Vec3> triangle{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    const std::vector<Vec3> square{{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
    struct Case {
        const std::vector<Vec3>& face;
        double maxDiameter;
        size_t patches;
    };
    const Case cases[] = {{triangle, 0.3, 64}, {square, 0.8, 8}, {square, 1.5, 1},
                          {triangle, 0, 1},    {square, -1, 1},  {triangle, 1e-9, 65536}};
    for (const Case& c : cases) {
        SCOPED_TRACE(c.maxDiameter);
        EXPECT_EQ(receiverPatchCount(c.face, c.maxDiameter), c.patches);
        EXPECT_EQ(subdivideReceiver(c.face, c.maxDiameter).patches.size(), c.patches);
    }
}

}  // namespace
}  // namespace penumbra::vis
