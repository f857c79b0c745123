// The viewer with a visibility file (`penumbra screenshot ... --visibility FILE.pvis`, headless):
// a current file's trees are all loaded and serve the inspected point (no tree built), a corrupt
// one is reported and rewritten by the precompute with the bytes `penumbra precompute` writes, a
// file written by 3 MPI ranks opens with every tree present.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "engine/io/scene_loader.h"
#include "engine/io/visibility_file.h"
#include "engine/precompute/precompute_scheduler.h"
#include "tests/app/viewer/viewer_test_support.h"
#include "tests/support/test_files.h"

namespace penumbra {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

fs::path cornell() { return test::sourceDir() / "assets" / "cornell_box.obj"; }

// The trees in `file` for the Cornell box with the default settings (as the viewer opens it), and
// how many pairs the scene has.
size_t treesIn(const fs::path& file, size_t* pairs = nullptr) {
    const Scene scene = loadScene(cornell());
    VisibilityStore store(scene);
    const size_t trees = readVisibilityFile(file, store);
    if (pairs) *pairs = everyPairKey(store).size();
    return trees;
}

json screenshot(const fs::path& dir, const fs::path& file, std::vector<std::string> extra) {
    std::vector<std::string> args = {"screenshot",
                                     cornell().string(),
                                     "--size",
                                     "800x500",
                                     "--no-preview",
                                     "--point",
                                     "278,0,280",
                                     "--visibility",
                                     file.string(),
                                     "--out",
                                     (dir / "shot.png").string(),
                                     "--state-out",
                                     (dir / "state.json").string()};
    args.insert(args.end(), extra.begin(), extra.end());
    const test::ProcessResult r = test::runPenumbraGl(args);
    EXPECT_EQ(r.exitCode, 0) << r.err;
    return test::readJson(dir / "state.json");
}

TEST(ViewerVisibility, ACurrentFileServesEveryTreeAndACorruptOneIsRewritten) {
    const fs::path dir = test::scratchDir("viewer_visibility");
    const fs::path file = dir / "box.pvis";
    const test::ProcessResult p =
        test::runPenumbra({"precompute", cornell().string(), "-o", file.string()});
    ASSERT_EQ(p.exitCode, 0) << p.err;
    size_t pairs = 0;
    const size_t trees = treesIn(file, &pairs);
    ASSERT_EQ(trees, pairs);
    const std::string bytes = test::readFile(file);

    // Every tree loaded; the inspected point's trees were among them: none built.
    json state = screenshot(dir, file, {});
    ASSERT_TRUE(state.contains("visibility")) << state.dump();
    EXPECT_EQ(state["visibility"]["state"], "current") << state["visibility"].dump();
    EXPECT_EQ(state["visibility"]["treesLoaded"].get<size_t>(), trees);
    EXPECT_EQ(state["visibility"]["treesInStore"].get<size_t>(), trees);
    EXPECT_NE(state["visibility"]["status"].get<std::string>().find(std::to_string(trees) +
                                                                    " trees loaded"),
              std::string::npos)
        << state["visibility"].dump();

    // A flipped byte: reported as corrupt, nothing loaded; the precompute writes the file again,
    // the same bytes as the precompute command's.
    std::string broken = bytes;
    broken[broken.size() / 2] ^= 0x01;
    std::ofstream(file, std::ios::binary | std::ios::trunc) << broken;
    state = screenshot(dir, file, {"--precompute"});
    EXPECT_EQ(state["visibility"]["treesLoaded"].get<size_t>(), 0u);
    EXPECT_EQ(state["visibility"]["state"], "written") << state["visibility"].dump();
    EXPECT_EQ(state["visibility"]["treesWritten"].get<size_t>(), trees);
    EXPECT_EQ(test::readFile(file), bytes);
}

// The file 3 MPI ranks write (docs/cluster.md) opens in the viewer with every tree present.
TEST(ViewerVisibility, AFileWrittenByThreeRanksOpensWithEveryTree) {
    if (!test::haveMpi())
        GTEST_SKIP() << "this build has no MPI (Open MPI not found, or PENUMBRA_MPI=OFF)";
    const fs::path dir = test::scratchDir("viewer_visibility_mpi");
    const fs::path file = dir / "box.pvis";
    const std::string command = test::mpirunCommand(3, {"precompute", cornell().string(), "-o",
                                                        file.string(), "--threads", "1"}) +
                                " >/dev/null";
    ASSERT_EQ(std::system(command.c_str()), 0);
    size_t pairs = 0;
    ASSERT_EQ(treesIn(file, &pairs), pairs);
    const json state = screenshot(dir, file, {});
    EXPECT_EQ(state["visibility"]["state"], "current") << state["visibility"].dump();
    EXPECT_EQ(state["visibility"]["treesLoaded"].get<size_t>(), pairs);
}

// Without a file nothing is read or written, and the state says nothing of one.
TEST(ViewerVisibility, NoFileNoVisibilityState) {
    const fs::path dir = test::scratchDir("viewer_visibility_none");
    const test::ProcessResult r = test::runPenumbraGl(
        {"screenshot", cornell().string(), "--size", "800x500", "--no-preview", "--out",
         (dir / "shot.png").string(), "--state-out", (dir / "state.json").string()});
    ASSERT_EQ(r.exitCode, 0) << r.err;
    EXPECT_FALSE(test::readJson(dir / "state.json").contains("visibility"));
}

}  // namespace
}  // namespace penumbra
