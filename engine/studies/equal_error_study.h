// What accuracy costs on one Table 1 scene: the image rendered with every point exact (no work
// limit; its precompute included), and the shadow rays per light at which stratified sampling
// of the same image comes within a relative error of it over the image's penumbra pixels, with
// that render's time: the exact render's speed-up at equal error.
//
// How the error is measured, and against what:
//   - The reference is the exact render itself, every point exact: what sampling converges to.
//     Both images use the same primary samples (RenderSettings::seed, spp), so they differ only
//     in how the area lights are integrated: the error is the shadow rays' alone.
//   - Penumbra pixels: those whose visible fraction lies strictly between 0 and 1 in the exact
//     render (engine/render/visible_fraction.h: some evaluation saw part of its light, or some
//     none and some all). Elsewhere a light is wholly visible or wholly hidden, and sampling's
//     error there is not what exactness buys.
//   - The error: the RMSE over the penumbra pixels and their RGB channels of linear radiance,
//     over the mean of the exact image's radiance there (penumbraError).
//   - The ray counts are stratified grids n x n (RenderSettings::lightSamples = n^2; a count
//     with no square grid would stratify worse, so the error would not fall with it). The side
//     doubles from 1 until the error is at most the target, then is bisected between the last
//     two sides (searchGridSide), every render with the same light seed: the run is
//     reproducible, and the count found is the smallest side whose error is within the target
//     where the error falls with the side (the measured points are kept to show it does).
//   - Times are wall and process CPU seconds of one run on a shared machine.
#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "engine/render/renderer.h"
#include "engine/scene/camera.h"
#include "engine/scene/scene.h"
#include "engine/studies/study_harness.h"

namespace penumbra {

class EmbreeScene;

// The error of a sampled film against the exact one over the exact film's penumbra pixels
// (Film::seen; the exact film must have it).
struct PenumbraError {
    uint64_t pixels = 0;      // penumbra pixels
    double meanRadiance = 0;  // of the exact film there, over the RGB channels
    double rmse = 0;          // over those pixels and channels
    double relative = 0;      // rmse / meanRadiance (0 without penumbra pixels or radiance)
};
// Throws std::invalid_argument for films of different sizes or an exact film without Film::seen.
PenumbraError penumbraError(const Film& sampled, const Film& exact);

// The search over stratified grid sides n (n x n rays per light): `errorAt(n)` measures the
// error at side n, or nullopt when it could not (a render cut at the time limit), which ends the
// search. Sides double from 1 up to maxSide until one is within `target`, then the bisection
// between the last side above it and that one, down to consecutive sides. `side`: the smallest
// side measured within the target (none when no side up to maxSide reached it, or a measurement
// failed first); `tried`: every side measured, in order, with its error.
struct GridSearch {
    std::optional<int> side;
    std::vector<std::pair<int, double>> tried;
    bool stopped = false;  // a measurement failed
};
GridSearch searchGridSide(const std::function<std::optional<double>(int side)>& errorAt,
                          double target, int maxSide);

struct EqualErrorOptions {
    int width = 512, height = 512, spp = 16;
    double target = 0.005;  // the relative error over the penumbra pixels
    int maxRays = 4096;     // the largest grid searched: the largest n with n^2 <= maxRays
    double limit = 180;     // seconds per render (the exact one, precompute included; each sampled)
    uint64_t seed = 1, lightSeed = 1;
};

// One sampled render of the search.
struct EqualErrorSample {
    int rays = 0;  // per light per shading point: n^2
    double wall = 0, cpu = 0;
    double relativeRmse = 0;
};

// The sampled render at the ray count found, and the exact render's speed-up over it.
struct EqualErrorFound {
    int rays = 0;
    double wall = 0, cpu = 0, relativeRmse = 0;
    double speedupWall = 0, speedupCpu = 0;  // its time over the exact render's (with precompute)
};

struct EqualErrorRun {
    double target = 0;
    int maxRays = 0;
    // The render with every point exact: its trees and the image, wall and CPU seconds; cut at
    // the limit when not complete (then exactWall is the limit).
    bool exactComplete = false;
    double exactWall = 0, exactCpu = 0, exactPrecomputeWall = 0;
    uint64_t pixels = 0, penumbraPixels = 0;
    double penumbraMeanRadiance = 0;
    std::vector<EqualErrorSample> searched;  // in the order measured
    std::optional<EqualErrorFound> found;
    std::string why;  // without `found`: why not
};

// Runs the study on `scene` from `camera` (a fresh store), on the studies' workers.
EqualErrorRun runEqualErrorStudy(const Scene& scene, const EmbreeScene& bvh, const Camera& camera,
                                 const EqualErrorOptions& options, const StudyLog& log);

}  // namespace penumbra
