#include "engine/studies/equal_error_study.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>

#include "engine/precompute/visibility_store.h"
#include "engine/raytrace/embree_scene.h"

namespace penumbra {

PenumbraError penumbraError(const Film& sampled, const Film& exact) {
    if (sampled.width != exact.width || sampled.height != exact.height)
        throw std::invalid_argument("penumbraError: films of different sizes");
    const size_t pixels = static_cast<size_t>(exact.width) * static_cast<size_t>(exact.height);
    if (exact.seen.size() != pixels)
        throw std::invalid_argument(
            "penumbraError: the exact film has no visible fractions "
            "(RenderSettings::recordVisibleFraction)");
    PenumbraError e;
    double squares = 0, radiance = 0;
    for (int y = 0; y < exact.height; ++y)
        for (int x = 0; x < exact.width; ++x) {
            if (!penumbraPixel(exact.seen[static_cast<size_t>(y) * exact.width + x])) continue;
            ++e.pixels;
            const Vec3 r = exact.mean(x, y);
            const Vec3 d = sampled.mean(x, y) - r;
            squares += d.x * d.x + d.y * d.y + d.z * d.z;
            radiance += r.x + r.y + r.z;
        }
    if (e.pixels == 0) return e;
    const double n = 3.0 * static_cast<double>(e.pixels);
    e.rmse = std::sqrt(squares / n);
    e.meanRadiance = radiance / n;
    e.relative = e.meanRadiance > 0 ? e.rmse / e.meanRadiance : 0;
    return e;
}

GridSearch searchGridSide(const std::function<std::optional<double>(int side)>& errorAt,
                          double target, int maxSide) {
    GridSearch s;
    // The error at `side`, recorded; false when it could not be measured.
    auto measure = [&](int side, bool& within) {
        const std::optional<double> e = errorAt(side);
        if (!e) {
            s.stopped = true;
            return false;
        }
        s.tried.emplace_back(side, *e);
        within = *e <= target;
        return true;
    };
    int above = 0, within = 0;  // the largest side measured above the target, the found one
    for (int side = 1;; side = std::min(2 * side, maxSide)) {
        bool ok = false;
        if (!measure(side, ok)) return s;
        if (ok) {
            within = side;
            break;
        }
        above = side;
        if (side >= maxSide) break;
    }
    if (within == 0) return s;
    while (within - above > 1) {
        const int mid = above + (within - above) / 2;
        bool ok = false;
        if (!measure(mid, ok)) break;
        (ok ? within : above) = mid;
    }
    s.side = within;
    return s;
}

namespace equal_error_detail {

// "180 s" (a limit as the options give it).
std::string secondsText(double s) {
    char b[32];
    std::snprintf(b, sizeof b, "%g s", s);
    return b;
}

// The largest grid side n with n^2 <= rays (at least 1).
int maxSideFor(int rays) {
    int n = 1;
    while ((n + 1) * (n + 1) <= rays) ++n;
    return n;
}

}  // namespace equal_error_detail

EqualErrorRun runEqualErrorStudy(const Scene& scene, const EmbreeScene& bvh, const Camera& camera,
                                 const EqualErrorOptions& o, const StudyLog& log) {
    EqualErrorRun run;
    run.target = o.target;
    run.maxRays = o.maxRays;
    RenderSettings base;
    base.width = o.width;
    base.height = o.height;
    base.spp = o.spp;
    base.seed = o.seed;
    run.pixels = static_cast<uint64_t>(o.width) * static_cast<uint64_t>(o.height);

    // The reference: every point exact, its trees built first (a fresh store), timed together.
    VisibilityStore store(scene, &bvh);
    ProgressiveRenderer renderer(scene, bvh, store);
    RenderSettings exactSettings = base;
    exactSettings.method = DirectMethod::Exact;
    exactSettings.exactWorkLimit = 0;
    exactSettings.recordVisibleFraction = true;
    Film exact;
    RenderTimes t;
    std::atomic<bool> cancel{false};
    run.exactComplete = runWithLimit(
        o.limit, cancel, [&] { exact = renderer.render(camera, exactSettings, &t, &cancel); });
    run.exactWall = run.exactComplete ? t.total : o.limit;
    run.exactCpu = t.totalCpu;
    run.exactPrecomputeWall = t.precompute;
    if (!run.exactComplete) {
        run.why = "the render with every point exact ran over the " +
                  equal_error_detail::secondsText(o.limit) + " limit";
        logLine(log, "  equal error: every point exact over the %.0f s limit", o.limit);
        return run;
    }
    const PenumbraError none = penumbraError(exact, exact);
    run.penumbraPixels = none.pixels;
    run.penumbraMeanRadiance = none.meanRadiance;
    logLine(log,
            "  every point exact: %.2f s wall (precompute %.2f s), %.2f s cpu; %llu penumbra "
            "pixels of %llu",
            run.exactWall, run.exactPrecomputeWall, run.exactCpu,
            static_cast<unsigned long long>(run.penumbraPixels),
            static_cast<unsigned long long>(run.pixels));
    if (none.pixels == 0 || !(none.meanRadiance > 0)) {
        run.why = none.pixels == 0 ? "no penumbra pixel in the image"
                                   : "the penumbra pixels have no radiance";
        return run;
    }

    // Sampled renders with n x n rays per light, the same pixel and light seeds.
    const GridSearch search = searchGridSide(
        [&](int side) -> std::optional<double> {
            RenderSettings s = base;
            s.method = DirectMethod::Sampled;
            s.lightSamples = side * side;
            s.lightSeed = o.lightSeed;
            Film sampled;
            RenderTimes ts;
            std::atomic<bool> stop{false};
            if (!runWithLimit(o.limit, stop,
                              [&] { sampled = renderer.render(camera, s, &ts, &stop); })) {
                logLine(log, "  sampled %d rays: over the %.0f s limit", side * side, o.limit);
                return std::nullopt;
            }
            const double e = penumbraError(sampled, exact).relative;
            run.searched.push_back({side * side, ts.total, ts.totalCpu, e});
            logLine(log, "  sampled %d rays: %.2f s wall, %.2f s cpu, error %.3f%%", side * side,
                    ts.total, ts.totalCpu, 100 * e);
            return e;
        },
        o.target, equal_error_detail::maxSideFor(o.maxRays));
    if (search.side) {
        for (const EqualErrorSample& p : run.searched)
            if (p.rays == *search.side * *search.side) {
                run.found = EqualErrorFound{p.rays,
                                            p.wall,
                                            p.cpu,
                                            p.relativeRmse,
                                            p.wall / run.exactWall,
                                            run.exactCpu > 0 ? p.cpu / run.exactCpu : 0};
                logLine(log, "  equal error (%.2f%%): %d rays, %.2f s wall: exact %.2fx",
                        100 * o.target, p.rays, p.wall, run.found->speedupWall);
            }
    } else if (search.stopped) {
        run.why =
            "a sampled render ran over the " + equal_error_detail::secondsText(o.limit) + " limit";
    } else {
        run.why = "no ray count up to " + std::to_string(o.maxRays) + " reached the target";
    }
    return run;
}

}  // namespace penumbra
