// The viewer's light moves off the UI thread (app/viewer/light_move_job.h, withLightMoves in
// loaded_scene.h): a moved version has its own BVH and an empty store, so no tree of the position
// before is used after the move; the point a user inspects there answers, at once without trees
// and then from the new trees, as an independent query of the Cornell box whose OBJ file has the
// lamp's coordinates moved by hand; a refused move says why and leaves no version.
#include "app/viewer/light_move_job.h"

#include <gtest/gtest.h>
#include <tbb/task_group.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "app/viewer/selection.h"
#include "engine/precompute/point_query.h"

namespace penumbra::viewer {
namespace {

namespace fs = std::filesystem;

fs::path source() { return fs::path(PENUMBRA_SOURCE_DIR) / "assets"; }

// assets/cornell_box.obj with its lamp (y = 548, x 213..343, z 227..332) at `lamp` (by hand).
fs::path handMovedCornellBox(const fs::path& dir, const std::string lamp[4]) {
    fs::create_directories(dir);
    std::ifstream in(source() / "cornell_box.obj");
    std::stringstream text;
    text << in.rdbuf();
    std::string obj = text.str();
    const std::string original[4] = {"v 343 548 227\n", "v 343 548 332\n", "v 213 548 332\n",
                                     "v 213 548 227\n"};
    for (int i = 0; i < 4; ++i) {
        const size_t at = obj.find(original[i]);
        EXPECT_NE(at, std::string::npos) << original[i];
        if (at != std::string::npos) obj.replace(at, original[i].size(), "v " + lamp[i] + "\n");
    }
    std::ofstream(dir / "cornell_box.obj") << obj;
    fs::copy_file(source() / "cornell_box.mtl", dir / "cornell_box.mtl",
                  fs::copy_options::overwrite_existing);
    return dir / "cornell_box.obj";
}

TEST(LightMoveJob, NewVersionUsesNoTreeOfThePositionBeforeAndAnswersAsTheSceneMovedByHand) {
    const std::shared_ptr<LoadedScene> before =
        loadScene(source() / "scenes" / "cornell_box.json", ExactOptions{});
    // A floor point in front of the tall block: the whole lamp before, the lamp moved down and to
    // the side partly behind the block.
    const uint32_t floor = 0;
    const Vec3 x{400, 0, 100};
    const uint32_t lamp = before->scene.lights[0];
    // The position before: its tree built.
    const PairKey key = before->store->layout().keyAt(floor, x, lamp);
    before->store->getOrBuild(key);
    ASSERT_EQ(before->store->treeCount(), 1u);
    const double fractionBefore = queryPoint(*before->store, floor, x, 0)[0].fraction;

    LightMoveJob job;
    tbb::task_group tasks;
    // Translate (-60, -150, 40), scale (1.5, 1, 0.5) about the centre (278, 548, 279.5).
    job.request(before, {LightMove{.translate = {-60, -150, 40}, .scale = {1.5, 1, 0.5}}},
                ExactOptions{}, tasks);
    tasks.wait();
    std::optional<LightMoveJob::Result> r = job.take();
    ASSERT_TRUE(r.has_value());
    ASSERT_TRUE(r->scene) << r->error;
    const std::shared_ptr<LoadedScene> moved = r->scene;
    EXPECT_GT(moved->version, before->version);
    EXPECT_EQ(moved->store->treeCount(), 0u);  // nothing of the store before
    EXPECT_NE(moved->store.get(), before->store.get());
    EXPECT_NE(moved->bvh.get(), before->bvh.get());
    EXPECT_FALSE(job.take().has_value());  // once

    const std::string hand[4] = {"315.5 398 293.25", "315.5 398 345.75", "120.5 398 345.75",
                                 "120.5 398 293.25"};
    const std::shared_ptr<LoadedScene> reference =
        loadScene(handMovedCornellBox(fs::temp_directory_path() / "penumbra_light_move_job", hand),
                  ExactOptions{});
    const LightAtPoint expected = queryPoint(*reference->store, floor, x, 0)[0];
    // The move matters at this point (else the test could not tell the trees apart).
    EXPECT_GT(std::abs(expected.fraction - fractionBefore), 0.05)
        << expected.fraction << " vs " << fractionBefore;

    Selection selection;
    selection.select(moved, floor, x, tasks);
    ASSERT_TRUE(selection.inspection().has_value());
    const LightAtPoint instant = selection.inspection()->lights[0].result;
    EXPECT_FALSE(instant.fromTree);
    EXPECT_NEAR(instant.fraction, expected.fraction, 1e-9);
    tasks.wait();
    std::string message;
    ASSERT_EQ(selection.poll(message), Selection::Event::Arrived) << message;
    const LightAtPoint full = selection.inspection()->lights[0].result;
    EXPECT_TRUE(full.fromTree);
    EXPECT_NEAR(full.fraction, expected.fraction, 1e-9);
    EXPECT_NEAR(full.formFactor, expected.formFactor, 1e-9 * expected.unoccludedFormFactor);
    // Its tree is the moved scene's, built after the move.
    EXPECT_EQ(moved->store->treeCount(), 1u);
    EXPECT_EQ(before->store->treeCount(), 1u);
    // The scene as the file has it is kept, unmoved, for the next move.
    ASSERT_TRUE(moved->asOpened);
    EXPECT_EQ(moved->asOpened->mesh.vertices, before->scene.mesh.vertices);
}

TEST(LightMoveJob, RefusedMoveSaysWhyAndGivesNoVersion) {
    const std::shared_ptr<LoadedScene> before =
        loadScene(source() / "scenes" / "cornell_box.json", ExactOptions{});
    LightMoveJob job;
    tbb::task_group tasks;
    job.request(before, {LightMove{.scale = {1, 1, 0}}}, ExactOptions{}, tasks);
    tasks.wait();
    std::optional<LightMoveJob::Result> r = job.take();
    ASSERT_TRUE(r.has_value());
    EXPECT_EQ(r->scene, nullptr);
    EXPECT_NE(r->error.find("light 0: scale: every factor must be positive"), std::string::npos)
        << r->error;
    EXPECT_FALSE(job.busy());
}

}  // namespace
}  // namespace penumbra::viewer
