// `penumbra merge` and `precompute --shards` in one process (no MPI), run as the user would: two
// disjoint halves of a scene's pairs (an interrupted precompute's file and the shard a rerun with
// --shards builds for the rest) merge to the bytes of one uninterrupted run; a pair present twice
// with the same bytes is kept once; an incomplete merge says how many pairs are missing and a
// precompute finishes it; another scene, other settings, a corrupt or truncated input and a pair
// built twice with different bytes are refused naming the file. The shards of 3 MPI ranks are in
// cluster_precompute_test.cpp.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "engine/io/scene_loader.h"
#include "engine/io/visibility_file.h"
#include "engine/precompute/precompute_scheduler.h"
#include "engine/scene/hash64.h"
#include "tests/support/run_penumbra.h"
#include "tests/support/test_files.h"

namespace penumbra {
namespace merge_command_test {

namespace fs = std::filesystem;
using test::ProcessResult;
using test::readFile;
using test::runPenumbra;

fs::path sourceDir() { return PENUMBRA_SOURCE_DIR; }

void writeBytes(const fs::path& p, const std::string& bytes) {
    std::ofstream(p, std::ios::binary) << bytes;
}

// The bytes with the trailing checksum recomputed (the file's own definition: Hash64 of all the
// bytes before it), so that a change inside reaches the record checks.
std::string withChecksum(std::string bytes) {
    Hash64 h;
    h.addBytes(std::span(reinterpret_cast<const unsigned char*>(bytes.data()), bytes.size() - 8));
    const uint64_t v = h.value();
    for (int k = 0; k < 8; ++k) bytes[bytes.size() - 8 + k] = static_cast<char>(v >> (8 * k));
    return bytes;
}

class MergeCommand : public ::testing::Test {
  protected:
    void SetUp() override {
        const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
        dir_ = fs::temp_directory_path() /
               ("penumbra_merge_" + std::to_string(::getpid()) + "_" + info->name());
        fs::remove_all(dir_);
        fs::create_directories(dir_);
    }
    void TearDown() override {
        std::error_code ec;
        fs::remove_all(dir_, ec);
    }
    std::string path(const std::string& name) const { return (dir_ / name).string(); }
    // `precompute BOX --max-lp-solves 40 -o FILE EXTRA...` (partial trees in the file).
    ProcessResult precompute(const std::string& file, std::vector<std::string> extra = {}) {
        std::vector<std::string> args = {"precompute", box_, "--max-lp-solves", "40", "-o", file};
        args.insert(args.end(), extra.begin(), extra.end());
        return runPenumbra(args);
    }
    size_t treesIn(const fs::path& file, size_t* total = nullptr) {
        const Scene scene = loadScene(box_);
        VisibilityStore::Options options;
        options.build.maxLpSolves = 40;
        VisibilityStore store(scene, nullptr, options);
        const size_t trees = readVisibilityFile(file, store);
        if (total) *total = everyPairKey(store).size();
        return trees;
    }

