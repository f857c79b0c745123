// The bench's report (app/cli/bench/bench_report.h) from results made up by hand: the conclusion
// at its top, with figures worked out here and found again in its own tables; a quick run's
// first line; the medians that are not order statistics of every timed evaluation, marked.
#include "app/cli/bench/bench_report.h"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <iterator>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

#include "tests/app/cli/bench/report_check.h"

#ifndef PENUMBRA_SOURCE_DIR
#error "PENUMBRA_SOURCE_DIR must name the source tree"
#endif

namespace penumbra::cli {
namespace {

// A Table 1 row: the sampled render's wall time against the exact precompute and render's.
Table1Row row(const std::string& scene, double sampledWall, double exactWall,
              uint64_t sampledEvaluations) {
    Table1Row r;
    r.scene = "assets/scenes/" + scene;
    r.faces = 100;
    r.areaLights = 1;
    r.width = r.height = 64;
    r.spp = 2;
    r.sampled128.wall = sampledWall;
    r.sampled128.cpu = 2 * sampledWall;
    r.exact.precomputeComplete = true;
    r.exact.precomputeWall = exactWall / 4;
    ExactRender e;
    e.renderWall = exactWall - exactWall / 4;
    e.wall = exactWall;
    e.evaluations = 1000;
    e.sampledEvaluations = sampledEvaluations;
    e.answers.image = "answers.png";
    r.exact.render = e;
    r.speedup = Speedups{sampledWall / exactWall, 1, sampledWall / e.renderWall, 1};
    return r;
}

// Three scenes with an exact render, exact faster on two (12.9 / 1 and 3 / 1.5) and slower on
// one (1 / 2), which sampled 100 of its 1000 evaluations; a fourth whose precompute was cut.
// The error-against-time study: 1, 2 and 4 rays in 0.010, 0.020 and 0.040 s against the exact
// image's 0.030 s, and sampling at the exact image's error in 0.8 s.
BenchResults results() {
    BenchResults b;
    b.machine = {"a CPU", 2, "0.5", "2026-01-01 00:00:00 UTC", "Release"};
    b.command = "penumbra bench --out DIR";
    b.options = {"64x64", "256x256", 2, false, false, 180, "128x128"};
    Table1Row cut;
    cut.scene = "assets/scenes/dragon.json";
    cut.exact.precomputeWall = 180;
    b.table1 = {row("stairs.json", 12.9, 1, 0), row("table.json", 1, 2, 100),
                row("cornell_box.json", 3, 1.5, 0), cut};
    // Sampling at equal error on the stairs: 144 rays in 2.5 s against 0.5 s every point exact.
    EqualErrorRun equal;
    equal.target = 0.005;
    equal.exactComplete = true;
    equal.exactWall = 0.5;
    equal.searched = {{144, 2.5, 5, 0.0049}};
    equal.found = EqualErrorFound{144, 2.5, 5, 0.0049, 5, 5};
    b.table1[0].equalError = equal;
    AccuracyStudy& a = b.accuracy.study;
    b.accuracy.scene = "assets/scenes/cornell_box.json";
    a.sampled = {{"sampled", 1, 0.010, 0.02, 0, 0.1, 0.5},
                 {"sampled", 2, 0.020, 0.04, 0, 0.05, 0.25},
                 {"sampled", 4, 0.040, 0.08, 0, 0.025, 0.1}};
    a.exact = {"exact", 0, 0.030, 0.05, 0.01, 0.001, 0.01};
    a.equalErrorSeconds = 0.8;
    a.equalErrorRays = 200;
    a.equalErrorExtrapolated = true;
    b.predicates.modes[0].mode = "filtered";
    b.predicates.modes[1].mode = "alwaysExact";
    b.predicates.modes[2].mode = "naive";
    return b;
}

std::string firstLine(const std::string& text) { return text.substr(0, text.find('\n')); }

TEST(BenchReport, OpensWithAConclusionThatItsTablesBearOut) {
    const std::string report = benchReport(results(), false, "--no-plots");
    const std::string top = test::reportSection(report, "## In short");
    ASSERT_FALSE(top.empty()) << report;
    EXPECT_EQ(report.rfind("# Penumbra: what accuracy costs in time\n\n## In short\n", 0), 0u)
        << report;
    // Short: at most 12 lines of text.
    std::istringstream lines(top);
    int text = 0;
    for (std::string line; std::getline(lines, line);) text += !line.empty();
    EXPECT_LE(text, 12) << top;
    // The figures, worked out by hand: 12.9 / 1, 3 / 1.5, 1 / 2 and its inverse; 100 of 1000.
    EXPECT_NE(top.find("- exact faster on 2 of 4 scenes: stairs.json 12.90x, cornell_box.json "
                       "2.00x.\n"),
              std::string::npos)
        << top;
    EXPECT_NE(top.find("- exact slower on 1 of 4 scenes: table.json 0.50x (sampling 2.00x "
                       "faster).\n"),
              std::string::npos)
        << top;
    EXPECT_NE(top.find("- no exact render (precompute over the 180 s limit): dragon.json.\n"),
              std::string::npos)
        << top;
    EXPECT_NE(top.find("table.json 10.0% of the evaluations that needed a query"),
              std::string::npos)
        << top;
    // Equal error: 0.8 s against 0.030 s, 26.67x; equal time: within 0.030 s, 2 rays (0.020 s),
    // RMSE 0.05 against the exact image's 0.001, 50x.
    EXPECT_NE(top.find("at about 200 rays per light and 0.800 s wall, against 0.030 s exact: "
                       "exact 26.67x, extrapolated beyond the measured curve."),
              std::string::npos)
        << top;
    EXPECT_NE(top.find("sampling affords 2 rays per light (0.020 s), whose RMSE against the "
                       "exact image, 0.05, is 50.0x"),
              std::string::npos)
        << top;
    EXPECT_NE(top.find("point exact, precompute included, against stratified sampling): "
                       "stairs.json 5.00x (144 rays).\n"),
              std::string::npos)
        << top;
    // And the same figures in the tables below.
    int checked = 0;
    const std::vector<std::string> wrong = test::conclusionAgainstTables(report, checked);
    EXPECT_TRUE(wrong.empty()) << ::testing::PrintToString(wrong) << "\n" << report;
    EXPECT_GE(checked, 15);
}

// The committed report (docs/bench/report.md, written by the bench and then given its notes by
// hand): its conclusion, too, is what its tables say.
TEST(BenchReport, TheCommittedReportsConclusionAgreesWithItsTables) {
    std::ifstream in(std::string(PENUMBRA_SOURCE_DIR) + "/docs/bench/report.md");
    ASSERT_TRUE(in) << "docs/bench/report.md";
    const std::string report{std::istreambuf_iterator<char>(in), {}};
    int checked = 0;
    const std::vector<std::string> wrong = test::conclusionAgainstTables(report, checked);
    EXPECT_TRUE(wrong.empty()) << ::testing::PrintToString(wrong);
    EXPECT_GE(checked, 20);
}

TEST(BenchReport, TheCheckOfTheConclusionFindsAFigureTheTableDoesNotHave) {
    // The same report with one Table 1 speed-up and one RMSE of the accuracy table changed.
    std::string report = benchReport(results(), false, "--no-plots");
    auto change = [&](const std::string& from, const std::string& to) {
        const size_t at = report.find(from);
        ASSERT_NE(at, std::string::npos) << from;
        report.replace(at, from.size(), to);
    };
    change("| 12.90x (", "| 12.80x (");
    change("| sampled vs exact | 2 | 0.020 | 0.040 | 0.05 |",
           "| sampled vs exact | 2 | 0.020 | 0.040 | 0.06 |");
    change("| 144 rays, 2.50 / 5.00 | 5.00x |", "| 144 rays, 2.50 / 5.00 | 5.10x |");
    int checked = 0;
    const std::vector<std::string> wrong = test::conclusionAgainstTables(report, checked);
    ASSERT_EQ(wrong.size(), 4u) << ::testing::PrintToString(wrong);
    EXPECT_NE(wrong[0].find("stairs.json speed-up"), std::string::npos) << wrong[0];
    EXPECT_NE(wrong[1].find("stairs.json speed-up at equal error"), std::string::npos) << wrong[1];
    EXPECT_NE(wrong[2].find("equal time: RMSE"), std::string::npos) << wrong[2];
    EXPECT_NE(wrong[3].find("equal time: 50.0x"), std::string::npos) << wrong[3];
}

TEST(BenchReport, WithoutAnEqualErrorFigureSaysSo) {
    BenchResults b = results();
    b.accuracy.study.equalErrorSeconds = std::numeric_limits<double>::quiet_NaN();
    b.accuracy.study.equalErrorRays = std::numeric_limits<double>::quiet_NaN();
    // Every sampled render slower than the exact image: no equal-time figure either.
    for (AccuracyPoint& p : b.accuracy.study.sampled) p.seconds += 1;
    const std::string top = test::reportSection(benchReport(b, false, "-"), "## In short");
    EXPECT_NE(top.find("**At equal error**: no figure."), std::string::npos) << top;
    EXPECT_NE(top.find("no sampled render is as fast as the exact image's 0.030 s: 1 ray per "
                       "light took 1.010 s."),
              std::string::npos)
        << top;
    EXPECT_EQ(top.find("sampling reaches"), std::string::npos) << top;
}

TEST(BenchReport, AQuickRunSaysOnItsFirstLineThatItIsNotForConclusions) {
    BenchResults b = results();
    EXPECT_EQ(firstLine(benchReport(b, false, "-")), "# Penumbra: what accuracy costs in time");
    b.options.quick = true;
    b.options.limit = 20;
    EXPECT_EQ(firstLine(benchReport(b, false, "-")),
              "> **Quick run (--quick): 64x64 images at 2 spp and a 20 s limit, sizes for CI and "
              "smoke tests, not for conclusions: run the bench without --quick for figures to "
              "compare.**");
}

TEST(BenchReport, MarksTheMediansThatAreNotOrderStatisticsOfEveryTimedEvaluation) {
    BenchResults b = results();
    ExactRender& e = *b.table1[0].exact.render;
    e.cost.times.evaluations = 10;
    e.cost.times.medianUs = 1.125;
    e.cost.times.p99Us = 25.25;
    const std::string plain = benchReport(b, false, "-");
    EXPECT_NE(plain.find("| stairs.json | 10 | 1.12 | 25.25 | 0.00 |"), std::string::npos) << plain;
    EXPECT_EQ(plain.find("†"), std::string::npos);
    EXPECT_EQ(plain.find("(1 in "), std::string::npos);
    // A subsample of one in 4, and a bench.json of the log-histogram days.
    e.cost.times.quantileStride = 4;
    b.table1[2].exact.render->cost.times.quantileStride = kHistogramQuantiles;
    const std::string marked = benchReport(b, false, "-");
    EXPECT_NE(marked.find("| stairs.json | 10 | 1.12 (1 in 4) | 25.25 (1 in 4) | 0.00 |"),
              std::string::npos)
        << marked;
    EXPECT_NE(marked.find("| cornell_box.json | 0 | 0.00 † | 0.00 † |"), std::string::npos)
        << marked;
    EXPECT_NE(marked.find("† Not an order statistic: the middle of a log-histogram bucket"),
              std::string::npos)
        << marked;
    EXPECT_NE(marked.find("(1 in N): the order statistic of one timed evaluation in N"),
              std::string::npos)
        << marked;
}

TEST(BenchReport, NamesNoInternalClass) {
    const std::string report = benchReport(results(), false, "-");
    for (const char* name :
         {"::", "RenderSettings", "BuildOptions", "VisibilityStore", "ProgressiveRenderer",
          "PrecomputeScheduler", "FPQuery", "FromPoint", "ChainOptions", "DeferredSilhouettes",
          "makeHardCases", "alwaysExact", "WorkStage", "engine/", ".h`"})
        EXPECT_EQ(report.find(name), std::string::npos) << name;
}

}  // namespace
}  // namespace penumbra::cli
