// ProgressiveRenderer: the CPU ray tracer with exact soft shadows (issue 3).
//
// CONTRACT HEADER: declared here so that the viewer (app/) and the bench can be written against it
// while it is implemented in engine/renderer.cpp. Additions are fine; changes need a reason.
//
// One pass = one jittered primary sample per pixel, rendered in tiles on oneTBB. Passes accumulate
// in a Film; a pass can be cancelled (the partial pass is discarded, the film keeps whole passes).
// Direct illumination only (emitted + one bounce from the area and point lights).
//   Exact:     the visible fragments of each area light from the shading point (FPQuery through the
//              VisibilityStore). Diffuse: L = kd * Le * F with F the point-to-polygon form factor
//              of the fragments (irradiance pi Le F, times kd / pi): analytic, no samples.
//              Glossy: samples drawn only inside the visible fragments.
//   Sampled:   N stratified shadow rays per light per shading point (Embree), the paper's baseline.
//   Reference: the same as Sampled with many rays (referenceSamples).
#pragma once

#include <atomic>
#include <cstdint>
#include <string>
#include <vector>

#include "engine/camera.h"
#include "engine/effects_summary.h"
#include "engine/scene.h"

namespace penumbra {

class EmbreeScene;
class VisibilityStore;

enum class DirectMethod { Exact, Sampled, Reference };
const char* toString(DirectMethod m);

struct RenderSettings {
    int width = 512;
    int height = 512;
    int spp = 16;                // primary samples per pixel (= passes)
    DirectMethod method = DirectMethod::Exact;
    int lightSamples = 128;      // shadow rays per light per shading point (Sampled)
    int referenceSamples = 1024; // (Reference)
    uint64_t seed = 1;           // the pixel sampling pattern; the same seed gives the same jitter
};

// Linear radiance, accumulated over passes.
struct Film {
    int width = 0, height = 0;
    int passes = 0;
    std::vector<Vec3> sum;  // width * height, row-major from the top-left
    void reset(int w, int h);
    Vec3 mean(int x, int y) const;  // sum / passes (0 when no pass)
};

struct RenderTimes {
    double precompute = 0;  // seconds building the history trees the image needs
    double primary = 0;     // tracing primary rays (summed over threads, then scaled to wall time)
    double shading = 0;     // direct illumination
    double total = 0;       // wall time
};

class ProgressiveRenderer {
public:
    // All three must outlive the renderer. The store is used only by DirectMethod::Exact.
    ProgressiveRenderer(const Scene& scene, const EmbreeScene& bvh, VisibilityStore& store);

    // The trees the image needs (for Exact), built in parallel before shading: the (receiver
    // patch, light) pairs hit by the primary rays of the first pass. Returns seconds spent.
    // Cancellable; returns early when cancelled.
    double prepare(const Camera& camera, const RenderSettings& settings,
                   const std::atomic<bool>* cancel = nullptr);
    // Adds one pass (pass index = film.passes) to the film. Returns false when cancelled (the film
    // is unchanged).
    bool renderPass(const Camera& camera, const RenderSettings& settings, Film& film,
                    const std::atomic<bool>* cancel = nullptr);
    // prepare + settings.spp passes.
    Film render(const Camera& camera, const RenderSettings& settings, RenderTimes* times = nullptr,
                const std::atomic<bool>* cancel = nullptr);

    // What was simulated and why (pairs by kind, materials analytic or sampled, point lights).
    EffectsSummary effects() const;
};

// Output. PFM: linear float, little-endian, bottom-to-top rows as the format requires. PNG:
// exposure then sRGB tone mapping. Both written atomically (temp file + rename).
void writePfm(const Film& film, const std::string& path);
void writePng(const Film& film, const std::string& path, double exposure = 1.0);

}  // namespace penumbra
