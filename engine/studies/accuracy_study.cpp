#include "engine/studies/accuracy_study.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "engine/raytrace/embree_scene.h"
#include "engine/render/default_camera.h"

namespace penumbra {

ImageError imageError(const Film& a, const Film& b) {
    if (a.width != b.width || a.height != b.height)
        throw std::invalid_argument("imageError: films of different sizes");
    ImageError e;
    double sum = 0;
    size_t n = 0;
    for (int y = 0; y < a.height; ++y)
        for (int x = 0; x < a.width; ++x) {
            const Vec3 d = a.mean(x, y) - b.mean(x, y);
            for (double c : {d.x, d.y, d.z}) {
                sum += c * c;
                e.maxError = std::max(e.maxError, std::abs(c));
                ++n;
            }
        }
    e.rmse = n ? std::sqrt(sum / static_cast<double>(n)) : 0.0;
    return e;
}

double equalErrorTime(const std::vector<AccuracyPoint>& curve, double rmse, double* rays,
                      bool* extrapolated) {
    const double nan = std::numeric_limits<double>::quiet_NaN();
    if (rays) *rays = nan;
    if (extrapolated) *extrapolated = false;
    std::vector<const AccuracyPoint*> p;
    for (const AccuracyPoint& q : curve)
        if (q.seconds > 0 && q.rmse > 0 && q.rays > 0) p.push_back(&q);
    if (p.size() < 2 || !(rmse > 0)) return nan;
    // Sorted by decreasing error (increasing rays).
    std::sort(p.begin(), p.end(),
              [](const AccuracyPoint* a, const AccuracyPoint* b) { return a->rays < b->rays; });
    size_t i = 0;  // the segment [i, i+1] that brackets rmse, else the end segment
    bool inside = false;
    for (size_t k = 0; k + 1 < p.size(); ++k) {
        const double hi = std::max(p[k]->rmse, p[k + 1]->rmse);
        const double lo = std::min(p[k]->rmse, p[k + 1]->rmse);
        if (rmse <= hi && rmse >= lo) {
            i = k;
            inside = true;
            break;
        }
    }
    if (!inside) i = rmse < p.back()->rmse ? p.size() - 2 : 0;
    if (extrapolated) *extrapolated = !inside;
    const AccuracyPoint& a = *p[i];
    const AccuracyPoint& b = *p[i + 1];
    const double le = std::log(rmse), la = std::log(a.rmse), lb = std::log(b.rmse);
    if (la == lb) return inside ? a.seconds : nan;
    const double t = (le - la) / (lb - la);
    if (rays) *rays = std::exp(std::log(a.rays) + t * (std::log(b.rays) - std::log(a.rays)));
    return std::exp(std::log(a.seconds) + t * (std::log(b.seconds) - std::log(a.seconds)));
}

namespace {

bool cancelled(const std::atomic<bool>* cancel) {
    return cancel != nullptr && cancel->load(std::memory_order_relaxed);
}

double meanValue(const Film& f) {
    double sum = 0;
    for (int y = 0; y < f.height; ++y)
        for (int x = 0; x < f.width; ++x) {
            const Vec3 m = f.mean(x, y);
            sum += m.x + m.y + m.z;
        }
    return f.width * f.height > 0 ? sum / (3.0 * f.width * f.height) : 0.0;
}

}  // namespace

AccuracyStudy runAccuracyStudy(const Scene& scene, const EmbreeScene& bvh, VisibilityStore& store,
                               const Camera& camera, const AccuracyStudyOptions& options,
                               const std::atomic<bool>* cancel, std::atomic<double>* progress) {
    AccuracyStudy study;
    study.options = options;
    study.equalErrorSeconds = study.equalErrorRays = std::numeric_limits<double>::quiet_NaN();
    if (options.referenceRays < 1)
        throw std::invalid_argument("accuracy study: referenceRays must be >= 1");
    for (int n : options.rayCounts)
        if (n < 1) throw std::invalid_argument("accuracy study: ray counts must be >= 1");

    ProgressiveRenderer renderer(scene, bvh, store);
    RenderSettings base;
    base.width = options.width;
    base.height = options.height;
    base.spp = options.spp;
    base.seed = options.seed;

    // Work estimate for the progress bar: rays per shading point, the exact image as 8.
    double total = 8.0 + 2.0 * options.referenceRays, done = 0;
    for (int n : options.rayCounts) total += n;
    auto advance = [&](double w) {
        done += w;
        if (progress) progress->store(std::min(1.0, done / total));
    };

    // The exact image.
    RenderSettings s = base;
    s.method = DirectMethod::Exact;
    RenderTimes times;
    const Film exact = renderer.render(camera, s, &times, cancel);
    if (cancelled(cancel)) return study;
    study.exact.method = "exact";
    study.exact.seconds = times.total;
    study.exact.cpuSeconds = times.totalCpu;
    study.exact.precomputeSeconds = times.precompute;
    study.meanRadiance = meanValue(exact);
    advance(8);

    // The sampled curve, one light seed for all counts (the pixel pattern is fixed by `seed`).
    for (int n : options.rayCounts) {
        s = base;
        s.method = DirectMethod::Sampled;
        s.lightSamples = n;
        s.lightSeed = 1;
        const Film f = renderer.render(camera, s, &times, cancel);
        if (cancelled(cancel)) return study;
        const ImageError e = imageError(f, exact);
        study.sampled.push_back({"sampled", n, times.total, times.totalCpu, 0, e.rmse, e.maxError});
        advance(n);
    }

    // The converged reference: two independent images, their mean and its noise.
    Film ref[2];
    for (int k = 0; k < 2; ++k) {
        s = base;
        s.method = DirectMethod::Sampled;
        s.lightSamples = options.referenceRays;
        s.lightSeed = 1000003 + 7919 * static_cast<uint64_t>(k);
        ref[k] = renderer.render(camera, s, &times, cancel);
        if (cancelled(cancel)) return study;
        study.referenceSeconds += times.total;
        advance(options.referenceRays);
    }
    Film mean = ref[0];
    for (size_t i = 0; i < mean.sum.size(); ++i)
        mean.sum[i] = (ref[0].sum[i] + ref[1].sum[i]) * 0.5;
    study.referenceNoise = imageError(ref[0], ref[1]).rmse / 2;
    const ImageError e = imageError(exact, mean);
    study.exact.rmse = e.rmse;
    study.exact.maxError = e.maxError;

    study.equalErrorSeconds = equalErrorTime(study.sampled, study.exact.rmse, &study.equalErrorRays,
                                             &study.equalErrorExtrapolated);
    study.complete = true;
    if (progress) progress->store(1.0);
    return study;
}

AccuracyBenchRun runAccuracyBench(const std::string& path, const Scene& scene,
                                  AccuracyStudyOptions options, int maxRays, const StudyLog& log) {
    const EmbreeScene bvh(scene.mesh);
    VisibilityStore store(scene, &bvh);
    options.rayCounts.clear();
    for (int n = 1; n <= maxRays; n *= 2) options.rayCounts.push_back(n);
    logLine(log, "accuracy %s: %dx%d, %d spp, 1..%d rays, reference 2 x %d rays", path.c_str(),
            options.width, options.height, options.spp, maxRays, options.referenceRays);
    AccuracyBenchRun run;
    run.scene = path;
    runOnWorkers([&] {
        run.study = runAccuracyStudy(scene, bvh, store, defaultCamera(scene, bvh), options);
    });
    run.partialTrees = store.partialCount();
    const AccuracyStudy& st = run.study;
    for (const AccuracyPoint& p : st.sampled)
        logLine(log, "  %4d rays: %.3f s, rmse %.4g, max %.4g", p.rays, p.seconds, p.rmse,
                p.maxError);
    logLine(log,
            "  exact: %.3f s (precompute %.3f s), rmse vs reference %.4g (reference noise "
            "%.4g); equal error at %.3f s (%.0f rays)%s",
            st.exact.seconds, st.exact.precomputeSeconds, st.exact.rmse, st.referenceNoise,
            st.equalErrorSeconds, st.equalErrorRays,
            st.equalErrorExtrapolated ? " (extrapolated)" : "");
    return run;
}

}  // namespace penumbra
