// The equal-error study (engine/studies/equal_error_study.h): its error over the penumbra pixels
// against a value derived by hand on a 2x2 film, its search over grid sides against a synthetic
// error curve whose answer is known in closed form, and the study run on a small scene. No
// timing assertions.
#include "engine/studies/equal_error_study.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <optional>
#include <stdexcept>
#include <utility>
#include <vector>

#include "engine/io/scene_file.h"
#include "engine/raytrace/embree_scene.h"

namespace penumbra {
namespace equal_error_test {

// A film of 2x2 pixels over `passes` passes whose means are `means` (row-major).
Film filmOf(const std::vector<Vec3>& means, int passes) {
    Film f;
    f.reset(2, 2);
    f.passes = passes;
    for (size_t i = 0; i < means.size(); ++i) f.sum[i] = means[i] * static_cast<double>(passes);
    return f;
}

TEST(EqualErrorStudy, PenumbraErrorMatchesAHandDerivedValue) {
    // Pixel 0 saw all of its light twice, pixel 1 part of it once, pixel 2 none once and all
    // once (a mean fraction of 1/2), pixel 3 none twice: pixels 1 and 2 are the penumbra.
    Film exact = filmOf({{9, 9, 9}, {1, 2, 3}, {2, 2, 2}, {0, 0, 0}}, 2);
    exact.seen = {SeenCounts{0, 0, 2}, SeenCounts{0, 1, 0}, SeenCounts{1, 0, 1},
                  SeenCounts{2, 0, 0}};
    // Far off outside the penumbra (not counted); inside it the differences (0, 0, 2) and
    // (1, 0, -1).
    const Film sampled = filmOf({{100, 0, 0}, {1, 2, 5}, {3, 2, 1}, {50, 50, 50}}, 3);
    const PenumbraError e = penumbraError(sampled, exact);
    EXPECT_EQ(e.pixels, 2u);
    // Squares 4 + 1 + 1 = 6 over 6 channels: RMSE 1; radiance (1+2+3+2+2+2) / 6 = 2.
    EXPECT_DOUBLE_EQ(e.rmse, 1.0);
    EXPECT_DOUBLE_EQ(e.meanRadiance, 2.0);
    EXPECT_DOUBLE_EQ(e.relative, 0.5);
    // Against itself: no error, the same pixels.
    const PenumbraError none = penumbraError(exact, exact);
    EXPECT_EQ(none.pixels, 2u);
    EXPECT_EQ(none.rmse, 0.0);
}

TEST(EqualErrorStudy, PenumbraErrorRefusesFilmsItCannotCompare) {
    Film exact = filmOf({{1, 1, 1}, {1, 1, 1}, {1, 1, 1}, {1, 1, 1}}, 1);
    EXPECT_THROW(penumbraError(exact, exact), std::invalid_argument);  // no visible fractions
    exact.seen.assign(4, SeenCounts{0, 1, 0});
    Film other;
    other.reset(3, 2);
    EXPECT_THROW(penumbraError(other, exact), std::invalid_argument);
}

TEST(EqualErrorStudy, AnEvaluationIsWholeOnlyWithinTheTolerance) {
    EXPECT_EQ(lightSeen(false, 0, 1), LightSeen::None);
    EXPECT_EQ(lightSeen(true, 1, 1), LightSeen::Whole);
    EXPECT_EQ(lightSeen(true, 1 - 1e-12, 1), LightSeen::Whole);  // a sum's rounding
    EXPECT_EQ(lightSeen(true, 1 - 1e-6, 1), LightSeen::Part);
    EXPECT_EQ(lightSeen(true, 1e-300, 1), LightSeen::Part);  // a sliver is seen
    EXPECT_FALSE(penumbraPixel({0, 0, 5}));
    EXPECT_FALSE(penumbraPixel({5, 0, 0}));
    EXPECT_FALSE(penumbraPixel({0, 0, 0}));
    EXPECT_TRUE(penumbraPixel({0, 1, 0}));
    EXPECT_TRUE(penumbraPixel({3, 0, 1}));
}

// error(n) = 0.4 n^-1.5 is within 0.005 from n >= 80^(2/3) = 18.57: side 19 (0.00483; 18 gives
// 0.00524).
std::optional<double> curve(int side) { return 0.4 * std::pow(side, -1.5); }

std::vector<int> sides(const GridSearch& s) {
    std::vector<int> out;
    for (const auto& [side, error] : s.tried) out.push_back(side);
    return out;
}

TEST(EqualErrorStudy, SearchDoublesThenBisectsToTheSmallestSide) {
    const GridSearch s = searchGridSide(curve, 0.005, 64);
    ASSERT_TRUE(s.side.has_value());
    EXPECT_EQ(*s.side, 19);
    EXPECT_FALSE(s.stopped);
    // Doubling to 32 (the first within), then (16, 32] bisected: 24, 20, 18, 19.
    EXPECT_EQ(sides(s), (std::vector<int>{1, 2, 4, 8, 16, 32, 24, 20, 18, 19}));
    for (const auto& [side, error] : s.tried) EXPECT_DOUBLE_EQ(error, *curve(side));
}

TEST(EqualErrorStudy, SearchStopsAtTheLargestSide) {
    // The largest side is tried when doubling would pass it.
    const GridSearch capped = searchGridSide(curve, 0.005, 20);
    ASSERT_TRUE(capped.side.has_value());
    EXPECT_EQ(*capped.side, 19);
    EXPECT_EQ(sides(capped), (std::vector<int>{1, 2, 4, 8, 16, 20, 18, 19}));
    // Nothing up to 10 is within: no side, every side tried, not stopped.
    const GridSearch none = searchGridSide(curve, 0.005, 10);
    EXPECT_FALSE(none.side.has_value());
    EXPECT_FALSE(none.stopped);
    EXPECT_EQ(sides(none), (std::vector<int>{1, 2, 4, 8, 10}));
    // A side already within at 1.
    const GridSearch first = searchGridSide(curve, 1.0, 64);
    ASSERT_TRUE(first.side.has_value());
    EXPECT_EQ(*first.side, 1);
}

TEST(EqualErrorStudy, AFailedMeasurementEndsTheSearchWithoutASide) {
    const GridSearch s = searchGridSide(
        [](int side) -> std::optional<double> {
            if (side >= 8) return std::nullopt;  // a render cut at the limit
            return curve(side);
        },
        0.005, 64);
    EXPECT_FALSE(s.side.has_value());
    EXPECT_TRUE(s.stopped);
    EXPECT_EQ(sides(s), (std::vector<int>{1, 2, 4}));
}

TEST(EqualErrorStudy, RunsOnTheCornellBox) {
    const Scene scene = loadJsonScene(std::filesystem::path(PENUMBRA_SOURCE_DIR) /
                                      "assets/scenes/cornell_box.json");
    ASSERT_TRUE(scene.camera.has_value());
    const EmbreeScene bvh(scene.mesh);
    EqualErrorOptions o;
    o.width = o.height = 24;
    o.spp = 1;
    o.target = 0.05;
    o.maxRays = 1024;
    const EqualErrorRun r = runEqualErrorStudy(scene, bvh, *scene.camera, o, {});
    ASSERT_TRUE(r.exactComplete) << r.why;
    EXPECT_EQ(r.pixels, 24u * 24u);
    EXPECT_GT(r.penumbraPixels, 0u);
    EXPECT_LT(r.penumbraPixels, r.pixels);
    EXPECT_GT(r.penumbraMeanRadiance, 0);
    ASSERT_TRUE(r.found.has_value()) << r.why;
    EXPECT_LE(r.found->relativeRmse, o.target);
    // The search's counts are squares, and the one found is the smallest within the target.
    for (const EqualErrorSample& p : r.searched) {
        const int side = static_cast<int>(std::lround(std::sqrt(p.rays)));
        EXPECT_EQ(side * side, p.rays);
        if (p.relativeRmse <= o.target) {
            EXPECT_GE(p.rays, r.found->rays);
        }
    }
    EXPECT_TRUE(r.why.empty());
}

}  // namespace equal_error_test
}  // namespace penumbra
