// penumbra bench [SCENES] --out DIR: what accuracy costs in time, every comparison
// measured in one run on one machine, written as DIR/bench.json, DIR/report.md and (through
// scripts/plot_bench.py) PNG plots.
//   table1     the paper's Table 1: 128-ray sampled rendering against the exact renderer (its
//              precompute of the trees the image needs, and all pairs for small scenes), the
//              visibility file's size, the speed-up; wall and CPU times (the machine is shared).
//   accuracy   error against time: sampled with 1..1024 rays against the exact image, the exact
//              image against a converged reference, the equal-error time
//              (engine/studies/accuracy_study.h).
//   predicates FPQuery with filtered, always-exact and naive double predicates on the hard cases.
//   options    quadric pruning and leaf merging on and off.
//   scaling    precompute time and size against the triangle count (the dragon's resolutions).
//   per point  the from-point query plus the exact form factor against 16 and 128 shadow rays.
// A default scene whose meshes scripts/fetch_meshes.sh has not fetched (the bunny, the motorbike,
// the dragon) is skipped, with a warning and a line in the report (canMeasure).
#include <sys/resource.h>
#include <tbb/global_control.h>
#include <tbb/info.h>
#include <tbb/task_arena.h>
#include <tbb/task_group.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <random>
#include <thread>

#include "app/cli/answers_json.h"
#include "app/cli/arguments.h"
#include "app/cli/bench/bench_report.h"
#include "app/cli/commands.h"
#include "app/viewer/point_inspection.h"
#include "app/viewer/selection.h"
#include "engine/io/atomic_file.h"
#include "engine/io/finite_output.h"
#include "engine/io/image_io.h"
#include "engine/io/visibility_file.h"
#include "engine/precompute/precompute_scheduler.h"
#include "engine/precompute/visibility_store.h"
#include "engine/raytrace/embree_scene.h"
#include "engine/render/cpu_time.h"
#include "engine/render/default_camera.h"
#include "engine/render/renderer.h"
#include "engine/studies/accuracy_study.h"
#include "engine/studies/predicate_study.h"
#include "visibility/form_factor.h"
#include "visibility/fp_query.h"
#include "visibility/visible_outline.h"

#ifndef PENUMBRA_BUILD_TYPE
#define PENUMBRA_BUILD_TYPE "unknown"
#endif

