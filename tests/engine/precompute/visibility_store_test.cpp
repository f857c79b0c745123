// VisibilityStore: a build cancelled through getOrBuild's flag publishes nothing and can be
// rebuilt. (Which key serves a point, and query-driven refinement through the store:
// patch_layout_test.cpp.) Built into penumbra_concurrency_tests, which CI also runs under
// ThreadSanitizer (scripts/run_tests.sh).
#include "engine/precompute/visibility_store.h"

#include <gtest/gtest.h>

#include <atomic>

#include "engine/raytrace/embree_scene.h"
#include "engine/scene/procedural_scenes.h"
#include "tests/support/tree_reference.h"

namespace penumbra {
namespace {

TEST(VisibilityStore, CancelledBuildPublishesNothingAndCanBeRebuilt) {
    const Scene scene = makeGrids();
    const EmbreeScene bvh(scene.mesh);
    VisibilityStore store(scene, &bvh);
    // A floor patch under the grids: a penumbra pair (the build reaches the cancel checks).
    const PairKey key{0, 0, scene.lights[0]};
    const vis::HistoryTree reference = test::referenceTree(store, key);
    ASSERT_EQ(reference.kind, vis::PairKind::Penumbra);
    const std::atomic<bool> cancelled{true};
    EXPECT_THROW(store.getOrBuild(key, &cancelled), vis::BuildCancelled);
    EXPECT_EQ(store.find(key), nullptr);
    EXPECT_EQ(store.treeCount(), 0u);
    EXPECT_EQ(store.bytes(), 0u);
    const std::atomic<bool> running{false};
    EXPECT_TRUE(test::sameTree(store.getOrBuild(key, &running).tree, reference));
    EXPECT_EQ(store.treeCount(), 1u);
}

}  // namespace
}  // namespace penumbra
