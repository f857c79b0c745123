// The viewer's progressive preview (app/viewer/preview_runner.h) when a scene is replaced: clear()
// leaves nothing of the old scene's render (image or effects) for the panels to show.
#include "app/viewer/preview_runner.h"

#include <gtest/gtest.h>

#include "app/viewer/loaded_scene.h"
#include "engine/render/default_camera.h"
#include "tests/app/viewer/viewer_test_support.h"

namespace penumbra {
namespace {

TEST(PreviewRunner, ClearForgetsTheOldScenesImageAndEffects) {
    const std::shared_ptr<viewer::LoadedScene> scene =
        viewer::loadScene(test::sourceDir() / "assets" / "cornell_box.obj", ExactOptions{});
    const Camera camera = defaultCamera(scene->scene, *scene->bvh);
    viewer::PreviewSettings settings;
    settings.mode = viewer::PreviewMode::Sampled;
    settings.width = 16;
    settings.height = 12;
    settings.passes = 1;
    settings.lightSamples = 1;
    viewer::PreviewRunner runner;
    runner.restart(scene, camera, settings);
    runner.wait();
    // A render: its image and what it simulated.
    const std::optional<viewer::PreviewImage> image = runner.takeUpdate();
    ASSERT_TRUE(image.has_value());
    EXPECT_EQ(image->passes, 1);
    EXPECT_EQ(runner.effects().method, "sampled");
    EXPECT_EQ(runner.effects().areaLights, scene->scene.lights.size());

    // Cleared at once, and after a render that the clear cancels or outlives.
    runner.clear();
    EXPECT_TRUE(runner.effects().method.empty());
    runner.restart(scene, camera, settings);
    runner.clear();
    runner.wait();
    EXPECT_FALSE(runner.running());
    EXPECT_FALSE(runner.takeUpdate().has_value());
    EXPECT_TRUE(runner.effects().method.empty());
    EXPECT_EQ(runner.effects().areaLights, 0u);
}

}  // namespace
}  // namespace penumbra