namespace penumbra::cli {
namespace {

using Clock = std::chrono::steady_clock;
using nlohmann::json;
namespace fs = std::filesystem;

struct BenchOptions {
    std::vector<std::string> scenes;
    std::string out;
    std::string size = "512x512";
    std::string largeSize = "256x256";
    int spp = 16;
    std::string accuracyScene = "assets/scenes/cornell_box.json";
    std::string accuracySize = "128x128";
    int accuracySpp = 4;
    int maxRays = 1024;
    int referenceRays = 2048;
    int points = 2000;
    double limit = 180;  // seconds per precompute before it is cancelled
    bool quick = false;
    bool skipLarge = false;
    bool noPlots = false;
    bool strict = false;
    // The image of the per-point cost with every point exact, for the scenes whose Table 1 image
    // is too costly to render without the work limit (the large ones, and those above
    // kAllPairsMaxFaces faces): one sample per pixel.
    std::string exactCostSize = "128x128";
};

double seconds(Clock::time_point a, Clock::time_point b) {
    return std::chrono::duration<double>(b - a).count();
}

// The exact queries' work in plane tests by the stage it went to (vis::FromPointQuery::
// stageWork), for the tree pairs and for those without a tree.
json workJson(const EffectsSummary& fx) {
    json w = json::object();
    const char* const paths[] = {"trees", "direct"};
    for (size_t p = 0; p < fx.workAt.size(); ++p) {
        json stages = json::object();
        for (size_t i = 0; i < vis::kWorkStages; ++i)
            stages[vis::toString(static_cast<vis::WorkStage>(i))] = fx.workAt[p][i];
        w[paths[p]] = stages;
    }
    return w;
}

json kindsJson(const VisibilityStore& store) {
    const std::array<size_t, vis::kPairKindCount> k = store.kindCounts();
    return {{"backFacing", k[0]},
            {"fullyVisible", k[1]},
            {"fullyHidden", k[2]},
            {"penumbra", k[3]},
            {"partial", store.partialCount()}};
}

size_t treeNodes(const VisibilityStore& store) {
    size_t n = 0;
    store.forEach([&](const PairKey&, const PairRecord& r) { n += r.tree.nodes.size(); });
    return n;
}

// Runs `work` on oneTBB while this thread watches the clock; raises `cancel` after `limit` s.
// Returns true when the work finished before the limit. Every timed run of the bench goes through
// here, so that all of them run on the same workers (runBench lets TBB have one per core, since
// this thread only polls).
template <class F>
bool runWithLimit(double limit, std::atomic<bool>& cancel, F&& work) {
    // An arena with a worker slot per core and none kept for this thread (it only polls).
    tbb::task_arena arena(std::max(1, tbb::info::default_concurrency()), 0);
    std::atomic<bool> done{false};
    tbb::task_group group;
    arena.execute([&] {
        group.run([&] {
            work();
            done = true;
        });
    });
    const auto t0 = Clock::now();
    while (!done.load()) {
        std::this_thread::sleep_for(std::chrono::milliseconds(50));
        if (!cancel.load() && seconds(t0, Clock::now()) > limit) cancel = true;
    }
    arena.execute([&] { group.wait(); });
    return !cancel.load();
}

size_t fileSize(const VisibilityStore& store, const fs::path& dir, const std::string& stem) {
    const fs::path p = dir / (stem + ".pvis");
    const size_t n = writeVisibilityFile(p, store);
    std::error_code ec;
    fs::remove(p, ec);
    return n;
}

// The scheduler builds `keys` (or every pair when empty); stops at the limit.
json precomputePairs(VisibilityStore& store, const std::vector<PairKey>* keys, double limit) {
    const double c0 = processCpuSeconds();
    const auto t0 = Clock::now();
    PrecomputeScheduler scheduler(store);
    if (keys)
        scheduler.request(*keys);
    else
        scheduler.requestAll();
    bool over = false;
    for (;;) {
        const PrecomputeProgress p = scheduler.progress();
        if (p.state != PrecomputeProgress::State::Running && p.done >= p.total) break;
        if (p.state == PrecomputeProgress::State::Failed)
            throw inputError("precompute failed: " + p.error);
        if (p.state != PrecomputeProgress::State::Running &&
            p.state != PrecomputeProgress::State::Idle)
            break;
        if (seconds(t0, Clock::now()) > limit) {
            scheduler.cancel();
            over = true;
            break;
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(50));
    }
    scheduler.wait();
    const PrecomputeProgress p = scheduler.progress();
    return {{"seconds", seconds(t0, Clock::now())},
            {"cpu", processCpuSeconds() - c0},
            {"pairs", p.total},
            {"done", p.done},
            {"complete", !over && p.done >= p.total},
            {"trees", store.treeCount()},
            {"nodes", treeNodes(store)},
            {"bytes", store.bytes()},
            {"kinds", kindsJson(store)}};
}

// ---- Scenes with fetched meshes --------------------------------------------------------------

// The files a scene needs and lacks: the scene file itself, or the mesh files a JSON scene names.
// The committed scenes of the bunny, the motorbike and the dragon name meshes that
// scripts/fetch_meshes.sh downloads into assets/external/ (too large to commit), so a fresh clone
// lacks them. A scene file that does not parse lacks nothing here: loading it says what is wrong.
std::vector<std::string> missingFiles(const std::string& scene) {
    if (!fs::exists(scene)) return {scene};
    if (fs::path(scene).extension() != ".json") return {};
    std::ifstream in(scene);
    const json j = json::parse(in, nullptr, /*allow_exceptions=*/false);
    std::vector<std::string> missing;
    if (!j.is_object() || !j.contains("meshes") || !j["meshes"].is_array()) return missing;
    for (const json& mesh : j["meshes"]) {
        if (!mesh.is_object() || !mesh.contains("file") || !mesh["file"].is_string()) continue;
        const fs::path file = fs::path(scene).parent_path() / mesh["file"].get<std::string>();
        if (!fs::exists(file)) missing.push_back(file.lexically_normal().string());
    }
    return missing;
}

// Whether `study` can measure `scene`. If not, says on stderr which files are missing and records
// the skip in `skipped` (bench.json's "skipped", which the report lists under the study): the
// one way the bench leaves out a scene whose meshes have not been fetched, so that a fresh clone
// still gets a report.
bool canMeasure(const std::string& scene, const std::string& study, json& skipped) {
    const std::vector<std::string> missing = missingFiles(scene);
    if (missing.empty()) return true;
    std::string list;
    for (const std::string& f : missing) list += (list.empty() ? "" : ", ") + f;
    std::fprintf(stderr,
                 "penumbra: warning: %s: %s skipped, missing %s (run scripts/fetch_meshes.sh to "
                 "fetch the meshes)\n",
                 study.c_str(), scene.c_str(), list.c_str());
    skipped.push_back({{"study", study}, {"scene", scene}, {"missing", missing}});
    return false;
}

// ---- Table 1 -------------------------------------------------------------------------------

// The distribution of a render's exact evaluations (one in 8 timed, query and shading) with
// the image it came from; `complete` false when the render was cut at the bench's limit (the
// evaluations timed until then).
json costJson(const EffectsSummary& fx, const RenderSettings& s, bool complete, const char* image) {
    // With the boundary chain's evaluations (all of them, not only the timed ones): what the
    // expensive points' cost follows (their chain edges and cells) against the fragments.
    return {{"evaluations", fx.costs.exactNs.count()},
            {"medianUs", fx.costs.exactNs.quantile(0.5) * 1e-3},
            {"p99Us", fx.costs.exactNs.quantile(0.99) * 1e-3},
            {"meanUs", fx.costs.exactNs.mean() * 1e-3},
            {"chainEvaluations", fx.costs.chainEvaluations},
            {"chainEdges", fx.costs.chainBoundaryEdges},
            {"chainCells", fx.costs.chainCells},
            {"chainFragments", fx.costs.chainFragments},
            {"width", s.width},
            {"height", s.height},
            {"spp", s.spp},
            {"image", image},
            {"complete", complete}};
}

json table1Row(const std::string& path, const BenchOptions& o, const fs::path& dir, bool large) {
    const Scene scene = loadSceneFile(path, o.strict);
    const auto [w, h] =
        parseSize(large ? "--large-size" : "--size", large ? o.largeSize : o.size, kImageSize);
    const EmbreeScene bvh(scene.mesh);
    const Camera camera = defaultCamera(scene, bvh);
    json row = {{"scene", path},
                {"faces", scene.faceCount()},
                {"areaLights", scene.lights.size()},
                {"width", w},
                {"height", h},
                {"spp", o.spp}};
    std::printf("table1 %s: %u faces, %dx%d, %d spp\n", path.c_str(), scene.faceCount(), w, h,
                o.spp);
    std::fflush(stdout);
    RenderSettings s;
    s.width = w;
    s.height = h;
    s.spp = o.spp;
    {
        VisibilityStore unused(scene, &bvh);
        ProgressiveRenderer r(scene, bvh, unused);
        s.method = DirectMethod::Sampled;
        s.lightSamples = 128;
        RenderTimes t;
        std::atomic<bool> never{false};
        runWithLimit(INFINITY, never, [&] { r.render(camera, s, &t); });
        const EffectsSummary fx = r.effects();
        row["sampled128"] = {{"wall", t.total},
                             {"cpu", t.totalCpu},
                             {"points", fx.costs.sampledNs.count()},
                             {"pointMedianUs", fx.costs.sampledNs.quantile(0.5) * 1e-3},
                             {"pointP99Us", fx.costs.sampledNs.quantile(0.99) * 1e-3},
                             {"pointMeanUs", fx.costs.sampledNs.mean() * 1e-3}};
        std::printf("  sampled 128: %.2f s wall, %.2f s cpu\n", t.total, t.totalCpu);
    }
    {
        VisibilityStore store(scene, &bvh);
        ProgressiveRenderer r(scene, bvh, store);
        s.method = DirectMethod::Exact;
        s.recordAnswers = true;  // (the answers images)
        std::atomic<bool> cancel{false};
        double prepWall = 0, prepCpu = 0;
        const double c0 = processCpuSeconds();
        const bool ok =
            runWithLimit(o.limit, cancel, [&] { prepWall = r.prepare(camera, s, &cancel); });
        prepCpu = processCpuSeconds() - c0;
        json e = {{"precomputeWall", prepWall}, {"precomputeCpu", prepCpu},
                  {"precomputeComplete", ok},   {"trees", store.treeCount()},
                  {"nodes", treeNodes(store)},  {"bytes", store.bytes()},
                  {"kinds", kindsJson(store)}};
        if (ok) {
            RenderTimes t;
            r.resetEffects();
            std::atomic<bool> never{false};
            // The trees are in the store: its prepare finds them.
            Film film;
            runWithLimit(INFINITY, never, [&] { film = r.render(camera, s, &t); });
            const EffectsSummary fx = r.effects();
            // How each pixel was answered (engine/render/answers.h): DIR/answers_SCENE.png and
            // the evaluations by answer.
            const std::string answers = "answers_" + fs::path(path).stem().string() + ".png";
            try {
                writeAnswersPng(film, (dir / answers).string());
            } catch (const std::runtime_error& err) {
                throw inputError(err.what());
            }
            e["answers"] = {{"image", answers}, {"counts", answerTotalsJson(film.answers)}};
            std::printf("  answers (%s): %s\n", answers.c_str(),
                        describeAnswers(film.answers).c_str());
            e["renderWall"] = t.total;
            e["renderCpu"] = t.totalCpu;
            e["wall"] = prepWall + t.total;
            e["cpu"] = prepCpu + t.totalCpu;
            e["pairsWithoutTree"] = fx.pairsDirect;
            // Of those, the ones seen often enough for a tree that the face groups answer
            // (RenderSettings::groupedShaftMin).
            e["pairsGroupedNoTree"] = fx.pairsGroupedNoTree;
            e["directEvaluations"] = fx.directEvaluations;
            // Of those, the ones that took face groups whole (vis::FaceClusters).
            e["directGroupedEvaluations"] = fx.directGroupedEvaluations;
            // Of those, the ones that left out back faces of closed surfaces, and the ones a
            // closed surface hid whole (vis::ClosedSurfaces).
            e["directSolidEvaluations"] = fx.directSolidEvaluations;
            e["directHiddenBySolidEvaluations"] = fx.directHiddenBySolidEvaluations;
            e["partialByGroupsEvaluations"] = fx.partialByGroupsEvaluations;
            e["evaluations"] = fx.exactEvaluations;
            e["sampledEvaluations"] = fx.sampledEvaluations;
            // Where the sampled points' queries reached the work limit (vis::WorkStage).
            json stages = json::object();
            for (size_t i = 0; i < fx.overLimitAt.size(); ++i)
                stages[vis::toString(static_cast<vis::WorkStage>(i))] = fx.overLimitAt[i];
            e["overLimitAt"] = stages;
            e["notTried"] = fx.notTriedEvaluations();
            e["workAt"] = workJson(fx);
            // Each exact evaluation timed (the query and its shading), and the boundary chain's
            // evaluations with their chain edges and fragments (must-have 5 of issue 13).
            e["cost"] = {{"evaluations", fx.costs.exactNs.count()},
                         {"medianUs", fx.costs.exactNs.quantile(0.5) * 1e-3},
                         {"p99Us", fx.costs.exactNs.quantile(0.99) * 1e-3},
                         {"meanUs", fx.costs.exactNs.mean() * 1e-3},
                         {"sampledMedianUs", fx.costs.sampledNs.quantile(0.5) * 1e-3},
                         {"chainEvaluations", fx.costs.chainEvaluations},
                         {"chainOccluderEdges", fx.costs.chainOccluderEdges},
                         {"chainEdges", fx.costs.chainBoundaryEdges},
                         {"chainCells", fx.costs.chainCells},
                         {"chainFragments", fx.costs.chainFragments}};
            // Where the evaluations' time went, estimated from the timed ones: what the work
            // limit's sampling costs the exact render (its rays, and the queries stopped first).
            const EvaluationCosts::TimeSplit split = fx.costs.timeSplit();
            e["cost"]["timeSplit"] = {{"exactSeconds", split.exact},
                                      {"attemptSeconds", split.attempts},
                                      {"raysSeconds", split.rays}};
            e["exactWorkLimit"] = s.exactWorkLimit;
            e["minTreeSamples"] = s.minTreeSamples;
            // Query-driven refinement between passes (RenderSettings::refineLevels).
            e["refined"] = {{"pairs", fx.refinedPairs},
                            {"trees", fx.refinedTrees},
                            {"treesUsed", fx.refinedTreesUsed},
                            {"notWorth", fx.refineNotWorth},
                            {"seconds", fx.refineSeconds}};
            row["speedupWall"] = row["sampled128"]["wall"].get<double>() / (prepWall + t.total);
            row["speedupCpu"] = row["sampled128"]["cpu"].get<double>() / (prepCpu + t.totalCpu);
            row["speedupRenderOnlyCpu"] = row["sampled128"]["cpu"].get<double>() / t.totalCpu;
            row["speedupRenderOnlyWall"] = row["sampled128"]["wall"].get<double>() / t.total;
            std::printf(
                "  exact: precompute %.2f s wall %.2f s cpu, render %.2f s wall %.2f s cpu, %zu "
                "trees (%zu partial), %zu pairs without a tree, %.2f%% of evaluations sampled\n",
                prepWall, prepCpu, t.total, t.totalCpu, store.treeCount(), store.partialCount(),
                fx.pairsDirect, fx.sampledPercent());
            // `all` rendered with every point exact (no work limit): the same trees, render
            // only, cut at the bench's limit (false then).
            auto renderEveryPointExact = [&](const RenderSettings& all, RenderTimes& ta) {
                std::atomic<bool> stop{false};
                r.resetEffects();
                return runWithLimit(o.limit, stop, [&] { r.render(camera, all, &ta, &stop); });
            };
            RenderSettings all = s;
            all.exactWorkLimit = 0;
            RenderTimes ta;
            // Every point exact, for the scenes whose hybrid sampled some points: what the last
            // part of exactness costs.
            if (fx.sampledEvaluations > 0 && !large && !o.quick &&
                scene.faceCount() <= kAllPairsMaxFaces) {
                const bool done = renderEveryPointExact(all, ta);
                e["everyPointExact"] = {{"complete", done},
                                        {"renderWall", done ? ta.total : o.limit},
                                        {"renderCpu", ta.totalCpu}};
                if (done) e["everyPointExact"]["workAt"] = workJson(r.effects());
                std::printf("  every point exact: render %s%.2f s wall\n", done ? "" : "over ",
                            done ? ta.total : o.limit);
                e["costEveryPointExact"] = costJson(r.effects(), all, done, "Table 1's image");
            } else if (fx.sampledEvaluations == 0) {
                // Nothing was sampled: this render's evaluations were all exact.
                e["costEveryPointExact"] = costJson(fx, s, true, "Table 1's image");
            } else if (!o.quick) {
                // The image above without the limit would cost minutes (the motorbike's
                // evaluations average milliseconds): a smaller one, one sample per pixel.
                const auto [cw, ch] = parseSize("--exact-cost-size", o.exactCostSize, kImageSize);
                all.width = cw;
                all.height = ch;
                all.spp = 1;
                const bool done = renderEveryPointExact(all, ta);
                e["costEveryPointExact"] = costJson(r.effects(), all, done, "--exact-cost-size");
                std::printf("  every point exact at %dx%d, 1 spp: render %s%.2f s wall\n",
                            all.width, all.height, done ? "" : "over ", done ? ta.total : o.limit);
            }
        } else {
            std::printf("  exact: precompute over the %.0f s limit (%zu trees so far)\n", o.limit,
                        store.treeCount());
        }
        e["fileBytes"] = fileSize(store, dir, "table1");
        row["exact"] = e;
    }
    if (!large && !o.quick && scene.faceCount() > kAllPairsMaxFaces) {
        std::printf("  all pairs: skipped (%u faces, above %u)\n", scene.faceCount(),
                    kAllPairsMaxFaces);
    } else if (!large && !o.quick) {
        VisibilityStore store(scene, &bvh);
        json all = precomputePairs(store, nullptr, o.limit);
        all["fileBytes"] = fileSize(store, dir, "all");
        std::printf("  all pairs: %.2f s wall, %.2f s cpu, %zu trees\n",
                    all["seconds"].get<double>(), all["cpu"].get<double>(), store.treeCount());
        row["allPairs"] = all;
    }
    std::fflush(stdout);
    return row;
}

// ---- Accuracy ------------------------------------------------------------------------------

json pointJson(const AccuracyPoint& p) {
    return {{"method", p.method},
            {"rays", p.rays},
            {"seconds", p.seconds},
            {"cpu", p.cpuSeconds},
            {"precompute", p.precomputeSeconds},
            {"rmse", p.rmse},
            {"maxError", p.maxError}};
}

json accuracy(const BenchOptions& o) {
    const Scene scene = loadSceneFile(o.accuracyScene, o.strict);
    const EmbreeScene bvh(scene.mesh);
    VisibilityStore store(scene, &bvh);
    AccuracyStudyOptions a;
    const auto [width, height] = parseSize("--accuracy-size", o.accuracySize, kImageSize);
    a.width = width;
    a.height = height;
    a.spp = o.accuracySpp;
    a.rayCounts.clear();
    for (int n = 1; n <= o.maxRays; n *= 2) a.rayCounts.push_back(n);
    a.referenceRays = o.referenceRays;
    std::printf("accuracy %s: %dx%d, %d spp, 1..%d rays, reference 2 x %d rays\n",
                o.accuracyScene.c_str(), a.width, a.height, a.spp, o.maxRays, a.referenceRays);
    std::fflush(stdout);
    AccuracyStudy st;
    std::atomic<bool> never{false};
    runWithLimit(INFINITY, never,
                 [&] { st = runAccuracyStudy(scene, bvh, store, defaultCamera(scene, bvh), a); });
    json j = {{"scene", o.accuracyScene},
              {"width", a.width},
              {"height", a.height},
              {"spp", a.spp},
              {"referenceRays", a.referenceRays},
              {"referenceNoise", st.referenceNoise},
              {"referenceSeconds", st.referenceSeconds},
              {"meanRadiance", st.meanRadiance},
              {"exact", pointJson(st.exact)},
              {"equalErrorExtrapolated", st.equalErrorExtrapolated},
              {"partial", store.partialCount()}};
    j["equalErrorSeconds"] =
        std::isfinite(st.equalErrorSeconds) ? json(st.equalErrorSeconds) : json();
    j["equalErrorRays"] = std::isfinite(st.equalErrorRays) ? json(st.equalErrorRays) : json();
    json pts = json::array();
    for (const AccuracyPoint& p : st.sampled) {
        pts.push_back(pointJson(p));
        std::printf("  %4d rays: %.3f s, rmse %.4g, max %.4g\n", p.rays, p.seconds, p.rmse,
                    p.maxError);
    }
    j["sampled"] = pts;
    std::printf(
        "  exact: %.3f s (precompute %.3f s), rmse vs reference %.4g (reference noise "
        "%.4g); equal error at %.3f s (%.0f rays)%s\n",
        st.exact.seconds, st.exact.precomputeSeconds, st.exact.rmse, st.referenceNoise,
        st.equalErrorSeconds, st.equalErrorRays,
        st.equalErrorExtrapolated ? " (extrapolated)" : "");
    std::fflush(stdout);
    return j;
}

// ---- Predicates ----------------------------------------------------------------------------

json predicates(const BenchOptions& o) {
    // Up to 200 points per penumbra patch; --points caps it (a smoke run asks for few).
    const PredicateStudy st =
        runPredicateStudy(o.quick ? 20 : std::min(200, o.points), o.quick ? 1 : 5);
    json modes = json::array(), cases = json::array();
    std::printf("predicates: %zu hard cases, %zu queries (x%d timed)\n", st.cases.size(),
                st.queries, st.repeats);
    for (const PredicateModeResult& m : st.modes) {
        modes.push_back({{"mode", m.mode},
                         {"usPerQuery", m.usPerQuery},
                         {"cpuUsPerQuery", m.cpuUsPerQuery},
                         {"wrong", m.wrong},
                         {"otherCount", m.otherCount}});
        std::printf("  %-12s %.3f us per query, %zu wrong, %zu other fragment count\n",
                    m.mode.c_str(), m.usPerQuery, m.wrong, m.otherCount);
    }
    for (const PredicateCaseResult& c : st.cases)
        cases.push_back({{"case", c.name},
                         {"queries", c.queries},
                         {"filteredWrong", c.wrong[0]},
                         {"alwaysExactWrong", c.wrong[1]},
                         {"naiveWrong", c.wrong[2]},
                         {"naiveOtherCount", c.otherCount[2]},
                         {"filteredOtherCount", c.otherCount[0]}});
    std::fflush(stdout);
    std::printf("  naive vs filtered: %zu answers with another fragment count\n",
                st.naiveOtherThanFiltered);
    return {{"cases", st.cases.size()},
            {"queries", st.queries},
            {"modes", modes},
            {"naiveOtherThanFiltered", st.naiveOtherThanFiltered},
            {"perCase", cases}};
}

// ---- Build options -------------------------------------------------------------------------

// Query time per point on random points of the receivers (faces chosen by area), light 0.
double queryMicros(const Scene& scene, const VisibilityStore& store, int points) {
    const vis::PolygonMesh& mesh = scene.mesh;
    std::mt19937_64 rng(1);
    std::vector<double> area(scene.faceCount());
    for (uint32_t f = 0; f < scene.faceCount(); ++f) area[f] = mesh.faceArea(f);
    std::discrete_distribution<uint32_t> pick(area.begin(), area.end());
    std::uniform_real_distribution<double> u(0.02, 1.0);
    const uint32_t l = scene.lights[0];
    std::vector<std::pair<const PairRecord*, Vec3>> xs;
    for (int tries = 0; xs.size() < static_cast<size_t>(points) && tries < 100 * points; ++tries) {
        const uint32_t f = pick(rng);
        if (f == l) continue;
        Vec3 x{};
        double w = 0;
        for (uint32_t v : mesh.faces[f]) {
            const double a = u(rng);
            x += mesh.vertices[v] * a;
            w += a;
        }
        x = x / w;
        const PairRecord* r = store.find(store.keyAt(f, x, l));
        if (r) xs.push_back({r, x});
    }
    if (xs.empty()) return 0;
    vis::FromPointQuery q;
    double sink = 0;
    const auto t0 = Clock::now();
    for (const auto& [r, x] : xs) sink += q.run(mesh, r->tree, x).size();
    const double t = seconds(t0, Clock::now());
    if (sink < 0) std::printf("?");
    return t / xs.size() * 1e6;
}

json buildOptions(const std::vector<std::string>& scenes, const BenchOptions& o) {
    json rows = json::array();
    for (const std::string& path : scenes) {
        const Scene scene = loadSceneFile(path, o.strict);
        const EmbreeScene bvh(scene.mesh);
        for (int merge = 1; merge >= 0; --merge)
            for (int quadric = 1; quadric >= 0; --quadric) {
                VisibilityStore::Options so;
                so.build.mergeLeaves = merge;
                so.build.quadricPruning = quadric;
                VisibilityStore store(scene, &bvh, so);
                json r = precomputePairs(store, nullptr, o.limit);
                r["scene"] = path;
                r["mergeLeaves"] = static_cast<bool>(merge);
                r["quadricPruning"] = static_cast<bool>(quadric);
                r["queryUs"] = queryMicros(scene, store, o.points);
                std::printf(
                    "options %s merge=%d quadric=%d: %zu nodes, %zu bytes, %.2f s, "
                    "%.3f us/query\n",
                    path.c_str(), merge, quadric, r["nodes"].get<size_t>(),
                    r["bytes"].get<size_t>(), r["seconds"].get<double>(),
                    r["queryUs"].get<double>());
                std::fflush(stdout);
                rows.push_back(r);
            }
    }
    return rows;
}

// ---- Scaling -------------------------------------------------------------------------------

// A fixed set of receiver patches: every patch of the non-mesh faces (the floor) and 32 faces of
// the model drawn by a fixed seed, against every light.
json scaling(const std::vector<std::string>& scenes, const BenchOptions& o, json& skipped) {
    json rows = json::array();
    for (const std::string& path : scenes) {
        if (!canMeasure(path, "scaling", skipped)) continue;
        const auto l0 = Clock::now();
        const Scene scene = loadSceneFile(path, o.strict);
        const EmbreeScene bvh(scene.mesh);
        const double loadSeconds = seconds(l0, Clock::now());
        VisibilityStore store(scene, &bvh);
        // The floor: the largest face.
        uint32_t floor = 0;
        for (uint32_t f = 1; f < scene.faceCount(); ++f)
            if (scene.mesh.faceArea(f) > scene.mesh.faceArea(floor)) floor = f;
        std::vector<PairKey> keys;
        for (uint32_t l : scene.lights) {
            for (uint32_t p = 0; p < store.patches(floor).patches.size(); ++p)
                keys.push_back({floor, p, l});
            std::mt19937_64 rng(3);
            std::uniform_int_distribution<uint32_t> pick(0, scene.faceCount() - 1);
            for (int i = 0; i < 32; ++i) {
                const uint32_t f = pick(rng);
                if (f == l || f == floor) continue;
                for (uint32_t p = 0; p < store.patches(f).patches.size(); ++p)
                    keys.push_back({f, p, l});
            }
        }
        json r = precomputePairs(store, &keys, o.limit);
        r["scene"] = path;
        r["faces"] = scene.faceCount();
        r["loadSeconds"] = loadSeconds;
        std::printf(
            "scaling %s: %u faces, %zu pairs, %.2f s wall, %.2f s cpu, %zu nodes, %zu "
            "bytes, %zu partial%s\n",
            path.c_str(), scene.faceCount(), keys.size(), r["seconds"].get<double>(),
            r["cpu"].get<double>(), r["nodes"].get<size_t>(), r["bytes"].get<size_t>(),
            store.partialCount(), r["complete"].get<bool>() ? "" : " (over the limit)");
        std::fflush(stdout);
        rows.push_back(r);
    }
    return rows;
}

// ---- Per point -----------------------------------------------------------------------------

struct Quantiles {
    double median = 0, p99 = 0, max = 0;
};

// Nearest-rank quantiles of `v` (sorted here); zeros for an empty list.
Quantiles quantiles(std::vector<double> v) {
    if (v.empty()) return {};
    std::sort(v.begin(), v.end());
    auto rank = [&](double q) {
        const size_t k = static_cast<size_t>(std::ceil(q * static_cast<double>(v.size())));
        return v[std::clamp<size_t>(k, 1, v.size()) - 1];
    };
    return {rank(0.5), rank(0.99), v.back()};
}

json perPoint(const std::string& path, const BenchOptions& o) {
    const Scene scene = loadSceneFile(path, o.strict);
    const vis::PolygonMesh& mesh = scene.mesh;
    const EmbreeScene embree(mesh);
    VisibilityStore store(scene, &embree);
    std::mt19937_64 rng(1);
    std::vector<double> area(scene.faceCount());
    for (uint32_t f = 0; f < scene.faceCount(); ++f) area[f] = mesh.faceArea(f);
    std::discrete_distribution<uint32_t> pickFace(area.begin(), area.end());
    std::uniform_real_distribution<double> u(0.02, 1.0);
    struct Sample {
        uint32_t face;
        Vec3 x;
        const PairRecord* rec;
    };
    const uint32_t l = scene.lights[0];
    std::vector<Sample> samples;
    while (samples.size() < static_cast<size_t>(o.points)) {
        const uint32_t f = pickFace(rng);
        if (f == l) continue;
        Vec3 p{};
        double w = 0;
        for (uint32_t v : mesh.faces[f]) {
            const double a = u(rng);
            p += mesh.vertices[v] * a;
            w += a;
        }
        samples.push_back({f, p / w, nullptr});
    }
    for (Sample& s : samples) s.rec = &store.getOrBuild(store.keyAt(s.face, s.x, l));
    double sink = 0;
    size_t visited = 0, fragments = 0;
    // The boundary chain (vis::FromPointQuery::ChainOptions): of the points clipped against
    // enough occluders for it to be considered, their edges and those left after cancellation;
    // of the points it evaluated, the cells and the fragments.
    size_t manyOccluders = 0, occluderEdges = 0, boundaryEdges = 0, chainPoints = 0, cells = 0,
           crossingLabels = 0, chainFragments = 0, silhouettePoints = 0;
    // The partial trees' silhouettes (vis::DeferredSilhouettes), once per tree the points use:
    // the deferred faces' edge uses, and those kept (potential silhouettes relative to the patch,
    // borders, edges of faces that cross a plane) in the trees whose silhouettes pay.
    uint64_t pairUses = 0, pairKept = 0;
    size_t silhouetteTrees = 0, partialTrees = 0;
    {
        std::set<const vis::HistoryTree*> seen;
        for (const Sample& s : samples) {
            const vis::HistoryTree& t = s.rec->tree;
            if (!t.partial() || !seen.insert(&t).second) continue;
            ++partialTrees;
            if (!t.silhouettes.usable()) continue;
            ++silhouetteTrees;
            pairUses += t.silhouettes.totalUses;
            pairKept += t.silhouettes.keptUses;
        }
    }
    vis::FromPointQuery query;
    // One untimed pass first: the timed loops below (the product's, then Algorithm 1 only) then
    // all start warm (the first pass over the points is some 20% slower on every scene). It
    // keeps each point's fragments for the visible region's boundary (vis::visibleOutline, what
    // `penumbra query` and the viewer show): their edges against the outline's loops and edges,
    // and per point the time of the fragments' form factor (the renderer's) against that of the
    // outline built and integrated (Lambert's contour integral: the same value).
    std::vector<std::vector<vis::Polygon3>> pieces;
    pieces.reserve(samples.size());
    size_t fragmentEdges = 0, outlineEdges = 0, outlineLoops = 0;
    for (const Sample& s : samples) {
        pieces.push_back(query.run(mesh, s.rec->tree, s.x).polygons());
        for (const vis::Polygon3& f : pieces.back()) fragmentEdges += f.size();
    }
    const auto f0 = Clock::now();
    for (size_t k = 0; k < samples.size(); ++k) {
        const Vec3 n = vis::normalize(mesh.faceAreaNormal(samples[k].face));
        for (const vis::Polygon3& f : pieces[k]) sink += vis::formFactor(samples[k].x, n, f);
    }
    const double integrationUs = seconds(f0, Clock::now()) / samples.size() * 1e6;
    const auto b0 = Clock::now();
    for (size_t k = 0; k < samples.size(); ++k) {
        const Vec3 n = vis::normalize(mesh.faceAreaNormal(samples[k].face));
        const vis::VisibleOutline outline = vis::visibleOutline(pieces[k]);
        sink += vis::formFactorOfLoops(samples[k].x, n, outline.loops);
        outlineEdges += outline.edges();
        outlineLoops += outline.loops.size();
    }
    const double outlineUs = seconds(b0, Clock::now()) / samples.size() * 1e6;
    const auto q0 = Clock::now();
    for (const Sample& s : samples) {
        const Vec3 n = vis::normalize(mesh.faceAreaNormal(s.face));
        const vis::FragmentList& r = query.run(mesh, s.rec->tree, s.x);
        for (size_t i = 0; i < r.size(); ++i) sink += vis::formFactor(s.x, n, r[i]);
        visited += query.nodesVisited();
        fragments += r.size();
        const vis::FromPointQuery::ChainCounts& c = query.chainCounts();
        manyOccluders += c.occluderEdges > 0;
        occluderEdges += c.occluderEdges;
        boundaryEdges += c.boundaryEdges;
        chainPoints += c.cells > 0;
        silhouettePoints += query.usedSilhouettes();
        cells += c.cells;
        crossingLabels += c.crossingLabels;
        if (c.cells > 0) chainFragments += r.size();
    }
    const double exactUs = seconds(q0, Clock::now()) / samples.size() * 1e6;
    // The same points with every occluder clipped one by one (Algorithm 1 only).
    vis::FromPointQuery oneByOne;
    oneByOne.setChainOptions({0, 0});
    const auto o0 = Clock::now();
    for (const Sample& s : samples) {
        const Vec3 n = vis::normalize(mesh.faceAreaNormal(s.face));
        const vis::FragmentList& r = oneByOne.run(mesh, s.rec->tree, s.x);
        for (size_t i = 0; i < r.size(); ++i) sink += vis::formFactor(s.x, n, r[i]);
    }
    const double oneByOneUs = seconds(o0, Clock::now()) / samples.size() * 1e6;
    // The distribution: each point timed alone (the clock's own cost, some 20-40 ns, included).
    std::vector<double> eachUs;
    eachUs.reserve(samples.size());
    for (const Sample& s : samples) {
        const auto a = Clock::now();
        const Vec3 n = vis::normalize(mesh.faceAreaNormal(s.face));
        const vis::FragmentList& r = query.run(mesh, s.rec->tree, s.x);
        for (size_t i = 0; i < r.size(); ++i) sink += vis::formFactor(s.x, n, r[i]);
        eachUs.push_back(seconds(a, Clock::now()) * 1e6);
    }
    const Quantiles exactQ = quantiles(eachUs);
    // A click in the viewer (app/viewer/selection.h): every light's fragments from the tree-less
    // query, within the click's work budget, on a store that has no tree yet; and what a click
    // cost before, the history trees built and walked (a fresh store: each point's pairs built
    // unless an earlier point of the run built them).
    const size_t clicks = std::min<size_t>(samples.size(), 200);
    std::vector<double> directMs;
    size_t overBudget = 0;
    const uint64_t clickWork =
        viewer::Selection::kClickWork / std::max<size_t>(1, scene.lights.size());
    for (size_t i = 0; i < clicks; ++i) {
        const auto a = Clock::now();
        const std::optional<viewer::PointInspection> p =
            viewer::inspectPointDirect(scene, embree.faceBoxes(), samples[i].face, samples[i].x,
                                       clickWork, &embree.faceClusters());
        directMs.push_back(seconds(a, Clock::now()) * 1e3);
        overBudget += !p.has_value();
    }
    const size_t treeClicks = std::min<size_t>(samples.size(), 20);
    std::vector<double> treeMs;
    {
        VisibilityStore cold(scene, &embree);
        for (size_t i = 0; i < treeClicks; ++i) {
            const auto a = Clock::now();
            viewer::inspectPoint(cold, samples[i].face, samples[i].x);
            treeMs.push_back(seconds(a, Clock::now()) * 1e3);
        }
    }
    const Quantiles directQ = quantiles(directMs), treeQ = quantiles(treeMs);
    auto timeRays = [&](int n) {
        const auto a = Clock::now();
        for (const Sample& s : samples) sink += embree.sampledFraction(s.face, l, s.x, n, 7);
        return seconds(a, Clock::now()) / samples.size() * 1e6;
    };
    const double rays16 = timeRays(16), rays128 = timeRays(128);
    std::printf(
        "per point %s: exact query + form factor %.2f us (median %.2f, p99 %.2f; %.1f nodes, "
        "%.2f fragments); 16 rays %.2f us; 128 rays %.2f us; click: fragments %.2f ms (median; "
        "p99 %.2f), with the trees %.1f ms (median; max %.1f) (checksum %.3g)\n",
        path.c_str(), exactUs, exactQ.median, exactQ.p99,
        static_cast<double>(visited) / samples.size(),
        static_cast<double>(fragments) / samples.size(), rays16, rays128, directQ.median,
        directQ.p99, treeQ.median, treeQ.max, sink);
    std::printf(
        "  boundary chain: %zu points with many occluders, %zu of their %zu edges left (%.1f%%); "
        "%zu points by the chain, %zu cells (%zu labelled by crossings), %zu fragments; "
        "Algorithm 1 only: %.2f us\n",
        manyOccluders, boundaryEdges, occluderEdges,
        occluderEdges == 0 ? 0.0 : 100.0 * static_cast<double>(boundaryEdges) / occluderEdges,
        chainPoints, cells, crossingLabels, chainFragments, oneByOneUs);
    std::printf(
        "  boundary of the visible region: per point %.1f fragment edges, %.2f loops of %.1f "
        "edges; the fragments' form factor %.3f us, the outline built and integrated %.3f us\n",
        static_cast<double>(fragmentEdges) / samples.size(),
        static_cast<double>(outlineLoops) / samples.size(),
        static_cast<double>(outlineEdges) / samples.size(), integrationUs, outlineUs);
    std::printf(
        "  silhouettes: %zu of %zu partial trees, %llu of their %llu edge uses kept (%.1f%%); %zu "
        "points by them\n",
        silhouetteTrees, partialTrees, static_cast<unsigned long long>(pairKept),
        static_cast<unsigned long long>(pairUses),
        pairUses == 0 ? 0.0 : 100.0 * static_cast<double>(pairKept) / pairUses, silhouettePoints);
    std::fflush(stdout);
    return {{"scene", path},
            {"points", samples.size()},
            {"exactUs", exactUs},
            {"exactMedianUs", exactQ.median},
            {"exactP99Us", exactQ.p99},
            {"exactMaxUs", exactQ.max},
            {"click",
             {{"points", clicks},
              {"fragmentsMedianMs", directQ.median},
              {"fragmentsP99Ms", directQ.p99},
              {"fragmentsMaxMs", directQ.max},
              {"overBudget", overBudget},
              {"treePoints", treeClicks},
              {"withTreesMedianMs", treeQ.median},
              {"withTreesMaxMs", treeQ.max}}},
            {"rays16Us", rays16},
            {"rays128Us", rays128},
            {"nodesPerQuery", static_cast<double>(visited) / samples.size()},
            {"chain",
             {{"manyOccluderPoints", manyOccluders},
              {"occluderEdges", occluderEdges},
              {"boundaryEdges", boundaryEdges},
              {"points", chainPoints},
              {"cells", cells},
              {"crossingLabels", crossingLabels},
              {"fragments", chainFragments},
              {"oneByOneUs", oneByOneUs},
              {"partialTrees", partialTrees},
              {"silhouetteTrees", silhouetteTrees},
              {"silhouetteUses", pairUses},
              {"silhouetteKept", pairKept},
              {"silhouettePoints", silhouettePoints}}},
            {"fragmentsPerQuery", static_cast<double>(fragments) / samples.size()},
            {"outline",
             {{"fragmentEdges", fragmentEdges},
              {"loops", outlineLoops},
              {"edges", outlineEdges},
              {"integrationUs", integrationUs},
              {"outlineUs", outlineUs}}}};
}

// ---- Machine and output ---------------------------------------------------------------------

json machine() {
    std::string cpu = "unknown";
    std::ifstream in("/proc/cpuinfo");
    for (std::string line; std::getline(in, line);)
        if (line.rfind("model name", 0) == 0) {
            cpu = line.substr(line.find(':') + 2);
            break;
        }
    std::string load;
    std::ifstream la("/proc/loadavg");
    std::getline(la, load);
    char date[64];
    const std::time_t now = std::time(nullptr);
    std::strftime(date, sizeof date, "%Y-%m-%d %H:%M:%S UTC", std::gmtime(&now));
    return {{"cpu", cpu},
            {"cores", std::thread::hardware_concurrency()},
            {"loadavg", load},
            {"date", date},
            {"buildType", PENUMBRA_BUILD_TYPE}};
}

void writeAtomically(const fs::path& path, const std::string& text) {
    try {
        writeFileAtomically(path, text);
    } catch (const AtomicWriteError& e) {
        throw inputError(e.what());
    }
}

void runBench(const BenchOptions& o, const std::string& commandLine) {
    if (o.out.empty()) throw usageError("--out DIR is required");
    // Every size now, not when its study comes after minutes of measuring.
    parseSize("--size", o.size, kImageSize);
    parseSize("--large-size", o.largeSize, kImageSize);
    parseSize("--accuracy-size", o.accuracySize, kImageSize);
    parseSize("--exact-cost-size", o.exactCostSize, kImageSize);
    // TBB keeps one core for the thread that waits by default; the bench's main thread only
    // polls (runWithLimit), so every core gets a worker.
    const tbb::global_control parallelism(tbb::global_control::max_allowed_parallelism,
                                          std::max(1, tbb::info::default_concurrency()) + 1);
    std::error_code ec;
    fs::create_directories(o.out, ec);
    if (ec) throw inputError("cannot create " + o.out + ": " + ec.message());
    const fs::path dir = o.out;
    json b;
    b["machine"] = machine();
    b["command"] = commandLine;
    b["options"] = {{"size", o.size},
                    {"largeSize", o.largeSize},
                    {"spp", o.spp},
                    {"quick", o.quick},
                    {"skipLarge", o.skipLarge},
                    {"limit", o.limit},
                    {"exactCostSize", o.exactCostSize}};
    json skipped = json::array();
    std::vector<std::string> small = o.scenes, large;
    if (small.empty()) {
        small = {"assets/scenes/stairs.json", "assets/scenes/table.json",
                 "assets/scenes/grids.json", "assets/scenes/cornell_box.json"};
        const std::string bunny = "assets/scenes/bunny_in_box.json";
        if (!o.quick && canMeasure(bunny, "table1", skipped)) small.push_back(bunny);
        // The large scenes of Table 1: the motorbike (332k faces, CAD parts) and the dragon
        // (871k, a scanned model), at --large-size.
        if (!o.skipLarge && !o.quick)
            large = {"assets/scenes/motorbike.json", "assets/scenes/dragon.json"};
    }
    for (const std::string& s : small)
        if (!fs::exists(s)) throw inputError(s + ": no such scene file");

    b["table1"] = json::array();
    for (const std::string& s : small) b["table1"].push_back(table1Row(s, o, dir, false));
    for (const std::string& s : large)
        if (canMeasure(s, "table1", skipped)) b["table1"].push_back(table1Row(s, o, dir, true));
    b["accuracy"] = accuracy(o);
    b["predicates"] = predicates(o);
    std::vector<std::string> optionScenes = {"assets/scenes/stairs.json",
                                             "assets/scenes/cornell_box.json"};
    if (o.quick) optionScenes = {"assets/scenes/cornell_box.json"};
    b["buildOptions"] = buildOptions(optionScenes, o);
    std::vector<std::string> scalingScenes;
    if (!o.quick)
        scalingScenes = {"assets/scenes/dragon_res4.json", "assets/scenes/dragon_res3.json"};
    if (!o.quick && !o.skipLarge) {
        scalingScenes.push_back("assets/scenes/dragon_res2.json");
        scalingScenes.push_back("assets/scenes/dragon.json");
    }
    b["scaling"] = scaling(scalingScenes, o, skipped);
    b["perPoint"] = json::array();
    for (const std::string& s : small) b["perPoint"].push_back(perPoint(s, o));
    b["skipped"] = skipped;

    requireFinite(b, (dir / "bench.json").string());
    writeAtomically(dir / "bench.json", b.dump(2));
    std::printf("wrote %s\n", (dir / "bench.json").c_str());
    bool plots = false;
    std::string note;
    if (o.noPlots) {
        note = "--no-plots";
    } else if (!fs::exists("/usr/bin/python3") || !fs::exists("scripts/plot_bench.py")) {
        note = "/usr/bin/python3 or scripts/plot_bench.py not found";
    } else {
        const std::string cmd = "/usr/bin/python3 scripts/plot_bench.py '" + o.out + "'";
        const int rc = std::system(cmd.c_str());
        plots = rc == 0;
        if (!plots) note = "`" + cmd + "` failed (matplotlib missing?)";
    }
    writeAtomically(dir / "report.md", benchReport(b, plots, note));
    std::printf("wrote %s\n", (dir / "report.md").c_str());
}

}  // namespace

void registerBenchCommand(CLI::App& app) {
    auto o = std::make_shared<BenchOptions>();
    CLI::App* sub = app.add_subcommand(
        "bench",
        "Measure what accuracy costs in time: Table 1, error against time, predicates, "
        "build options, scaling; writes DIR/bench.json, DIR/report.md and plots");
    sub->add_option("scenes", o->scenes,
                    "Scene files for Table 1 and the per-point costs (default: the committed "
                    "assets, the bunny in the box, the motorbike and the dragon)");
    sub->add_option("--out", o->out, "Output directory")->required();
    sub->add_option("--size", o->size, "Image size of Table 1 (WxH)");
    sub->add_option("--large-size", o->largeSize, "Image size of Table 1 for the large scenes");
    sub->add_option("--spp", o->spp, "Primary samples per pixel of Table 1")
        ->check(CLI::PositiveNumber);
    sub->add_option("--accuracy-scene", o->accuracyScene, "Scene of the error-against-time study");
    sub->add_option("--accuracy-size", o->accuracySize, "Image size of the study (WxH)");
    sub->add_option("--accuracy-spp", o->accuracySpp, "Primary samples per pixel of the study")
        ->check(CLI::PositiveNumber);
    sub->add_option("--max-rays", o->maxRays, "Largest shadow-ray count of the study")
        ->check(CLI::PositiveNumber);
    sub->add_option("--reference-rays", o->referenceRays,
                    "Rays per reference image (the reference averages two)")
        ->check(CLI::PositiveNumber);
    sub->add_option("--points", o->points,
                    "Query points per scene (and at most per patch of the predicate study, up to "
                    "200)")
        ->check(CLI::PositiveNumber);
    sub->add_option("--limit", o->limit, "Seconds allowed per precompute before it is cancelled")
        ->check(CLI::PositiveNumber);
    sub->add_flag("--quick", o->quick,
                  "CI-sized run: small scenes, small images, few rays, 20 s precompute limit, no "
                  "scaling study");
    sub->add_option("--exact-cost-size", o->exactCostSize,
                    "Image size (WxH, 1 spp) of the per-point cost with every point exact for "
                    "the scenes whose Table 1 image is too costly to render so");
    sub->add_flag("--skip-large", o->skipLarge, "Skip the scenes above 300k triangles");
    sub->add_flag("--no-plots", o->noPlots, "Do not run scripts/plot_bench.py");
    addStrictOption(*sub, o->strict);
    sub->callback([o, sub] {
        BenchOptions opt = *o;
        if (opt.quick) {
            if (sub->count("--size") == 0) opt.size = "64x64";
            if (sub->count("--spp") == 0) opt.spp = 2;
            if (sub->count("--accuracy-size") == 0) opt.accuracySize = "32x32";
            if (sub->count("--accuracy-spp") == 0) opt.accuracySpp = 1;
            if (sub->count("--max-rays") == 0) opt.maxRays = 64;
            if (sub->count("--reference-rays") == 0) opt.referenceRays = 256;
            if (sub->count("--points") == 0) opt.points = 200;
            if (sub->count("--limit") == 0) opt.limit = 20;
        }
        std::string cmd = "penumbra bench";
        for (const std::string& s : o->scenes) cmd += " " + s;
        cmd += " --out " + opt.out + " --size " + opt.size + " --spp " + std::to_string(opt.spp);
        cmd += " --large-size " + opt.largeSize + " --limit " + fmt("%g", opt.limit) +
               " --accuracy-size " + opt.accuracySize + " --accuracy-spp " +
               std::to_string(opt.accuracySpp) + " --max-rays " + std::to_string(opt.maxRays) +
               " --reference-rays " + std::to_string(opt.referenceRays) + " --exact-cost-size " +
               opt.exactCostSize;
        if (opt.quick) cmd += " --quick";
        if (opt.skipLarge) cmd += " --skip-large";
        if (opt.strict) cmd += " --strict";
        runBench(opt, cmd);
    });
}

}  // namespace penumbra::cli
