// The viewer's click (app/viewer/selection.h): the answer is there the moment select() returns,
// from the tree-less query, and the full inspection that arrives later through the history trees
// gives the same fragments (two independent exact evaluations) and adds the trees and paths.
#include "app/viewer/selection.h"

#include <gtest/gtest.h>
#include <tbb/task_group.h>

#include <filesystem>
#include <string>

#include "engine/render/exact_options.h"
#include "engine/scene/surface_samples.h"

namespace penumbra::viewer {
namespace {

std::shared_ptr<LoadedScene> loadAsset(const std::string& file) {
    return loadScene(std::filesystem::path(PENUMBRA_SOURCE_DIR) / "assets" / "scenes" / file,
                     ExactOptions{});
}

std::vector<SurfaceSample> surfacePoints(const Scene& scene, size_t count) {
    return surfaceSamples(scene, count, 5);
}

void expectInstantClickAgreesWithTheTrees(const std::string& file, int count) {
    const std::shared_ptr<LoadedScene> scene = loadAsset(file);
    tbb::task_group tasks;
    int penumbra = 0, withPath = 0;
    for (const auto& [face, x] : surfacePoints(scene->scene, static_cast<size_t>(count))) {
        SCOPED_TRACE(file + ": face " + std::to_string(face) + " at " + vis::toString(x));
        Selection selection;
        ASSERT_TRUE(selection.select(scene, face, x, tasks));
        // Before any poll: the immediate answer, without trees.
        ASSERT_TRUE(selection.inspection().has_value());
        const PointInspection instant = *selection.inspection();
        EXPECT_TRUE(instant.treesPending);
        ASSERT_EQ(instant.lights.size(), scene->scene.lights.size());
        for (const LightInspection& li : instant.lights) {
            EXPECT_FALSE(li.result.fromTree);
            EXPECT_EQ(li.tree, nullptr);
            EXPECT_TRUE(li.steps.empty());
        }
        tasks.wait();
        std::string message;
        ASSERT_EQ(selection.poll(message), Selection::Event::Arrived) << message;
        ASSERT_TRUE(selection.inspection().has_value());
        const PointInspection& full = *selection.inspection();
        EXPECT_FALSE(full.treesPending);
        EXPECT_FALSE(selection.pending());
        ASSERT_EQ(full.lights.size(), instant.lights.size());
        for (size_t k = 0; k < full.lights.size(); ++k) {
            const LightAtPoint& a = instant.lights[k].result;
            const LightAtPoint& b = full.lights[k].result;
            EXPECT_TRUE(b.fromTree);
            EXPECT_NEAR(a.visibleArea, b.visibleArea, 1e-9 * b.lightArea);
            EXPECT_NEAR(a.formFactor, b.formFactor, 1e-9 * std::max(1e-12, b.unoccludedFormFactor));
            EXPECT_EQ(a.unoccludedFormFactor, b.unoccludedFormFactor);
            penumbra += b.fraction > 0 && b.fraction < 1;
            withPath += !full.lights[k].steps.empty();
        }
    }
    // The points do cover shadows' edges, and the trees' paths do arrive.
    EXPECT_GT(penumbra, count / 20);
    EXPECT_GT(withPath, count / 20);
}

TEST(Selection, InstantAnswerOnStairsEqualsTheTreesAnswer) {
    expectInstantClickAgreesWithTheTrees("stairs.json", 60);
}

TEST(Selection, InstantAnswerOnTableEqualsTheTreesAnswer) {
    expectInstantClickAgreesWithTheTrees("table.json", 12);
}

// A newer click replaces an older one whose trees are still being built: the older result never
// shows up.
TEST(Selection, ANewClickDropsThePendingOne) {
    const std::shared_ptr<LoadedScene> scene = loadAsset("stairs.json");
    const auto points = surfacePoints(scene->scene, 2);
    tbb::task_group tasks;
    Selection selection;
    ASSERT_TRUE(selection.select(scene, points[0].face, points[0].x, tasks));
    ASSERT_TRUE(selection.select(scene, points[1].face, points[1].x, tasks));
    EXPECT_EQ(selection.inspection()->point, points[1].x);
    tasks.wait();
    std::string message;
    ASSERT_EQ(selection.poll(message), Selection::Event::Arrived);
    EXPECT_EQ(selection.inspection()->point, points[1].x);
    EXPECT_EQ(selection.inspection()->face, points[1].face);
    EXPECT_EQ(selection.poll(message), Selection::Event::None);
}

}  // namespace
}  // namespace penumbra::viewer
