#include "app/cli/bench/bench_report.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <ostream>
#include <sstream>
#include <string>
#include <vector>

#include "engine/render/answers.h"
#include "visibility/fp_query/work_budget.h"

namespace penumbra::cli {
namespace {

namespace fs = std::filesystem;

std::string num(double v, const char* f = "%.2f") { return fmt(f, v); }

// A quantity the study may not have estimated (NaN: null in bench.json), or "-".
std::string numOrDash(double v, const char* f = "%.2f") {
    return std::isfinite(v) ? fmt(f, v) : std::string("-");
}

// The scene's file name: the tables have no room for the directories.
std::string sceneName(const std::string& scene) { return fs::path(scene).filename().string(); }

// Whether some Table 1 row has an exact render (its sections are written only then).
bool anyExactRender(const std::vector<Table1Row>& rows) {
    for (const Table1Row& row : rows)
        if (row.exact.render) return true;
    return false;
}

// An exact render's sampled evaluations (over the work limit) as a percentage of those that
// needed a query.
double sampledPercent(const ExactRender& exact) {
    return 100.0 * static_cast<double>(exact.sampledEvaluations) /
           std::max(1.0, static_cast<double>(exact.evaluations));
}

// A boundary-chain count of a render's evaluations per chain evaluation, or "-" where the chain
// answered none.
std::string chainPer(const EvaluationTimes& cost, uint64_t count) {
    const double chain = static_cast<double>(cost.chainEvaluations);
    if (!(chain > 0)) return "-";
    return fmt("%.1f", static_cast<double>(count) / chain);
}

// The scenes `study` skipped because files they need are missing.
std::vector<SkippedScene> skippedBy(const BenchResults& b, const std::string& study) {
    std::vector<SkippedScene> out;
    for (const SkippedScene& s : b.skipped)
        if (s.study == study) out.push_back(s);
    return out;
}

void writeSkipped(std::ostream& r, const std::vector<SkippedScene>& skipped) {
    if (skipped.empty()) return;
    r << "Skipped because files they need are missing (run `scripts/fetch_meshes.sh` to fetch "
         "the meshes): ";
    for (size_t i = 0; i < skipped.size(); ++i) {
        r << (i == 0 ? "" : ", ") << sceneName(skipped[i].scene) << " (missing";
        for (const std::string& file : skipped[i].missing) r << " " << file;
        r << ")";
    }
    r << ".\n\n";
}

void writeHeading(std::ostream& r, const BenchResults& b) {
    const BenchMachine& m = b.machine;
    r << "# Penumbra: what accuracy costs in time\n\n"
      << "Measured by `" << b.command << "` on " << m.date << ".\n\nMachine: " << m.cpu << ", "
      << m.cores << " logical cores, load average at the start `" << m.loadavg
      << "` (shared machine: compare CPU times), build type " << m.buildType << ".\n\n";
}

// ---- Table 1 -------------------------------------------------------------------------------

void writeTable1Row(std::ostream& r, const Table1Row& row) {
    const ExactRun& x = row.exact;
    const ExactRender* e = x.render ? &*x.render : nullptr;
    r << "| " << sceneName(row.scene) << " | " << row.faces << " | " << row.width << "x"
      << row.height << ", " << row.spp << " spp | " << num(row.sampled128.wall) << " / "
      << num(row.sampled128.cpu) << " | " << num(x.precomputeWall) << " / " << num(x.precomputeCpu)
      << (x.precomputeComplete ? "" : " (over the limit)") << " | "
      << (e ? num(e->renderWall) + " / " + num(e->renderCpu) : std::string("-")) << " | "
      << (row.speedup ? num(row.speedup->wall) + "x (" + num(row.speedup->renderOnlyWall) + "x)"
                      : std::string("-"))
      << " | " << x.trees << " (" << x.kinds.partial << ") | "
      << (e ? std::to_string(e->pairsWithoutTree) : "-")
      << (e && e->pairsGroupedNoTree > 0
              ? " (" + std::to_string(e->pairsGroupedNoTree) + " by groups)"
              : std::string())
      << " | ";
    if (e)
        r << num(sampledPercent(*e), "%.1f") << "% | ";
    else
        r << "- | ";
    if (e && e->everyPointExact) {
        const EveryPointExactRender& a = *e->everyPointExact;
        r << (a.complete ? "" : "over ") << num(a.renderWall) << " | ";
    } else {
        r << (e && e->sampledEvaluations == 0 ? "(the same) | " : "- | ");
    }
    r << num(static_cast<double>(x.fileBytes) / 1024.0, "%.1f") << " KB | ";
    if (row.allPairs) {
        const AllPairsRun& a = *row.allPairs;
        r << num(a.precompute.seconds) << " / " << num(a.precompute.cpu)
          << (a.precompute.complete ? "" : " (over the limit)") << " | "
          << num(static_cast<double>(a.fileBytes) / 1024.0, "%.1f") << " KB |\n";
    } else {
        r << (row.faces > kAllPairsMaxFaces ? "skipped | - |\n" : "- | - |\n");
    }
}

// Of Table 1's sampled points, the stage each query was in when it reached the work limit
// (vis::WorkStage), and those not tried: later points of a region whose query had reached it.
void writeOverLimit(std::ostream& r, const std::vector<Table1Row>& rows) {
    if (!anyExactRender(rows)) return;
    std::vector<std::string> stages;  // in the order a query goes through them
    for (size_t i = 0; i < vis::kWorkStages; ++i)
        stages.emplace_back(vis::toString(static_cast<vis::WorkStage>(i)));
    r << "### Where the sampled points reached the work limit\n\n"
      << "Of each scene's sampled points (Table 1), those whose query reached the limit, by the "
         "stage it was in (`vis::WorkStage`), and those not tried: later points of a region "
         "(one receiver patch in a few pixels of a tile) whose query had reached it.\n\n"
      << "| scene | sampled | not tried |";
    for (const std::string& s : stages) r << " " << s << " |";
    r << "\n|---|---|---|";
    for (size_t i = 0; i < stages.size(); ++i) r << "---|";
    r << "\n";
    for (const Table1Row& row : rows) {
        if (!row.exact.render) continue;
        const ExactRender& e = *row.exact.render;
        r << "| " << sceneName(row.scene) << " | " << e.sampledEvaluations << " | " << e.notTried
          << " |";
        for (uint64_t n : e.overLimitAt) r << " " << n << " |";
        r << "\n";
    }
    r << "\n";
}

// Of Table 1's exact renders, how each pixel was answered (engine/render/answers.h): the shares
// of the evaluations and the images.
void writeAnswers(std::ostream& r, const std::vector<Table1Row>& rows) {
    if (!anyExactRender(rows)) return;
    r << "### How each pixel was answered\n\n"
      << "Table 1's exact renders, each evaluation (point, light) by the answer it took "
         "(`engine/render/answers.h`; `penumbra render --out-answers`, the viewer's answers "
         "view): a fully visible pair (the whole light, no query), no light (a back-facing or "
         "fully hidden pair, or a point behind the light's plane), a history tree's walk, the "
         "direct path (no tree), the boundary chain (on either), or sampled over the work limit "
         "(not exact). Shares of all evaluations (Table 1's sampled points are a share of those "
         "that needed a query: tree walk, direct, chain and sampled); in the images each pixel "
         "is the mean colour of its evaluations, black where it has none (the background, the "
         "light itself).\n\n"
      << "| scene |";
    for (size_t i = 0; i < kAnswers; ++i) {
        const auto a = static_cast<Answer>(i);
        r << " " << toString(a) << " (" << answerColour(a).name << ") |";
    }
    r << "\n|---|";
    for (size_t i = 0; i < kAnswers; ++i) r << "---|";
    r << "\n";
    std::string images;
    for (const Table1Row& row : rows) {
        if (!row.exact.render) continue;
        const AnswersImage& answers = row.exact.render->answers;
        const std::string name = sceneName(row.scene);
        r << "| " << name << " |";
        for (double share : answerShares(answers.counts)) r << " " << fmt("%.1f%%", share) << " |";
        r << "\n";
        images += "<img src=\"" + answers.image + "\" width=\"200\" alt=\"" + name + "\" title=\"" +
                  name + "\"> ";
    }
    r << "\n" << images << "\n\n";
}

// Of Table 1's exact renders, the query-driven refinement between passes.
void writeRefined(std::ostream& r, const std::vector<Table1Row>& rows) {
    if (!anyExactRender(rows)) return;
    r << "### Query-driven refinement\n\n"
      << "After each pass, the trees whose walks reached the work limit have their receiver "
         "patch split (`PatchLayout::refine`), and the sub-patches holding those points get "
         "their own trees where the build costs less than sampling them would in the passes "
         "left, both counted in shadow rays (`RenderSettings::refineLevels`, `refineCostShare`). "
         "The time is part of the exact render's.\n\n"
      << "| scene | pairs refined | sub-patch trees built | used | left unrefined (not worth "
         "it) | seconds |\n|---|---|---|---|---|---|\n";
    for (const Table1Row& row : rows) {
        if (!row.exact.render) continue;
        const Refinement& f = row.exact.render->refined;
        r << "| " << sceneName(row.scene) << " | " << f.pairs << " | " << f.trees << " | "
          << f.treesUsed << " | " << f.notWorth << " | " << num(f.seconds, "%.3f") << " |\n";
    }
    r << "\n";
}

// Of Table 1's exact renders, where the queries' plane tests went (vis::WorkStage): per scene
// and path (walking trees, without a tree), at the default work limit and, where the bench ran
// it, with every point exact.
void writeWork(std::ostream& r, const std::vector<Table1Row>& rows) {
    if (!anyExactRender(rows)) return;
    r << "### Where the exact work goes\n\n"
      << "The plane tests of Table 1's exact renders (the unit of the work limit; "
         "`FromPointQuery::stageWork`), by the stage they went to: walking history trees and "
         "evaluating pairs without a tree, at the default work limit and, for the scenes the "
         "bench also renders with every point exact, without a limit. Tests per evaluation: "
         "all of that path's tests over all the exact evaluations.\n\n"
      << "| scene | work limit | path | tests per evaluation |";
    for (size_t i = 0; i < vis::kWorkStages; ++i)
        r << " " << vis::toString(static_cast<vis::WorkStage>(i)) << " |";
    r << "\n|---|---|---|---|";
    for (size_t i = 0; i < vis::kWorkStages; ++i) r << "---|";
    r << "\n";
    auto rowsOf = [&](const Table1Row& row, const WorkByPath& work, const std::string& limit) {
        const double evaluations = static_cast<double>(row.exact.render->evaluations);
        for (const auto& [path, stages] :
             {std::pair{"trees", &work.trees}, std::pair{"without a tree", &work.direct}}) {
            double total = 0;
            for (uint64_t n : *stages) total += static_cast<double>(n);
            if (total == 0) continue;
            r << "| " << sceneName(row.scene) << " | " << limit << " | " << path << " | "
              << fmt("%.1f", evaluations > 0 ? total / evaluations : 0.0) << " |";
            for (uint64_t count : *stages) {
                const double n = static_cast<double>(count);
                r << " " << (n > 0 ? fmt("%.1f%%", 100.0 * n / total) : "-") << " |";
            }
            r << "\n";
        }
    };
    for (const Table1Row& row : rows) {
        if (!row.exact.render) continue;
        const ExactRender& e = *row.exact.render;
        rowsOf(row, e.workAt, std::to_string(e.exactWorkLimit));
        if (e.everyPointExact && e.everyPointExact->workAt)
            rowsOf(row, *e.everyPointExact->workAt, "none");
    }
    r << "\n";
}

// Of Table 1's renders, each evaluation timed: the exact ones answered exactly (query and
// shading; the points over the work limit are not among them) against the sampled render's
// points (128 rays per light), and the boundary chain's edges against its fragments.
void writeCost(std::ostream& r, const std::vector<Table1Row>& rows) {
    if (!anyExactRender(rows)) return;
    r << "### Cost per evaluation\n\n"
      << "One evaluation in 8 of Table 1's renders timed alone (wall, one thread; the clock's own "
         "cost, some 20-40 ns, included): the exact render's (point, light) evaluations that "
         "needed a query and were answered exactly (the query and the shading of its fragments; "
         "the points over the work limit are not among them: their 128 rays are the last "
         "column), and the sampled render's points (128 rays per light). Median and 99th "
         "percentile from a log histogram (to within 19%). Chain: the exact evaluations the "
         "boundary chain answered, with its edges (silhouettes and borders), their share of the "
         "edges of the occluders they came from (each use by a face; a face group taken whole "
         "counts its boundary only, so the share understates what groups save), the cells the "
         "chain cut the light into (each cut, then labelled: the chain's work) and the convex "
         "fragments kept (the cells seen: the shading's work), per evaluation.\n\n"
      << "| scene | exact evaluations timed | median us | p99 us | mean us | sampled points timed "
         "| 128 "
         "rays median us | p99 us | by the chain | chain edges | of the occluders' edges | cells | "
         "fragments | over the limit: 128 rays median us "
         "|\n|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n";
    for (const Table1Row& row : rows) {
        if (!row.exact.render) continue;
        const ExactRender& e = *row.exact.render;
        const EvaluationTimes& c = e.cost.times;
        const SampledRender& sp = row.sampled128;
        r << "| " << sceneName(row.scene) << " | " << c.evaluations << " | "
          << num(c.medianUs, "%.2f") << " | " << num(c.p99Us, "%.2f") << " | "
          << num(c.meanUs, "%.2f") << " | " << sp.points << " | " << num(sp.pointMedianUs) << " | "
          << num(sp.pointP99Us) << " | " << c.chainEvaluations << " | " << chainPer(c, c.chainEdges)
          << " | "
          << (c.chainEvaluations > 0 && e.cost.chainOccluderEdges > 0
                  ? fmt("%.1f%%", 100.0 * static_cast<double>(c.chainEdges) /
                                      static_cast<double>(e.cost.chainOccluderEdges))
                  : "-")
          << " | " << chainPer(c, c.chainCells) << " | " << chainPer(c, c.chainFragments) << " | "
          << (e.sampledEvaluations > 0 ? num(e.cost.sampledMedianUs, "%.2f") : "-") << " |\n";
    }
    r << "\n";
    r << "Where the exact render's evaluations that needed a query spent their time, estimated "
         "from the same timed evaluations (their sums times 8, CPU seconds): the exact answers, "
         "the queries that reached the work limit before they stopped (lost), and the sampled "
         "points' 128 rays. The last two are what the work limit's sampling costs the exact "
         "render.\n\n"
      << "| scene | sampled points | exact answers | queries stopped at the limit | "
         "sampled points' rays | in all, s |\n|---|---|---|---|---|---|\n";
    for (const Table1Row& row : rows) {
        if (!row.exact.render) continue;
        const ExactRender& e = *row.exact.render;
        const TimeSplit& t = e.cost.timeSplit;
        const double all = t.exactSeconds + t.attemptSeconds + t.raysSeconds;
        auto share = [&](double v) { return all > 0 ? fmt("%.1f%%", 100 * v / all) : "-"; };
        r << "| " << sceneName(row.scene) << " | " << fmt("%.1f%%", sampledPercent(e)) << " | "
          << share(t.exactSeconds) << " | " << share(t.attemptSeconds) << " | "
          << share(t.raysSeconds) << " | " << fmt("%.2f", all) << " |\n";
    }
    r << "\n";
}

// Issue 13's per-point goals, measured without the work limit (the cost above leaves out the
// points over it, which are the expensive ones): the exact evaluations' distribution against
// the sampled render's 128 rays per point, and 16 rays taken as an eighth of their median (strict:
// with a point's own cost, 16 rays measure about a seventh of 128).
void writeCostEveryPointExact(std::ostream& r, const std::vector<Table1Row>& rows) {
    const auto has = [](const Table1Row& row) {
        return row.exact.render && row.exact.render->costEveryPointExact;
    };
    if (std::none_of(rows.begin(), rows.end(), has)) return;
    r << "### Per-point cost with every point exact\n\n"
      << "The goals of issue 13 per evaluation: the median exact evaluation costing at most 16 "
         "shadow rays, the 99th percentile at most 128. Measured on a render without the work "
         "limit, so that the points the default render samples count too: Table 1's image where "
         "the default render sampled nothing (the same render) or where the bench also renders it "
         "with every point exact, else a smaller image at one sample per pixel "
         "(`--exact-cost-size`; the large scenes' evaluations average milliseconds). One "
         "evaluation in 8 timed, query and shading, as above; 128 rays: the sampled render's "
         "points (Table 1's image); 16 rays: an eighth of their median (strict: the per-point "
         "section below measures 16 rays at about a seventh of 128, a point's own cost "
         "included). Chain: of all the render's evaluations, those the boundary chain answered, "
         "and per such evaluation its edges, the cells they cut the light into and the fragments "
         "kept (what the expensive points' cost follows: the cells, each cut and labelled, "
         "against the fragments).\n\n"
      << "| scene | image | evaluations timed | median us | p99 us | mean us | 128 rays median "
         "us | 128 rays p99 us | median <= 16 rays | p99 <= 128 rays | by the chain | chain "
         "edges | cells | fragments |\n"
      << "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n";
    for (const Table1Row& row : rows) {
        if (!has(row)) continue;
        const EveryPointExactCost& every = *row.exact.render->costEveryPointExact;
        const EvaluationTimes& c = every.times;
        const SampledRender& sp = row.sampled128;
        const bool have = c.evaluations > 0;
        auto verdict = [&](bool met) { return have ? (met ? "yes" : "no") : "-"; };
        r << "| " << sceneName(row.scene) << " | " << every.width << "x" << every.height << ", "
          << every.spp << " spp (" << every.image << (every.complete ? "" : "; cut at the limit")
          << ") | " << c.evaluations << " | " << num(c.medianUs, "%.2f") << " | "
          << num(c.p99Us, "%.2f") << " | " << num(c.meanUs, "%.2f") << " | "
          << num(sp.pointMedianUs) << " | " << num(sp.pointP99Us) << " | "
          << verdict(have && c.medianUs <= sp.pointMedianUs / 8) << " | "
          << verdict(have && c.p99Us <= sp.pointP99Us) << " | " << c.chainEvaluations << " | "
          << chainPer(c, c.chainEdges) << " | " << chainPer(c, c.chainCells) << " | "
          << chainPer(c, c.chainFragments) << " |\n";
    }
    r << "\n";
}

void writeTable1(std::ostream& r, const std::vector<Table1Row>& rows,
                 const std::vector<SkippedScene>& skipped, bool plots) {
    r << "## Table 1 re-measured\n\n"
      << "Sampled: 128 shadow rays per light per shading point. Exact: the trees the image "
         "needs (`ProgressiveRenderer::prepare`) then the render, with the product's "
         "defaults: a build budget of `BuildOptions::maxLpSolves` linear programs per tree "
         "(a tree that reaches it is *partial*: its other occluders are clipped by each "
         "point's query, still exact), no tree for a pair the image samples fewer than "
         "`RenderSettings::minTreeSamples` times (its points are evaluated directly, exact) "
         "nor for one whose shaft holds `RenderSettings::groupedShaftMin` faces or more, a "
         "quarter of them in face groups (*by groups*: the direct path with the groups answers "
         "its points, as it would its partial tree's), "
         "and a work limit of `RenderSettings::exactWorkLimit` plane tests per query: a "
         "point whose exact answer needs more is sampled with 128 rays (the *sampled "
         "points* column; not exact). *Every point exact*: the same render with no work "
         "limit. All pairs: every (receiver patch, light) pair on the `PrecomputeScheduler` "
         "(skipped above "
      << kAllPairsMaxFaces
      << " faces). Times in seconds, wall / CPU (all threads). Speed-up = sampled time / "
         "(exact precompute + render), wall; in parentheses the render alone.\n\n"
      << "| scene | faces | image | sampled 128 | exact precompute | exact render | speed-up "
         "| trees (partial) | pairs without a tree | sampled points | every point exact | "
         "file (image) | all pairs: time | all pairs: file |\n"
         "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n";
    for (const Table1Row& row : rows) writeTable1Row(r, row);
    r << "\n";
    if (plots) r << "![Table 1](table1.png)\n\n";
    writeSkipped(r, skipped);
    writeAnswers(r, rows);
    writeOverLimit(r, rows);
    writeRefined(r, rows);
    writeWork(r, rows);
    writeCost(r, rows);
    writeCostEveryPointExact(r, rows);
}

// ---- The other studies ---------------------------------------------------------------------

void writeAccuracy(std::ostream& r, const AccuracyBenchRun& run, bool plots) {
    const AccuracyStudy& a = run.study;
    r << "## Error against time\n\n"
      << "Scene " << run.scene << ", " << a.options.width << "x" << a.options.height << ", "
      << a.options.spp
      << " primary samples per pixel, the same for every image (so the sampled images differ "
         "from the exact one only by their shadow-ray noise). RMSE and max error over all "
         "pixels and RGB channels of linear radiance (mean radiance of the exact image "
      << num(a.meanRadiance, "%.4g") << ").\n\n"
      << "| method | rays | wall s | CPU s | RMSE | max error |\n|---|---|---|---|---|---|\n";
    for (const AccuracyPoint& p : a.sampled)
        r << "| sampled vs exact | " << p.rays << " | " << num(p.seconds, "%.3f") << " | "
          << num(p.cpuSeconds, "%.3f") << " | " << num(p.rmse, "%.4g") << " | "
          << num(p.maxError, "%.4g") << " |\n";
    const AccuracyPoint& e = a.exact;
    r << "| exact vs reference | - | " << num(e.seconds, "%.3f") << " | "
      << num(e.cpuSeconds, "%.3f") << " | " << num(e.rmse, "%.4g") << " | "
      << num(e.maxError, "%.4g") << " |\n\n"
      << "Reference: the mean of two sampled images of " << a.options.referenceRays
      << " rays each (different light seeds); its own noise (standard error, RMS) is "
      << num(a.referenceNoise, "%.4g") << ", against the exact image's RMSE of "
      << num(e.rmse, "%.4g")
      << ": the exact image agrees with the converged reference when these are close. The "
         "exact time includes its precompute ("
      << num(e.precomputeSeconds, "%.3f") << " s wall).\n\n";
    if (std::isfinite(a.equalErrorSeconds))
        r << "**Equal error:** the sampled method reaches the exact image's error level ("
          << num(e.rmse, "%.4g") << ", an upper bound on the exact image's error) at about "
          << numOrDash(a.equalErrorRays, "%.0f") << " rays per light and "
          << num(a.equalErrorSeconds, "%.3f") << " s wall, against " << num(e.seconds, "%.3f")
          << " s for the exact method: " << num(a.equalErrorSeconds / e.seconds) << "x"
          << (a.equalErrorExtrapolated ? " (extrapolated beyond the measured curve)" : "")
          << ". Interpolated linearly on the log-log curve.\n\n";
    if (plots) r << "![error against time](accuracy.png)\n\n";
}

void writePredicates(std::ostream& r, const PredicateStudy& p) {
    r << "## What exactness costs: predicates\n\n"
      << "FPQuery on the " << p.cases.size() << " hard cases (`makeHardCases()`), " << p.queries
      << " queries (patch vertices, edge midpoints and random points of every penumbra pair). "
         "Wrong: the visible fraction differs from the AlwaysExact answer by more than 1e-9 "
         "of L's area, or the fragments overlap or leave L. (The test suite checks Filtered "
         "against an exact CGAL reference.)\n\n"
      << "| predicates | us per query (wall) | us per query (CPU) | wrong | other fragment "
         "count than AlwaysExact |\n|---|---|---|---|---|\n";
    for (const PredicateModeResult& m : p.modes)
        r << "| " << m.mode << " | " << num(m.usPerQuery, "%.3f") << " | "
          << num(m.cpuUsPerQuery, "%.3f") << " | " << m.wrong << " | " << m.otherCount << " |\n";
    r << "\nNaive answers with another fragment count than Filtered: " << p.naiveOtherThanFiltered
      << ". A different fragment count is a sliver more or less (the topology of the answer); "
         "Filtered decides rounded constructed vertices by its filter and so may drop slivers "
         "that AlwaysExact's exact sign of the rounded vertex keeps.\n\nPer case (naive wrong "
         "/ naive other count / filtered other count): ";
    for (const PredicateCaseResult& c : p.cases)
        r << c.name << " " << c.wrong[2] << "/" << c.otherCount[2] << "/" << c.otherCount[0]
          << "; ";
    r << "\n\n";
}

void writeBuildOptions(std::ostream& r, const std::vector<BuildOptionsRow>& rows) {
    r << "## Quadric pruning and leaf merging\n\nAll pairs of each scene.\n\n"
      << "| scene | merge leaves | quadric pruning | nodes | bytes | precompute wall / CPU s "
         "| us per query |\n|---|---|---|---|---|---|---|\n";
    for (const BuildOptionsRow& o : rows) {
        const PrecomputeRun& p = o.precompute;
        r << "| " << sceneName(o.scene) << " | " << (o.mergeLeaves ? "on" : "off") << " | "
          << (o.quadricPruning ? "on" : "off") << " | " << p.nodes << " | " << p.bytes << " | "
          << num(p.seconds) << " / " << num(p.cpu)
          << (p.complete ? std::string()
                         : " (over the limit: " + std::to_string(p.done) + "/" +
                               std::to_string(p.pairs) + " pairs)")
          << " | " << num(o.queryUs, "%.3f") << " |\n";
    }
    r << "\n";
}

// Without rows (every resolution skipped) the section only says what is missing.
void writeScaling(std::ostream& r, const std::vector<ScalingRow>& rows, double limit,
                  const std::vector<SkippedScene>& skipped, bool plots) {
    r << "## Precompute against triangle count\n\n";
    if (!rows.empty()) {
        r << "A fixed set of receiver patches: every patch of the floor and 32 faces of the model "
             "drawn with a fixed seed, against the light; built on the `PrecomputeScheduler` ("
          << num(limit, "%.0f") << " s limit per scene).\n\n"
          << "| scene | faces | pairs | done | wall s | CPU s | nodes | bytes | penumbra | "
             "partial |\n|---|---|---|---|---|---|---|---|---|---|\n";
        for (const ScalingRow& s : rows) {
            const PrecomputeRun& p = s.precompute;
            r << "| " << sceneName(s.scene) << " | " << s.faces << " | " << p.pairs << " | "
              << p.done << " | " << num(p.seconds) << " | " << num(p.cpu) << " | " << p.nodes
              << " | " << p.bytes << " | " << p.kinds.penumbra << " | " << p.kinds.partial
              << " |\n";
        }
        if (plots) r << "\n![scaling](scaling.png)\n";
        r << "\n";
    }
    writeSkipped(r, skipped);
}

void writePerPoint(std::ostream& r, const std::vector<PerPointRow>& rows) {
    r << "## Per point: exact query against shadow rays\n\nLight 0, one thread. The exact "
         "query's mean over all points, then its median, 99th percentile and maximum with each "
         "point timed alone.\n\n"
      << "| scene | points | exact query + form factor us | median | p99 | max | nodes | "
         "fragments | 16 rays us | 128 rays us |\n|---|---|---|---|---|---|---|---|---|---|\n";
    for (const PerPointRow& p : rows)
        r << "| " << sceneName(p.scene) << " | " << p.points << " | " << num(p.exactUs) << " | "
          << num(p.exactMedianUs) << " | " << num(p.exactP99Us) << " | " << num(p.exactMaxUs)
          << " | " << num(p.nodesPerQuery, "%.1f") << " | " << num(p.fragmentsPerQuery) << " | "
          << num(p.rays16Us) << " | " << num(p.rays128Us) << " |\n";
    r << "\n";
}

// The same points: the visible region's boundary against the fragments.
void writeOutline(std::ostream& r, const std::vector<PerPointRow>& rows) {
    r << "### The visible region's boundary\n\nThe same points: the fragments' edges, and "
         "the boundary of their union (`vis::visibleOutline`, what `penumbra query` and the "
         "viewer show): its loops (outer boundaries and holes) and edges, once the edges two "
         "fragments share cancel and straight runs merge. Then per point the fragments' form "
         "factor (what the renderer computes) and the outline built and integrated (Lambert's "
         "contour integral over the boundary: the same value). Per point, means.\n\n"
      << "| scene | fragments | their edges | boundary loops | boundary edges | fragments' form "
         "factor us | outline + its form factor us |\n|---|---|---|---|---|---|---|\n";
    for (const PerPointRow& p : rows) {
        const OutlineStats& o = p.outline;
        const double points = std::max(1.0, static_cast<double>(p.points));
        r << "| " << sceneName(p.scene) << " | " << num(p.fragmentsPerQuery) << " | "
          << fmt("%.1f", static_cast<double>(o.fragmentEdges) / points) << " | "
          << fmt("%.2f", static_cast<double>(o.loops) / points) << " | "
          << fmt("%.1f", static_cast<double>(o.edges) / points) << " | "
          << num(o.integrationUs, "%.3f") << " | " << num(o.outlineUs, "%.3f") << " |\n";
    }
    r << "\n";
}

// The same points: the boundary chain and the partial trees' silhouettes.
void writeChain(std::ostream& r, const std::vector<PerPointRow>& rows) {
    r << "### The boundary chain\n\nOf the points clipped against at least "
         "`ChainOptions::minOccluders` occluders per point (a partial tree's deferred ones): "
         "their occluder edges, and the boundary edges left once edges shared by faces turned "
         "the same way cancel (silhouettes, borders, chords). The points where few enough remain "
         "are evaluated by the chain: the cells it cut L into (and of them, those labelled from "
         "the cell before by the chain edges between the two, without a line test) and the "
         "fragments kept. Last, the "
         "mean query with every occluder clipped one by one (Algorithm 1 only) against the "
         "product's. The partial trees' silhouettes (`DeferredSilhouettes`): of the partial trees "
         "the points use, those whose deferred faces share enough edges, the share of their edge "
         "uses kept for the patch (the others cancel for all of it), and the points answered "
         "from them.\n\n"
      << "| scene | points with many occluders | occluder edges | boundary edges | share | "
         "points by the chain | cells | by crossings | fragments | Algorithm 1 only us | with the "
         "chain us | trees with silhouettes | uses kept | points by them "
         "|\n|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n";
    for (const PerPointRow& p : rows) {
        const ChainStats& c = p.chain;
        const double edges = static_cast<double>(c.occluderEdges);
        r << "| " << sceneName(p.scene) << " | " << c.manyOccluderPoints << " | " << c.occluderEdges
          << " | " << c.boundaryEdges << " | "
          << (edges > 0 ? fmt("%.1f%%", 100.0 * static_cast<double>(c.boundaryEdges) / edges)
                        : std::string("-"))
          << " | " << c.points << " | " << c.cells << " | " << c.crossingLabels << " | "
          << c.fragments << " | " << num(c.oneByOneUs) << " | " << num(p.exactUs) << " | "
          << c.silhouetteTrees << " of " << c.partialTrees << " | "
          << (c.silhouetteUses > 0 ? fmt("%.1f%%", 100.0 * static_cast<double>(c.silhouetteKept) /
                                                       static_cast<double>(c.silhouetteUses))
                                   : std::string("-"))
          << " | " << c.silhouettePoints << " |\n";
    }
    r << "\n";
}

// The same points clicked in the viewer.
void writeClicks(std::ostream& r, const std::vector<PerPointRow>& rows) {
    r << "### A click in the viewer\n\nEvery light at a point: the fragments from the "
         "tree-less query the viewer answers a click with (within its work budget; points over "
         "it wait for the trees), and the former click, with the pairs' history trees built and "
         "walked (a fresh store).\n\n"
      << "| scene | clicks | fragments median ms | p99 | max | over budget | clicks with trees | "
         "trees median ms | max |\n|---|---|---|---|---|---|---|---|---|\n";
    for (const PerPointRow& p : rows) {
        const ClickLatency& c = p.click;
        r << "| " << sceneName(p.scene) << " | " << c.points << " | "
          << num(c.fragmentsMedianMs, "%.3f") << " | " << num(c.fragmentsP99Ms, "%.3f") << " | "
          << num(c.fragmentsMaxMs, "%.3f") << " | " << c.overBudget << " | " << c.treePoints
          << " | " << num(c.withTreesMedianMs, "%.1f") << " | " << num(c.withTreesMaxMs, "%.1f")
          << " |\n";
    }
    r << "\n";
}

}  // namespace

std::string fmt(const char* f, double v) {
    char b[64];
    std::snprintf(b, sizeof b, f, v);
    return b;
}

std::string benchReport(const BenchResults& b, bool plots, const std::string& plotNote) {
    std::ostringstream r;
    writeHeading(r, b);
    writeTable1(r, b.table1, skippedBy(b, "table1"), plots);
    writeAccuracy(r, b.accuracy, plots);
    writePredicates(r, b.predicates);
    if (!b.buildOptions.empty()) writeBuildOptions(r, b.buildOptions);
    const std::vector<SkippedScene> scalingSkipped = skippedBy(b, "scaling");
    if (!b.scaling.empty() || !scalingSkipped.empty())
        writeScaling(r, b.scaling, b.options.limit, scalingSkipped, plots);
    writePerPoint(r, b.perPoint);
    writeOutline(r, b.perPoint);
    writeChain(r, b.perPoint);
    writeClicks(r, b.perPoint);
    if (!plots) r << "Plots skipped: " << plotNote << "\n";
    return r.str();
}

}  // namespace penumbra::cli
