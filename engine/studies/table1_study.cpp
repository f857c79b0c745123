#include "engine/studies/table1_study.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <stdexcept>
#include <system_error>

#include "engine/io/image_io.h"
#include "engine/io/visibility_file.h"
#include "engine/precompute/visibility_store.h"
#include "engine/raytrace/embree_scene.h"
#include "engine/render/cpu_time.h"
#include "engine/render/default_camera.h"
#include "engine/render/renderer.h"
#include "visibility/light_silhouette_edges.h"
#include "visibility/mesh_edges.h"

namespace penumbra {
namespace table1_detail {

namespace fs = std::filesystem;

// The size of the store's visibility file: written into `dir`, measured, removed.
size_t fileSize(const VisibilityStore& store, const fs::path& dir, const std::string& stem) {
    const fs::path p = dir / (stem + ".pvis");
    const size_t n = writeVisibilityFile(p, store);
    std::error_code ec;
    fs::remove(p, ec);
    return n;
}

WorkByPath workByPath(const EffectsSummary& fx) { return {fx.workAt[0], fx.workAt[1]}; }

EvaluationTimes evaluationTimes(const EffectsSummary& fx) {
    const EvaluationCosts& c = fx.costs;
    EvaluationTimes t;
    const Quantiles q = c.exactNs.quantiles();
    t.evaluations = c.exactNs.count();
    t.medianUs = q.median * 1e-3;
    t.p99Us = q.p99 * 1e-3;
    t.meanUs = c.exactNs.mean() * 1e-3;
    t.quantileStride = c.exactNs.stride();
    t.chainEvaluations = c.chainEvaluations;
    t.chainEdges = c.chainBoundaryEdges;
    t.chainCells = c.chainCells;
    t.chainFragments = c.chainFragments;
    return t;
}

// The cost of a render's exact evaluations with the image it came from.
EveryPointExactCost everyPointCost(const EffectsSummary& fx, const RenderSettings& s, bool complete,
                                   const char* image) {
    return {evaluationTimes(fx), s.width, s.height, s.spp, image, complete};
}

SampledRender measureSampled(const Scene& scene, const EmbreeScene& bvh, const Camera& camera,
                             RenderSettings s, const StudyLog& log) {
    VisibilityStore unused(scene, &bvh);
    ProgressiveRenderer r(scene, bvh, unused);
    s.method = DirectMethod::Sampled;
    s.lightSamples = 128;
    RenderTimes t;
    runOnWorkers([&] { r.render(camera, s, &t); });
    const EffectsSummary fx = r.effects();
    SampledRender out;
    out.wall = t.total;
    out.cpu = t.totalCpu;
    const Quantiles q = fx.costs.sampledNs.quantiles();
    out.points = fx.costs.sampledNs.count();
    out.pointMedianUs = q.median * 1e-3;
    out.pointP99Us = q.p99 * 1e-3;
    out.pointMeanUs = fx.costs.sampledNs.mean() * 1e-3;
    out.pointQuantileStride = fx.costs.sampledNs.stride();
    logLine(log, "  sampled 128: %.2f s wall, %.2f s cpu", t.total, t.totalCpu);
    return out;
}

// The exact render's evaluations, as the effects summary counts them.
void countEvaluations(const EffectsSummary& fx, ExactRender& e) {
    e.pairsWithoutTree = fx.pairsDirect;
    e.pairsGroupedNoTree = fx.pairsGroupedNoTree;
    e.directEvaluations = fx.directEvaluations;
    e.directGroupedEvaluations = fx.directGroupedEvaluations;
    e.directSolidEvaluations = fx.directSolidEvaluations;
    e.directHiddenBySolidEvaluations = fx.directHiddenBySolidEvaluations;
    e.partialByGroupsEvaluations = fx.partialByGroupsEvaluations;
    e.evaluations = fx.exactEvaluations;
    e.sampledEvaluations = fx.sampledEvaluations;
    e.overLimitAt = fx.overLimitAt;
    e.notTried = fx.notTriedEvaluations();
    e.workAt = workByPath(fx);
    e.cost.times = evaluationTimes(fx);
    e.cost.sampledMedianUs = fx.costs.sampledNs.quantiles().median * 1e-3;
    e.cost.sampledQuantileStride = fx.costs.sampledNs.stride();
    e.cost.chainOccluderEdges = fx.costs.chainOccluderEdges;
    const EvaluationCosts::TimeSplit split = fx.costs.timeSplit();
    e.cost.timeSplit = {split.exact, split.attempts, split.rays};
    e.cost.lightEdges = LightEdgeCounts{fx.costs.lightEdgeEvaluations, fx.costs.lightEdgesExamined,
                                        fx.costs.lightEdgesWeighted, fx.costs.lightEdgesInCone};
    e.refined = {fx.refinedPairs, fx.refinedTrees, fx.refinedTreesUsed, fx.refineNotWorth,
                 fx.refineSeconds};
}

// The per-evaluation cost without the work limit (ExactRender::costEveryPointExact), and for the
// small scenes whose render sampled points, Table 1's image with every point exact: the same
// trees, render only, cut at the limit.
void measureEveryPointExact(ProgressiveRenderer& r, const Camera& camera, const RenderSettings& s,
                            const EffectsSummary& fx, const Scene& scene, const Table1Options& o,
                            ExactRender& e, const StudyLog& log) {
    auto renderEveryPointExact = [&](const RenderSettings& all, RenderTimes& ta) {
        std::atomic<bool> stop{false};
        r.resetEffects();
        return runWithLimit(o.limit, stop, [&] { r.render(camera, all, &ta, &stop); });
    };
    RenderSettings all = s;
    all.exactWorkLimit = 0;
    RenderTimes ta;
    if (fx.sampledEvaluations > 0 && !o.large && !o.quick &&
        scene.faceCount() <= kAllPairsMaxFaces) {
        const bool done = renderEveryPointExact(all, ta);
        e.everyPointExact = EveryPointExactRender{done, done ? ta.total : o.limit, ta.totalCpu, {}};
        if (done) e.everyPointExact->workAt = workByPath(r.effects());
        logLine(log, "  every point exact: render %s%.2f s wall", done ? "" : "over ",
                done ? ta.total : o.limit);
        e.costEveryPointExact = everyPointCost(r.effects(), all, done, "Table 1's image");
    } else if (fx.sampledEvaluations == 0) {
        // Nothing was sampled: this render's evaluations were all exact.
        e.costEveryPointExact = everyPointCost(fx, s, true, "Table 1's image");
    } else if (!o.quick) {
        // The image above without the limit would cost minutes (the motorbike's evaluations
        // average milliseconds): a smaller one, one sample per pixel.
        all.width = o.exactCostWidth;
        all.height = o.exactCostHeight;
        all.spp = 1;
        const bool done = renderEveryPointExact(all, ta);
        e.costEveryPointExact = everyPointCost(r.effects(), all, done, "--exact-cost-size");
        logLine(log, "  every point exact at %dx%d, 1 spp: render %s%.2f s wall", all.width,
                all.height, done ? "" : "over ", done ? ta.total : o.limit);
    }
}

// The exact render once its trees are in the store (prepare finds them), with the answers image
// written to the output directory.
ExactRender renderExact(const std::string& path, ProgressiveRenderer& r, const Camera& camera,
                        const RenderSettings& s, const ExactRun& run, const VisibilityStore& store,
                        const Scene& scene, const Table1Options& o, const StudyLog& log) {
    RenderTimes t;
    r.resetEffects();
    Film film;
    runOnWorkers([&] { film = r.render(camera, s, &t); });
    const EffectsSummary fx = r.effects();
    ExactRender e;
    e.answers.image = "answers_" + fs::path(path).stem().string() + ".png";
    try {
        writeAnswersPng(film, (o.outDir / e.answers.image).string());
    } catch (const std::runtime_error& err) {
        throw StudyError(err.what());
    }
    e.answers.counts = totalAnswers(film.answers);
    logLine(log, "  answers (%s): %s", e.answers.image.c_str(),
            describeAnswers(film.answers).c_str());
    e.renderWall = t.total;
    e.renderCpu = t.totalCpu;
    e.wall = run.precomputeWall + t.total;
    e.cpu = run.precomputeCpu + t.totalCpu;
    countEvaluations(fx, e);
    e.exactWorkLimit = s.exactWorkLimit;
    e.minTreeSamples = s.minTreeSamples;
    logLine(log,
            "  exact: precompute %.2f s wall %.2f s cpu, render %.2f s wall %.2f s cpu, %zu "
            "trees (%zu partial), %zu pairs without a tree, %.2f%% of evaluations sampled",
            run.precomputeWall, run.precomputeCpu, t.total, t.totalCpu, store.treeCount(),
            store.partialCount(), fx.pairsDirect, fx.sampledPercent());
    measureEveryPointExact(r, camera, s, fx, scene, o, e, log);
    return e;
}

// The exact renderer: the trees the image needs, within the limit, then the render.
ExactRun measureExact(const std::string& path, const Scene& scene, const EmbreeScene& bvh,
                      const Camera& camera, RenderSettings s, const Table1Options& o,
                      const StudyLog& log) {
    VisibilityStore store(scene, &bvh);
    ProgressiveRenderer r(scene, bvh, store);
    s.method = DirectMethod::Exact;
    s.recordAnswers = true;  // (the answers image)
    std::atomic<bool> cancel{false};
    ExactRun run;
    const double c0 = processCpuSeconds();
    run.precomputeComplete =
        runWithLimit(o.limit, cancel, [&] { run.precomputeWall = r.prepare(camera, s, &cancel); });
    run.precomputeCpu = processCpuSeconds() - c0;
    run.trees = store.treeCount();
    run.nodes = treeNodes(store);
    run.bytes = store.bytes();
    run.kinds = pairKinds(store);
    if (run.precomputeComplete)
        run.render = renderExact(path, r, camera, s, run, store, scene, o, log);
    else
        logLine(log, "  exact: precompute over the %.0f s limit (%zu trees so far)", o.limit,
                store.treeCount());
    run.fileBytes = fileSize(store, o.outDir, "table1");
    return run;
}

std::optional<AllPairsRun> measureAllPairs(const Scene& scene, const EmbreeScene& bvh,
                                           const Table1Options& o, const StudyLog& log) {
    if (o.large || o.quick) return std::nullopt;
    if (scene.faceCount() > kAllPairsMaxFaces) {
        logLine(log, "  all pairs: skipped (%u faces, above %u)", scene.faceCount(),
                kAllPairsMaxFaces);
        return std::nullopt;
    }
    VisibilityStore store(scene, &bvh);
    AllPairsRun all;
    all.precompute = precomputePairs(store, nullptr, o.limit);
    all.fileBytes = fileSize(store, o.outDir, "all");
    logLine(log, "  all pairs: %.2f s wall, %.2f s cpu, %zu trees", all.precompute.seconds,
            all.precompute.cpu, store.treeCount());
    return all;
}

// S_L of every area light (visibility/light_silhouette_edges.h): its share of the mesh's edges.
ShadowEdges measureShadowEdges(const Scene& scene, const StudyLog& log) {
    const auto t0 = std::chrono::steady_clock::now();
    const vis::MeshEdges edges(scene.mesh);
    ShadowEdges out;
    out.edges = edges.size();
    out.minShare = scene.lights.empty() ? 0 : 1;
    for (uint32_t light : scene.lights) {
        const vis::LightSilhouetteEdges set(scene.mesh, edges, light);
        out.open = set.open();
        out.keptOverLights += set.size();
        out.minShare = std::min(out.minShare, set.share());
        out.maxShare = std::max(out.maxShare, set.share());
    }
    out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    logLine(log, "  S_L: %zu edges (%zu open), share per light %.1f%%-%.1f%%, %.3f s", out.edges,
            out.open, 100 * out.minShare, 100 * out.maxShare, out.seconds);
    return out;
}

}  // namespace table1_detail

Table1Row runTable1Study(const std::string& path, const Scene& scene, const Table1Options& o,
                         const StudyLog& log) {
    using namespace table1_detail;
    const EmbreeScene bvh(scene.mesh);
    const Camera camera = defaultCamera(scene, bvh);
    Table1Row row;
    row.scene = path;
    row.faces = scene.faceCount();
    row.areaLights = scene.lights.size();
    row.width = o.width;
    row.height = o.height;
    row.spp = o.spp;
    logLine(log, "table1 %s: %u faces, %dx%d, %d spp", path.c_str(), scene.faceCount(), o.width,
            o.height, o.spp);
    RenderSettings s;
    s.width = o.width;
    s.height = o.height;
    s.spp = o.spp;
    s.lightEdgeWorkLimit = o.lightEdgeWorkLimit;
    row.shadowEdges = measureShadowEdges(scene, log);
    row.sampled128 = measureSampled(scene, bvh, camera, s, log);
    row.exact = measureExact(path, scene, bvh, camera, s, o, log);
    if (const std::optional<ExactRender>& e = row.exact.render) {
        const SampledRender& sampled = row.sampled128;
        row.speedup = Speedups{sampled.wall / e->wall, sampled.cpu / e->cpu,
                               sampled.wall / e->renderWall, sampled.cpu / e->renderCpu};
    }
    row.allPairs = measureAllPairs(scene, bvh, o, log);
    EqualErrorOptions eq;
    eq.width = o.width;
    eq.height = o.height;
    eq.spp = o.spp;
    eq.maxRays = o.equalErrorMaxRays;
    eq.limit = o.limit;
    row.equalError = runEqualErrorStudy(scene, bvh, camera, eq, log);
    return row;
}

}  // namespace penumbra
