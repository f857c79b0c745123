// `penumbra precompute` across the ranks of an MPI job, run as the user would:
// `mpirun --allow-run-as-root --oversubscribe -np 3 penumbra precompute ...` as a child process,
// always under a timeout (a hang fails the test instead of blocking the suite). Skipped, saying
// why, in a build without MPI (PENUMBRA_MPI off, or Open MPI not installed).
//
// What is checked: the file 3 ranks write has the bytes a single process writes (two committed
// scenes, one with partial trees); a bad scene is refused once, by rank 0; a rank killed in the
// middle ends the job within seconds with rank 0's error naming it; an interrupted run (the memory
// budget, Ctrl-C to mpirun) leaves a valid file that a rerun completes; with --shards, the ranks'
// shards merge (`penumbra merge`) to the bytes of one process, also after an interruption.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <string>
#include <thread>
#include <vector>

#include "engine/io/scene_loader.h"
#include "engine/io/visibility_file.h"
#include "engine/precompute/precompute_scheduler.h"
#include "tests/support/mpi_job.h"
#include "tests/support/run_penumbra.h"
#include "tests/support/test_files.h"

namespace penumbra {
namespace {

namespace fs = std::filesystem;
using test::ProcessResult;
using test::readFile;
using test::runPenumbra;
using Clock = std::chrono::steady_clock;

fs::path sourceDir() { return PENUMBRA_SOURCE_DIR; }

class ClusterPrecompute : public test::MpiJobTest {
  protected:
    // Waits until rank 0 printed a progress line (the builds run), at most `limit`.
    bool awaitProgress(std::chrono::seconds limit) { return awaitStderr("precompute: ", limit); }

