// `penumbra render` across the ranks of an MPI job, run as the user would:
// `mpirun --allow-run-as-root --oversubscribe -np 3 penumbra render ...` as a child process under
// a timeout (tests/support/mpi_job.h). Skipped, saying why, in a build without MPI.
//
// What is checked: the image 3 ranks write is bit for bit the one a single process writes (the
// PFM's bytes), and the effects summary holds the same numbers, on two committed scenes (the
// Cornell box with a tree for every pair seen and a small build budget: partial trees; the table
// at a small size with the defaults: light-edge answers, over-limit cells carried from pass to
// pass); the trees were built once each, spread over
// the ranks, as were the tiles; an option that cannot work across ranks is refused once; a rank
// killed in the middle ends the job within seconds with rank 0's error naming it.
#include <gtest/gtest.h>
#include <signal.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <sstream>
#include <string>
#include <vector>

#include "tests/support/mpi_job.h"
#include "tests/support/run_penumbra.h"
#include "tests/support/test_files.h"

namespace penumbra {
namespace cluster_render_test {

namespace fs = std::filesystem;
using test::ProcessResult;
using test::readFile;
using test::runPenumbra;

fs::path scenePath(const std::string& name) { return fs::path(PENUMBRA_SOURCE_DIR) / name; }

// The effects summary's lines (stdout after "effects:"), less those that hold times: the same
// numbers for one process and for any number of ranks.
std::string effectCounts(const std::string& out) {
    const size_t at = out.find("effects:\n");
    if (at == std::string::npos) return "";
    std::istringstream in(out.substr(at));
    std::string line, kept;
    while (std::getline(in, line)) {
        if (line.rfind("wrote ", 0) == 0) break;
        const bool timed =
            line.find(" s ") != std::string::npos || line.find(" s)") != std::string::npos ||
            line.find(" s,") != std::string::npos || line.find(" us") != std::string::npos ||
            line.find(" ms") != std::string::npos || line.find(" ns") != std::string::npos ||
            line.find("CPU") != std::string::npos;
        if (!timed) kept += line + '\n';
    }
    return kept;
}

// The numbers after "rank 0 ", "1 ", "2 " that follow `label` in `out` ("trees built by rank",
// "tiles shaded by rank").
std::vector<size_t> perRank(const std::string& out, const std::string& label) {
    std::vector<size_t> n(3, 0);
    const size_t at = out.find(label + " 0 ");
    if (at == std::string::npos || std::sscanf(out.c_str() + at + label.size(),
                                               " 0 %zu, 1 %zu, 2 %zu", &n[0], &n[1], &n[2]) != 3)
        return {};
    return n;
}

// The trees in the store after the render (the summary's "time: precompute S s (N trees").
size_t treesIn(const std::string& out) {
    size_t trees = 0;
    const size_t at = out.find("time: precompute ");
    if (at == std::string::npos ||
        std::sscanf(out.c_str() + at, "time: precompute %*f s (%zu trees", &trees) != 1)
        ADD_FAILURE() << "no tree count in: " << out;
    return trees;
}

class ClusterRender : public test::MpiJobTest {};

TEST_F(ClusterRender, ThreeRanksWriteTheImageOfOneProcess) {
    SKIP_WITHOUT_MPI();
    const std::vector<std::vector<std::string>> cases = {
        {scenePath("assets/cornell_box.obj").string(), "--size", "48x48", "--spp", "3",
         "--max-lp-solves", "40", "--min-tree-samples", "0"},
        {scenePath("assets/scenes/table.json").string(), "--size", "40x40", "--spp", "2"},
    };
    for (const auto& args : cases) {
        std::vector<std::string> one = {"render"};
        one.insert(one.end(), args.begin(), args.end());
        one.insert(one.end(), {"--out", (dir_ / "one.pfm").string()});
        const ProcessResult single = runPenumbra(one);
        ASSERT_EQ(single.exitCode, 0) << single.err;

        std::vector<std::string> three = {"render"};
        three.insert(three.end(), args.begin(), args.end());
        three.insert(three.end(), {"--out", (dir_ / "three.pfm").string(), "--threads", "1"});
        const ProcessResult r = mpirun(3, three);
        ASSERT_EQ(r.exitCode, 0) << r.err << r.out;

        const std::string a = readFile(dir_ / "one.pfm"), b = readFile(dir_ / "three.pfm");
        ASSERT_GT(a.size(), 48u * 48u) << args[0];
        EXPECT_TRUE(a == b) << args[0] << ": the images differ";
        const std::string counts = effectCounts(single.out);
        EXPECT_NE(counts.find("pairs with a tree"), std::string::npos) << single.out;
        EXPECT_EQ(counts, effectCounts(r.out)) << args[0];
        // The trees the image needed: the same count.
        const size_t trees = treesIn(single.out);
        EXPECT_EQ(trees, treesIn(r.out)) << r.out;

        // Each tree built once, by some rank; every rank shaded tiles.
        EXPECT_NE(r.out.find("(0 built twice)"), std::string::npos) << r.out;
        const std::vector<size_t> built = perRank(r.out, "trees built by rank");
        const std::vector<size_t> tiles = perRank(r.out, "tiles shaded by rank");
        ASSERT_EQ(built.size(), 3u) << r.out;
        ASSERT_EQ(tiles.size(), 3u) << r.out;
        EXPECT_GT(built[0] + built[1] + built[2], 0u) << r.out;
        // Between them the ranks built every tree one process builds, each once.
        EXPECT_EQ(built[0] + built[1] + built[2], trees) << r.out;
        if (args[0].find("cornell") != std::string::npos) {
            EXPECT_NE(counts.find("partial tree"), std::string::npos) << counts;
        }
        EXPECT_GT(tiles[1], 0u) << r.out;
        EXPECT_GT(tiles[2], 0u) << r.out;
        fs::remove(dir_ / "one.pfm");
        fs::remove(dir_ / "three.pfm");
    }
}

TEST_F(ClusterRender, WhatCannotWorkAcrossRanksIsRefusedOnce) {
    SKIP_WITHOUT_MPI();
    for (const std::vector<std::string>& args :
         {std::vector<std::string>{"render", (dir_ / "none.obj").string(), "--out",
                                   (dir_ / "x.pfm").string()},
          std::vector<std::string>{"render", scenePath("assets/cornell_box.obj").string(), "--size",
                                   "8x8", "--out", (dir_ / "x.pfm").string(), "--out-answers",
                                   (dir_ / "a.png").string()}}) {
        const ProcessResult r = mpirun(3, args);
        EXPECT_NE(r.exitCode, 0) << r.err;
        EXPECT_NE(r.exitCode, 124) << "timed out: " << r.err;
        size_t errors = 0;
        for (size_t at = r.err.find("penumbra: error:"); at != std::string::npos;
             at = r.err.find("penumbra: error:", at + 1))
            ++errors;
        EXPECT_EQ(errors, 1u) << r.err;
        EXPECT_FALSE(fs::exists(dir_ / "x.pfm"));
    }
}

// A worker killed in the middle of the passes (kill -9): the job ends within seconds, never
// hangs, and rank 0 names the rank; no image is written.
TEST_F(ClusterRender, AKilledRankEndsTheJobWithAnErrorNamingIt) {
    SKIP_WITHOUT_MPI();
    const fs::path image = dir_ / "killed.pfm";
    giveRanksAfterSigterm(3);
    start(3, {"render", scenePath("assets/scenes/table.json").string(), "--size", "96x96", "--spp",
              "400", "--out", image.string(), "--threads", "1"});
    // The workers are up and shading once they have been running a while.
    pid_t victim = -1;
    for (int i = 0; i < 300 && victim <= 0; ++i) {
        victim = findRank(image.string(), 2);
        std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    ASSERT_GT(victim, 0) << readFile(dir_ / "mpi.err");
    std::this_thread::sleep_for(std::chrono::seconds(3));
    ASSERT_EQ(awaitEnd(std::chrono::seconds(0)), -1)
        << "ended before the kill: " << readFile(dir_ / "mpi.out");
    const auto killedAt = Clock::now();
    ASSERT_EQ(::kill(victim, SIGKILL), 0);
    const int rc = awaitEnd(std::chrono::seconds(30));
    const double seconds = std::chrono::duration<double>(Clock::now() - killedAt).count();
    const std::string err = readFile(dir_ / "mpi.err");
    ASSERT_NE(rc, -1) << "the job did not end within 30 s of the kill: " << err;
    EXPECT_NE(rc, 0) << err;
    EXPECT_NE(rc, 124) << "the timeout ended it: " << err;
    EXPECT_LT(seconds, 15.0) << err;
    EXPECT_NE(err.find("penumbra: error: rank 2"), std::string::npos) << err;
    EXPECT_FALSE(fs::exists(image));
}

}  // namespace cluster_render_test
}  // namespace penumbra
