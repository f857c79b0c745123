// The paper's Table 1 re-measured on one scene: 128-ray sampled rendering against the exact
// renderer (its precompute of the trees the image needs, then the render), with how each pixel
// was answered, where the exact work went, the cost of each evaluation, the image with every
// point exact, the visibility file's size and, for the small scenes, every pair precomputed.
//
// Exact and measured: the counts (evaluations, trees, pairs, answers, plane tests) are exact for
// this render; the times are wall and process CPU seconds of one run on a shared machine; the
// per-evaluation costs time one evaluation in EvaluationCosts::kTimedEvery, and their medians and
// 99th percentiles are nearest-rank order statistics of the timed ones (CostSamples: of one in
// n of them where more were timed than it keeps; each figure's *QuantileStride says which).
#pragma once

#include <array>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>

#include "engine/render/answers.h"
#include "engine/render/renderer.h"
#include "engine/scene/scene.h"
#include "engine/studies/equal_error_study.h"
#include "engine/studies/precompute_run.h"
#include "engine/studies/study_harness.h"
#include "visibility/fp_query/work_budget.h"

namespace penumbra {

// Every (patch, light) pair of a scene above this many faces is not a precompute anyone would run
// (the image's pairs are the Table 1 figure there): the all-pairs run is skipped.
inline constexpr uint32_t kAllPairsMaxFaces = 10000;

// Counts by the stage of the query they happened in (indexed by vis::WorkStage).
using StageCounts = std::array<uint64_t, vis::kWorkStages>;

// The exact queries' plane tests by stage (vis::FromPointQuery::stageWork): walking history
// trees, and evaluating pairs without a tree.
struct WorkByPath {
    StageCounts trees{}, direct{};
};

// Of what the median and 99th percentile of a set of timed costs are the order statistics: 1,
// every timed cost; n > 1, one in n of them (CostSamples::stride). 0 is kept for the bench.json
// files written before the exact quantiles, read back to write their report again: there they
// are the middles of log-histogram buckets, to within 19% (the report says so).
inline constexpr uint64_t kHistogramQuantiles = 0;

// The sampled render (128 shadow rays per light): its times and its timed points (all lights of a
// shading point together).
struct SampledRender {
    double wall = 0, cpu = 0;
    uint64_t points = 0;
    double pointMedianUs = 0, pointP99Us = 0, pointMeanUs = 0;
    uint64_t pointQuantileStride = 1;  // (kHistogramQuantiles)
};

// An exact render's timed evaluations answered exactly (query and shading), and the boundary
// chain's evaluations (all of them, not only the timed ones) with its edges, cells and fragments.
struct EvaluationTimes {
    uint64_t evaluations = 0;
    double medianUs = 0, p99Us = 0, meanUs = 0;
    uint64_t quantileStride = 1;  // (kHistogramQuantiles)
    uint64_t chainEvaluations = 0, chainEdges = 0, chainCells = 0, chainFragments = 0;
};

// Where the evaluations that needed a query spent their CPU time, estimated from the timed ones:
// the exact answers, the queries stopped at the work limit, the sampled points' rays.
struct TimeSplit {
    double exactSeconds = 0, attemptSeconds = 0, raysSeconds = 0;
};

// The light-edge path's evaluations in the default exact render (EvaluationCosts, all of them,
// not only the timed ones), summed: the S_L edges each examined (its weight taken; those in the
// subtrees seen wholly from one side are skipped uncounted), those of nonzero weight, and those of
// them that meet the cone over L (K: the edges that can bound the point's shadow).
struct LightEdgeCounts {
    uint64_t evaluations = 0, examined = 0, weighted = 0, inCone = 0;
};

// The default exact render's evaluation costs.
struct ExactCost {
    EvaluationTimes times;
    double sampledMedianUs = 0;          // the points over the work limit: their 128 rays
    uint64_t sampledQuantileStride = 1;  // (of sampledMedianUs: kHistogramQuantiles)
    uint64_t chainOccluderEdges = 0;     // the edges of the occluders the chain's edges came from
    TimeSplit timeSplit;
    std::optional<LightEdgeCounts> lightEdges;  // (absent from a bench.json that predates it)
};

// The evaluation costs of a render without the work limit, and the image it came from.
struct EveryPointExactCost {
    EvaluationTimes times;
    int width = 0, height = 0, spp = 0;
    std::string image;      // "Table 1's image", or "--exact-cost-size" (a smaller one, 1 spp)
    bool complete = false;  // false when cut at the limit (the evaluations timed until then)
};

// Table 1's image rendered again with every point exact (no work limit), the same trees.
struct EveryPointExactRender {
    bool complete = false;
    double renderWall = 0, renderCpu = 0;  // renderWall: the limit when cut
    std::optional<WorkByPath> workAt;      // when complete
};

// Query-driven refinement between passes (RenderSettings::refineLevels).
struct Refinement {
    size_t pairs = 0, trees = 0, treesUsed = 0, notWorth = 0;
    double seconds = 0;
};

// How each evaluation was answered (engine/render/answers.h), and the image drawn from them.
struct AnswersImage {
    std::string image;  // its file name, in the bench's output directory
    std::array<uint64_t, kAnswers> counts{};
};

// The exact render, after a precompute that finished within the limit.
struct ExactRender {
    AnswersImage answers;
    double renderWall = 0, renderCpu = 0;
    double wall = 0, cpu = 0;  // precompute and render
    // Pairs without a tree (evaluated directly), and of them those left without one because the
    // face groups answer them (RenderSettings::groupedShaftMin).
    size_t pairsWithoutTree = 0, pairsGroupedNoTree = 0;
    // Evaluations: direct ones, of them those that took face groups whole, left out solids' back
    // faces, or were hidden by a solid; partial trees' evaluations answered by the groups; all
    // that needed a query, and of those the ones sampled over the work limit.
    uint64_t directEvaluations = 0, directGroupedEvaluations = 0, directSolidEvaluations = 0,
             directHiddenBySolidEvaluations = 0, partialByGroupsEvaluations = 0, evaluations = 0,
             sampledEvaluations = 0;
    StageCounts overLimitAt{};  // the sampled ones whose query reached the limit, by stage
    uint64_t notTried = 0;      // the sampled ones not tried (their region's query had reached it)
    WorkByPath workAt;
    ExactCost cost;
    uint64_t exactWorkLimit = 0, minTreeSamples = 0;  // the render's settings
    Refinement refined;
    // Where the render sampled points and the scene is small enough: the image with every point
    // exact.
    std::optional<EveryPointExactRender> everyPointExact;
    // The per-evaluation cost without the work limit: this render's own when it sampled nothing,
    // else everyPointExact's, else a smaller image's (not in a quick run).
    std::optional<EveryPointExactCost> costEveryPointExact;
};

struct ExactRun {
    double precomputeWall = 0, precomputeCpu = 0;
    bool precomputeComplete = false;  // within the limit
    size_t trees = 0, nodes = 0, bytes = 0;
    PairKinds kinds;
    size_t fileBytes = 0;               // the visibility file of the trees built
    std::optional<ExactRender> render;  // when the precompute finished
};

// Sampled time over exact time (precompute and render, or the render only).
struct Speedups {
    double wall = 0, cpu = 0, renderOnlyWall = 0, renderOnlyCpu = 0;
};

// Every pair of the scene precomputed, and its visibility file.
struct AllPairsRun {
    PrecomputeRun precompute;
    size_t fileBytes = 0;
};

// S_L (visibility/light_silhouette_edges.h) over the scene's area lights: the mesh's edges, the
// open ones (kept for every light), the edges S_L holds summed over the lights and its smallest
// and largest share of the edges, and the seconds it took (edge table and every light's set).
struct ShadowEdges {
    size_t edges = 0, open = 0, keptOverLights = 0;
    double minShare = 0, maxShare = 0, seconds = 0;
};

struct Table1Row {
    std::string scene;  // the scene file
    uint32_t faces = 0;
    size_t areaLights = 0;
    std::optional<ShadowEdges> shadowEdges;  // absent in the runs written before it
    int width = 0, height = 0, spp = 0;
    SampledRender sampled128;
    ExactRun exact;
    std::optional<Speedups> speedup;      // when the exact render ran
    std::optional<AllPairsRun> allPairs;  // small scenes, not in a quick run
    // Table 1's image with every point exact (precompute and render) and sampling at equal error
    // (equal_error_study.h); absent in the runs written before it.
    std::optional<EqualErrorRun> equalError;
};

struct Table1Options {
    int width = 512, height = 512, spp = 16;
    double limit = 180;  // seconds per precompute, and per render with every point exact
    bool quick = false;  // no all-pairs run and no render with every point exact but its own
    bool large = false;  // a large scene: neither the all-pairs run nor the full-image exact one
    // The smaller image (1 spp) of the per-point cost with every point exact, for the scenes
    // whose Table 1 image is too costly to render so.
    int exactCostWidth = 128, exactCostHeight = 128;
    // The equal-error study's largest ray count per light (EqualErrorOptions::maxRays); its
    // target is EqualErrorOptions's, its limit per render the one above.
    int equalErrorMaxRays = 4096;
    // The exact render's light-edge budget (RenderSettings::lightEdgeWorkLimit).
    uint64_t lightEdgeWorkLimit = RenderSettings{}.lightEdgeWorkLimit;
    // Where the answers image goes (answers_<scene stem>.png) and the visibility files are
    // written to be measured (then removed).
    std::filesystem::path outDir;
};

// Measures `scene` (loaded from `path`). Throws StudyError when a precompute fails or the answers
// image cannot be written.
Table1Row runTable1Study(const std::string& path, const Scene& scene, const Table1Options& options,
                         const StudyLog& log);

}  // namespace penumbra
