// BoxTree's plane query against a loop over every box: it must report every box that is not
// strictly outside one of the planes (it may report more), and skip a good share of the others.
#include "visibility/box_tree.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <random>

namespace penumbra {
namespace {

using vis::Bounds3;
using vis::Vec3;

// The eight corners of a box, exactly.
bool strictlyOutside(const vis::PlaneOrient& p, const Bounds3& b) {
    for (double x : {b.lo.x, b.hi.x})
        for (double y : {b.lo.y, b.hi.y})
            for (double z : {b.lo.z, b.hi.z})
                if (p.sign({x, y, z}) != vis::Sign::Negative) return false;
    return true;
}

TEST(BoxTree, PlaneQueryNeverMissesABoxInsideThePlanes) {
    std::mt19937_64 rng(3);
    std::uniform_real_distribution<double> u(-1, 1), size(0.001, 0.05);
    std::vector<Bounds3> boxes(2000);
    for (Bounds3& b : boxes) {
        const Vec3 c{u(rng), u(rng), u(rng)};
        const Vec3 h{size(rng), size(rng), size(rng)};
        b.add(c - h);
        b.add(c + h);
    }
    const vis::BoxTree tree(boxes);
    size_t reported = 0, inside = 0, skippedOutside = 0, outsideTotal = 0;
    for (int q = 0; q < 50; ++q) {
        // A thin pyramid from a random apex over a random small quad: four planes through the
        // apex, inside positive.
        const Vec3 apex{u(rng), u(rng), u(rng)};
        const Vec3 centre{u(rng), u(rng), u(rng)};
        const double r = 0.2;
        const Vec3 quad[4] = {centre + Vec3{-r, -r, 0}, centre + Vec3{r, -r, 0},
                              centre + Vec3{r, r, 0}, centre + Vec3{-r, r, 0}};
        std::vector<vis::PlaneOrient> planes;
        for (int i = 0; i < 4; ++i) {
            vis::PlaneOrient p(apex, quad[i], quad[(i + 1) % 4]);
            if (p.sign(quad[(i + 2) % 4]) == vis::Sign::Negative)
                p = vis::PlaneOrient(apex, quad[(i + 1) % 4], quad[i]);
            planes.push_back(p);
        }
        std::vector<uint32_t> out;
        tree.notOutside(planes, out);
        std::sort(out.begin(), out.end());
        EXPECT_TRUE(std::adjacent_find(out.begin(), out.end()) == out.end()) << "duplicates";
        for (uint32_t i = 0; i < boxes.size(); ++i) {
            bool outside = false;
            for (const vis::PlaneOrient& p : planes) outside |= strictlyOutside(p, boxes[i]);
            const bool listed = std::binary_search(out.begin(), out.end(), i);
            if (!outside) {
                ++inside;
                EXPECT_TRUE(listed) << "box " << i << " meets the pyramid but was skipped";
            } else {
                ++outsideTotal;
                skippedOutside += !listed;
            }
        }
        reported += out.size();
    }
    EXPECT_GT(inside, 100u);
    EXPECT_GT(skippedOutside, outsideTotal * 9 / 10);  // the query does cull
    EXPECT_LE(reported, inside + outsideTotal / 10);
}

}  // namespace
}  // namespace penumbra
