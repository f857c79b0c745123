// Inputs that once crashed, hung or misled the program (tests/fuzz/regressions/FORMAT/: the
// reproducers of the hostile-input defects, and every finding of scripts/fuzz.sh), loaded as the
// fuzz harness loads them, in repair and in strict mode: each must load, or be refused with a
// SceneError that names the file;
// never crash, hang (the test's timeout) or throw anything else. The reproducers of issue-sized
// defects are also checked for their exact message in hostile_input_test.cpp.
#include <gtest/gtest.h>

#include <filesystem>

#include "engine/io/scene_loader.h"
#include "tests/support/answer_check.h"

namespace penumbra {
namespace {

namespace fs = std::filesystem;

TEST(FuzzRegressions, EveryRecordedInputLoadsOrIsRefusedWithAnErrorNamingTheFile) {
    const fs::path root = fs::path(PENUMBRA_SOURCE_DIR) / "tests" / "fuzz" / "regressions";
    int inputs = 0, refused[2] = {0, 0};
    for (const fs::directory_entry& e : fs::recursive_directory_iterator(root)) {
        if (!e.is_regular_file()) continue;
        ++inputs;
        for (const bool strict : {false, true}) {
            try {
                const Scene scene =
                    loadScene(e.path(), strict ? LoadOptions::strictMode() : LoadOptions{});
                // What loads must also be answered soundly (the harnesses' contract).
                if (const auto problem = test::answerProblem(scene))
                    ADD_FAILURE() << e.path() << ": " << *problem;
            } catch (const SceneError& error) {
                ++refused[strict];
                EXPECT_EQ(error.file, e.path().string()) << error.what();
            } catch (const std::exception& other) {
                ADD_FAILURE() << e.path() << ": not a SceneError: " << other.what();
            }
        }
    }
    EXPECT_GE(inputs, 10);
    // The hostile reproducers are refused in both modes (in repair mode a light whose area rounds
    // to zero is a degenerate face, dropped: that scene loads without it).
    EXPECT_GE(refused[1], 8);
    EXPECT_GE(refused[0], 8);
}

}  // namespace
}  // namespace penumbra