    fs::path dir_;
    const std::string box_ = (sourceDir() / "assets/cornell_box.obj").string();
};

size_t number(const std::string& out, const char* format) {
    size_t v = SIZE_MAX;
    const std::string head(format, std::string_view(format).find('%'));
    const size_t at = out.find(head);
    if (at != std::string::npos) std::sscanf(out.c_str() + at, format, &v);
    return v;
}

TEST_F(MergeCommand, TwoHalvesMergeToTheBytesOfOneProcess) {
    ASSERT_EQ(precompute(path("one.pvis")).exitCode, 0);
    const std::string one = readFile(path("one.pvis"));

    // Half: a run stopped by the memory budget (a valid whole file with some pairs).
    ProcessResult r = precompute(path("box.pvis"), {"--memory-budget", "0.002"});
    ASSERT_EQ(r.exitCode, 1) << r.err;
    size_t total = 0;
    const size_t first = treesIn(path("box.pvis"), &total);
    ASSERT_GT(first, 0u);
    ASSERT_LT(first, total);

    // The other half: --shards builds only what box.pvis lacks, into its own shard, and leaves
    // box.pvis as it was.
    const std::string half = readFile(path("box.pvis"));
    r = precompute(path("box.pvis"), {"--shards"});
    ASSERT_EQ(r.exitCode, 0) << r.err;
    const fs::path shard = path("box.pvis.rank-00000-of-00001");
    ASSERT_TRUE(fs::exists(shard)) << r.out;
    EXPECT_EQ(readFile(path("box.pvis")), half);
    EXPECT_EQ(treesIn(shard), total - first);  // a shard reads as a visibility file
    EXPECT_NE(r.out.find("pairs    " + std::to_string(total) + " of " + std::to_string(total)),
              std::string::npos)
        << r.out;

    r = runPenumbra({"merge", "-o", path("merged.pvis"), path("box.pvis"), shard.string()});
    ASSERT_EQ(r.exitCode, 0) << r.err;
    EXPECT_NE(r.out.find("complete"), std::string::npos) << r.out;
    EXPECT_EQ(number(r.out, "trees    %zu"), total) << r.out;
    EXPECT_EQ(readFile(path("merged.pvis")), one) << "merged file differs from one process's";

    // The same pairs twice (the whole file and the shard): kept once, counted.
    r = runPenumbra({"merge", "-o", path("again.pvis"), path("one.pvis"), shard.string()});
    ASSERT_EQ(r.exitCode, 0) << r.err;
    EXPECT_EQ(number(r.out, "trees    %zu"), total) << r.out;
    EXPECT_NE(r.out.find("(" + std::to_string(total - first) + " present twice"), std::string::npos)
        << r.out;
    EXPECT_EQ(readFile(path("again.pvis")), one);
}

// The shard alone lacks the first half: the merge says how many, writes a valid file, and a
// precompute with that file builds the rest, to the bytes of one process.
TEST_F(MergeCommand, AnIncompleteMergeIsValidAndAPrecomputeFinishesIt) {
    ASSERT_EQ(precompute(path("one.pvis")).exitCode, 0);
    ASSERT_EQ(precompute(path("box.pvis"), {"--memory-budget", "0.002"}).exitCode, 1);
    size_t total = 0;
    const size_t first = treesIn(path("box.pvis"), &total);
    ASSERT_EQ(precompute(path("box.pvis"), {"--shards"}).exitCode, 0);

    ProcessResult r =
        runPenumbra({"merge", "-o", path("part.pvis"), path("box.pvis.rank-00000-of-00001")});
    ASSERT_EQ(r.exitCode, 0) << r.err;
    EXPECT_NE(r.out.find(std::to_string(first) + " missing"), std::string::npos) << r.out;
    EXPECT_NE(r.err.find("lacks " + std::to_string(first) + " of " + std::to_string(total)),
              std::string::npos)
        << r.err;
    EXPECT_EQ(treesIn(path("part.pvis")), total - first);

    r = precompute(path("part.pvis"));
    ASSERT_EQ(r.exitCode, 0) << r.err;
    EXPECT_NE(r.out.find(std::to_string(total - first) + " trees loaded"), std::string::npos)
        << r.out;
    EXPECT_EQ(readFile(path("part.pvis")), readFile(path("one.pvis")));
}

TEST_F(MergeCommand, MismatchesAreRefusedNamingTheFile) {
    ASSERT_EQ(precompute(path("a.pvis"), {"--shards"}).exitCode, 0);
    const std::string a = path("a.pvis.rank-00000-of-00001");
    const auto refused = [&](const std::vector<std::string>& inputs) {
        std::vector<std::string> args = {"merge", "-o", path("out.pvis")};
        args.insert(args.end(), inputs.begin(), inputs.end());
        const ProcessResult r = runPenumbra(args);
        EXPECT_EQ(r.exitCode, 1) << r.err;
        EXPECT_FALSE(fs::exists(path("out.pvis")));
        return r.err;
    };

    // Other settings: named, with both values.
    ASSERT_EQ(runPenumbra({"precompute", box_, "-o", path("b.pvis"), "--shards"}).exitCode, 0);
    const std::string b = path("b.pvis.rank-00000-of-00001");
    std::string err = refused({a, b});
    EXPECT_NE(err.find(b + ": made with other settings than " + a +
                       ": --max-lp-solves 10000 here, 40 there"),
              std::string::npos)
        << err;

    // Another scene with the same settings.
    ASSERT_EQ(runPenumbra({"precompute", (sourceDir() / "assets/scenes/stairs.json").string(),
                           "--max-lp-solves", "40", "-o", path("c.pvis"), "--shards"})
                  .exitCode,
              0);
    const std::string c = path("c.pvis.rank-00000-of-00001");
    err = refused({a, c});
    EXPECT_NE(err.find(c + ": made for another scene than " + a), std::string::npos) << err;

    // A flipped byte: the checksum. A truncated file. A record whose counts overrun the file
    // (checksum made valid): the record is named.
    const std::string bytes = readFile(a);
    std::string flipped = bytes;
    flipped[bytes.size() / 2] ^= 0x10;
    writeBytes(path("flipped"), flipped);
    err = refused({a, path("flipped")});
    EXPECT_NE(err.find(path("flipped") + ": checksum mismatch"), std::string::npos) << err;
    writeBytes(path("short"), bytes.substr(0, bytes.size() - 100));
    err = refused({path("short"), a});
    EXPECT_NE(err.find(path("short") + ": truncated"), std::string::npos) << err;
    std::string counts = bytes;
    counts[88 + 28 + 3] = 0x7f;  // tree 0's node count (u32 at 28 in the record), high byte
    writeBytes(path("counts"), withChecksum(counts));
    err = refused({a, path("counts")});
    EXPECT_NE(err.find(path("counts") + ": tree 0 (byte 88): truncated or bad counts"),
              std::string::npos)
        << err;

    // The same pair with other bytes (the last tree's last build statistic).
    std::string other = bytes;
    other[bytes.size() - 9] ^= 0x01;
    writeBytes(path("other"), withChecksum(other));
    err = refused({a, path("other")});
    EXPECT_NE(err.find(path("other") + ": the tree of pair (receiver"), std::string::npos) << err;
    EXPECT_NE(err.find("differs from the one in " + a), std::string::npos) << err;
}

}  // namespace merge_command_test
}  // namespace penumbra
