// The accuracy study (engine/studies/accuracy_study.h) and the predicate study
// (engine/studies/predicate_study.h) on tiny inputs: the sampled error falls with the ray count,
// the exact image agrees with a converged sampled reference within that reference's own noise, and
// naive double predicates change hard-case answers where the filtered and always-exact ones agree.
// No timing assertions.
#include "engine/studies/accuracy_study.h"

#include <gtest/gtest.h>

#include <atomic>
#include <cmath>

#include "engine/io/scene_file.h"
#include "engine/raytrace/embree_scene.h"
#include "engine/scene/procedural_scenes.h"
#include "engine/studies/predicate_study.h"

namespace penumbra {
namespace {

AccuracyStudyOptions tinyOptions() {
    AccuracyStudyOptions o;
    o.width = 24;
    o.height = 24;
    o.spp = 1;
    o.rayCounts = {1, 4, 16, 64};
    o.referenceRays = 1024;
    return o;
}

TEST(AccuracyStudy, SampledErrorFallsAndExactAgreesWithTheReference) {
    // The Cornell box through its open front (the bench's accuracy scene), 24x24 pixels.
    const Scene scene = loadJsonScene(std::filesystem::path(PENUMBRA_SOURCE_DIR) /
                                      "assets/scenes/cornell_box.json");
    ASSERT_TRUE(scene.camera.has_value());
    const EmbreeScene bvh(scene.mesh);
    VisibilityStore store(scene, &bvh);
    const AccuracyStudy s = runAccuracyStudy(scene, bvh, store, *scene.camera, tinyOptions());
    ASSERT_TRUE(s.complete);
    ASSERT_EQ(s.sampled.size(), 4u);
    ASSERT_GT(s.meanRadiance, 0) << "the camera sees nothing lit";
    // Shadow-ray noise: 64 rays have a clearly smaller error than 1 (about 8x in theory).
    EXPECT_GT(s.sampled.front().rmse, 0);
    EXPECT_LT(s.sampled.back().rmse, 0.5 * s.sampled.front().rmse);
    for (const AccuracyPoint& p : s.sampled) EXPECT_GE(p.maxError, p.rmse);
    // The exact image against the converged reference: their difference is the reference's noise
    // (for an unbiased pair, E[RMSE^2] = noise^2), so allow a statistical margin only.
    EXPECT_GT(s.referenceNoise, 0);
    EXPECT_LT(s.exact.rmse, 1.5 * s.referenceNoise);
    // And the noise itself is small against the image (a converged reference).
    EXPECT_LT(s.referenceNoise, 0.05 * s.meanRadiance);
}

TEST(AccuracyStudy, CancelledBeforeTheStartReturnsIncomplete) {
    const Scene scene = makeRandomSoup(4, 1);
    const EmbreeScene bvh(scene.mesh);
    VisibilityStore store(scene, &bvh);
    const Camera camera = Camera::fitting(scene.mesh.bounds(), {0.3, 1.0, 0.8}, 45, {0, 0, 1});
    std::atomic<bool> cancel{true};
    const AccuracyStudy s = runAccuracyStudy(scene, bvh, store, camera, tinyOptions(), &cancel);
    EXPECT_FALSE(s.complete);
    EXPECT_TRUE(s.sampled.empty());
}

TEST(AccuracyStudy, EqualErrorInterpolatesOnTheLogLogCurve) {
    // rmse = 1/sqrt(rays), seconds = rays / 100: hand-derived, rmse 0.25 at 16 rays, 0.16 s.
    std::vector<AccuracyPoint> curve;
    for (int n : {1, 4, 64})
        curve.push_back({"sampled", n, n / 100.0, 0, 0, 1 / std::sqrt(double(n)), 0});
    double rays = 0;
    bool extrapolated = true;
    EXPECT_NEAR(equalErrorTime(curve, 0.25, &rays, &extrapolated), 0.16, 1e-12);
    EXPECT_NEAR(rays, 16, 1e-9);
    EXPECT_FALSE(extrapolated);
    // Below the last point: extrapolated along the last segment (rmse 1/32 at 1024 rays).
    EXPECT_NEAR(equalErrorTime(curve, 1.0 / 32, &rays, &extrapolated), 10.24, 1e-9);
    EXPECT_TRUE(extrapolated);
    EXPECT_TRUE(std::isnan(equalErrorTime({curve[0]}, 0.5)));
}

TEST(PredicateStudy, NaiveGetsHardCasesWrongFilteredAndExactAgree) {
    const PredicateStudy s = runPredicateStudy(12, 1);
    ASSERT_GT(s.queries, 0u);
    EXPECT_EQ(s.modes[0].wrong, 0u) << "filtered";
    EXPECT_EQ(s.modes[1].wrong, 0u) << "always exact (its own reference)";
    EXPECT_EQ(s.modes[1].otherCount, 0u);
    // Naive double signs change the answer (a sliver fragment more or less) at the hard cases'
    // exact contacts, where the filtered predicates (checked against CGAL in
    // exact_reference_test.cpp) do not. Their visible area stays within 1e-9 of L's: a sign
    // error at a near-zero determinant moves a vertex by about that determinant.
    EXPECT_GE(s.naiveOtherThanFiltered, 1u) << "naive double predicates";
}

}  // namespace
}  // namespace penumbra
