// bench.json's schema (app/cli/bench/bench_json.h): what the bench writes reads back into the same
// structs, and a key the writer and the reader spell differently, a missing key or a value of the
// wrong type stops the reading with the key's place, instead of a "-" in the report
// (bench_report.h, which reads typed fields).
#include "app/cli/bench/bench_json.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "app/cli/bench/bench_report.h"

namespace penumbra::cli {
namespace {

using nlohmann::json;

// The first Table 1 row with every optional part (the exact render, its render with every point
// exact, the all-pairs run), the second with none (its precompute cut at the limit).
std::vector<Table1Row> sampleTable1() {
    Table1Row full;
    full.scene = "assets/scenes/table.json";
    full.faces = 1348;
    full.areaLights = 1;
    full.shadowEdges = ShadowEdges{3181, 2316, 2911, 0.25, 0.5, 0.125};
    full.width = full.height = 64;
    full.spp = 2;
    full.sampled128 = {1.5, 2.5, 64, 10, 20, 12};
    full.exact.precomputeWall = 0.25;
    full.exact.precomputeComplete = true;
    full.exact.trees = 22;
    full.exact.kinds = {1, 2, 3, 4, 10};
    full.exact.fileBytes = 2048;
    ExactRender e;
    e.answers = {"answers_table.png", {1, 2, 3, 4, 5, 6, 7}};
    e.renderWall = 0.5;
    e.evaluations = 1000;
    e.sampledEvaluations = 100;
    e.overLimitAt[0] = 7;
    e.workAt.trees[1] = 50;
    e.workAt.direct[2] = 25;
    e.cost.times.evaluations = 125;
    e.cost.timeSplit = {0.1, 0.2, 0.3};
    e.cost.lightEdges = LightEdgeCounts{4, 36, 10, 8};
    e.exactWorkLimit = 1024;
    e.everyPointExact = EveryPointExactRender{true, 0.75, 1.5, WorkByPath{}};
    e.costEveryPointExact = EveryPointExactCost{{}, 8, 8, 1, "--exact-cost-size", false};
    full.exact.render = e;
    full.speedup = Speedups{3, 4, 5, 6};
    full.allPairs = AllPairsRun{{0.5, 1.0, 10, 10, true, 4, 40, 400, {}}, 4096};
    EqualErrorRun equal;
    equal.target = 0.005;
    equal.maxRays = 4096;
    equal.exactComplete = true;
    equal.exactWall = 0.5;
    equal.exactCpu = 0.75;
    equal.exactPrecomputeWall = 0.125;
    equal.pixels = 4096;
    equal.penumbraPixels = 300;
    equal.penumbraMeanRadiance = 0.25;
    equal.searched = {{1, 0.0625, 0.125, 0.5}, {4, 0.25, 0.5, 0.004}};
    equal.found = EqualErrorFound{4, 0.25, 0.5, 0.004, 0.5, 0.6666};
    full.equalError = equal;
    Table1Row cut;
    cut.scene = "assets/scenes/dragon.json";
    cut.faces = 871414;
    cut.areaLights = 1;
    cut.width = cut.height = 16;
    cut.spp = 1;
    cut.exact.precomputeWall = 20;
    cut.exact.trees = 3;
    return {full, cut};
}

BenchResults sample() {
    BenchResults b;
    b.machine = {"a CPU", 2, "0.50 0.40 0.30 1/100 1", "2026-01-01 00:00:00 UTC", "Release"};
    b.command = "penumbra bench --out DIR";
    b.options = {"512x512", "256x256", 16, false, false, 180, "128x128"};
    b.table1 = sampleTable1();
    b.accuracy.scene = "assets/scenes/cornell_box.json";
    b.accuracy.study.sampled = {{"sampled", 1, 0.01, 0.02, 0, 0.1, 0.5},
                                {"sampled", 2, 0.02, 0.04, 0, 0.05, 0.25}};
    b.accuracy.study.exact = {"exact", 0, 0.03, 0.05, 0.01, 0.001, 0.01};
    b.accuracy.study.equalErrorSeconds = std::numeric_limits<double>::quiet_NaN();
    b.accuracy.study.equalErrorRays = std::numeric_limits<double>::quiet_NaN();
    b.accuracy.partialTrees = 2;
    b.predicates.queries = 12;
    b.predicates.modes[0].mode = "filtered";
    b.predicates.modes[1].mode = "alwaysExact";
    b.predicates.modes[2].mode = "naive";
    b.predicates.cases = {PredicateCaseResult{"sliver", 12, {1, 0, 3}, {4, 0, 6}, 0}};
    BuildOptionsRow options;
    options.scene = "assets/scenes/cornell_box.json";
    options.queryUs = 0.75;
    b.buildOptions = {options};
    ScalingRow scaling;
    scaling.scene = "assets/scenes/dragon_res4.json";
    scaling.faces = 11102;
    b.scaling = {scaling};
    PerPointRow point;
    point.scene = "assets/scenes/stairs.json";
    point.points = 200;
    point.chain.silhouetteUses = 8;
    point.chain.silhouetteKept = 2;
    b.perPoint = {point};
    b.skipped = {{"scaling", "assets/scenes/dragon_res3.json", {"assets/external/x.ply"}}};
    return b;
}

// Every object key of `j`, as the pointer to its value.
void collectKeys(const json& j, const json::json_pointer& at,
                 std::vector<json::json_pointer>& out) {
    if (j.is_object()) {
        for (auto it = j.begin(); it != j.end(); ++it) {
            out.push_back(at / it.key());
            collectKeys(*it, at / it.key(), out);
        }
    } else if (j.is_array()) {
        for (size_t i = 0; i < j.size(); ++i) collectKeys(j[i], at / i, out);
    }
}

std::string readError(const json& j) {
    try {
        readBenchJson(j);
    } catch (const BenchJsonError& e) {
        return e.what();
    }
    return "(read without an error)";
}

TEST(BenchJson, ReadsBackWhatItWrites) {
    const json written = benchJson(sample());
    const BenchResults back = readBenchJson(written);
    EXPECT_EQ(benchJson(back), written);
    ASSERT_EQ(back.table1.size(), 2u);
    ASSERT_TRUE(back.table1[0].exact.render.has_value());
    EXPECT_EQ(back.table1[0].exact.render->answers.counts[5], 6u);
    EXPECT_EQ(back.table1[0].exact.render->overLimitAt[0], 7u);
    EXPECT_EQ(back.table1[0].exact.render->workAt.direct[2], 25u);
    ASSERT_TRUE(back.table1[0].exact.render->costEveryPointExact.has_value());
    EXPECT_EQ(back.table1[0].exact.render->costEveryPointExact->image, "--exact-cost-size");
    ASSERT_TRUE(back.table1[0].allPairs.has_value());
    EXPECT_EQ(back.table1[0].allPairs->fileBytes, 4096u);
    ASSERT_TRUE(back.table1[0].shadowEdges.has_value());
    EXPECT_EQ(back.table1[0].shadowEdges->keptOverLights, 2911u);
    ASSERT_TRUE(back.table1[0].exact.render->cost.lightEdges.has_value());
    EXPECT_EQ(back.table1[0].exact.render->cost.lightEdges->inCone, 8u);
    EXPECT_FALSE(back.table1[1].shadowEdges.has_value());  // a run written before S_L
    EXPECT_FALSE(back.table1[1].exact.render.has_value());
    EXPECT_FALSE(back.table1[1].speedup.has_value());
    EXPECT_FALSE(back.table1[1].allPairs.has_value());
    ASSERT_TRUE(back.table1[0].equalError.has_value());
    ASSERT_EQ(back.table1[0].equalError->searched.size(), 2u);
    EXPECT_EQ(back.table1[0].equalError->searched[1].rays, 4);
    ASSERT_TRUE(back.table1[0].equalError->found.has_value());
    EXPECT_EQ(back.table1[0].equalError->found->speedupWall, 0.5);
    EXPECT_FALSE(back.table1[1].equalError.has_value());  // a run written before the study
    EXPECT_TRUE(std::isnan(back.accuracy.study.equalErrorSeconds));
    EXPECT_EQ(back.predicates.cases[0].wrong[2], 3u);
    EXPECT_EQ(back.predicates.cases[0].otherCount[0], 4u);
    // What is absent is an absent key (scripts/plot_bench.py tests "renderWall" in a row's
    // "exact"), and an estimate the study could not make is null.
    EXPECT_FALSE(written["table1"][1]["exact"].contains("renderWall"));
    EXPECT_FALSE(written["table1"][1].contains("allPairs"));
    EXPECT_TRUE(written["table1"][0]["exact"].contains("renderWall"));
    EXPECT_TRUE(written["accuracy"]["equalErrorSeconds"].is_null());
    // (bench.json's keys as the report's readers and the tests know them.)
    EXPECT_EQ(written["table1"][0]["speedupWall"], 3.0);
    EXPECT_EQ(written["table1"][0]["exact"]["answers"]["counts"]["sampled"], 7);
    EXPECT_EQ(written["predicates"]["perCase"][0]["naiveWrong"], 3);
    EXPECT_EQ(written["predicates"]["cases"], 1);
}

TEST(BenchJson, EveryRenamedKeyStopsTheReading) {
    const json written = benchJson(sample());
    std::vector<json::json_pointer> keys;
    collectKeys(written, json::json_pointer(), keys);
    ASSERT_GT(keys.size(), 200u);
    for (const json::json_pointer& key : keys) {
        json renamed = written;
        json& parent = renamed[key.parent_pointer()];
        parent[key.back() + "_renamed"] = parent[key.back()];
        parent.erase(key.back());
        EXPECT_NE(readError(renamed).find("bench.json: "), std::string::npos) << key.to_string();
    }
}

// A bench.json from before the horizon-clipped answer (docs/bench/bench.json) still reads: its
// count is 0 there, the others as written; any other missing count stays an error.
TEST(BenchJson, AFileFromBeforeTheHorizonClippedAnswerStillReads) {
    json j = benchJson(sample());
    json& counts = j["table1"][0]["exact"]["answers"]["counts"];
    const uint64_t fully = counts["fully visible"];
    counts.erase("horizon-clipped");
    const BenchResults back = readBenchJson(j);
    const auto& c = back.table1[0].exact.render->answers.counts;
    EXPECT_EQ(c[static_cast<size_t>(Answer::HorizonClipped)], 0u);
    EXPECT_EQ(c[static_cast<size_t>(Answer::FullyVisible)], fully);
    counts.erase("fully visible");
    EXPECT_EQ(readError(j),
              "bench.json: table1[0].exact.answers.counts: missing \"fully visible\"");
}

// A bench.json from before the equal-error study still reads, the study absent; the report says
// in its place that it was not measured and why. Inside the study's object every key is required.
TEST(BenchJson, AFileFromBeforeTheEqualErrorStudyStillReads) {
    json j = benchJson(sample());
    j["table1"][0].erase("equalError");
    const BenchResults back = readBenchJson(j);
    EXPECT_FALSE(back.table1[0].equalError.has_value());
    const std::string report = benchReport(back, false, "--no-plots");
    EXPECT_NE(report.find("| 4.0 KB | - | - (not measured: this bench.json predates the "
                          "equal-error study) | - |"),
              std::string::npos)
        << report;
    EXPECT_NE(report.find("### At equal error\n\nNot measured: this bench.json predates the "
                          "equal-error study.\n"),
              std::string::npos)
        << report;
    j = benchJson(sample());
    j["table1"][0]["equalError"].erase("penumbraPixels");
    EXPECT_EQ(readError(j), "bench.json: table1[0].equalError: missing \"penumbraPixels\"");
}

// A bench.json from before the light-edge counts still reads, the counts absent, and the report
// leaves their table out; inside their object every key is required.
TEST(BenchJson, AFileFromBeforeTheLightEdgeCountsStillReads) {
    json j = benchJson(sample());
    ASSERT_NE(benchReport(readBenchJson(j), false, "--no-plots")
                  .find("### Edges examined per point against K"),
              std::string::npos);
    j["table1"][0]["exact"]["cost"].erase("lightEdges");
    const BenchResults back = readBenchJson(j);
    EXPECT_FALSE(back.table1[0].exact.render->cost.lightEdges.has_value());
    EXPECT_EQ(benchReport(back, false, "--no-plots").find("### Edges examined per point against K"),
              std::string::npos);
    j = benchJson(sample());
    j["table1"][0]["exact"]["cost"]["lightEdges"].erase("inCone");
    EXPECT_EQ(readError(j), "bench.json: table1[0].exact.cost.lightEdges: missing \"inCone\"");
}

TEST(BenchJson, AMissingKeyOrAWrongTypeNamesItsPlace) {
    json j = benchJson(sample());
    j["table1"][1]["exact"].erase("trees");
    EXPECT_EQ(readError(j), "bench.json: table1[1].exact: missing \"trees\"");
    j = benchJson(sample());
    j["perPoint"][0]["points"] = "200";
    EXPECT_EQ(readError(j), "bench.json: perPoint[0].points: expected a count");
    j = benchJson(sample());
    j["table1"][0]["exact"]["answers"]["counts"]["tree walk"] = -1;
    EXPECT_EQ(readError(j),
              "bench.json: table1[0].exact.answers.counts.tree walk: expected a count");
    j = benchJson(sample());
    j["predicates"]["cases"] = 2;
    EXPECT_EQ(readError(j), "bench.json: predicates.cases: 2, but 1 entries");
    j = benchJson(sample());
    j["table1"][0]["exact"]["renderWall"] = nullptr;
    EXPECT_EQ(readError(j), "bench.json: table1[0].exact.renderWall: expected a number");
}

// The report from the typed fields: the exact render's columns where the row has one, "-" where
// it has none (a precompute cut at the limit), and the dragon's all-pairs column skipped.
TEST(BenchReport, WritesTheRowsFromTheStructs) {
    const std::string report = benchReport(readBenchJson(benchJson(sample())), false, "--no-plots");
    EXPECT_NE(
        report.find("| table.json | 1348 | 64x64, 2 spp | 1.50 / 2.50 | 0.25 / 0.00 | "
                    "0.50 / 0.00 | 3.00x (5.00x) | 22 (10) | 0 | 10.0% | 0.75 / 1.50 | 2.0 KB | "
                    "0.50 / 1.00 | 4.0 KB |"),
        std::string::npos)
        << report;
    EXPECT_NE(report.find("| dragon.json | 871414 | 16x16, 1 spp | 0.00 / 0.00 | 20.00 / 0.00 "
                          "(over the limit) | - | - | 3 (0) | - | - | - | 0.0 KB | skipped | - |"),
              std::string::npos)
        << report;
    EXPECT_NE(report.find("| table.json | 3181 | 2316 | 25.0-50.0% | 0.125 |"), std::string::npos)
        << report;
    // The light-edge path's 4 evaluations: 36 edges examined, 10 of nonzero weight, 8 in the cone,
    // per evaluation 9, 2.5 and 2; examined over K 36 / 8.
    EXPECT_NE(report.find("| table.json | 4 | 9.0 | 2.5 | 2.0 | 4.5x |\n"), std::string::npos)
        << report;
    // Table 1's last columns: every point exact (0.5 s wall, 0.75 CPU), the sampled render at
    // equal error (4 rays, 0.25 / 0.5) and the speed-up 0.25 / 0.5; the dragon has none.
    EXPECT_NE(report.find("| 4.0 KB | 0.50 / 0.75 | 4 rays, 0.25 / 0.50 | 0.50x |\n"),
              std::string::npos)
        << report;
    EXPECT_NE(report.find("| 0.0 KB | skipped | - | - | - (not measured: this bench.json "
                          "predates the equal-error study) | - |\n"),
              std::string::npos)
        << report;
    EXPECT_NE(report.find("| table.json | 64x64, 2 spp | 300 of 4096 | 0.25 | 0.50 / 0.75 (0.12) "
                          "| 0.5% | 4 | 0.25 / 0.50 | 0.400% | 0.50x (0.67x) | 1 (50.000%), 4 "
                          "(0.400%) |"),
              std::string::npos)
        << report;
    EXPECT_NE(report.find("| dragon.json | - | - | - | - | - | - (not measured: this bench.json "
                          "predates the equal-error study) | - | - | - | - |"),
              std::string::npos)
        << report;
    EXPECT_NE(report.find("- at equal error (0.5% relative RMSE over the penumbra pixels; every "
                          "point exact, precompute included, against stratified sampling): "
                          "table.json 0.50x (4 rays)."),
              std::string::npos)
        << report;
    // The accuracy study without an equal-error estimate leaves its sentence out.
    EXPECT_EQ(report.find("**Equal error:**"), std::string::npos) << report;
    EXPECT_NE(report.find("Per case (naive wrong / naive other count / filtered other count): "
                          "sliver 3/6/4; "),
              std::string::npos)
        << report;
    EXPECT_NE(report.find("| stairs.json | 0 | 0 | 0 | - | 0 | 0 | 0 | 0 | 0.00 | 0.00 | 0 of 0 | "
                          "25.0% | 0 |"),
              std::string::npos)
        << report;
    EXPECT_NE(report.find("Skipped because files they need are missing (run "
                          "`scripts/fetch_meshes.sh` to fetch the meshes): dragon_res3.json "
                          "(missing assets/external/x.ply)."),
              std::string::npos)
        << report;
    EXPECT_NE(report.find("Plots skipped: --no-plots"), std::string::npos) << report;
}

}  // namespace
}  // namespace penumbra::cli
