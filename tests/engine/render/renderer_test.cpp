// Tests of the progressive renderer: exact shading against independent references (a closed-form
// form factor, converged shadow-ray estimates), determinism, cancellation, image output.
#include "engine/render/renderer.h"

#include <gtest/gtest.h>
#include <tbb/global_control.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <initializer_list>
#include <map>
#include <memory>
#include <numbers>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "engine/io/image_io.h"
#include "engine/precompute/visibility_store.h"
#include "engine/raytrace/embree_scene.h"
#include "engine/render/shading.h"
#include "tests/support/closed_forms.h"
#include "tests/support/read_pfm.h"
#include "tests/support/test_scale.h"
#include "visibility/light_silhouette_edges.h"
#include "visibility/mesh_edges.h"

namespace {

using namespace penumbra;

// A face over existing vertices (counter-clockwise seen from its front).
uint32_t addIndexedFace(Scene& s, std::vector<uint32_t> ids, int32_t material) {
    s.mesh.faces.push_back(std::move(ids));
    s.faceMaterial.push_back(material);
    s.faceSourceLine.push_back(0);
    return s.faceCount() - 1;
}

uint32_t addFace(Scene& s, std::initializer_list<Vec3> ccwFromFront, int32_t material) {
    std::vector<uint32_t> idx;
    for (const Vec3& p : ccwFromFront) {
        idx.push_back(static_cast<uint32_t>(s.mesh.vertices.size()));
        s.mesh.vertices.push_back(p);
    }
    return addIndexedFace(s, std::move(idx), material);
}

// Axis-aligned rectangle at height z, facing up (+z) or down (-z).
uint32_t addRect(Scene& s, double x0, double x1, double y0, double y1, double z, bool up,
                 int32_t material) {
    if (up) return addFace(s, {{x0, y0, z}, {x1, y0, z}, {x1, y1, z}, {x0, y1, z}}, material);
    return addFace(s, {{x0, y0, z}, {x0, y1, z}, {x1, y1, z}, {x1, y0, z}}, material);
}

int32_t addMaterial(Scene& s, Vec3 kd, Vec3 ks = {}, double ns = 0, Vec3 ke = {}) {
    Material m;
    m.name = "m" + std::to_string(s.materials.size());
    m.kd = kd;
    m.ks = ks;
    m.ns = ns;
    m.ke = ke;
    s.materials.push_back(m);
    return static_cast<int32_t>(s.materials.size() - 1);
}

// A floor (face 0, [-2,2]^2 at z=0, facing up, material 0: `floorMaterial`) and a light
// [-0.5,0.5]^2 at z=2 facing down (face 1). Returns a grey material for the occluders.
int32_t addFloorAndLight(Scene& s, const Material& floorMaterial = {}) {
    s.materials.push_back(floorMaterial);
    const int32_t light = addMaterial(s, {0.2, 0.2, 0.2}, {}, 0, {6, 5, 4});
    const int32_t grey = addMaterial(s, {0.6, 0.6, 0.6});
    addRect(s, -2, 2, -2, 2, 0, true, 0);
    addRect(s, -0.5, 0.5, -0.5, 0.5, 2, false, light);
    return grey;
}

// The floor and the light, a back wall at y=2 facing the camera, and a tilted triangle floating
// between floor and light (its shadow on the floor has a wide penumbra). `floorMaterial` lets
// tests make the floor glossy.
Scene penumbraScene(const Material& floorMaterial) {
    Scene s;
    const int32_t grey = addFloorAndLight(s, floorMaterial);
    addFace(s, {{-2, 2, 0}, {2, 2, 0}, {2, 2, 2.5}, {-2, 2, 2.5}}, grey);  // facing -y
    addFace(s, {{-0.8, -0.6, 1.0}, {0.3, -0.2, 1.2}, {-0.2, 0.7, 0.9}}, grey);
    s.collectLights();
    return s;
}

Camera penumbraCamera() {
    Camera c;
    c.eye = {0.3, -6, 1.6};
    c.target = {0, 0, 0.4};
    c.fovYDegrees = 40;
    return c;
}

// The scene and everything the renderer needs, in construction order.
struct Rig {
    explicit Rig(Scene s)
        : scene(std::move(s)), bvh(scene.mesh), store(scene, &bvh), renderer(scene, bvh, store) {}
    Scene scene;
    EmbreeScene bvh;
    VisibilityStore store;
    ProgressiveRenderer renderer;
};

double channelSum(const Vec3& v) { return v.x + v.y + v.z; }

// Two renders of the same exact image: every pixel within 1e-9 (relative above 1), and a quarter
// of them lit at least, so that the comparison is not of two dark images.
void expectSameImage(const Film& a, const Film& b) {
    ASSERT_EQ(a.sum.size(), b.sum.size());
    size_t lit = 0;
    for (size_t i = 0; i < a.sum.size(); ++i) {
        const double va = channelSum(a.sum[i]), vb = channelSum(b.sum[i]);
        EXPECT_NEAR(va, vb, 1e-9 * std::max(1.0, std::fabs(vb))) << "pixel " << i;
        lit += va > 0;
    }
    EXPECT_GT(lit, a.sum.size() / 4);
}

// Per-pixel mean and variance of the mean over K renders that differ only in lightSeed (the
// pixel pattern, RenderSettings::seed, stays fixed): the light-sampling noise alone.
struct Replicates {
    std::vector<double> mean, varianceOfMean;  // of the pixel's channel sum
};

Replicates replicate(Rig& rig, const Camera& camera, RenderSettings settings, int count) {
    const size_t n = static_cast<size_t>(settings.width) * settings.height;
    std::vector<double> sum(n, 0), sumSq(n, 0);
    for (int k = 0; k < count; ++k) {
        settings.lightSeed = 1000 + static_cast<uint64_t>(k);
        const Film film = rig.renderer.render(camera, settings);
        for (size_t i = 0; i < n; ++i) {
            const double v = channelSum(film.sum[i] / film.passes);
            sum[i] += v;
            sumSq[i] += v * v;
        }
    }
    Replicates r;
    r.mean.resize(n);
    r.varianceOfMean.resize(n);
    for (size_t i = 0; i < n; ++i) {
        r.mean[i] = sum[i] / count;
        const double var = std::max(0.0, (sumSq[i] - count * r.mean[i] * r.mean[i]) / (count - 1));
        r.varianceOfMean[i] = var / count;
    }
    return r;
}

// Checks that `estimate` agrees with `reference` within the noise: per pixel |diff| < 4 sigma +
// tiny for at least 99.5% of the pixels, and the mean difference within 4 of its standard errors.
void expectAgreement(const std::vector<double>& estimate, const std::vector<double>& estimateVar,
                     const Replicates& reference, const char* what) {
    const size_t n = estimate.size();
    ASSERT_EQ(reference.mean.size(), n);
    size_t outside = 0, lit = 0;
    double diffSum = 0, varSum = 0;
    for (size_t i = 0; i < n; ++i) {
        const double diff = estimate[i] - reference.mean[i];
        const double var = estimateVar[i] + reference.varianceOfMean[i];
        const double tiny = 1e-9 + 1e-6 * std::fabs(reference.mean[i]);
        if (std::fabs(diff) >= 4 * std::sqrt(var) + tiny) ++outside;
        if (reference.mean[i] > 0.01) ++lit;
        diffSum += diff;
        varSum += var;
    }
    EXPECT_GT(lit, n / 4) << what << ": the image should be mostly lit";
    EXPECT_LE(static_cast<double>(outside), 0.005 * n) << what << ": pixels outside 4 sigma";
    const double meanDiff = diffSum / n, meanSe = std::sqrt(varSum) / n;
    EXPECT_LE(std::fabs(meanDiff), 4 * meanSe + 1e-9)
        << what << ": mean difference " << meanDiff << ", standard error " << meanSe;
}

TEST(Renderer, ExactDiffuseIsIndependentOfTheLightSeed) {
    Rig rig(penumbraScene(Material{}));
    RenderSettings s;
    s.width = s.height = 24;
    s.spp = 2;
    s.lightSeed = 1;
    const Film a = rig.renderer.render(penumbraCamera(), s);
    s.lightSeed = 987654321;
    const Film b = rig.renderer.render(penumbraCamera(), s);
    ASSERT_EQ(a.sum.size(), b.sum.size());
    size_t lit = 0;
    for (size_t i = 0; i < a.sum.size(); ++i) {
        EXPECT_EQ(a.sum[i], b.sum[i]) << "pixel " << i;
        if (channelSum(a.sum[i]) > 0) ++lit;
    }
    EXPECT_GT(lit, a.sum.size() / 3);
    // The sampled render does depend on it (so the seed reaches the light sampling at all).
    s.method = DirectMethod::Sampled;
    s.lightSamples = 4;
    const Film c = rig.renderer.render(penumbraCamera(), s);
    s.lightSeed = 1;
    const Film d = rig.renderer.render(penumbraCamera(), s);
    EXPECT_NE(c.sum, d.sum);
}

// The tiles of a pass go to whichever core is free, in an order set by the last pass's costs
// (tile_schedule.h): the image must not depend on it. One thread against the default pool, and
// a second film on the same renderer (its passes ordered by the first film's costs).
TEST(Renderer, ExactImageIsTheSameForAnyThreadCountAndTileOrder) {
    RenderSettings s;
    s.width = 40;
    s.height = 28;
    s.spp = 3;
    s.minTreeSamples = 0;
    Film one;
    {
        const tbb::global_control single(tbb::global_control::max_allowed_parallelism, 1);
        Rig rig(penumbraScene(Material{}));
        one = rig.renderer.render(penumbraCamera(), s);
    }
    Rig rig(penumbraScene(Material{}));
    const Film first = rig.renderer.render(penumbraCamera(), s);
    const Film again = rig.renderer.render(penumbraCamera(), s);
    ASSERT_EQ(one.sum.size(), first.sum.size());
    size_t lit = 0;
    for (size_t i = 0; i < one.sum.size(); ++i) {
        EXPECT_EQ(one.sum[i], first.sum[i]) << "pixel " << i;
        EXPECT_EQ(first.sum[i], again.sum[i]) << "pixel " << i;
        if (channelSum(one.sum[i]) > 0) ++lit;
    }
    EXPECT_GT(lit, one.sum.size() / 3);
}

// The exact image of `s` (trees for every pair: minTreeSamples 0) as channel sums, checked against
// the same render with no tree at all (every pair below minTreeSamples: each point evaluated
// directly, from a fresh store): the same image up to rounding. Then checks it against converged
// shadow rays (24 replicates of lightSamples 64, scaled).
void expectExactPathsAgreeWithShadowRays(const Scene& scene, const Camera& camera,
                                         RenderSettings s) {
    Rig rig(scene);
    s.minTreeSamples = 0;
    const Film exact = rig.renderer.render(camera, s);
    // The image has a penumbra: some receiver patches are partly blocked.
    EXPECT_GT(rig.renderer.effects().pairsPenumbra, 0u);
    EXPECT_EQ(rig.renderer.effects().pairsDirect, 0u);
    if (const char* dump = std::getenv("PENUMBRA_TEST_DUMP")) writePng(exact, dump);
    std::vector<double> e(exact.sum.size());
    for (size_t i = 0; i < e.size(); ++i) e[i] = channelSum(exact.sum[i] / exact.passes);
    {
        Rig fresh(scene);
        RenderSettings d = s;
        d.minTreeSamples = 1u << 30;
        const Film direct = fresh.renderer.render(camera, d);
        EXPECT_GT(fresh.renderer.effects().pairsDirect, 0u);
        EXPECT_EQ(fresh.store.treeCount(), 0u);  // nothing was built
        for (size_t i = 0; i < e.size(); ++i)
            EXPECT_NEAR(channelSum(direct.sum[i] / direct.passes), e[i], 1e-9 * (1 + e[i]))
                << "pixel " << i;
    }
    s.method = DirectMethod::Sampled;
    s.lightSamples = test::scaled(64);
    const Replicates sampled = replicate(rig, camera, s, 24);
    expectAgreement(e, std::vector<double>(e.size(), 0.0), sampled, "exact vs sampled");
}

// Both exact paths: history trees for every pair (minTreeSamples 0), and no tree at all (every
// pair below minTreeSamples: each point evaluated directly). Same image up to rounding.
TEST(Renderer, ExactDiffuseAgreesWithConvergedShadowRays) {
    RenderSettings s;
    s.width = s.height = 32;
    s.spp = 2;
    s.seed = 7;
    expectExactPathsAgreeWithShadowRays(penumbraScene(Material{}), penumbraCamera(), s);
}

// Occluders standing on the floor with a vertex a hair below it (2^-60, the decimal residue
// 0.1 * 3 - 0.3, a subnormal; one with two such vertices): exactly the configuration where the
// exact render used to lose an occluder whole (its clipped edges were rounded points that
// coincided or swapped) and so lit pixels that lie in its shadow. The exact image must agree with
// converged shadow rays (Embree sees the same shadows in floats), and the tree-less direct render
// with the exact one.
TEST(Renderer, HairCrossingOccludersKeepTheirShadows) {
    auto scene = [] {
        Scene s;
        const int32_t grey = addFloorAndLight(s);
        addFace(s, {{-2, 2, 0}, {2, 2, 0}, {2, 2, 2.5}, {-2, 2, 2.5}}, grey);
        addFace(s, {{-0.9, -0.5, -0x1p-60}, {-0.2, -0.6, 1.1}, {-0.5, 0.1, 0.9}}, grey);
        addFace(s, {{0.2, -0.3, 0.1 * 3 - 0.3}, {0.5, 0.4, 1.0}, {0.9, -0.2, 1.2}}, grey);
        addFace(s, {{-0.3, 0.5, -1e-310}, {0.3, 0.6, -1e-310}, {0.0, 0.2, 1.3}}, grey);
        s.collectLights();
        return s;
    };
    RenderSettings s;
    s.width = s.height = 32;
    s.spp = 2;
    s.seed = 3;
    expectExactPathsAgreeWithShadowRays(scene(), penumbraCamera(), s);
}

// The work-limit tests' render: 24x24 pixels, 8 shadow rays for a sampled point, and no
// light-edge path after the limit (these tests are about the sampling that follows it; the
// path's own tests are below).
RenderSettings workLimitSettings(int spp, uint64_t exactWorkLimit) {
    RenderSettings s;
    s.width = s.height = 24;
    s.spp = spp;
    s.lightSamples = 8;
    s.exactWorkLimit = exactWorkLimit;
    s.lightEdgeWorkLimit = 0;
    return s;
}

// A point whose exact query needs more plane tests than RenderSettings::exactWorkLimit is shaded
// by the sampled estimator with the point's own random numbers: such pixels come out bit for bit
// as in the sampled render, the effects summary counts them, and without a limit none is sampled.
TEST(Renderer, PointsOverTheWorkLimitAreSampledAndCounted) {
    Rig rig(penumbraScene(Material{}));
    const Camera camera = penumbraCamera();
    RenderSettings s = workLimitSettings(2, 0);
    const Film exact = rig.renderer.render(camera, s);
    EXPECT_EQ(rig.renderer.effects().sampledEvaluations, 0u);
    EXPECT_GT(rig.renderer.effects().exactEvaluations, 0u);
    // Without a limit all the timed time is the exact answers', and the summary has no split.
    const EvaluationCosts& unlimited = rig.renderer.effects().costs;
    EXPECT_EQ(unlimited.attemptNs.count(), 0u);
    EXPECT_EQ(unlimited.sampledNs.count(), 0u);
    EXPECT_GT(unlimited.timeSplit().exact, 0.0);
    EXPECT_EQ(unlimited.timeSplit().attempts + unlimited.timeSplit().rays, 0.0);
    EXPECT_EQ(rig.renderer.effects().text().find("where their time went"), std::string::npos);
    rig.renderer.resetEffects();
    s.exactWorkLimit = 1;
    const Film limited = rig.renderer.render(camera, s);
    const EffectsSummary e = rig.renderer.effects();
    // One queried evaluation in kTimedEvery is timed, whichever way it was answered: per
    // renderer scratch the first of every kTimedEvery, so the timed ones are between an eighth
    // of all and that plus one per scratch (one per range of tiles a task shades in a pass: at
    // most the 4 tiles of this 24x24 image). A timed one over the limit times its rays, and its
    // query too where it ran.
    const uint64_t timedCount = e.costs.exactNs.count() + e.costs.sampledNs.count();
    EXPECT_GE(timedCount * EvaluationCosts::kTimedEvery, e.exactEvaluations);
    EXPECT_LE(timedCount, e.exactEvaluations / EvaluationCosts::kTimedEvery + 1 + 4 * s.spp);
    EXPECT_GT(e.costs.attemptNs.count(), 0u);
    EXPECT_LT(e.costs.attemptNs.count(), e.costs.sampledNs.count());  // (others not tried)
    const EvaluationCosts::TimeSplit split = e.costs.timeSplit();
    EXPECT_GT(split.attempts, 0.0);
    EXPECT_GT(split.rays, 0.0);
    EXPECT_NEAR(split.total(),
                (e.costs.exactNs.sum() + e.costs.attemptNs.sum() + e.costs.sampledNs.sum()) *
                    EvaluationCosts::kTimedEvery * 1e-9,
                1e-12);
    EXPECT_NE(e.text().find("where their time went: exact answers "), std::string::npos)
        << e.text();
    EXPECT_GT(e.sampledEvaluations, e.exactEvaluations / 4);
    EXPECT_LE(e.sampledEvaluations, e.exactEvaluations);
    EXPECT_NE(e.text().find("points sampled: "), std::string::npos) << e.text();
    // With a limit of one plane test each query stops in its first stages: the walk, or (no
    // tree) the hierarchy query for the occluders or their activation, never later; the rest
    // were skipped with their region.
    uint64_t tried = 0, early = 0;
    for (size_t i = 0; i < e.overLimitAt.size(); ++i) {
        tried += e.overLimitAt[i];
        const auto stage = static_cast<vis::WorkStage>(i);
        if (stage == vis::WorkStage::Walk || stage == vis::WorkStage::FindOccluders ||
            stage == vis::WorkStage::ActivateOccluders)
            early += e.overLimitAt[i];
    }
    EXPECT_GT(tried, 0u);
    EXPECT_LE(tried, e.sampledEvaluations);
    EXPECT_EQ(early, tried);
    EXPECT_NE(e.text().find("where they reached the limit: "), std::string::npos) << e.text();
    rig.renderer.resetEffects();
    s.method = DirectMethod::Sampled;
    const Film sampled = rig.renderer.render(camera, s);
    size_t likeSampled = 0, likeExact = 0, unlike = 0;
    for (size_t i = 0; i < limited.sum.size(); ++i) {
        if (limited.sum[i] == exact.sum[i] && limited.sum[i] == sampled.sum[i]) continue;
        if (limited.sum[i] == sampled.sum[i])
            ++likeSampled;
        else if (limited.sum[i] == exact.sum[i])
            ++likeExact;
        else
            ++unlike;  // a pixel whose samples went both ways
    }
    EXPECT_GT(likeSampled, limited.sum.size() / 10);
    EXPECT_GT(likeExact, 0u);  // fully visible pairs need no query: still exact
    EXPECT_LT(unlike, limited.sum.size() / 4);
}

// A pixel whose point reached the work limit in one pass has its later passes' points sampled
// for that light without trying (ExactScratch::overLimitBefore): over four passes the queries
// tried are far fewer than four times one pass's, and a new film tries again.
TEST(Renderer, PixelsOverTheWorkLimitAreNotTriedAgainInLaterPasses) {
    Rig rig(penumbraScene(Material{}));
    const Camera camera = penumbraCamera();
    RenderSettings s = workLimitSettings(1, 1);
    auto triedIn = [&](int spp, uint64_t* notTried = nullptr) {
        s.spp = spp;
        rig.renderer.resetEffects();
        rig.renderer.render(camera, s);
        const EffectsSummary e = rig.renderer.effects();
        if (notTried != nullptr) *notTried = e.notTriedEvaluations();
        return e.triedEvaluations();
    };
    const uint64_t one = triedIn(1);
    ASSERT_GT(one, 20u);
    EXPECT_EQ(triedIn(1), one);  // a new film: nothing remembered from the last one
    uint64_t notTried = 0;
    const uint64_t four = triedIn(4, &notTried);
    EXPECT_LT(four, 3 * one) << "passes 2 to 4 tried again the pixels pass 1 found over the limit";
    EXPECT_GT(notTried, 2 * one);
}

// Within a pass, a region's later points skip the attempt after one reached the limit on a
// tree's walk, but not on the direct path (a pair without a tree): there each point is tried.
TEST(Renderer, OnlyTreeWalksOverTheWorkLimitSkipTheirRegionsLaterPoints) {
    const Camera camera = penumbraCamera();
    RenderSettings s = workLimitSettings(1, 1);
    auto notTriedWith = [&](uint64_t minTreeSamples, uint64_t* sampled) {
        Rig rig(penumbraScene(Material{}));
        s.minTreeSamples = minTreeSamples;
        rig.renderer.render(camera, s);
        const EffectsSummary e = rig.renderer.effects();
        *sampled = e.sampledEvaluations;
        return e.notTriedEvaluations();
    };
    uint64_t sampled = 0;
    EXPECT_EQ(notTriedWith(1u << 30, &sampled), 0u);  // every pair direct
    EXPECT_GT(sampled, 20u);
    EXPECT_GT(notTriedWith(0, &sampled), 0u);  // a tree for every pair
    EXPECT_GT(sampled, 20u);
}

// The viewer's preview keeps adding passes while its background precompute adds trees: a pixel
// remembered over the limit on the direct path is tried again once the store holds more trees
// (its pair may have one now).
TEST(Renderer, PixelsOverTheWorkLimitAreTriedAgainOnceTreesAreAdded) {
    Rig rig(penumbraScene(Material{}));
    const Camera camera = penumbraCamera();
    RenderSettings s = workLimitSettings(1, 1);
    s.minTreeSamples = 1u << 30;  // no tree from prepare: every pair on the direct path
    rig.renderer.prepare(camera, s);
    ASSERT_EQ(rig.store.treeCount(), 0u);
    Film film;
    auto triedInPass = [&] {
        rig.renderer.resetEffects();
        EXPECT_TRUE(rig.renderer.renderPass(camera, s, film));
        return rig.renderer.effects().triedEvaluations();
    };
    // (Measured: 51 tried in the first pass, 29 in the second, 54 after the tree, then 33.)
    const uint64_t first = triedInPass();
    ASSERT_GT(first, 20u);
    const uint64_t second = triedInPass();
    EXPECT_LT(4 * second, 3 * first);        // remembered: sampled without trying
    rig.store.getOrBuild(PairKey{0, 0, 1});  // the floor's first patch and the light
    ASSERT_EQ(rig.store.treeCount(), 1u);
    const uint64_t third = triedInPass();
    EXPECT_GT(2 * third, first + second)
        << "a tree was added, yet the remembered pixels were not tried again";
    EXPECT_LT(2 * triedInPass(), first + second);  // and remembered again
}

// Query-driven refinement (RenderSettings::refineLevels): after a pass whose tree walks reached
// the work limit, the sub-patches holding those points get their own trees, and later passes
// walk them. Rendered again with every point exact through the refined store, the image is the
// unrefined store's (two exact computations of one answer); with the limit, refining samples
// fewer points than not refining; with refinement off, or no build worth its cost, nothing is
// refined.
TEST(Renderer, RefinedSubPatchTreesServeLaterPassesWithTheSameExactImage) {
    const Camera camera = penumbraCamera();
    RenderSettings s = workLimitSettings(4, 2);
    s.minTreeSamples = 0;      // a tree for every pair: walks reach the limit
    s.refineCostShare = 1e12;  // refine wherever a walk reached it (no cost model)
    auto sampledWith = [&](int levels, Rig& rig) {
        s.refineLevels = levels;
        rig.renderer.resetEffects();
        rig.renderer.render(camera, s);
        return rig.renderer.effects();
    };
    Rig refined(penumbraScene(Material{})), plain(penumbraScene(Material{}));
    const EffectsSummary on = sampledWith(PatchLayout::kMaxRefineLevels, refined);
    const EffectsSummary off = sampledWith(0, plain);
    EXPECT_GT(on.refinedTrees, 0u);
    EXPECT_GT(on.refinedTreesUsed, 0u);
    EXPECT_GT(refined.store.layout().refinedCount(), 0u);
    EXPECT_NE(on.text().find("pairs refined: "), std::string::npos) << on.text();
    EXPECT_EQ(off.refinedTrees, 0u);
    EXPECT_EQ(plain.store.layout().refinedCount(), 0u);
    EXPECT_LT(on.sampledEvaluations, off.sampledEvaluations);
    // Where no build is worth its cost, the sub-patches are counted and left without a tree.
    Rig frugal(penumbraScene(Material{}));
    s.refineCostShare = 0;
    const EffectsSummary none = sampledWith(PatchLayout::kMaxRefineLevels, frugal);
    EXPECT_EQ(none.refinedTrees, 0u);
    EXPECT_GT(none.refineNotWorth, 0u);
    EXPECT_EQ(none.sampledEvaluations, off.sampledEvaluations);

    s.exactWorkLimit = 0;
    s.refineLevels = 0;
    refined.renderer.resetEffects();
    const Film a = refined.renderer.render(camera, s);
    EXPECT_GT(refined.renderer.effects().refinedTreesUsed, 0u);
    const Film b = plain.renderer.render(camera, s);
    expectSameImage(a, b);
}

// A closed box of 6 x 2 n^2 triangles, [x0, x1] x [y0, y1] x [z0, z1], facing out: each side a
// flat n x n grid of quads (its faces make groups: vis::FaceClusters).
void addGridBox(Scene& s, Vec3 lo, Vec3 hi, int n, int32_t material) {
    // Side k: the corner, two edge directions (their cross product points out).
    const Vec3 d = hi - lo;
    const struct {
        Vec3 o, u, v;
    } sides[6] = {
        {lo, {0, d.y, 0}, {d.x, 0, 0}},                  // bottom, -z
        {{lo.x, lo.y, hi.z}, {d.x, 0, 0}, {0, d.y, 0}},  // top, +z
        {lo, {d.x, 0, 0}, {0, 0, d.z}},                  // front, -y
        {{lo.x, hi.y, lo.z}, {0, 0, d.z}, {d.x, 0, 0}},  // back, +y
        {lo, {0, 0, d.z}, {0, d.y, 0}},                  // left, -x
        {{hi.x, lo.y, lo.z}, {0, d.y, 0}, {0, 0, d.z}},  // right, +x
    };
    for (const auto& side : sides) {
        const uint32_t base = static_cast<uint32_t>(s.mesh.vertices.size());
        for (int j = 0; j <= n; ++j)
            for (int i = 0; i <= n; ++i)
                s.mesh.vertices.push_back(side.o + side.u * (double(i) / n) +
                                          side.v * (double(j) / n));
        auto at = [&](int i, int j) { return base + static_cast<uint32_t>(j * (n + 1) + i); };
        for (int j = 0; j < n; ++j) {
            for (int i = 0; i < n; ++i) {
                addIndexedFace(s, {at(i, j), at(i + 1, j), at(i + 1, j + 1)}, material);
                addIndexedFace(s, {at(i, j), at(i + 1, j + 1), at(i, j + 1)}, material);
            }
        }
    }
}

// The floor and the light with a box of 768 triangles between them (flat sides: its faces make
// face groups).
Scene gridBoxScene() {
    Scene scene;
    const int32_t grey = addFloorAndLight(scene);
    addGridBox(scene, {-0.35, -0.3, 0.7}, {0.3, 0.4, 1.3}, 8, grey);
    scene.collectLights();
    return scene;
}

// Over the work limit the light-edge path answers before anything is sampled
// (RenderSettings::lightEdgeWorkLimit; where it declines, the default path again with its limit).
// At a limit of 8 plane tests the default paths give up on most of the floor's points under the
// box; with the path off those are sampled, with it on none is: the answers map names the path
// for exactly the evaluations the summary counts, and
// the image is the every-point-exact render's (the same fractions from another exact
// computation), with trees and without. The light's index is built once, its S_L the one
// vis::LightSilhouetteEdges finds on its own.
TEST(Renderer, PointsOverTheWorkLimitTakeTheLightEdgePathWithTheExactImage) {
    const Scene scene = gridBoxScene();
    const Camera camera = penumbraCamera();
    for (const bool trees : {true, false}) {
        SCOPED_TRACE(trees ? "a tree for every pair" : "no tree: every point direct");
        RenderSettings s;
        s.width = s.height = 24;
        s.spp = 2;
        s.recordAnswers = true;
        s.minTreeSamples = trees ? 0 : 1u << 30;
        s.exactWorkLimit = 0;
        Rig exactRig(scene);
        const Film exact = exactRig.renderer.render(camera, s);
        ASSERT_EQ(exactRig.renderer.effects().sampledEvaluations, 0u);
        EXPECT_EQ(exactRig.renderer.effects().lightEdgeEvaluations, 0u);  // nothing gave up

        s.exactWorkLimit = 8;
        s.lightEdgeWorkLimit = 0;
        Rig offRig(scene);
        offRig.renderer.render(camera, s);
        const EffectsSummary off = offRig.renderer.effects();
        EXPECT_GT(off.sampledEvaluations, off.exactEvaluations / 10) << off.text();
        EXPECT_EQ(off.lightEdgeEvaluations + off.lightEdgeNotTaken + off.lightEdgeOverLimit, 0u);
        EXPECT_EQ(off.lightEdgeIndex.lights, 0u);

        s.lightEdgeWorkLimit = RenderSettings{}.lightEdgeWorkLimit;
        Rig onRig(scene);
        const Film on = onRig.renderer.render(camera, s);
        const EffectsSummary e = onRig.renderer.effects();
        EXPECT_EQ(e.sampledEvaluations, 0u) << e.text();
        // The default paths gave up on the same points (their decisions do not depend on it):
        // each answered by the light-edge path, or where it declined (the edges near the cone
        // hardly cancel) by the default path again with its limit.
        EXPECT_GT(e.lightEdgeEvaluations, 0u) << e.text();
        EXPECT_EQ(e.lightEdgeEvaluations + e.retriedEvaluations, off.sampledEvaluations)
            << e.text();
        EXPECT_EQ(e.retriedEvaluations, e.lightEdgeNotTaken);
        // Each decline at the point itself has its reason (the rest were their pixel's earlier
        // point's), and none is "taken".
        uint64_t declined = 0;
        for (uint64_t n : e.lightEdgeDeclinedBy) declined += n;
        EXPECT_LE(declined, e.lightEdgeNotTaken);
        EXPECT_EQ(declined > 0, e.lightEdgeNotTaken > 0);
        EXPECT_EQ(e.lightEdgeDeclinedBy[static_cast<size_t>(vis::EdgeDecline::None)], 0u);
        EXPECT_EQ(e.lightEdgeOverLimit + e.retriedOverLimit + e.lightEdgeSkipped, 0u);
        EXPECT_EQ(e.costs.lightEdgeEvaluations, e.lightEdgeEvaluations);
        EXPECT_LE(e.costs.lightEdgesInCone, e.costs.lightEdgesWeighted);
        EXPECT_LE(e.costs.lightEdgesWeighted, e.costs.lightEdgesExamined);
        EXPECT_NE(e.text().find("light-edge path: "), std::string::npos) << e.text();
        const std::array<uint64_t, kAnswers> total = totalAnswers(on.answers);
        EXPECT_EQ(total[static_cast<size_t>(Answer::LightEdges)], e.lightEdgeEvaluations);
        EXPECT_EQ(total[static_cast<size_t>(Answer::Sampled)], 0u);
        EXPECT_NE(describeAnswers(on.answers).find("light-edge path (cyan)"), std::string::npos);
        expectSameImage(on, exact);
        // One index, for the one light, its S_L found independently.
        const vis::MeshEdges edges(scene.mesh);
        const vis::LightSilhouetteEdges sl(scene.mesh, edges, scene.lights[0]);
        EXPECT_EQ(e.lightEdgeIndex.lights, 1u);
        EXPECT_EQ(e.lightEdgeIndex.silhouetteEdges, sl.size());
        EXPECT_EQ(e.lightEdgeIndex.meshEdges, edges.size());
        EXPECT_GT(e.lightEdgeIndex.bytes, sl.size() * sizeof(vis::MeshEdges::Edge));
        EXPECT_NE(e.text().find("its indices (built once per light, on first use): 1 light, "),
                  std::string::npos)
            << e.text();

        // With a light-edge limit of one plane test the path gives up too: those points are
        // sampled, and their pixels' later points sampled without trying it again.
        s.lightEdgeWorkLimit = 1;
        Rig tightRig(scene);
        tightRig.renderer.render(camera, s);
        const EffectsSummary tight = tightRig.renderer.effects();
        EXPECT_GT(tight.lightEdgeOverLimit, 0u) << tight.text();
        EXPECT_GT(tight.lightEdgeSkipped, 0u) << tight.text();
        // Each run over its limit counted at the stage it was in, and shown.
        uint64_t overAt = 0;
        for (uint64_t n : tight.lightEdgeOverLimitAt) overAt += n;
        EXPECT_EQ(overAt, tight.lightEdgeOverLimit);
        EXPECT_NE(tight.text().find("where it reached its limit: "), std::string::npos)
            << tight.text();
        EXPECT_EQ(tight.sampledEvaluations + tight.retriedEvaluations - tight.retriedOverLimit,
                  tight.lightEdgeOverLimit + tight.lightEdgeNotTaken + tight.lightEdgeSkipped);
    }
}

// Where nothing is over the work limit, the light-edge path is never taken and its index never
// built: the image is bit for bit the one rendered with the path off.
TEST(Renderer, ImagesWithNothingOverTheWorkLimitAreTheSameWithTheLightEdgePath) {
    const Camera camera = penumbraCamera();
    RenderSettings s;
    s.width = s.height = 24;
    s.spp = 2;
    s.lightEdgeWorkLimit = 0;
    Rig offRig(penumbraScene(Material{}));
    const Film off = offRig.renderer.render(camera, s);
    ASSERT_EQ(offRig.renderer.effects().sampledEvaluations, 0u);
    s.lightEdgeWorkLimit = RenderSettings{}.lightEdgeWorkLimit;
    Rig onRig(penumbraScene(Material{}));
    const Film on = onRig.renderer.render(camera, s);
    const EffectsSummary e = onRig.renderer.effects();
    EXPECT_EQ(e.lightEdgeEvaluations + e.lightEdgeNotTaken + e.lightEdgeOverLimit, 0u);
    EXPECT_EQ(e.lightEdgeIndex.lights, 0u);
    ASSERT_EQ(on.sum.size(), off.sum.size());
    EXPECT_EQ(std::memcmp(on.sum.data(), off.sum.data(), on.sum.size() * sizeof(Vec3)), 0);
}

// Renders `scene` twice, with a store over the BVH (which knows the face groups) and a store
// without one (which knows none, so every pair seen gets its tree, walked per point), and
// expects the same image up to rounding: two different exact computations. Returns the two
// renders' effects.
std::pair<EffectsSummary, EffectsSummary> expectGroupsAgreeWithTrees(
    const Scene& scene, const RenderSettings& s, const VisibilityStore::Options& options,
    size_t* treesWithGroups = nullptr, size_t* treesWithout = nullptr) {
    const EmbreeScene bvh(scene.mesh);
    EXPECT_GT(bvh.faceClusters().size(), 0u);
    VisibilityStore grouped(scene, &bvh, options), plain(scene, nullptr, options);
    ProgressiveRenderer byGroups(scene, bvh, grouped), byTrees(scene, bvh, plain);
    const Camera camera = penumbraCamera();
    const Film a = byGroups.render(camera, s);
    const Film b = byTrees.render(camera, s);
    expectSameImage(a, b);
    if (treesWithGroups != nullptr) *treesWithGroups = grouped.treeCount();
    if (treesWithout != nullptr) *treesWithout = plain.treeCount();
    return {byGroups.effects(), byTrees.effects()};
}

TEST(Renderer, PartialTreesOverFaceGroupsAreAnsweredByTheGroupsWithTheSameImage) {
    // A build budget of a few linear programs: the floor's trees are partial, their deferred
    // occluders the box's faces, all in groups. The renderer answers those points by the direct
    // path with the groups (answeredByGroups); the store without the BVH walks the partial trees.
    VisibilityStore::Options options;
    options.build.maxLpSolves = 20;
    RenderSettings s;
    s.width = s.height = 24;
    s.spp = 2;
    s.exactWorkLimit = 0;
    s.minTreeSamples = 1;   // every pair seen gets a tree
    s.groupedShaftMin = 0;  // even over a large grouped shaft (the next test)
    const auto [ea, eb] = expectGroupsAgreeWithTrees(gridBoxScene(), s, options);
    EXPECT_GT(ea.pairsPartial, 0u);  // (partial trees are penumbra pairs: the box shadows them)
    EXPECT_GT(eb.pairsPartial, 0u);
    EXPECT_GT(ea.partialByGroupsEvaluations, 0u) << ea.text();
    EXPECT_NE(ea.text().find("answered without the tree"), std::string::npos) << ea.text();
    EXPECT_EQ(eb.partialByGroupsEvaluations, 0u);
    EXPECT_EQ(ea.sampledEvaluations, 0u);
    EXPECT_EQ(ea.pairsGroupedNoTree, 0u);
}

// A small image, every point exact, a tree for every pair seen except those whose shaft holds
// 64 faces or more, a quarter of them in face groups: those the direct path answers.
RenderSettings groupedShaftSettings() {
    RenderSettings s;
    s.width = s.height = 24;
    s.spp = 2;
    s.exactWorkLimit = 0;
    s.minTreeSamples = 1;
    s.groupedShaftMin = 64;
    return s;
}

TEST(Renderer, PairsWhoseShaftTheGroupsAnswerGetNoTreeAndTheSameImage) {
    // The same scene with the product's build budget: a floor patch under the box has its box
    // faces in the shaft, all in groups. With groupedShaftMin below that count the renderer
    // builds no tree for those pairs (groupsWillAnswer) and answers their points by the direct
    // path; the store without the BVH builds and walks them. The same image, fewer trees.
    const RenderSettings s = groupedShaftSettings();
    size_t withGroups = 0, without = 0;
    const auto [ea, eb] = expectGroupsAgreeWithTrees(gridBoxScene(), s, VisibilityStore::Options{},
                                                     &withGroups, &without);
    EXPECT_GT(ea.pairsGroupedNoTree, 0u) << ea.text();
    EXPECT_GE(ea.groupedNoTreeFaces, 64 * ea.pairsGroupedNoTree);
    EXPECT_NE(ea.text().find("left without one"), std::string::npos) << ea.text();
    EXPECT_EQ(eb.pairsGroupedNoTree, 0u);
    EXPECT_EQ(withGroups + ea.pairsGroupedNoTree, without);
    EXPECT_GT(eb.pairsPenumbra, ea.pairsPenumbra);
    EXPECT_EQ(ea.sampledEvaluations, 0u);
}

// A closed box of n^3 lattice cells' outer quads, split into triangles, facing out, its sides
// sharing their edges' vertices (one closed surface: vis::ClosedSurfaces).
void addClosedGridBox(Scene& s, Vec3 lo, Vec3 hi, int n, int32_t material) {
    std::map<std::array<int, 3>, uint32_t> ids;
    auto at = [&](std::array<int, 3> c) {
        auto [it, added] = ids.try_emplace(c, static_cast<uint32_t>(s.mesh.vertices.size()));
        if (added) {
            double p[3];
            for (int k = 0; k < 3; ++k)
                p[k] = c[k] == n ? hi[k] : lo[k] + (hi[k] - lo[k]) * c[k] / n;
            s.mesh.vertices.push_back({p[0], p[1], p[2]});
        }
        return it->second;
    };
    for (int axis = 0; axis < 3; ++axis) {
        for (int end = 0; end <= n; end += n) {
            for (int a = 0; a < n; ++a) {
                for (int b = 0; b < n; ++b) {
                    auto g = [&](int u, int v) {
                        std::array<int, 3> c{};
                        c[axis] = end;
                        c[(axis + 1) % 3] = u;
                        c[(axis + 2) % 3] = v;
                        return at(c);
                    };
                    uint32_t q[4] = {g(a, b), g(a + 1, b), g(a + 1, b + 1), g(a, b + 1)};
                    if (end == 0) std::swap(q[1], q[3]);
                    addIndexedFace(s, {q[0], q[1], q[2]}, material);
                    addIndexedFace(s, {q[0], q[2], q[3]}, material);
                }
            }
        }
    }
}

TEST(Renderer, ClosedBoxLeavesOutItsBackFacesWithTheSameImage) {
    // Each box's sides share their vertices: a closed surface. The floor points whose pairs the
    // groups answer take them as solids (their faces seen from behind left out; the second box
    // stands on the floor, its bottom in the floor's plane); the store without the BVH walks
    // trees over all their faces.
    Scene scene;
    const int32_t grey = addFloorAndLight(scene);
    addClosedGridBox(scene, {-0.35, -0.3, 0.7}, {0.3, 0.4, 1.3}, 8, grey);
    addClosedGridBox(scene, {0.6, -0.9, 0}, {1.0, -0.5, 0.4}, 6, grey);  // on the floor
    scene.collectLights();
    const RenderSettings s = groupedShaftSettings();
    const auto [ea, eb] = expectGroupsAgreeWithTrees(scene, s, VisibilityStore::Options{});
    EXPECT_EQ(ea.closedComponents, 2u);
    EXPECT_GT(ea.directSolidEvaluations, 0u) << ea.text();
    EXPECT_NE(ea.text().find("closed surfaces (solids) seen from behind"), std::string::npos)
        << ea.text();
    EXPECT_EQ(eb.directSolidEvaluations, 0u);
    // The boundary chain answered the floor points under the boxes: each such evaluation cut the
    // light into at least one cell and kept as fragments only cells (those seen), and its edges
    // are what is left of its occluders' (a group counts its boundary only). Summed over all the
    // render's evaluations, as the summary's line reports them per evaluation.
    const EvaluationCosts& c = ea.costs;
    EXPECT_GT(c.chainEvaluations, 0u) << ea.text();
    EXPECT_GE(c.chainCells, c.chainEvaluations);
    EXPECT_LE(c.chainFragments, c.chainCells);
    EXPECT_GT(c.chainFragments, 0u);  // (the penumbra's points see part of the light)
    EXPECT_LE(c.chainBoundaryEdges, c.chainOccluderEdges);
    EXPECT_NE(ea.text().find(" cells and "), std::string::npos) << ea.text();
}

TEST(Renderer, GroupsAnswerAShaftOfAtLeastTheMinimumWithAQuarterGrouped) {
    // groupsWillAnswer's rule, by hand: at least minFaces faces, at least a quarter grouped.
    EXPECT_TRUE(groupsWillAnswer({1024, 256}, 1024));
    EXPECT_FALSE(groupsWillAnswer({1024, 255}, 1024));
    EXPECT_FALSE(groupsWillAnswer({1023, 1023}, 1024));
    EXPECT_TRUE(groupsWillAnswer({5000, 5000}, 1024));
    EXPECT_FALSE(groupsWillAnswer({5000, 5000}, 0));  // 0 = never
    EXPECT_FALSE(groupsWillAnswer({0, 0}, 1));
}

TEST(Renderer, GlossyExactAgreesWithReference) {
    Material glossy;
    glossy.kd = {0.3, 0.3, 0.3};
    glossy.ks = {0.5, 0.4, 0.3};
    glossy.ns = 12;
    Rig rig(penumbraScene(glossy));
    const Camera camera = penumbraCamera();
    RenderSettings s;
    s.width = s.height = 32;
    s.spp = 1;
    s.seed = 3;
    s.glossySamples = 16;
    const Replicates exact = replicate(rig, camera, s, 24);
    s.method = DirectMethod::Reference;
    s.referenceSamples = test::scaled(64);
    const Replicates reference = replicate(rig, camera, s, 24);
    expectAgreement(exact.mean, exact.varianceOfMean, reference, "glossy exact vs reference");
    const EffectsSummary fx = rig.renderer.effects();
    EXPECT_EQ(fx.method, "reference");
}

using test::cornerFormFactor;  // the closed form (tests/support/closed_forms.h)

TEST(Renderer, PointUnderSquareLightMatchesClosedForm) {
    Scene scene;
    const Vec3 kd{0.5, 0.6, 0.7}, ke{3, 4, 5};
    const int32_t floor = addMaterial(scene, kd);
    const int32_t light = addMaterial(scene, {0, 0, 0}, {}, 0, ke);
    addRect(scene, -2, 2, -2, 2, 0, true, floor);
    addRect(scene, -0.5, 0.5, -0.5, 0.5, 1, false, light);
    scene.collectLights();
    Rig rig(std::move(scene));
    // One pixel with a tiny field of view, looking at the origin (under the light's centre) from
    // the side, below the light.
    Camera camera;
    camera.eye = {4, 0.1, 0.5};
    camera.target = {0, 0, 0};
    camera.fovYDegrees = 1e-3;
    RenderSettings s;
    s.width = s.height = 1;
    s.spp = 3;
    s.minTreeSamples = 0;  // a tree per pair, to count the pairs below
    const Film film = rig.renderer.render(camera, s);
    const double f = 4 * cornerFormFactor(0.5, 0.5, 1.0);
    const Vec3 expected{kd.x * ke.x * f, kd.y * ke.y * f, kd.z * ke.z * f};
    const Vec3 got = film.mean(0, 0);
    EXPECT_NEAR(got.x, expected.x, 1e-6 * expected.x);
    EXPECT_NEAR(got.y, expected.y, 1e-6 * expected.y);
    EXPECT_NEAR(got.z, expected.z, 1e-6 * expected.z);

    // What was simulated: fully visible pairs for the floor patches under the pixel (the origin
    // is a corner of several patches, so the jittered samples may fall in a few), every other
    // floor patch never seen, the floor's material analytic.
    const EffectsSummary fx = rig.renderer.effects();
    EXPECT_EQ(fx.method, "exact");
    EXPECT_GE(fx.pairsFullyVisible, 1u);
    EXPECT_LE(fx.pairsFullyVisible, 8u);
    EXPECT_EQ(fx.pairsPenumbra + fx.pairsFullyHidden + fx.pairsBackFacing, 0u);
    const size_t floorPatches = std::max<size_t>(1, rig.store.layout().patches(0).patches.size());
    EXPECT_GT(floorPatches, 8u);
    EXPECT_EQ(fx.pairsNeverSeen, floorPatches - fx.pairsFullyVisible);
    EXPECT_EQ(fx.materialsAnalytic, 1u);
    EXPECT_EQ(fx.materialsSampled, 0u);
    EXPECT_EQ(fx.areaLights, 1u);
    EXPECT_NE(fx.text().find("never seen: " + std::to_string(fx.pairsNeverSeen)),
              std::string::npos);

    // A point light straight above the origin adds I cos / r^2 * kd / pi.
    rig.scene.pointLights.push_back({{0, 0, 0.5}, {2, 2, 2}});
    const Film withPoint = rig.renderer.render(camera, s);
    const double pointTerm = 2 / 0.25 / std::numbers::pi;
    EXPECT_NEAR(withPoint.mean(0, 0).x, expected.x + kd.x * pointTerm, 1e-5);
}

// The answer map (Film::answers) says how each pixel was answered, and each claim is checked
// against an independent outcome: a pixel answered "fully visible" on every evaluation is as
// bright as in the same scene without its occluder (same camera and jitter; pixels near the
// occluder's image are left out, since their samples may hit it), one answered "no light" is
// black, the counts add up to the evaluations the effects summary counted, and a work limit of
// one plane test turns queried answers into "sampled" (the same points: pixel by pixel, the
// queries are as many) while leaving the answers that need no query as they were.
TEST(Renderer, AnswerMapSaysHowEachPixelWasAnsweredAndItIsTrue) {
    const Camera camera = penumbraCamera();
    Scene open = penumbraScene(Material{});
    const std::vector<uint32_t> occluder = open.mesh.faces.back();  // the floating triangle
    open.mesh.faces.pop_back();
    open.faceMaterial.pop_back();
    open.faceSourceLine.pop_back();
    for (const bool trees : {true, false}) {
        SCOPED_TRACE(trees ? "a tree for every pair" : "no tree: every point direct");
        RenderSettings s;
        s.width = s.height = 32;
        s.spp = 2;
        s.exactWorkLimit = 0;
        s.minTreeSamples = trees ? 0 : 1u << 30;
        Rig rig(penumbraScene(Material{}));
        {
            // Not asked for: none kept, and writing them is an error naming the file.
            const Film none = rig.renderer.render(camera, s);
            EXPECT_TRUE(none.answers.empty());
            const std::string file =
                (std::filesystem::temp_directory_path() /
                 ("penumbra_no_answers_" + std::to_string(::getpid()) + ".png"))
                    .string();
            try {
                writeAnswersPng(none, file);
                ADD_FAILURE() << "wrote answers the film does not hold";
            } catch (const std::runtime_error& e) {
                EXPECT_NE(std::string(e.what()).find(file), std::string::npos) << e.what();
            }
            EXPECT_FALSE(std::filesystem::exists(file));
        }
        s.recordAnswers = true;
        rig.renderer.resetEffects();
        const Film film = rig.renderer.render(camera, s);
        const EffectsSummary e = rig.renderer.effects();
        Rig unblocked(open);
        const Film free = unblocked.renderer.render(camera, s);
        ASSERT_EQ(film.answers.size(), film.sum.size());
        ASSERT_EQ(free.sum.size(), film.sum.size());
        // The occluder's image: its vertices' pixel box, a pixel wider on every side.
        double x0 = s.width, x1 = 0, y0 = s.height, y1 = 0;
        for (uint32_t v : occluder) {
            double px = 0, py = 0;
            ASSERT_TRUE(camera.project(open.mesh.vertices[v], s.width, s.height, px, py));
            x0 = std::min(x0, px - 1), x1 = std::max(x1, px + 1);
            y0 = std::min(y0, py - 1), y1 = std::max(y1, py + 1);
        }
        auto count = [](const AnswerCounts& c, Answer a) { return c[static_cast<size_t>(a)]; };
        size_t onlyVisible = 0, onlyNoLight = 0;
        for (size_t i = 0; i < film.sum.size(); ++i) {
            const AnswerCounts& c = film.answers[i];
            uint32_t all = 0;
            for (uint32_t n : c) all += n;
            EXPECT_LE(all, static_cast<uint32_t>(film.passes)) << "pixel " << i;  // one light
            if (all == 0) continue;
            const double px = static_cast<double>(i % s.width),
                         py = static_cast<double>(i / s.width);
            const bool nearOccluder = px + 1 >= x0 && px <= x1 && py + 1 >= y0 && py <= y1;
            if (count(c, Answer::FullyVisible) == all && !nearOccluder) {
                ++onlyVisible;
                EXPECT_NEAR(channelSum(film.sum[i]), channelSum(free.sum[i]),
                            1e-12 * (1 + channelSum(free.sum[i])))
                    << "pixel " << i << " was answered fully visible";
            }
            if (count(c, Answer::NoLight) == all) {
                // Black, but for the light's own emission where its other samples saw the light
                // (ke = (6, 5, 4): addFloorAndLight; those samples evaluate no light).
                ++onlyNoLight;
                const double k = film.sum[i].x / 6;
                EXPECT_EQ(film.sum[i], (Vec3{6, 5, 4} * k))
                    << "pixel " << i << " was answered without light";
                EXPECT_EQ(k, std::floor(k)) << "pixel " << i;
                EXPECT_LE(k + all, film.passes) << "pixel " << i;
            }
        }
        const std::array<uint64_t, kAnswers> total = totalAnswers(film.answers);
        auto of = [&](Answer a) { return total[static_cast<size_t>(a)]; };
        EXPECT_EQ(of(Answer::Sampled), 0u);
        // The queries the summary counted: those answers, and the points that a query's first
        // signs left without light (no light).
        const uint64_t byQueries = of(Answer::TreeWalk) + of(Answer::Direct) + of(Answer::Chain);
        EXPECT_LE(byQueries, e.exactEvaluations);
        EXPECT_LE(e.exactEvaluations, byQueries + of(Answer::NoLight));
        if (!trees) {
            EXPECT_EQ(byQueries + of(Answer::NoLight), e.exactEvaluations);
        }
        EXPECT_GT(onlyNoLight, 0u);  // the back wall above the light's plane
        if (trees) {
            EXPECT_GT(onlyVisible, film.sum.size() / 10);
            EXPECT_GT(of(Answer::TreeWalk), 0u);
            EXPECT_EQ(of(Answer::Direct), 0u);
        } else {
            EXPECT_EQ(of(Answer::FullyVisible) + of(Answer::HorizonClipped) + of(Answer::TreeWalk),
                      0u);
            EXPECT_GT(of(Answer::Direct), 0u);
        }
        // Over a limit of one plane test, with no light-edge path after it: the queried answers
        // are sampled (a trivial query may still fit), the others stay.
        rig.renderer.resetEffects();
        s.exactWorkLimit = 1;
        s.lightEdgeWorkLimit = 0;
        const Film limited = rig.renderer.render(camera, s);
        const std::array<uint64_t, kAnswers> after = totalAnswers(limited.answers);
        EXPECT_EQ(after[static_cast<size_t>(Answer::Sampled)],
                  rig.renderer.effects().sampledEvaluations);
        EXPECT_GT(after[static_cast<size_t>(Answer::Sampled)],
                  (of(Answer::TreeWalk) + of(Answer::Direct)) / 4);
        auto queried = [&](const AnswerCounts& c) {
            return count(c, Answer::TreeWalk) + count(c, Answer::Direct) + count(c, Answer::Chain);
        };  // (a query that reaches the limit makes some plane test: none was a NoLight)
        for (size_t i = 0; i < film.sum.size(); ++i) {
            const AnswerCounts& c = limited.answers[i];
            EXPECT_EQ(queried(c) + count(c, Answer::Sampled), queried(film.answers[i]))
                << "pixel " << i;
            for (const Answer a : {Answer::FullyVisible, Answer::HorizonClipped, Answer::NoLight})
                EXPECT_EQ(count(limited.answers[i], a), count(film.answers[i], a))
                    << "pixel " << i << ", " << toString(a);
        }
    }
}

// "Fully visible" only where a point sees the whole light: a wall whose plane (x = 0.2) cuts the
// light ([-0.5, 0.5]^2 at z = 2) in two, nothing between them. Its pixels are answered
// "horizon-clipped" (nothing in the shaft, the part above the horizon), never "fully visible",
// and are as bright as in the same scene whose light is only that part, [0.2, 0.5] x [-0.5, 0.5]
// (an independent outcome: there the wall's plane touches the light's edge and cuts nothing, so
// those pixels are answered "fully visible"). The floor, under the whole light, is answered
// fully visible where the wall is not in its pair's shaft (a few patches far from the wall).
TEST(Renderer, HorizonClippedLightIsNotCalledFullyVisible) {
    const auto wallScene = [](double lightX0) {
        Scene s;
        s.materials.push_back(Material{});
        const int32_t light = addMaterial(s, {0.2, 0.2, 0.2}, {}, 0, {6, 5, 4});
        addRect(s, -2, 2, -2, 2, 0, true, 0);
        addRect(s, lightX0, 0.5, -0.5, 0.5, 2, false, light);
        // The wall at x = 0.2 facing +x, floating above the floor.
        const uint32_t wall =
            addFace(s, {{0.2, -1.5, 0.1}, {0.2, 1.5, 0.1}, {0.2, 1.5, 1.5}, {0.2, -1.5, 1.5}}, 0);
        s.collectLights();
        return std::pair{std::move(s), wall};
    };
    Camera camera;
    camera.eye = {4, -3, 1.2};
    camera.target = {0.2, 0, 0.7};
    camera.up = {0, 0, 1};
    camera.fovYDegrees = 45;
    RenderSettings s;
    s.width = s.height = 32;
    s.spp = 2;
    s.exactWorkLimit = 0;
    s.minTreeSamples = 0;
    s.recordAnswers = true;
    auto [whole, wall] = wallScene(-0.5);
    auto [part, partWall] = wallScene(0.2);
    ASSERT_EQ(wall, partWall);
    Rig cut(std::move(whole)), above(std::move(part));
    const Film film = cut.renderer.render(camera, s);
    const Film partFilm = above.renderer.render(camera, s);
    ASSERT_EQ(film.answers.size(), film.sum.size());
    ASSERT_EQ(partFilm.answers.size(), film.sum.size());
    // How many of the rays through pixel i's centre and its 8 neighbours' meet the wall: 9, and
    // every sample of the pixel lies on it; 0, and none does.
    const auto wallRays = [&](size_t i) {
        int n = 0;
        for (double dx : {-1.0, 0.0, 1.0})
            for (double dy : {-1.0, 0.0, 1.0}) {
                const Ray ray =
                    camera.ray(static_cast<double>(i % s.width) + 0.5 + dx,
                               static_cast<double>(i / s.width) + 0.5 + dy, s.width, s.height);
                if (!(ray.direction.x < 0)) continue;
                const double t = (0.2 - ray.origin.x) / ray.direction.x;
                const Vec3 p = ray.origin + ray.direction * t;
                n += std::fabs(p.y) < 1.5 && p.z > 0.1 && p.z < 1.5;
            }
        return n;
    };
    auto count = [](const AnswerCounts& c, Answer a) { return c[static_cast<size_t>(a)]; };
    size_t wallPixels = 0, floorVisible = 0;
    for (size_t i = 0; i < film.sum.size(); ++i) {
        const AnswerCounts& c = film.answers[i];
        uint32_t all = 0;
        for (uint32_t n : c) all += n;
        const int rays = wallRays(i);
        if (rays == 9) {
            ++wallPixels;
            EXPECT_GT(all, 0u) << "wall pixel " << i;
            EXPECT_EQ(count(c, Answer::HorizonClipped), all) << "wall pixel " << i;
            EXPECT_EQ(count(partFilm.answers[i], Answer::FullyVisible), all) << "wall pixel " << i;
            EXPECT_NEAR(channelSum(film.sum[i]), channelSum(partFilm.sum[i]),
                        1e-9 * (1 + channelSum(partFilm.sum[i])))
                << "wall pixel " << i;
        } else if (rays == 0) {
            EXPECT_EQ(count(c, Answer::HorizonClipped), 0u) << "pixel " << i << " is off the wall";
            floorVisible += all > 0 && count(c, Answer::FullyVisible) == all;
        }
    }
    EXPECT_GT(wallPixels, film.sum.size() / 20);
    EXPECT_GT(floorVisible, 0u);
}

TEST(Renderer, CancelledPassLeavesTheFilmUnchanged) {
    Rig rig(penumbraScene(Material{}));
    RenderSettings s;
    s.width = s.height = 20;
    s.recordAnswers = true;
    Film film;
    ASSERT_TRUE(rig.renderer.renderPass(penumbraCamera(), s, film));
    ASSERT_EQ(film.passes, 1);
    ASSERT_EQ(film.answers.size(), film.sum.size());
    const Film before = film;
    std::atomic<bool> cancel{true};
    EXPECT_FALSE(rig.renderer.renderPass(penumbraCamera(), s, film, &cancel));
    EXPECT_EQ(film.passes, before.passes);
    EXPECT_EQ(film.sum, before.sum);
    EXPECT_EQ(film.answers, before.answers);
    // A fresh film stays empty.
    Film empty;
    EXPECT_FALSE(rig.renderer.renderPass(penumbraCamera(), s, empty, &cancel));
    EXPECT_EQ(empty.passes, 0);
    // And render() stops: no pass.
    const Film none = rig.renderer.render(penumbraCamera(), s, nullptr, &cancel);
    EXPECT_EQ(none.passes, 0);
    // Passes add up: a second pass at index 1 matches a two-pass render.
    cancel = false;
    ASSERT_TRUE(rig.renderer.renderPass(penumbraCamera(), s, film, &cancel));
    s.spp = 2;
    const Film two = rig.renderer.render(penumbraCamera(), s);
    EXPECT_EQ(film.sum, two.sum);
    EXPECT_EQ(film.answers, two.answers);
}

TEST(Renderer, RejectsBadSettings) {
    Rig rig(penumbraScene(Material{}));
    RenderSettings s;
    s.width = 0;
    Film film;
    EXPECT_THROW(rig.renderer.renderPass(penumbraCamera(), s, film), std::invalid_argument);
    s.width = 4;
    s.spp = 0;
    EXPECT_THROW(rig.renderer.render(penumbraCamera(), s), std::invalid_argument);
}

TEST(Renderer, PfmRoundTrip) {
    Film film;
    film.reset(5, 3);
    film.passes = 2;
    for (int y = 0; y < 3; ++y)
        for (int x = 0; x < 5; ++x) film.sum[y * 5 + x] = {x + 0.25, y * 10.5, -1.0 / (1 + x + y)};
    const auto dir = std::filesystem::temp_directory_path() /
                     ("penumbra_renderer_test_" + std::to_string(::getpid()));
    std::filesystem::create_directories(dir);
    const std::string path = (dir / "image.pfm").string();
    writePfm(film, path);
    int w = 0, h = 0;
    const std::vector<float> pixels = test::readPfm(path, w, h);
    ASSERT_EQ(w, 5);
    ASSERT_EQ(h, 3);
    for (int y = 0; y < 3; ++y) {
        for (int x = 0; x < 5; ++x) {
            const Vec3 m = film.mean(x, y);
            const float* p = &pixels[(y * 5 + x) * 3];
            EXPECT_EQ(p[0], static_cast<float>(m.x));
            EXPECT_EQ(p[1], static_cast<float>(m.y));
            EXPECT_EQ(p[2], static_cast<float>(m.z));
        }
    }
    // PNG: the signature, and no temporary file left behind.
    const std::string png = (dir / "image.png").string();
    writePng(film, png);
    std::ifstream in(png, std::ios::binary);
    char sig[8] = {};
    in.read(sig, 8);
    EXPECT_EQ(std::memcmp(sig, "\x89PNG\r\n\x1a\n", 8), 0);
    size_t files = 0;
    for ([[maybe_unused]] const auto& e : std::filesystem::directory_iterator(dir)) ++files;
    EXPECT_EQ(files, 2u);
    // A directory that does not exist: a clear error naming the file.
    try {
        writePfm(film, (dir / "missing" / "x.pfm").string());
        ADD_FAILURE() << "no error";
    } catch (const std::runtime_error& e) {
        EXPECT_NE(std::string(e.what()).find("x.pfm"), std::string::npos) << e.what();
    }
    std::filesystem::remove_all(dir);
}

TEST(Renderer, SrgbToneMapping) {
    Film film;
    film.reset(3, 1);
    film.passes = 2;  // the mean is sum / 2
    film.sum = {{0, 0.2, 2}, {4, -1, 0.0062616}, {0.6, NAN, 0.1}};
    // Independent values of the sRGB curve: 1.055 v^(1/2.4) - 0.055 (12.92 v below 0.0031308),
    // times 255, rounded: 0.1 -> 89.04, 0.3 -> 148.88, 0.05 -> 63.19, 0.0031308 -> 10.31.
    const std::vector<uint8_t> px = toSrgb8(film);
    const std::vector<uint8_t> expected = {0, 89, 255, 255, 0, 10, 149, 0, 63};
    EXPECT_EQ(px, expected);
    // Exposure scales before the curve: 0.05 * 2 = 0.1.
    EXPECT_EQ(toSrgb8(film, 2.0)[8], 89);
}

}  // namespace
