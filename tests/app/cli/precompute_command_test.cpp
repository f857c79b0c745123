// `penumbra precompute`, run as a real process: writes a file whose trees equal direct builds,
// loads a current file without recomputing, recomputes a corrupt or stale one, rejects bad flags.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "engine/io/obj_io.h"
#include "engine/io/visibility_file.h"
#include "engine/scene/procedural_scenes.h"
#include "tests/support/run_penumbra.h"
#include "tests/support/tree_reference.h"

namespace penumbra {
namespace {

namespace fs = std::filesystem;
using test::ProcessResult;
using test::runPenumbra;

std::string readText(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

class PrecomputeCommand : public ::testing::Test {
  protected:
    void SetUp() override {
        const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
        dir_ = fs::temp_directory_path() /
               ("penumbra_precompute_" + std::to_string(::getpid()) + "_" + info->name());
        fs::remove_all(dir_);
        fs::create_directories(dir_);
        writeObj(makeCornellBox(), dir_ / "box.obj");
    }
    void TearDown() override {
        std::error_code ec;
        fs::remove_all(dir_, ec);
    }
    std::string scene() const { return (dir_ / "box.obj").string(); }
    std::string file() const { return (dir_ / "box.pvis").string(); }

    fs::path dir_;
};

TEST_F(PrecomputeCommand, WritesEveryPairThenLoadsWithoutRecomputing) {
    const ProcessResult first =
        runPenumbra({"precompute", scene(), "-o", file(), "--threads", "2"});
    ASSERT_EQ(first.exitCode, 0) << first.err;
    EXPECT_NE(first.out.find("box.pvis: written"), std::string::npos) << first.out;
    EXPECT_NE(first.out.find("threads  "), std::string::npos) << first.out;

    // The file holds one tree per (receiver patch, light) pair, each equal to a direct build.
    const Scene box = loadObj(dir_ / "box.obj");
    VisibilityStore store(box);
    const size_t trees = readVisibilityFile(file(), store);
    size_t expected = 0;
    for (uint32_t f = 0; f < box.faceCount(); ++f)
        for (uint32_t l : box.lights)
            if (l != f) expected += std::max<size_t>(store.layout().patches(f).patches.size(), 1);
    EXPECT_EQ(trees, expected);
    const auto kinds = store.kindCounts();
    EXPECT_NE(
        first.out.find("pairs    " + std::to_string(expected) + " of " + std::to_string(expected) +
                       ": " + std::to_string(kinds[0]) + " back-facing, " +
                       std::to_string(kinds[1]) + " fully visible, " + std::to_string(kinds[2]) +
                       " fully hidden, " + std::to_string(kinds[3]) + " penumbra"),
        std::string::npos)
        << first.out;
    store.forEach([&](const PairKey& k, const PairRecord& r) {
        EXPECT_TRUE(test::sameTree(r.tree, test::referenceTree(store, k)))
            << "receiver " << k.receiver << " patch " << k.patch;
    });

    const auto written = fs::last_write_time(file());
    const ProcessResult second = runPenumbra({"precompute", scene(), "-o", file()});
    ASSERT_EQ(second.exitCode, 0) << second.err;
    EXPECT_NE(second.out.find("valid and current"), std::string::npos) << second.out;
    EXPECT_NE(second.out.find("nothing recomputed"), std::string::npos) << second.out;
    EXPECT_EQ(fs::last_write_time(file()), written);  // not rewritten
}

// A visibility file depends only on the scene and the settings: one thread or several, complete
// trees or partial ones (a low --max-lp-solves defers occluders), the same bytes. Before version 4
// each tree's build time was in the file and two runs differed in thousands of bytes.
TEST_F(PrecomputeCommand, TheSameSceneAndSettingsWriteTheSameBytesWhateverTheThreads) {
    for (const char* budget : {"0", "40"}) {
        std::vector<std::string> bytes;
        for (const char* threads : {"1", "2", "2"}) {
            fs::remove(file());
            const ProcessResult r = runPenumbra({"precompute", scene(), "-o", file(), "--threads",
                                                 threads, "--max-lp-solves", budget});
            ASSERT_EQ(r.exitCode, 0) << r.err;
            bytes.push_back(readText(file()));
        }
        ASSERT_GT(bytes[0].size(), 48u);
        EXPECT_EQ(bytes[0], bytes[1]) << "--max-lp-solves " << budget;
        EXPECT_EQ(bytes[1], bytes[2]) << "--max-lp-solves " << budget;
        if (std::string(budget) != "0") {  // the budget made partial trees
            const ProcessResult r =
                runPenumbra({"precompute", scene(), "-o", file(), "--max-lp-solves", budget});
            EXPECT_NE(r.out.find("partial"), std::string::npos) << r.out;
        }
    }
}

TEST_F(PrecomputeCommand, CorruptOrStaleFileIsRecomputed) {
    ASSERT_EQ(runPenumbra({"precompute", scene(), "-o", file()}).exitCode, 0);
    std::string bytes = readText(file());
    bytes[bytes.size() / 2] ^= 0x01;
    std::ofstream(file(), std::ios::binary | std::ios::trunc) << bytes;
    ProcessResult r = runPenumbra({"precompute", scene(), "-o", file()});
    ASSERT_EQ(r.exitCode, 0) << r.err;
    EXPECT_NE(r.err.find("checksum mismatch"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("recomputing"), std::string::npos) << r.err;
    EXPECT_NE(r.out.find("box.pvis: written"), std::string::npos) << r.out;

    // Other settings shape other trees: the file is stale.
    r = runPenumbra({"precompute", scene(), "-o", file(), "--patch-fraction", "0.5"});
    ASSERT_EQ(r.exitCode, 0) << r.err;
    EXPECT_NE(r.err.find("stale"), std::string::npos) << r.err;
    VisibilityStore::Options half;
    half.patchFraction = 0.5;
    const Scene box = loadObj(dir_ / "box.obj");
    VisibilityStore store(box, nullptr, half);
    EXPECT_GT(readVisibilityFile(file(), store), 0u);
}

TEST_F(PrecomputeCommand, BadArgumentsAndMemoryBudget) {
    EXPECT_EQ(runPenumbra({"precompute", scene()}).exitCode, 2);  // no -o
    EXPECT_EQ(runPenumbra({"precompute", scene(), "-o", file(), "--threads", "0"}).exitCode, 2);
    EXPECT_EQ(runPenumbra({"precompute", (dir_ / "none.obj").string(), "-o", file()}).exitCode, 1);
    EXPECT_FALSE(fs::exists(file()));
    // A budget far below one tree: stops, writes what it has, exits 1 with the reason.
    const ProcessResult r = runPenumbra(
        {"precompute", scene(), "-o", file(), "--memory-budget", "0.000001", "--threads", "1"});
    EXPECT_EQ(r.exitCode, 1);
    EXPECT_NE(r.err.find("memory budget"), std::string::npos) << r.err;
    const Scene box = loadObj(dir_ / "box.obj");
    VisibilityStore store(box);
    const size_t trees = readVisibilityFile(file(), store);
    EXPECT_GT(trees, 0u);
    EXPECT_EQ(store.kindCounts()[static_cast<int>(vis::PairKind::Penumbra)], 1u);
}

}  // namespace
}  // namespace penumbra
