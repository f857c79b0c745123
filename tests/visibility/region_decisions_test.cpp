// RegionDecisions: a node decided for a box must send every line from the box to the light that
// way (checked with exact orient3d signs of random lines), and from-point queries that use the
// decisions must still match the exact CGAL reference.
#include "visibility/region_decisions.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <random>

#include "engine/precompute/visibility_store.h"
#include "engine/scene/procedural_scenes.h"
#include "tests/support/exact_reference.h"
#include "tests/support/random_points.h"
#include "tests/support/test_scale.h"
#include "visibility/exact_orient.h"
#include "visibility/form_factor.h"
#include "visibility/fp_query/from_point_query.h"

namespace penumbra {
namespace {

using vis::Vec3;

using test::randomPointOn;

// A small cluster of points on face f around a random centre (what a tile of pixels gives):
// points within `radius` of the centre, pulled back into the face.
std::vector<Vec3> cluster(const vis::PolygonMesh& m, uint32_t f, double radius, int count,
                          std::mt19937_64& rng) {
    const Vec3 centre = randomPointOn(m, f, rng);
    std::vector<Vec3> out;
    for (int i = 0; i < count; ++i) {
        const Vec3 y = randomPointOn(m, f, rng);
        const double len = vis::length(y - centre);
        const double t = len > radius ? radius / len : 1.0;
        out.push_back(centre + (y - centre) * t);  // on the segment to a face point: on the face
    }
    return out;
}

std::vector<Vec3> boxCorners(std::span<const Vec3> points) {
    vis::Bounds3 b;
    for (const Vec3& p : points) b.add(p);
    std::vector<Vec3> out;
    for (double x : {b.lo.x, b.hi.x})
        for (double y : {b.lo.y, b.hi.y})
            for (double z : {b.lo.z, b.hi.z}) out.push_back({x, y, z});
    return out;
}

// Random clusters on random receivers until `clusters` of them fall on a penumbra tree; calls
// visit(tree, points) for those.
template <typename Visit>
void forClusters(const Scene& scene, int clusters, double radius, uint64_t seed, Visit visit) {
    VisibilityStore store(scene);
    std::mt19937_64 rng(seed);
    std::uniform_int_distribution<uint32_t> faceDist(0, scene.faceCount() - 1);
    int found = 0;
    for (int attempt = 0; attempt < 50 * clusters && found < clusters; ++attempt) {
        const uint32_t f = faceDist(rng);
        const uint32_t l = scene.lights[0];
        if (f == l) continue;
        const std::vector<Vec3> points = cluster(scene.mesh, f, radius, 12, rng);
        // All points of one cluster must share the patch (as the renderer's groups do).
        const PairKey key = store.layout().keyAt(f, points[0], l);
        std::vector<Vec3> same;
        for (const Vec3& p : points)
            if (store.layout().keyAt(f, p, l) == key) same.push_back(p);
        const vis::HistoryTree& tree = store.getOrBuild(key).tree;
        if (tree.kind != vis::PairKind::Penumbra) continue;
        ++found;
        visit(tree, same);
    }
}

TEST(RegionDecisions, EveryLineOfTheRegionGoesTheDecidedWay) {
    const Scene scene = makeGrids();
    const vis::PolygonMesh& m = scene.mesh;
    std::mt19937_64 rng(7);
    size_t positive = 0, negative = 0, split = 0, lines = 0;
    forClusters(scene, test::scaled(60), 0.05, 11,
                [&](const vis::HistoryTree& tree, const std::vector<Vec3>& points) {
                    const std::vector<Vec3> corners = boxCorners(points);
                    vis::RegionDecisions decisions;
                    decisions.reset(m, tree, corners);
                    std::vector<Vec3> light;
                    for (uint32_t v : m.faces[tree.light]) light.push_back(m.vertices[v]);
                    for (uint32_t node = 0; node < tree.nodes.size(); ++node) {
                        const auto d = decisions.at(node);
                        positive += d == vis::RegionDecisions::Decision::Positive;
                        negative += d == vis::RegionDecisions::Decision::Negative;
                        split += d == vis::RegionDecisions::Decision::Split;
                        if (d == vis::RegionDecisions::Decision::Split) continue;
                        const vis::EdgeLine edge = tree.edgeLine(m, tree.nodes[node]);
                        for (int i = 0; i < 8; ++i) {
                            // A random point of the box and a random point of L.
                            const Vec3 x = test::randomCombination(corners, rng, 0.0);
                            const Vec3 y = test::randomCombination(light, rng, 0.0);
                            const int e = sgn(vis::sideExact(x, y, edge));  // rationals alone
                            const vis::Sign s =
                                e > 0 ? vis::Sign::Positive
                                      : (e < 0 ? vis::Sign::Negative : vis::Sign::Zero);
                            ++lines;
                            if (d == vis::RegionDecisions::Decision::Positive)
                                EXPECT_NE(s, vis::Sign::Negative) << "node " << node;
                            else
                                EXPECT_NE(s, vis::Sign::Positive) << "node " << node;
                        }
                    }
                });
    // Not vacuous: small regions decide most nodes, and some are split.
    const auto atLeast = [](int n) { return static_cast<size_t>(test::scaled(n)); };
    EXPECT_GT(positive, atLeast(100));
    EXPECT_GT(negative, atLeast(100));
    EXPECT_GT(split, atLeast(10));
    EXPECT_GT(lines, atLeast(1000));
}

TEST(RegionDecisions, QueriesWithDecisionsMatchTheExactReference) {
    size_t skipped = 0;  // nodes the decisions sent one way: plane tests the queries did not make
    for (const Scene& scene : {makeGrids(), makeStairs()}) {
        const vis::PolygonMesh& m = scene.mesh;
        vis::FromPointQuery query;
        vis::RegionDecisions decisions;
        size_t compared = 0;
        forClusters(scene, test::scaled(80), 0.08, 3,
                    [&](const vis::HistoryTree& tree, const std::vector<Vec3>& points) {
                        decisions.reset(m, tree, boxCorners(points));
                        const Vec3 n = vis::normalize(m.faceAreaNormal(tree.receiver));
                        for (const Vec3& x : points) {
                            const vis::FragmentList& fragments =
                                query.run(m, tree, x, nullptr, &decisions);
                            double area = 0, ff = 0;
                            for (size_t i = 0; i < fragments.size(); ++i) {
                                area += vis::polygonArea(fragments[i]);
                                ff += vis::formFactor(x, n, fragments[i]);
                            }
                            const test::ReferenceResult ref =
                                test::exactReference(m, tree.receiver, tree.light, x);
                            ++compared;
                            EXPECT_NEAR(area / m.faceArea(tree.light), ref.fraction, 1e-9)
                                << "receiver " << tree.receiver << " x " << vis::toString(x);
                            EXPECT_NEAR(ff, ref.formFactor, 1e-9 * std::max(ref.formFactor, 1e-6))
                                << "receiver " << tree.receiver << " x " << vis::toString(x);
                            if (::testing::Test::HasFailure()) return;
                        }
                        skipped += decisions.decided() - decisions.splits();
                    });
        EXPECT_GT(compared, static_cast<size_t>(test::scaled(50)));
    }
    // The decisions were used (the queries above went through decided nodes).
    EXPECT_GT(skipped, static_cast<size_t>(test::scaled(100)));
}

TEST(RegionDecisions, RejectsRegionsOfAnotherTreeAndBadCorners) {
    const Scene scene = makeGrids();
    VisibilityStore store(scene);
    vis::RegionDecisions decisions;
    std::vector<Vec3> none;
    const vis::HistoryTree* a = nullptr;
    const vis::HistoryTree* b = nullptr;
    for (uint32_t f = 0; f < scene.faceCount() && b == nullptr; ++f) {
        if (f == scene.lights[0]) continue;
        const vis::HistoryTree& t = store.getOrBuild({f, 0, scene.lights[0]}).tree;
        if (t.kind != vis::PairKind::Penumbra) continue;
        (a == nullptr ? a : b) = &t;
    }
    ASSERT_NE(b, nullptr);
    EXPECT_THROW(decisions.reset(scene.mesh, *a, none), std::invalid_argument);
    const Vec3 x = scene.mesh.vertices[scene.mesh.faces[a->receiver][0]];
    decisions.reset(scene.mesh, *a, std::span<const Vec3>(&x, 1));
    vis::FromPointQuery query;
    EXPECT_THROW(query.run(scene.mesh, *b, x, nullptr, &decisions), std::invalid_argument);
}

}  // namespace
}  // namespace penumbra
