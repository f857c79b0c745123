// Accuracy against time: sampled direct illumination with 1, 2, 4 ... shadow rays per
// light against the exact image, the exact method's own point against a converged sampled
// reference, and the equal-error time. Used by `penumbra bench` and the viewer's panel.
//
// What is exact and what is estimated:
//   - Every image uses the same primary samples (RenderSettings::seed, spp): the images differ
//     only in how the area lights are integrated, so the RMSE of a sampled image against the
//     exact one is the error of its shadow-ray estimate alone (no pixel-sampling noise).
//   - The exact image's own error is measured against a converged sampled reference: the mean
//     of two independent sampled images (different light seeds) of `referenceRays` rays each. Its
//     noise is estimated from their difference: RMS(A - B) / 2 is the standard error of (A+B)/2
//     per channel, as A and B are independent with equal variance. An exact image agrees with
//     the reference when their RMSE is about that noise.
//   - The equal-error time interpolates the sampled curve linearly in log(time) against
//     log(RMSE); below the curve's last point it extrapolates with the last segment's slope and
//     says so. The exact image's measured error is bounded below by the reference's noise, so
//     this time is a lower bound on what the sampled method needs.
#pragma once

#include <atomic>
#include <cstdint>
#include <string>
#include <vector>

#include "engine/precompute/visibility_store.h"
#include "engine/render/renderer.h"
#include "engine/scene/camera.h"
#include "engine/scene/scene.h"
#include "engine/studies/study_harness.h"

namespace penumbra {

class EmbreeScene;

struct AccuracyStudyOptions {
    int width = 128, height = 128;
    int spp = 4;  // primary samples per pixel, the same for every image
    std::vector<int> rayCounts{1, 2, 4, 8, 16, 32, 64, 128, 256, 512, 1024};
    int referenceRays = 2048;  // per image; the reference averages two images
    uint64_t seed = 1;         // the primary sampling, shared by all images
};

struct AccuracyPoint {
    std::string method;            // "sampled" or "exact"
    int rays = 0;                  // shadow rays per light per shading point (0: exact)
    double seconds = 0;            // wall time of the whole render (exact: its precompute included)
    double cpuSeconds = 0;         // process CPU time of the render (all threads)
    double precomputeSeconds = 0;  // exact: the trees it built (0 when the store had them)
    double rmse = 0;               // sampled: against the exact image; exact: against the reference
    double maxError = 0;           // the largest absolute channel difference, same images
};

struct AccuracyStudy {
    AccuracyStudyOptions options;
    std::vector<AccuracyPoint> sampled;  // in options.rayCounts order
    AccuracyPoint exact;
    double referenceNoise = 0;    // standard error of the reference, RMS over pixels and channels
    double referenceSeconds = 0;  // wall time of the two reference images
    double meanRadiance = 0;      // of the exact image, all channels: a scale for the errors
    // Equal error: the sampled method's time and ray count at the exact image's RMSE (NaN when
    // the curve has fewer than two usable points).
    double equalErrorSeconds = 0, equalErrorRays = 0;
    bool equalErrorExtrapolated = false;
    bool complete = false;  // false when cancelled (the points measured so far are kept)
};

// Runs the study. The store is used (and filled) by the exact image. Cancellable between and
// inside renders; progress (when given) is set to the fraction done in [0, 1].
AccuracyStudy runAccuracyStudy(const Scene& scene, const EmbreeScene& bvh, VisibilityStore& store,
                               const Camera& camera, const AccuracyStudyOptions& options,
                               const std::atomic<bool>* cancel = nullptr,
                               std::atomic<double>* progress = nullptr);

// The study as `penumbra bench` runs it: ray counts 1, 2, 4, ... up to `maxRays` (the options'
// rayCounts are replaced), a fresh store, the scene's default camera, on the studies' workers
// (study_harness.h), its results to `log` at the end.
struct AccuracyBenchRun {
    std::string scene;  // the scene file
    AccuracyStudy study;
    size_t partialTrees = 0;  // of the exact image's precompute
};
AccuracyBenchRun runAccuracyBench(const std::string& path, const Scene& scene,
                                  AccuracyStudyOptions options, int maxRays, const StudyLog& log);

// RMS and max of the per-channel differences of two films of the same size (their means).
struct ImageError {
    double rmse = 0, maxError = 0;
};
ImageError imageError(const Film& a, const Film& b);

// The time at which a curve of (seconds, rmse) points reaches `rmse`, interpolated in log-log
// space (points need not be sorted; non-positive values are skipped). Sets *rays likewise and
// *extrapolated when `rmse` lies outside the curve's range. NaN when fewer than two points.
double equalErrorTime(const std::vector<AccuracyPoint>& curve, double rmse, double* rays = nullptr,
                      bool* extrapolated = nullptr);

}  // namespace penumbra
