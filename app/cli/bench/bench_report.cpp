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
namespace bench_report_detail {

namespace fs = std::filesystem;

std::string num(double v, const char* f = "%.2f") { return fmt(f, v); }

// A quantity the study may not have estimated (NaN: null in bench.json), or "-".
std::string numOrDash(double v, const char* f = "%.2f") {
    return std::isfinite(v) ? fmt(f, v) : std::string("-");
}

// The scene's file name: the tables have no room for the directories.
std::string sceneName(const std::string& scene) { return fs::path(scene).filename().string(); }

// A speed-up (sampled time over exact time) as the tables print it, "12.90x".
std::string speedup(double ratio) { return num(ratio) + "x"; }

// Whether some Table 1 row has an exact render (its sections are written only then).
bool anyExactRender(const std::vector<Table1Row>& rows) {
    for (const Table1Row& row : rows)
        if (row.exact.render) return true;
    return false;
}

// An exact render's evaluations over the work limit (sampled) as a percentage of those that
// needed a query.
double sampledPercent(const ExactRender& exact) {
    return 100.0 * static_cast<double>(exact.sampledEvaluations) /
           std::max(1.0, static_cast<double>(exact.evaluations));
}

// Why a Table 1 row has no equal-error figure, or "" when it has one.
std::string equalErrorMissing(const Table1Row& row) {
    if (!row.equalError) return "not measured: this bench.json predates the equal-error study";
    return row.equalError->found ? std::string() : row.equalError->why;
}

// The percentage the equal-error study aims at, "0.5%".
std::string targetPercent(double target) { return fmt("%.2g%%", 100 * target); }

// A boundary-chain count of a render's evaluations per chain evaluation, or "-" where the chain
// answered none.
std::string chainPer(const EvaluationTimes& cost, uint64_t count) {
    const double chain = static_cast<double>(cost.chainEvaluations);
    if (!(chain > 0)) return "-";
    return fmt("%.1f", static_cast<double>(count) / chain);
}

// ---- Medians and percentiles of timed evaluations -------------------------------------------

// A median or 99th percentile of timed evaluations in microseconds, marked where it is not an
// order statistic of every timed evaluation: "(1 in N)" where it is one of a subsample, "†"
// where it is a log-histogram bucket's middle (bench.json files written before the exact
// quantiles).
std::string quantileUs(double us, uint64_t stride) {
    if (stride == kHistogramQuantiles) return num(us) + " †";
    if (stride > 1) return num(us) + " (1 in " + std::to_string(stride) + ")";
    return num(us);
}

// What the marks of quantileUs mean, after a table that has any (`strides`: its figures').
void writeQuantileNote(std::ostream& r, const std::vector<uint64_t>& strides) {
    const bool histogram = std::count(strides.begin(), strides.end(), kHistogramQuantiles) > 0;
    const bool subsampled =
        std::any_of(strides.begin(), strides.end(), [](uint64_t s) { return s > 1; });
    if (histogram)
        r << "† Not an order statistic: the middle of a log-histogram bucket, to within 19% (this "
             "run predates exact quantiles), so scenes whose costs fall in one bucket print the "
             "same value.\n\n";
    if (subsampled)
        r << "(1 in N): the order statistic of one timed evaluation in N, spread evenly: more "
             "were timed than the 2^20 the renderer keeps per distribution.\n\n";
}

// ---- The top: the conclusion, the run, the terms ---------------------------------------------

// "stairs.json 12.90x, cornell_box.json 23.17x" (or with the slow-downs' inverse) of `rows`.
std::string speedupList(const std::vector<const Table1Row*>& rows) {
    std::string out;
    for (const Table1Row* row : rows) {
        const double s = row->speedup->wall;
        out += (out.empty() ? "" : ", ") + sceneName(row->scene) + " " + speedup(s);
        if (s < 1) out += " (sampling " + speedup(1 / s) + " faster)";
    }
    return out;
}

// Exact against 128 rays per scene (Table 1): where exact wins, where it loses, where it had no
// render, and how much of it was not exact.
void writeTable1Conclusion(std::ostream& r, const std::vector<Table1Row>& rows, double limit) {
    std::vector<const Table1Row*> faster, slower, none, sampled;
    for (const Table1Row& row : rows) {
        if (!row.speedup)
            none.push_back(&row);
        else
            (row.speedup->wall > 1 ? faster : slower).push_back(&row);
        if (row.exact.render && row.exact.render->sampledEvaluations > 0) sampled.push_back(&row);
    }
    const auto bySpeedup = [](const Table1Row* a, const Table1Row* b) {
        return a->speedup->wall > b->speedup->wall;
    };
    std::sort(faster.begin(), faster.end(), bySpeedup);
    std::sort(slower.begin(), slower.end(), bySpeedup);
    const std::string of = " of " + std::to_string(rows.size()) + " scenes";
    r << "**Exact against 128 shadow rays per light, the same image** (Table 1: the sampled "
         "render's wall time over the exact precompute and render's; above 1x exact is "
         "faster):\n\n"
      << "- exact faster on " << faster.size() << of
      << (faster.empty() ? "" : ": " + speedupList(faster)) << ".\n"
      << "- exact slower on " << slower.size() << of
      << (slower.empty() ? "" : ": " + speedupList(slower)) << ".\n";
    if (!none.empty()) {
        r << "- no exact render (precompute over the " << num(limit, "%.0f") << " s limit): ";
        for (size_t i = 0; i < none.size(); ++i)
            r << (i == 0 ? "" : ", ") << sceneName(none[i]->scene);
        r << ".\n";
    }
    std::vector<std::string> equal;
    double target = 0;
    for (const Table1Row& row : rows)
        if (row.equalError && row.equalError->found) {
            equal.push_back(sceneName(row.scene) + " " +
                            speedup(row.equalError->found->speedupWall) + " (" +
                            std::to_string(row.equalError->found->rays) + " rays)");
            target = row.equalError->target;
        }
    if (!equal.empty()) {
        r << "- at equal error (" << targetPercent(target)
          << " relative RMSE over the penumbra pixels; every point exact, precompute included, "
             "against stratified sampling): ";
        for (size_t i = 0; i < equal.size(); ++i) r << (i == 0 ? "" : ", ") << equal[i];
        r << ".\n";
    }
    if (sampled.empty()) {
        r << "- every evaluation exact: none over the work limit.\n";
    } else {
        r << "- not all exact: over the work limit, shaded with 128 rays instead, ";
        for (size_t i = 0; i < sampled.size(); ++i)
            r << (i == 0 ? "" : ", ") << sceneName(sampled[i]->scene) << " "
              << fmt("%.1f%%", sampledPercent(*sampled[i]->exact.render));
        r << " of the evaluations that needed a query.\n";
    }
    r << "\n";
}

// Exact against sampling at equal error and at equal time: the error-against-time study, the one
// study that measures error (on one scene).
void writeAccuracyConclusion(std::ostream& r, const AccuracyBenchRun& run) {
    const AccuracyStudy& a = run.study;
    const AccuracyPoint& e = a.exact;
    const std::string scene = sceneName(run.scene);
    if (std::isfinite(a.equalErrorSeconds) && e.seconds > 0) {
        const double ratio = a.equalErrorSeconds / e.seconds;
        r << "**At equal error** (" << scene
          << " only: the bench measures error on no other scene): sampling reaches the exact "
             "image's RMSE ("
          << num(e.rmse, "%.4g") << ") at about " << numOrDash(a.equalErrorRays, "%.0f")
          << " rays per light and " << num(a.equalErrorSeconds, "%.3f") << " s wall, against "
          << num(e.seconds, "%.3f") << " s exact: exact " << speedup(ratio)
          << (ratio < 1 ? " (sampling " + speedup(1 / ratio) + " faster)" : std::string())
          << (a.equalErrorExtrapolated ? ", extrapolated beyond the measured curve" : "")
          << ".\n\n";
    } else {
        r << "**At equal error**: no figure. The error-against-time study (" << scene
          << ") has fewer than two usable points on its sampled curve, and the bench measures "
             "error on no other scene.\n\n";
    }
    // Equal time: the most rays whose measured render took no longer than the exact one.
    const AccuracyPoint* within = nullptr;
    const AccuracyPoint* fastest = nullptr;
    for (const AccuracyPoint& p : a.sampled) {
        if (fastest == nullptr || p.seconds < fastest->seconds) fastest = &p;
        if (p.seconds <= e.seconds && (within == nullptr || p.rays > within->rays)) within = &p;
    }
    if (within != nullptr) {
        r << "**At equal time** (" << scene << "): in the exact image's " << num(e.seconds, "%.3f")
          << " s, sampling affords " << within->rays << (within->rays == 1 ? " ray" : " rays")
          << " per light (" << num(within->seconds, "%.3f") << " s), whose RMSE against the exact "
          << "image, " << num(within->rmse, "%.4g") << ", is "
          << (e.rmse > 0 ? num(within->rmse / e.rmse, "%.1f") + "x" : std::string("-"))
          << " the exact image's against the converged reference (" << num(e.rmse, "%.4g")
          << ").\n\n";
    } else if (fastest != nullptr) {
        r << "**At equal time** (" << scene << "): no sampled render is as fast as the exact "
          << "image's " << num(e.seconds, "%.3f") << " s: " << fastest->rays
          << (fastest->rays == 1 ? " ray" : " rays") << " per light took "
          << num(fastest->seconds, "%.3f") << " s.\n\n";
    }
}

void writeConclusion(std::ostream& r, const BenchResults& b) {
    r << "## In short\n\n";
    if (!b.table1.empty()) writeTable1Conclusion(r, b.table1, b.options.limit);
    writeAccuracyConclusion(r, b.accuracy);
}

void writeHeading(std::ostream& r, const BenchResults& b) {
    if (b.options.quick) r << "> **" << quickRunNote(b.options) << "**\n\n";
    r << "# Penumbra: what accuracy costs in time\n\n";
    writeConclusion(r, b);
    const BenchMachine& m = b.machine;
    r << "## This run\n\nMeasured by `" << b.command << "` on " << m.date << ". Machine: " << m.cpu
      << ", " << m.cores << " logical cores, load average at the start `" << m.loadavg
      << "`, build type " << m.buildType
      << ". Compare ratios and CPU times, not seconds across runs (a shared machine varies "
         "10-25% from run to run).\n\n"
      << "Terms: an *evaluation* is one (shading point, area light) pair of a render; a *tree* "
         "is the history tree of one (receiver patch, light) pair, the exact visibility "
         "precomputed for every point of the patch, and a *partial* one left some occluders to be "
         "clipped per point (still exact); *over the work limit*: an evaluation whose exact answer "
         "needs more than `--exact-work-limit` plane tests, answered next by the light-edge "
         "path (exact) or, over `--light-edge-work-limit` too, shaded with 128 shadow rays (not "
         "exact); times are wall / CPU seconds (CPU: all threads); *us*: microseconds.\n\n";
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

// ---- Table 1 -------------------------------------------------------------------------------

void writeTable1Row(std::ostream& r, const Table1Row& row) {
    const ExactRun& x = row.exact;
    const ExactRender* e = x.render ? &*x.render : nullptr;
    r << "| " << sceneName(row.scene) << " | " << row.faces << " | " << row.width << "x"
      << row.height << ", " << row.spp << " spp | " << num(row.sampled128.wall) << " / "
      << num(row.sampled128.cpu) << " | " << num(x.precomputeWall) << " / " << num(x.precomputeCpu)
      << (x.precomputeComplete ? "" : " (over the limit)") << " | "
      << (e ? num(e->renderWall) + " / " + num(e->renderCpu) : std::string("-")) << " | "
      << (row.speedup
              ? speedup(row.speedup->wall) + " (" + speedup(row.speedup->renderOnlyWall) + ")"
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
        r << (a.complete ? "" : "over ") << num(a.renderWall) << " / " << num(a.renderCpu) << " | ";
    } else {
        r << (e && e->sampledEvaluations == 0 ? "(the same) | " : "- | ");
    }
    r << num(static_cast<double>(x.fileBytes) / 1024.0, "%.1f") << " KB | ";
    if (row.allPairs) {
        const AllPairsRun& a = *row.allPairs;
        r << num(a.precompute.seconds) << " / " << num(a.precompute.cpu)
          << (a.precompute.complete ? "" : " (over the limit)") << " | "
          << num(static_cast<double>(a.fileBytes) / 1024.0, "%.1f") << " KB | ";
    } else {
        r << (row.faces > kAllPairsMaxFaces ? "skipped | - | " : "- | - | ");
    }
    // The image with every point exact (its own precompute) and sampling at equal error.
    if (!row.equalError)
        r << "- | ";
    else if (row.equalError->exactComplete)
        r << num(row.equalError->exactWall) << " / " << num(row.equalError->exactCpu) << " | ";
    else
        r << "over " << num(row.equalError->exactWall, "%.0f") << " | ";
    if (row.equalError && row.equalError->found) {
        const EqualErrorFound& f = *row.equalError->found;
        r << f.rays << " rays, " << num(f.wall) << " / " << num(f.cpu) << " | "
          << speedup(f.speedupWall) << " |\n";
    } else {
        r << "- (" << equalErrorMissing(row) << ") | - |\n";
    }
}

// Of Table 1's evaluations over the work limit, the stage each query was in when it reached it,
// and those not tried: later points of a region whose query had reached it.
void writeOverLimit(std::ostream& r, const std::vector<Table1Row>& rows) {
    if (!anyExactRender(rows)) return;
    std::vector<std::string> stages;  // in the order a query goes through them
    for (size_t i = 0; i < vis::kWorkStages; ++i)
        stages.emplace_back(vis::toString(static_cast<vis::WorkStage>(i)));
    r << "### Where the evaluations over the work limit stopped\n\n"
      << "Of each scene's evaluations over the work limit (Table 1), those whose exact query "
         "reached the limit, by the stage of the query it was in, and those not tried: later "
         "points of a region (one receiver patch in a few pixels of a tile) whose query had "
         "reached it. The largest stage is the one to make cheaper.\n\n"
      << "| scene | over the limit | not tried |";
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

// Of Table 1's exact renders, how each evaluation was answered: the shares and the images.
void writeAnswers(std::ostream& r, const std::vector<Table1Row>& rows) {
    if (!anyExactRender(rows)) return;
    r << "### How each evaluation was answered\n\n"
      << "Table 1's exact renders, each evaluation by the answer it took (the colours of "
         "`penumbra render --out-answers` and of the viewer's answers view): fully visible "
         "(nothing in the pair's shaft: the whole light, no query), horizon-clipped (nothing in "
         "the shaft, but the receiver's plane cuts the light: the part above it, no query), no "
         "light (a back-facing or fully hidden pair, or a point behind the light's plane), a "
         "history tree's walk, the direct path (no tree), "
         "the boundary chain (on either), or sampled over the work limit (not exact). Shares of "
         "all evaluations (Table 1's *over the work limit* is a share of those that needed a "
         "query: tree walk, direct, chain and sampled); in the images each pixel is the mean "
         "colour of its evaluations, black where it has none (the background, the light "
         "itself).\n\n"
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
      << "After each pass, a tree whose walks reached the work limit has its receiver patch "
         "split (up to `--refine-levels` times), and the sub-patches holding those points get "
         "their own trees where building them costs less than sampling the points would in the "
         "passes left, both counted in shadow rays. The time is part of the exact render's.\n\n"
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
      << "The plane tests of Table 1's exact renders (the work limit's unit), by the stage of "
         "the query they went to: walking history trees and evaluating pairs without a tree, at "
         "the default work limit and, for the scenes the bench also renders with every point "
         "exact, without a limit. Plane tests per evaluation: all of that path's tests over all "
         "the evaluations that needed a query.\n\n"
      << "| scene | work limit | path | plane tests per evaluation |";
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
// shading; those over the work limit are not among them) against the sampled render's points
// (128 rays per light), and the boundary chain's edges against its fragments.
void writeCost(std::ostream& r, const std::vector<Table1Row>& rows) {
    if (!anyExactRender(rows)) return;
    r << "### Cost per evaluation\n\n"
      << "One evaluation in 8 of Table 1's renders timed alone (wall, one thread; the clock's own "
         "cost, some 20-40 ns, included): the exact render's evaluations that needed a query and "
         "were answered exactly (the query and the shading of its fragments; those over the work "
         "limit are not among them: their 128 rays are the last column), and the sampled "
         "render's shading points (128 rays per light, every light). Medians and 99th "
         "percentiles are order statistics of the timed evaluations (nearest rank). Chain: the "
         "exact evaluations the boundary chain answered, per such evaluation its edges "
         "(silhouettes and borders), their share of the edges of the occluders they came from "
         "(a face group taken whole counts its boundary only, so the share understates what "
         "groups save), the cells the chain cut the light into (the chain's work) and the convex "
         "fragments kept (the shading's work).\n\n"
      << "| scene | exact: timed | exact: median us | exact: p99 us | exact: mean us | 128 rays: "
         "points timed | 128 rays: median us | 128 rays: p99 us | by the chain | chain edges | "
         "share of the occluders' edges | cells | fragments | over the limit: 128 rays median us "
         "|\n|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n";
    std::vector<uint64_t> strides;
    for (const Table1Row& row : rows) {
        if (!row.exact.render) continue;
        const ExactRender& e = *row.exact.render;
        const EvaluationTimes& c = e.cost.times;
        const SampledRender& sp = row.sampled128;
        strides.insert(strides.end(), {c.quantileStride, sp.pointQuantileStride});
        if (e.sampledEvaluations > 0) strides.push_back(e.cost.sampledQuantileStride);
        r << "| " << sceneName(row.scene) << " | " << c.evaluations << " | "
          << quantileUs(c.medianUs, c.quantileStride) << " | "
          << quantileUs(c.p99Us, c.quantileStride) << " | " << num(c.meanUs) << " | " << sp.points
          << " | " << quantileUs(sp.pointMedianUs, sp.pointQuantileStride) << " | "
          << quantileUs(sp.pointP99Us, sp.pointQuantileStride) << " | " << c.chainEvaluations
          << " | " << chainPer(c, c.chainEdges) << " | "
          << (c.chainEvaluations > 0 && e.cost.chainOccluderEdges > 0
                  ? fmt("%.1f%%", 100.0 * static_cast<double>(c.chainEdges) /
                                      static_cast<double>(e.cost.chainOccluderEdges))
                  : "-")
          << " | " << chainPer(c, c.chainCells) << " | " << chainPer(c, c.chainFragments) << " | "
          << (e.sampledEvaluations > 0
                  ? quantileUs(e.cost.sampledMedianUs, e.cost.sampledQuantileStride)
                  : "-")
          << " |\n";
    }
    r << "\n";
    writeQuantileNote(r, strides);
    r << "Where the exact render's evaluations that needed a query spent their time, estimated "
         "from the same timed evaluations (their sums times 8, CPU seconds): the exact answers, "
         "the queries that reached the work limit before they stopped (lost), and the 128 rays "
         "of the evaluations over the limit. The last two are what the work limit costs the "
         "exact render.\n\n"
      << "| scene | over the work limit | exact answers | queries stopped at the limit | 128 rays "
         "over the limit | in all, s |\n|---|---|---|---|---|---|\n";
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

// The per-evaluation goals, measured without the work limit (the cost above leaves out the
// evaluations over it, which are the expensive ones): the exact evaluations' distribution
// against the sampled render's 128 rays per point, and 16 rays taken as an eighth of their
// median (strict: with a point's own cost, 16 rays measure about a seventh of 128).
void writeCostEveryPointExact(std::ostream& r, const std::vector<Table1Row>& rows) {
    const auto has = [](const Table1Row& row) {
        return row.exact.render && row.exact.render->costEveryPointExact;
    };
    if (std::none_of(rows.begin(), rows.end(), has)) return;
    r << "### Per-point cost with every point exact\n\n"
      << "The goals per evaluation: the median exact evaluation costing at most 16 shadow rays, "
         "the 99th percentile at most 128. Measured on a render without the work limit, so that "
         "the evaluations the default render samples count too: Table 1's image where the "
         "default render sampled nothing (the same render) or where the bench also renders it "
         "with every point exact, else a smaller image at one sample per pixel "
         "(`--exact-cost-size`; the large scenes' evaluations average milliseconds). One "
         "evaluation in 8 timed, query and shading, as above; 128 rays: the sampled render's "
         "points (Table 1's image); 16 rays: an eighth of their median (strict: the per-point "
         "section below measures 16 rays at about a seventh of 128, a point's own cost "
         "included). Chain: of all the render's evaluations, those the boundary chain answered, "
         "and per such evaluation its edges, the cells they cut the light into and the fragments "
         "kept.\n\n"
      << "| scene | image | exact: timed | exact: median us | exact: p99 us | exact: mean us | "
         "128 rays: median us | 128 rays: p99 us | median <= 16 rays | p99 <= 128 rays | by the "
         "chain | chain edges | cells | fragments |\n"
      << "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n";
    std::vector<uint64_t> strides;
    for (const Table1Row& row : rows) {
        if (!has(row)) continue;
        const EveryPointExactCost& every = *row.exact.render->costEveryPointExact;
        const EvaluationTimes& c = every.times;
        const SampledRender& sp = row.sampled128;
        strides.insert(strides.end(), {c.quantileStride, sp.pointQuantileStride});
        const bool have = c.evaluations > 0;
        auto verdict = [&](bool met) { return have ? (met ? "yes" : "no") : "-"; };
        r << "| " << sceneName(row.scene) << " | " << every.width << "x" << every.height << ", "
          << every.spp << " spp (" << every.image << (every.complete ? "" : "; cut at the limit")
          << ") | " << c.evaluations << " | " << quantileUs(c.medianUs, c.quantileStride) << " | "
          << quantileUs(c.p99Us, c.quantileStride) << " | " << num(c.meanUs) << " | "
          << quantileUs(sp.pointMedianUs, sp.pointQuantileStride) << " | "
          << quantileUs(sp.pointP99Us, sp.pointQuantileStride) << " | "
          << verdict(have && c.medianUs <= sp.pointMedianUs / 8) << " | "
          << verdict(have && c.p99Us <= sp.pointP99Us) << " | " << c.chainEvaluations << " | "
          << chainPer(c, c.chainEdges) << " | " << chainPer(c, c.chainCells) << " | "
          << chainPer(c, c.chainFragments) << " |\n";
    }
    r << "\n";
    writeQuantileNote(r, strides);
}

void writeShadowEdges(std::ostream& r, const std::vector<Table1Row>& rows) {
    const auto has = [](const Table1Row& row) { return row.shadowEdges.has_value(); };
    if (std::none_of(rows.begin(), rows.end(), has)) return;
    r << "### Edges that can bound a shadow\n\n"
      << "An occluder edge bounds a shadow of light L only if it is a silhouette seen from some "
         "point of L: S_L, decided exactly per light from the signs of L's vertices against the "
         "two face planes of each edge (open edges, i.e. borders, non-manifold edges and edges "
         "between inconsistently oriented faces, always in; docs/exactness.md). Its share of "
         "the mesh's edges bounds what a per-point search over S_L must look at; the seconds "
         "are the edge table's and every light's set.\n\n"
      << "| scene | edges | open | S_L share, per light | seconds |\n|---|---|---|---|---|\n";
    for (const Table1Row& row : rows) {
        if (!has(row)) continue;
        const ShadowEdges& e = *row.shadowEdges;
        const std::string share =
            e.minShare == e.maxShare
                ? num(100 * e.minShare, "%.1f") + "%"
                : num(100 * e.minShare, "%.1f") + "-" + num(100 * e.maxShare, "%.1f") + "%";
        r << "| " << sceneName(row.scene) << " | " << e.edges << " | " << e.open << " | "
          << (row.areaLights == 0 ? std::string("-") : share) << " | " << num(e.seconds, "%.3f")
          << " |\n";
    }
    r << "\n";
}

// Of Table 1's exact renders: the light-edge path's edges per evaluation against K, the edges
// that can bound the point's shadow (what an output-sensitive finder would look at).
void writeLightEdges(std::ostream& r, const std::vector<Table1Row>& rows) {
    const auto has = [](const Table1Row& row) {
        return row.exact.render && row.exact.render->cost.lightEdges.has_value();
    };
    if (std::none_of(rows.begin(), rows.end(), has)) return;
    r << "### Edges examined per point against K\n\n"
      << "Table 1's exact renders, the evaluations the light-edge path answered (all of them, not "
         "only the timed ones), per evaluation: the S_L edges near the point's cone whose weight "
         "was taken (those of the subtrees the point sees wholly from one side are skipped "
         "without it: docs/design.md, the light-edge path), those of nonzero weight, and those of "
         "them that meet the cone over L: *K*, the edges that can bound this point's shadow. An "
         "output-sensitive finder would examine about K; the last column says how far from that "
         "the search is.\n\n"
      << "| scene | light-edge evaluations | edges examined | of nonzero weight | in the cone (K) "
         "| examined / K |\n|---|---|---|---|---|---|\n";
    for (const Table1Row& row : rows) {
        if (!has(row)) continue;
        const LightEdgeCounts& c = *row.exact.render->cost.lightEdges;
        r << "| " << sceneName(row.scene) << " | " << c.evaluations << " | ";
        if (c.evaluations == 0) {
            r << "- | - | - | - |\n";
            continue;
        }
        const double n = static_cast<double>(c.evaluations);
        r << num(static_cast<double>(c.examined) / n, "%.1f") << " | "
          << num(static_cast<double>(c.weighted) / n, "%.1f") << " | "
          << num(static_cast<double>(c.inCone) / n, "%.1f") << " | "
          << (c.inCone > 0
                  ? num(static_cast<double>(c.examined) / static_cast<double>(c.inCone), "%.1f") +
                        "x"
                  : std::string("-"))
          << " |\n";
    }
    r << "\n";
}

// Of Table 1's scenes: the image with every point exact, and the shadow rays at which sampling
// comes within the target error over its penumbra, with the search's points.
void writeEqualError(std::ostream& r, const std::vector<Table1Row>& rows) {
    const auto has = [](const Table1Row& row) { return row.equalError.has_value(); };
    r << "### At equal error\n\n";
    if (std::none_of(rows.begin(), rows.end(), has)) {
        r << "Not measured: this bench.json predates the equal-error study.\n\n";
        return;
    }
    r << "What accuracy costs: per scene, Table 1's image rendered with every point exact (no "
         "work limit; its trees built first, timed with it), and the shadow rays per light at "
         "which stratified sampling of the same image comes within the target of it. The "
         "reference is that exact image; both use the same primary samples, so they differ only "
         "in how the lights are integrated. The error: the RMSE over the *penumbra pixels* (those "
         "whose visible fraction lies strictly between 0 and 1 in the exact render: some "
         "evaluation saw part of its light, or some none and some all of it) and their RGB "
         "channels of linear radiance, over the exact image's mean radiance there. The ray counts "
         "are square stratified grids n x n; n doubles from 1 until the error is within the "
         "target, then is bisected, every render with the same light seed (reproducible). "
         "Speed-up: the sampled render's wall time over the exact one's.\n\n"
      << "| scene | image | penumbra pixels | their mean radiance | every point exact: wall / "
         "CPU s (precompute) | target | rays per light | sampled wall / CPU s | its error | "
         "exact's speed-up (CPU) | searched: rays (error) |\n"
         "|---|---|---|---|---|---|---|---|---|---|---|\n";
    for (const Table1Row& row : rows) {
        const std::string name = sceneName(row.scene);
        if (!row.equalError) {
            r << "| " << name << " | - | - | - | - | - | - (" << equalErrorMissing(row)
              << ") | - | - | - | - |\n";
            continue;
        }
        const EqualErrorRun& q = *row.equalError;
        r << "| " << name << " | " << row.width << "x" << row.height << ", " << row.spp
          << " spp | ";
        if (q.exactComplete)
            r << q.penumbraPixels << " of " << q.pixels << " | "
              << num(q.penumbraMeanRadiance, "%.4g") << " | " << num(q.exactWall) << " / "
              << num(q.exactCpu) << " (" << num(q.exactPrecomputeWall) << ") | ";
        else
            r << "- | - | over " << num(q.exactWall, "%.0f") << " | ";
        r << targetPercent(q.target) << " | ";
        if (q.found) {
            const EqualErrorFound& f = *q.found;
            r << f.rays << " | " << num(f.wall) << " / " << num(f.cpu) << " | "
              << fmt("%.3f%%", 100 * f.relativeRmse) << " | " << speedup(f.speedupWall) << " ("
              << speedup(f.speedupCpu) << ") | ";
        } else {
            r << "- (" << q.why << ") | - | - | - | ";
        }
        for (size_t i = 0; i < q.searched.size(); ++i)
            r << (i == 0 ? "" : ", ") << q.searched[i].rays << " ("
              << fmt("%.3f%%", 100 * q.searched[i].relativeRmse) << ")";
        r << (q.searched.empty() ? "- |\n" : " |\n");
    }
    r << "\n";
}

void writeTable1(std::ostream& r, const std::vector<Table1Row>& rows,
                 const std::vector<SkippedScene>& skipped, bool plots) {
    r << "## Table 1: exact against 128 shadow rays\n\n"
      << "The paper's Table 1 re-measured: per scene the same image rendered twice, *sampled* "
         "with 128 shadow rays per light per shading point, and *exact*: the history trees the "
         "image needs (precompute), then the render. The exact renderer runs with the defaults of "
         "its options (docs/cli.md, the exact-visibility options): a build budget per tree "
         "(`--max-lp-solves`; a tree that reaches it is *partial*), no tree for a pair the image "
         "samples fewer than `--min-tree-samples` times nor for one whose shaft holds "
         "`--grouped-shaft-min` faces or more, a quarter of them in groups of faces seen from one "
         "side (*by groups*): the points of the pairs without a tree are evaluated directly, "
         "exact; and the work limit (`--exact-work-limit`): the evaluations over it take the "
         "light-edge path, and are sampled with 128 rays (not exact) only over its own limit "
         "(`--light-edge-work-limit`). *Every point exact*: the same render with no work limit. "
         "*All pairs*: every (receiver patch, light) pair precomputed, skipped above "
      << kAllPairsMaxFaces
      << " triangles. Times in seconds, wall / CPU (with every point exact, CPU over wall near the "
         "core count says the cores stayed busy). Speed-up: the sampled wall time over the "
         "exact precompute and render's, above 1x where exact is faster; in parentheses the "
         "render alone. The last three columns: the image rendered again with every point exact, "
         "its own trees built first (a fresh store), and stratified sampling at equal error over "
         "the penumbra (*At equal error* below).\n\n"
      << "| scene | triangles | image | sampled, 128 rays | exact: precompute | exact: render | "
         "speed-up (render only) | trees (partial) | pairs without a tree | over the work limit "
         "| render with every point exact | visibility file, the image's trees | all pairs: "
         "precompute | all pairs: file | every point exact: precompute + render | sampled at "
         "equal error: rays per light, wall / CPU | exact's speed-up at equal error |\n"
         "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n";
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
    writeShadowEdges(r, rows);
    writeLightEdges(r, rows);
    writeEqualError(r, rows);
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
      << "| method | rays per light | wall s | CPU s | RMSE | max error |\n"
         "|---|---|---|---|---|---|\n";
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
          << " s for the exact method: " << speedup(a.equalErrorSeconds / e.seconds)
          << (a.equalErrorExtrapolated ? " (extrapolated beyond the measured curve)" : "")
          << ". Interpolated linearly on the log-log curve.\n\n";
    if (plots) r << "![error against time](accuracy.png)\n\n";
}

// The predicate modes as a reader names them (PredicateStudy::modes).
std::string predicateName(const std::string& mode) {
    if (mode == "filtered") return "filtered (the product's)";
    if (mode == "alwaysExact") return "always exact";
    if (mode == "naive") return "naive doubles";
    return mode;
}

void writePredicates(std::ostream& r, const PredicateStudy& p) {
    r << "## What exactness costs: predicates\n\n"
      << "The from-point query on the test suite's " << p.cases.size() << " hard cases, "
      << p.queries
      << " queries (patch vertices, edge midpoints and random points of every penumbra pair), "
         "with three kinds of geometric predicates: filtered (an interval filter, exact "
         "arithmetic where it cannot decide: the product's), always exact, and naive doubles. "
         "Wrong: the visible fraction differs from the always-exact answer by "
         "more than 1e-9 of the light's area, or the fragments overlap or leave the light. (The "
         "test suite checks the filtered query against an exact CGAL reference.)\n\n"
      << "| predicates | us per query (wall) | us per query (CPU) | wrong | another fragment "
         "count than always exact |\n|---|---|---|---|---|\n";
    for (const PredicateModeResult& m : p.modes)
        r << "| " << predicateName(m.mode) << " | " << num(m.usPerQuery, "%.3f") << " | "
          << num(m.cpuUsPerQuery, "%.3f") << " | " << m.wrong << " | " << m.otherCount << " |\n";
    r << "\nNaive answers with another fragment count than filtered: " << p.naiveOtherThanFiltered
      << ". A different fragment count is a sliver more or less (the topology of the answer); "
         "filtered decides rounded constructed vertices by its filter and so may drop slivers "
         "that always exact's exact sign of the rounded vertex keeps.\n\nPer case (naive wrong "
         "/ naive other count / filtered other count): ";
    for (const PredicateCaseResult& c : p.cases)
        r << c.name << " " << c.wrong[2] << "/" << c.otherCount[2] << "/" << c.otherCount[0]
          << "; ";
    r << "\n\n";
}

void writeBuildOptions(std::ostream& r, const std::vector<BuildOptionsRow>& rows) {
    r << "## Quadric pruning and leaf merging\n\nEvery pair of each scene precomputed with the "
         "tree builder's two savings on and off.\n\n"
      << "| scene | merge leaves | quadric pruning | tree nodes | tree bytes | precompute wall / "
         "CPU s | us per query |\n|---|---|---|---|---|---|---|\n";
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
             "drawn with a fixed seed, against the light, precomputed on every core ("
          << num(limit, "%.0f") << " s limit per scene).\n\n"
          << "| scene | triangles | pairs | built | wall s | CPU s | tree nodes | tree bytes | "
             "penumbra pairs | partial trees |\n|---|---|---|---|---|---|---|---|---|---|\n";
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
         "query and its form factor: the mean over all points, then the median, 99th percentile "
         "and maximum with each point timed alone (order statistics, nearest rank).\n\n"
      << "| scene | points | exact: mean us | exact: median us | exact: p99 us | exact: max us "
         "| tree nodes visited | fragments | 16 rays us | 128 rays us "
         "|\n|---|---|---|---|---|---|---|---|---|---|\n";
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
         "the boundary of their union (what `penumbra query` and the viewer show): its loops "
         "(outer boundaries and holes) and edges, once the edges two fragments share cancel and "
         "straight runs merge. Then per point the fragments' form factor (what the renderer "
         "computes) and the outline built and integrated (Lambert's contour integral over the "
         "boundary: the same value). Per point, means.\n\n"
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
         "`--chain-min-occluders` occluders (a partial tree's deferred ones): their occluder "
         "edges, and the boundary edges left once edges shared by faces "
         "turned the same way cancel (silhouettes, borders, chords). The points where few "
         "enough remain are evaluated by the chain: the cells it cut the light into (and of "
         "them, those labelled from the cell before by the chain edges between the two, without "
         "a line test) and the fragments kept. Then the mean query with every occluder clipped "
         "one by one (Algorithm 1 alone) against the product's. Last, the partial "
         "trees' silhouettes: of the partial trees the points use, those whose deferred faces "
         "share enough edges, the share of their edge uses kept for the patch (the others "
         "cancel for all of it), and the points answered from them.\n\n"
      << "| scene | points with many occluders | occluder edges | boundary edges | share | "
         "points by the chain | cells | labelled by crossings | fragments | Algorithm 1 alone us "
         "| with the chain us | trees with silhouettes | edge uses kept | points by them "
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
         "it wait for the trees), and the same click with the pairs' history trees built and "
         "walked (a fresh store).\n\n"
      << "| scene | clicks | fragments: median ms | fragments: p99 ms | fragments: max ms | "
         "over budget | clicks with trees | with trees: median ms | with trees: max ms "
         "|\n|---|---|---|---|---|---|---|---|---|\n";
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

}  // namespace bench_report_detail

std::string fmt(const char* f, double v) {
    char b[64];
    std::snprintf(b, sizeof b, f, v);
    return b;
}

std::string quickRunNote(const BenchSettings& o) {
    return "Quick run (--quick): " + o.size + " images at " + std::to_string(o.spp) +
           " spp and a " + fmt("%g", o.limit) +
           " s limit, sizes for CI and smoke tests, not for conclusions: run the bench without "
           "--quick for figures to compare.";
}

std::string benchReport(const BenchResults& b, bool plots, const std::string& plotNote) {
    using namespace bench_report_detail;
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
