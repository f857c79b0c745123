// Tests of `penumbra bench`, run as a real process (PENUMBRA_EXE) on a copy of the committed assets
// without the meshes scripts/fetch_meshes.sh downloads: what a fresh clone gets, whether or not
// this checkout has fetched them (the bench finds its default scenes relative to the current
// directory, so it runs in the copy).
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "engine/io/obj_io.h"
#include "engine/scene/procedural_scenes.h"
#include "tests/app/cli/bench/report_check.h"
#include "tests/app/viewer/viewer_test_support.h"
#include "tests/support/run_penumbra.h"
#include "tests/support/test_files.h"

#ifndef PENUMBRA_SOURCE_DIR
#error "PENUMBRA_SOURCE_DIR must name the source tree"
#endif

namespace {

namespace fs = std::filesystem;

using penumbra::test::ProcessResult;

using penumbra::test::readFile;

// The smallest run the command allows without --quick (which has no scaling study nor the
// per-point cost with every point exact), on `scene`, then `extra`. Its --limit (seconds) cuts the
// all-pairs precomputes short (Table 1's and the build options', 4-5 s each under the sanitizers)
// where a test does not read them. Table 1's exact render runs only if the precompute of the trees
// its image needs finishes within the limit too: stairs builds no tree there, but a machine loaded
// far beyond its cores once took over a second for it, so a test that reads that render gives it
// `limit` 10 (stairs' all-pairs precomputes then finish, in about a second each).
std::vector<std::string> smallestBench(const std::string& scene, const fs::path& out,
                                       const std::vector<std::string>& extra,
                                       const std::string& limit = "1") {
    std::vector<std::string> args = {"bench",
                                     scene,
                                     "--out",
                                     out.string(),
                                     "--size",
                                     "8x8",
                                     "--spp",
                                     "1",
                                     "--accuracy-size",
                                     "8x8",
                                     "--accuracy-spp",
                                     "1",
                                     "--max-rays",
                                     "1",
                                     "--reference-rays",
                                     "1",
                                     "--points",
                                     "1",
                                     "--limit",
                                     limit,
                                     "--no-plots"};
    args.insert(args.end(), extra.begin(), extra.end());
    return args;
}

class BenchCommand : public ::testing::Test {
  protected:
    void SetUp() override {
        root_ = fs::temp_directory_path() /
                ("penumbra_bench_cmd_" + std::to_string(::getpid()) + "_" +
                 ::testing::UnitTest::GetInstance()->current_test_info()->name());
        fs::remove_all(root_);
        fs::create_directories(root_ / "assets");
        // Everything committed under assets/, not what fetch_meshes.sh put in assets/external/.
        for (const fs::directory_entry& e :
             fs::directory_iterator(fs::path(PENUMBRA_SOURCE_DIR) / "assets")) {
            if (e.path().filename() == "external") continue;
            fs::copy(e.path(), root_ / "assets" / e.path().filename(), fs::copy_options::recursive);
        }
    }
    void TearDown() override { fs::remove_all(root_); }
    fs::path root_;
};

TEST_F(BenchCommand, SkipsTheScalingRowsWhoseMeshesAreMissing) {
    ASSERT_TRUE(fs::exists(root_ / "assets/scenes/dragon_res4.json"));
    ASSERT_FALSE(fs::exists(root_ / "assets/external"));
    const fs::path out = root_ / "out";
    const ProcessResult r =
        penumbra::test::runPenumbra(smallestBench("assets/stairs.obj", out, {}, "10"), root_);
    ASSERT_EQ(r.exitCode, 0) << r.out << r.err;
    EXPECT_NE(r.err.find("scaling: assets/scenes/dragon_res4.json skipped, missing "
                         "assets/external/dragon_vrip_res4.ply"),
              std::string::npos)
        << r.err;
    EXPECT_NE(r.err.find("scripts/fetch_meshes.sh"), std::string::npos) << r.err;

    ASSERT_TRUE(fs::exists(out / "report.md"));
    const std::string report = readFile(out / "report.md");
    const size_t scaling = report.find("## Precompute against triangle count");
    ASSERT_NE(scaling, std::string::npos) << report;
    const std::string section = report.substr(scaling, report.find("\n## ", scaling) - scaling);
    EXPECT_NE(section.find("Skipped because files they need are missing (run "
                           "`scripts/fetch_meshes.sh` to fetch the meshes)"),
              std::string::npos)
        << section;
    for (const char* mesh : {"dragon_vrip_res4.ply", "dragon_vrip_res3.ply", "dragon_vrip_res2.ply",
                             "dragon_vrip.ply"})
        EXPECT_NE(section.find(std::string("(missing assets/external/") + mesh + ")"),
                  std::string::npos)
            << mesh << "\n"
            << section;
    EXPECT_EQ(section.find("| scene |"), std::string::npos) << "no rows: " << section;

    // The per-point section: the cost distribution and the viewer's click, for the one point.
    const nlohmann::json bench = nlohmann::json::parse(readFile(out / "bench.json"));
    ASSERT_EQ(bench.at("perPoint").size(), 1u);
    const nlohmann::json& p = bench.at("perPoint").at(0);
    EXPECT_LE(p.at("exactMedianUs").get<double>(), p.at("exactP99Us").get<double>());
    EXPECT_LE(p.at("exactP99Us").get<double>(), p.at("exactMaxUs").get<double>());
    EXPECT_GT(p.at("exactMaxUs").get<double>(), 0.0);
    // The visible region's boundary of that point's fragments: never more edges than they
    // have, and at least one loop where the point sees some of the light.
    const nlohmann::json& outline = p.at("outline");
    EXPECT_LE(outline.at("edges").get<double>(), outline.at("fragmentEdges").get<double>());
    EXPECT_EQ(outline.at("loops").get<double>() > 0, p.at("fragmentsPerQuery").get<double>() > 0);
    EXPECT_GT(outline.at("outlineUs").get<double>(), 0.0);
    EXPECT_NE(report.find("| scene | fragments | their edges | boundary loops | boundary edges |"),
              std::string::npos)
        << report;
    const nlohmann::json& click = p.at("click");
    EXPECT_EQ(click.at("points"), 1);
    EXPECT_EQ(click.at("treePoints"), 1);
    EXPECT_EQ(click.at("overBudget"), 0);  // stairs is far below the click's work budget
    EXPECT_GT(click.at("fragmentsMedianMs").get<double>(), 0.0);
    EXPECT_GT(click.at("withTreesMedianMs").get<double>(), 0.0);
    // Table 1's renders timed per evaluation: the sampled render's points (8x8, 1 spp: at most
    // 64 shaded) and the exact render's evaluations, each distribution ordered.
    ASSERT_EQ(bench.at("table1").size(), 1u);
    const nlohmann::json& row = bench.at("table1").at(0);
    EXPECT_GT(row.at("sampled128").at("points").get<uint64_t>(), 0u);
    EXPECT_LE(row.at("sampled128").at("points").get<uint64_t>(), 64u);
    EXPECT_LE(row.at("sampled128").at("pointMedianUs").get<double>(),
              row.at("sampled128").at("pointP99Us").get<double>());
    const nlohmann::json& cost = row.at("exact").at("cost");
    EXPECT_LE(cost.at("evaluations").get<uint64_t>(),
              row.at("exact").at("evaluations").get<uint64_t>());
    EXPECT_LE(cost.at("medianUs").get<double>(), cost.at("p99Us").get<double>());
    EXPECT_NE(report.find("### Cost per evaluation"), std::string::npos) << report;
    // Where the evaluations' time went: nothing sampled, so no rays and no stopped query, and
    // the exact answers' estimate is the timed ones' mean times their count times 8.
    const nlohmann::json& split = cost.at("timeSplit");
    EXPECT_EQ(split.at("raysSeconds").get<double>(), 0.0);
    EXPECT_EQ(split.at("attemptSeconds").get<double>(), 0.0);
    EXPECT_NEAR(split.at("exactSeconds").get<double>(),
                cost.at("meanUs").get<double>() * 1e-6 * cost.at("evaluations").get<double>() * 8,
                1e-9);
    EXPECT_NE(report.find("| stairs.obj | 0.0% | 100.0% | 0.0% | 0.0% |"), std::string::npos)
        << report;
    // Nothing was sampled: the per-point cost with every point exact is this render's own.
    const nlohmann::json& every = row.at("exact").at("costEveryPointExact");
    EXPECT_EQ(every.at("evaluations"), cost.at("evaluations"));
    EXPECT_EQ(every.at("medianUs"), cost.at("medianUs"));
    EXPECT_EQ(every.at("chainEvaluations"), cost.at("chainEvaluations"));
    EXPECT_EQ(every.at("chainCells"), cost.at("chainCells"));
    EXPECT_EQ(every.at("image"), "Table 1's image");
    EXPECT_TRUE(every.at("complete").get<bool>());
    const size_t goals = report.find("### Per-point cost with every point exact");
    ASSERT_NE(goals, std::string::npos) << report;
    EXPECT_NE(report.find("| stairs.obj | 8x8, 1 spp (Table 1's image) |", goals),
              std::string::npos)
        << report.substr(goals);
    EXPECT_NE(report.find("| by the chain | chain edges | cells | fragments |", goals),
              std::string::npos)
        << report.substr(goals);
    const size_t clicks = report.find("### A click in the viewer");
    ASSERT_NE(clicks, std::string::npos) << report;
    EXPECT_NE(report.find("| stairs.obj | 1 |", clicks), std::string::npos) << report;
    // The conclusion at the top: exact against sampling on the one scene, faster or slower as
    // Table 1 has it, and at equal error and equal time as the error-against-time study has it.
    EXPECT_EQ(report.rfind("# Penumbra: what accuracy costs in time\n\n## In short\n", 0), 0u)
        << report;
    int checked = 0;
    const std::vector<std::string> wrong = penumbra::test::conclusionAgainstTables(report, checked);
    EXPECT_TRUE(wrong.empty()) << ::testing::PrintToString(wrong) << "\n" << report;
    EXPECT_GE(checked, 4) << report;
    // The timed evaluations' medians: order statistics of every one (a few dozen here).
    EXPECT_EQ(cost.at("quantileStride"), 1);
    EXPECT_EQ(row.at("sampled128").at("pointQuantileStride"), 1);
    EXPECT_EQ(report.find("†"), std::string::npos) << report;
    // Written again from bench.json, measuring nothing: the same report, but for the plots' line.
    fs::remove(out / "report.md");
    const ProcessResult again =
        penumbra::test::runPenumbra({"bench", "--out", out.string(), "--report-only"}, root_);
    ASSERT_EQ(again.exitCode, 0) << again.out << again.err;
    const std::string rewritten = readFile(out / "report.md");
    const size_t plots = report.rfind("Plots skipped: ");
    ASSERT_NE(plots, std::string::npos) << report;
    EXPECT_EQ(rewritten.substr(0, plots), report.substr(0, plots));
    EXPECT_EQ(rewritten.substr(plots),
              "Plots skipped: table1.png or accuracy.png not in " + out.string() + "\n");
    EXPECT_EQ(again.out.find("table1 "), std::string::npos) << again.out;  // nothing measured
}

TEST_F(BenchCommand, ReportOnlyRefusesABenchJsonItDidNotWrite) {
    const fs::path out = root_ / "out";
    fs::create_directories(out);
    std::ofstream(out / "bench.json") << R"({"machine": {}})";
    const ProcessResult r =
        penumbra::test::runPenumbra({"bench", "--out", out.string(), "--report-only"}, root_);
    EXPECT_EQ(r.exitCode, 1) << r.out << r.err;
    EXPECT_NE(r.err.find("bench.json: machine: missing \"cpu\""), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(out / "report.md"));
    fs::remove(out / "bench.json");
    const ProcessResult none =
        penumbra::test::runPenumbra({"bench", "--out", out.string(), "--report-only"}, root_);
    EXPECT_EQ(none.exitCode, 1) << none.out << none.err;
    EXPECT_NE(none.err.find("bench.json: cannot read file"), std::string::npos) << none.err;
}

TEST_F(BenchCommand, AQuickRunSaysFirstThatItsSizesAreNotForConclusions) {
    // --quick with the smallest sizes given (they override its own): its first line on stderr
    // and in the report says what its figures are for.
    const fs::path out = root_ / "out";
    const ProcessResult r =
        penumbra::test::runPenumbra(smallestBench("assets/stairs.obj", out, {"--quick"}), root_);
    ASSERT_EQ(r.exitCode, 0) << r.out << r.err;
    const std::string note =
        "Quick run (--quick): 8x8 images at 1 spp and a 1 s limit, sizes for CI and smoke tests, "
        "not for conclusions: run the bench without --quick for figures to compare.";
    EXPECT_EQ(r.err.substr(0, r.err.find('\n')), "penumbra bench: " + note) << r.err;
    const std::string report = readFile(out / "report.md");
    EXPECT_EQ(report.substr(0, report.find('\n')), "> **" + note + "**") << report;
    int checked = 0;
    EXPECT_TRUE(penumbra::test::conclusionAgainstTables(report, checked).empty()) << report;
}

TEST_F(BenchCommand, MeasuresEveryPointExactOnASmallerImageAboveTheAllPairsSize) {
    // 12000 random triangles between a floor and a light: above the bench's all-pairs size
    // (10000 faces), and every floor point's pyramid holds thousands of them, so the render's
    // points go over the work limit (sampled: no light-edge path after it here) and the
    // per-point cost with every point exact comes from a render of --exact-cost-size at 1 spp,
    // cut at --limit where it takes longer.
    const fs::path scene = root_ / "soup.obj";
    penumbra::writeObj(penumbra::makeRandomSoup(12000, 3), scene);
    const fs::path out = root_ / "out";
    const ProcessResult r = penumbra::test::runPenumbra(
        smallestBench(scene.string(), out,
                      {"--exact-cost-size", "6x5", "--light-edge-work-limit", "0"}),
        root_);
    ASSERT_EQ(r.exitCode, 0) << r.out << r.err;
    const nlohmann::json bench = nlohmann::json::parse(readFile(out / "bench.json"));
    ASSERT_EQ(bench.at("table1").size(), 1u);
    const nlohmann::json& e = bench.at("table1").at(0).at("exact");
    ASSERT_GT(e.at("sampledEvaluations").get<uint64_t>(), 0u) << e.dump(1);
    EXPECT_FALSE(e.contains("everyPointExact"));  // (the small scenes' full-image render)
    // How each pixel was answered: the sampled ones are the evaluations the summary sampled; the
    // queried ones (tree walk, direct, chain, light-edge path, sampled) are all that needed a
    // query, but for the direct points that the pair's first signs left without light (no
    // light).
    const nlohmann::json& answers = e.at("answers").at("counts");
    EXPECT_EQ(answers.at("sampled"), e.at("sampledEvaluations")) << answers;
    const uint64_t queried =
        answers.at("tree walk").get<uint64_t>() + answers.at("direct").get<uint64_t>() +
        answers.at("boundary chain").get<uint64_t>() +
        answers.at("light-edge path").get<uint64_t>() + answers.at("sampled").get<uint64_t>();
    EXPECT_LE(queried, e.at("evaluations").get<uint64_t>()) << answers;
    EXPECT_LE(e.at("evaluations").get<uint64_t>(), queried + answers.at("no light").get<uint64_t>())
        << answers;
    EXPECT_EQ(e.at("answers").at("image"), "answers_soup.png");
    EXPECT_NE(r.out.find("  answers (answers_soup.png): fully visible (yellow) "),
              std::string::npos)
        << r.out;
    const penumbra::test::Image map = penumbra::test::readPng(out / "answers_soup.png");
    EXPECT_EQ(map.width, bench.at("table1").at(0).at("width").get<int>());
    EXPECT_EQ(map.height, bench.at("table1").at(0).at("height").get<int>());
    const nlohmann::json& every = e.at("costEveryPointExact");
    EXPECT_EQ(every.at("image"), "--exact-cost-size");
    EXPECT_EQ(every.at("width"), 6);
    EXPECT_EQ(every.at("height"), 5);
    EXPECT_EQ(every.at("spp"), 1);
    // One evaluation in 8 is timed: of 30 pixels and one light, at most 4.
    EXPECT_LE(every.at("evaluations").get<uint64_t>(), 30u / 8 + 1);
    const std::string report = readFile(out / "report.md");
    EXPECT_NE(report.find("### How each evaluation was answered"), std::string::npos) << report;
    EXPECT_NE(report.find("<img src=\"answers_soup.png\""), std::string::npos) << report;
    const size_t goals = report.find("### Per-point cost with every point exact");
    ASSERT_NE(goals, std::string::npos) << report;
    EXPECT_NE(report.find(std::string("| soup.obj | 6x5, 1 spp (--exact-cost-size") +
                              (every.at("complete").get<bool>() ? ")" : "; cut at the limit)"),
                          goals),
              std::string::npos)
        << report.substr(goals);
}

TEST_F(BenchCommand, BadSizesAreUsageErrorsBeforeAnyMeasuring) {
    for (const char* flag : {"--size", "--large-size", "--accuracy-size", "--exact-cost-size"}) {
        const ProcessResult r = penumbra::test::runPenumbra(
            {"bench", "assets/stairs.obj", "--out", (root_ / "out").string(), flag, "0x8"}, root_);
        EXPECT_EQ(r.exitCode, 2) << flag << "\n" << r.out << r.err;
        EXPECT_NE(r.err.find(flag), std::string::npos) << r.err;
        EXPECT_EQ(r.out.find("table1"), std::string::npos) << flag << ": measured first\n" << r.out;
    }
}

}  // namespace