    // The file a single process writes for these arguments.
    std::string singleProcessBytes(const std::vector<std::string>& args, const fs::path& file) {
        std::vector<std::string> all = {"precompute"};
        all.insert(all.end(), args.begin(), args.end());
        all.insert(all.end(), {"-o", file.string()});
        const ProcessResult r = runPenumbra(all);
        EXPECT_EQ(r.exitCode, 0) << r.err;
        return readFile(file);
    }
};

size_t treesIn(const fs::path& scenePath, const fs::path& file, size_t* total,
               const VisibilityStore::Options& options = {}) {
    const Scene scene = loadScene(scenePath);
    VisibilityStore store(scene, nullptr, options);
    const size_t trees = readVisibilityFile(file, store);
    if (total) *total = everyPairKey(store).size();
    return trees;
}

// 3 ranks write the bytes one process writes: the Cornell box with a build budget of 40 linear
// programs (partial trees, deferred occluders in the file) and the stairs with the defaults.
TEST_F(ClusterPrecompute, ThreeRanksWriteTheBytesOfOneProcess) {
    SKIP_WITHOUT_MPI();
    const std::vector<std::vector<std::string>> cases = {
        {(sourceDir() / "assets/cornell_box.obj").string(), "--max-lp-solves", "40"},
        {(sourceDir() / "assets/scenes/stairs.json").string(), "--patch-fraction", "0.5"},
    };
    for (const auto& args : cases) {
        const std::string one = singleProcessBytes(args, dir_ / "one.pvis");
        ASSERT_GT(one.size(), 48u);
        std::vector<std::string> all = {"precompute"};
        all.insert(all.end(), args.begin(), args.end());
        all.insert(all.end(), {"-o", (dir_ / "three.pvis").string(), "--threads", "1"});
        const ProcessResult r = mpirun(3, all);
        ASSERT_EQ(r.exitCode, 0) << r.err << r.out;
        EXPECT_NE(r.out.find("ranks    3"), std::string::npos) << r.out;
        EXPECT_EQ(one, readFile(dir_ / "three.pvis")) << args[0] << ": the files differ";
        if (args[1] == "--max-lp-solves") {
            EXPECT_EQ(r.out.find("(0 partial"), std::string::npos) << r.out;
            EXPECT_NE(r.out.find("partial"), std::string::npos) << r.out;
        }
        // The trees each rank built add up to the file's, every rank built some (each worker
        // gets two batches at once), and what the workers sent is what rank 0 did not build.
        const size_t at = r.out.find("ranks    3: trees built by rank 0 ");
        ASSERT_NE(at, std::string::npos) << r.out;
        size_t byRank[3] = {0, 0, 0}, sent = 0;
        ASSERT_EQ(std::sscanf(r.out.c_str() + at,
                              "ranks    3: trees built by rank 0 %zu, 1 %zu, 2 %zu\nsent     %zu",
                              &byRank[0], &byRank[1], &byRank[2], &sent),
                  4)
            << r.out;
        size_t built = 0, total = 0;
        const size_t pairsAt = r.out.find("pairs    ");
        ASSERT_NE(pairsAt, std::string::npos) << r.out;
        ASSERT_EQ(std::sscanf(r.out.c_str() + pairsAt, "pairs    %zu of %zu", &built, &total), 2);
        EXPECT_EQ(built, total) << r.out;
        EXPECT_EQ(byRank[0] + byRank[1] + byRank[2], total) << r.out;
        EXPECT_EQ(byRank[1] + byRank[2], sent) << r.out;
        for (size_t n : byRank) EXPECT_GT(n, 0u) << r.out;
        fs::remove(dir_ / "three.pvis");
    }
}

TEST_F(ClusterPrecompute, ABadSceneIsRefusedOnceByRankZero) {
    SKIP_WITHOUT_MPI();
    const ProcessResult r =
        mpirun(3, {"precompute", (dir_ / "none.obj").string(), "-o", (dir_ / "x.pvis").string()});
    EXPECT_EQ(r.exitCode, 1) << r.err;
    size_t errors = 0;
    for (size_t at = r.err.find("penumbra: error:"); at != std::string::npos;
         at = r.err.find("penumbra: error:", at + 1))
        ++errors;
    EXPECT_EQ(errors, 1u) << r.err;
    EXPECT_NE(r.err.find("none.obj"), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(dir_ / "x.pvis"));
}

// A worker killed in the middle (kill -9): the job ends within seconds, never hangs, and rank 0
// says which rank and why, and keeps what was finished (a valid file).
TEST_F(ClusterPrecompute, AKilledRankEndsTheJobWithAnErrorNamingIt) {
    SKIP_WITHOUT_MPI();
    const fs::path file = dir_ / "killed.pvis";
    const std::string scene = (sourceDir() / "assets/scenes/table.json").string();
    start(3, {"precompute", scene, "-o", file.string(), "--threads", "1"});
    ASSERT_TRUE(awaitProgress(std::chrono::seconds(60))) << readFile(dir_ / "mpi.err");
    const pid_t victim = findRank(file.string(), 2);
    ASSERT_GT(victim, 0);
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
    // What was finished is kept: a valid file with some of the pairs, not all.
    ASSERT_TRUE(fs::exists(file)) << err;
    size_t total = 0;
    const size_t kept = treesIn(scene, file, &total);
    EXPECT_GT(kept, 0u);
    EXPECT_LT(kept, total);
}

// Interrupted runs leave a valid file holding what was finished, and a rerun (with another number
// of ranks) completes it to the bytes of one process: the memory budget, then Ctrl-C to mpirun
// (which sends SIGTERM to every rank and kills them about a second later).
TEST_F(ClusterPrecompute, AnInterruptedRunIsValidAndARerunCompletesIt) {
    SKIP_WITHOUT_MPI();
    const std::string scene = (sourceDir() / "assets/cornell_box.obj").string();
    const fs::path file = dir_ / "box.pvis";
    const std::string one = singleProcessBytes({scene}, dir_ / "one.pvis");

    ProcessResult r =
        mpirun(3, {"precompute", scene, "-o", file.string(), "--memory-budget", "0.002"});
    EXPECT_EQ(r.exitCode, 1) << r.err;
    EXPECT_NE(r.err.find("memory budget"), std::string::npos) << r.err;
    size_t total = 0;
    const size_t partial = treesIn(scene, file, &total);
    EXPECT_GT(partial, 0u);
    EXPECT_LT(partial, total);

    r = mpirun(2, {"precompute", scene, "-o", file.string()});
    ASSERT_EQ(r.exitCode, 0) << r.err;
    EXPECT_NE(r.out.find(std::to_string(partial) + " trees loaded"), std::string::npos) << r.out;
    EXPECT_EQ(readFile(file), one);

    // Ctrl-C: mpirun gets SIGINT.
    const fs::path tableFile = dir_ / "table.pvis";
    const std::string table = (sourceDir() / "assets/scenes/table.json").string();
    start(3, {"precompute", table, "-o", tableFile.string(), "--threads", "1"});
    ASSERT_TRUE(awaitProgress(std::chrono::seconds(60))) << readFile(dir_ / "mpi.err");
    const pid_t launcher = findLauncher(tableFile.string());
    ASSERT_GT(launcher, 0);
    ASSERT_EQ(::kill(launcher, SIGINT), 0);
    const int rc = awaitEnd(std::chrono::seconds(30));
    const std::string err = readFile(dir_ / "mpi.err");
    ASSERT_NE(rc, -1) << err;
    EXPECT_NE(rc, 0) << err;
    ASSERT_TRUE(fs::exists(tableFile)) << err;
    // Valid, and short of complete (the rerun that completes a file is above).
    const size_t interrupted = treesIn(table, tableFile, &total);
    EXPECT_GT(interrupted, 0u) << err;
    EXPECT_LT(interrupted, total) << err;
    EXPECT_NE(err.find("penumbra: stopping"), std::string::npos) << err;
}

// --shards: each of 3 ranks writes its own shard (no tree travels to rank 0, which writes no whole
// file), and `penumbra merge` joins them to the bytes of one process (partial trees included).
// Interrupted (the memory budget, which counts each rank's own store), the shards hold what was
// finished; a rerun with 2 ranks builds only the rest (the merge finds no pair twice), and the
// merge of all five shards is again the bytes of one process.
TEST_F(ClusterPrecompute, ShardsOfThreeRanksMergeToTheBytesOfOneProcess) {
    SKIP_WITHOUT_MPI();
    const std::string box = (sourceDir() / "assets/cornell_box.obj").string();
    const std::vector<std::string> settings = {box, "--max-lp-solves", "40"};
    const std::string one = singleProcessBytes(settings, dir_ / "one.pvis");
    const fs::path file = dir_ / "box.pvis";
    VisibilityStore::Options options;
    options.build.maxLpSolves = 40;
    const auto precompute = [&](int ranks, std::vector<std::string> extra) {
        std::vector<std::string> all = {"precompute"};
        all.insert(all.end(), settings.begin(), settings.end());
        all.insert(all.end(), {"-o", file.string(), "--shards", "--threads", "1"});
        all.insert(all.end(), extra.begin(), extra.end());
        return mpirun(ranks, all);
    };
    const auto merge = [&](const fs::path& out, const std::vector<fs::path>& inputs) {
        std::vector<std::string> args = {"merge", "-o", out.string()};
        for (const fs::path& p : inputs) args.push_back(p.string());
        return runPenumbra(args);
    };
    const auto shard = [&](int index, int count) {
        return shardPath(file, static_cast<uint32_t>(index), static_cast<uint32_t>(count));
    };

    ProcessResult r = precompute(3, {});
    ASSERT_EQ(r.exitCode, 0) << r.err << r.out;
    EXPECT_FALSE(fs::exists(file)) << "rank 0 wrote a whole file";
    EXPECT_NE(r.out.find("sent     no trees"), std::string::npos) << r.out;
    size_t total = 0, sum = 0;
    for (int k = 0; k < 3; ++k) {
        ASSERT_TRUE(fs::exists(shard(k, 3))) << r.out;
        const size_t trees = treesIn(box, shard(k, 3), &total, options);
        EXPECT_GT(trees, 0u) << "rank " << k << " built nothing";
        sum += trees;
    }
    EXPECT_EQ(sum, total);
    r = merge(dir_ / "merged.pvis", {shard(0, 3), shard(1, 3), shard(2, 3)});
    ASSERT_EQ(r.exitCode, 0) << r.err;
    EXPECT_NE(r.out.find("(0 present twice"), std::string::npos) << r.out;
    EXPECT_EQ(readFile(dir_ / "merged.pvis"), one) << "the merged shards differ from one process";

    // Interrupted, then finished with another rank count.
    for (int k = 0; k < 3; ++k) fs::remove(shard(k, 3));
    r = precompute(3, {"--memory-budget", "0.002"});
    EXPECT_EQ(r.exitCode, 1) << r.err;
    EXPECT_NE(r.err.find("memory budget"), std::string::npos) << r.err;
    size_t first = 0;
    for (int k = 0; k < 3; ++k)
        if (fs::exists(shard(k, 3))) first += treesIn(box, shard(k, 3), nullptr, options);
    EXPECT_GT(first, 0u);
    EXPECT_LT(first, total);
    r = precompute(2, {});
    ASSERT_EQ(r.exitCode, 0) << r.err << r.out;
    std::vector<fs::path> all = shardPaths(file);
    EXPECT_GE(all.size(), 3u);
    r = merge(dir_ / "resumed.pvis", all);
    ASSERT_EQ(r.exitCode, 0) << r.err;
    EXPECT_NE(r.out.find("(0 present twice"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("complete"), std::string::npos) << r.out;
    EXPECT_EQ(readFile(dir_ / "resumed.pvis"), one);
}

}  // namespace
}  // namespace penumbra
