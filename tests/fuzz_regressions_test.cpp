// Inputs that once crashed, hung or misled the program (tests/fuzz/regressions/FORMAT/: the
// reproducers of the hostile-input defects, and every finding of scripts/fuzz.sh), loaded as the
// fuzz harness loads them: each must be refused with a SceneError that names the file.
#include <gtest/gtest.h>

#include <filesystem>

#include "engine/scene_loader.h"

namespace penumbra {
namespace {

namespace fs = std::filesystem;

TEST(FuzzRegressions, EveryRecordedInputIsRefusedWithAnErrorNamingTheFile) {
    const fs::path root = fs::path(PENUMBRA_SOURCE_DIR) / "tests" / "fuzz" / "regressions";
    int inputs = 0;
    for (const fs::directory_entry& e : fs::recursive_directory_iterator(root)) {
        if (!e.is_regular_file()) continue;
        ++inputs;
        try {
            (void)loadScene(e.path());
            ADD_FAILURE() << e.path() << ": loaded";
        } catch (const SceneError& error) {
            EXPECT_EQ(error.file, e.path().string()) << error.what();
        } catch (const std::exception& other) {
            ADD_FAILURE() << e.path() << ": not a SceneError: " << other.what();
        }
    }
    EXPECT_GE(inputs, 6);
}

}  // namespace
}  // namespace penumbra
