// Which history trees a light move keeps (engine/precompute/moved_light_trees.h), on the two-light
// scene of tests/support/two_light_scene.h with every pair built: light 1 moved where no shaft of
// light 0 reaches keeps exactly light 0's trees but the one whose receiver is light 1 (counted by
// hand from the patches); light 1 moved into light 0's shafts keeps fewer; a move that changes the
// scene's bounds keeps none and says why. Every kept tree is the tree built from scratch in the
// moved scene (every face a candidate: tests/support/tree_reference.h), field by field.
#include "engine/precompute/moved_light_trees.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <vector>

#include "engine/io/scene_loader.h"
#include "engine/precompute/visibility_store.h"
#include "engine/raytrace/embree_scene.h"
#include "engine/scene/light_move.h"
#include "tests/support/loader_test_support.h"
#include "tests/support/tree_reference.h"
#include "tests/support/two_light_scene.h"

namespace penumbra {
namespace moved_light_trees_test {

// Every (receiver patch, light) pair of the store built, as the precompute does.
void buildEveryPair(VisibilityStore& store) {
    const Scene& scene = store.scene();
    for (uint32_t f = 0; f < scene.faceCount(); ++f)
        for (uint32_t p = 0; p < store.layout().patchCount(f); ++p)
            for (uint32_t light : scene.lights)
                if (light != f) (void)store.getOrBuild({f, p, light});
}

struct Moved {
    Scene scene;
    std::unique_ptr<EmbreeScene> bvh;
    std::unique_ptr<VisibilityStore> store;
    KeptTrees kept;
};

// Light 1 of `before` moved by `move`, its store given the trees the move keeps.
Moved moveLightOne(const Scene& scene, const EmbreeScene& bvh, const VisibilityStore& store,
                   const LightMove& move) {
    Moved m{scene, nullptr, nullptr, {}};
    moveLight(m.scene, 1, move);
    m.bvh = std::make_unique<EmbreeScene>(m.scene.mesh);
    m.store = std::make_unique<VisibilityStore>(m.scene, m.bvh.get());
    const std::vector<uint32_t> movedFaces = {m.scene.lights[1]};
    m.kept = keepTreesPastLightMove(store, bvh, *m.store, *m.bvh, movedFaces);
    return m;
}

// Every tree of the moved store is the one built from scratch there; returns how many.
size_t expectKeptTreesAreRebuiltOnes(const Moved& m) {
    size_t n = 0;
    m.store->forEach([&](const PairKey& key, const PairRecord& record) {
        EXPECT_NE(key.receiver, m.scene.lights[1]);
        EXPECT_NE(key.lightFace, m.scene.lights[1]);
        EXPECT_TRUE(test::sameTree(record.tree, test::referenceTree(*m.store, key)))
            << "receiver " << key.receiver << " patch " << key.patch;
        ++n;
    });
    return n;
}

class MovedLightTrees : public test::LoaderFiles {  // (its temporary directory)
  protected:
    void SetUp() override {
        LoaderFiles::SetUp();
        scene_ = loadScene(test::writeTwoLightScene(dir_));
        ASSERT_EQ(scene_.lights, (std::vector<uint32_t>{3, 4}));
        bvh_ = std::make_unique<EmbreeScene>(scene_.mesh);
        store_ = std::make_unique<VisibilityStore>(scene_, bvh_.get());
        buildEveryPair(*store_);
        // P patches in all, the lights one each: each light has a tree per patch of the other
        // faces, P - 1.
        for (uint32_t f = 0; f < scene_.faceCount(); ++f)
            patches_ += store_->layout().patchCount(f);
        ASSERT_EQ(store_->layout().patchCount(3), 1u);
        ASSERT_EQ(store_->layout().patchCount(4), 1u);
        ASSERT_GT(store_->layout().patchCount(0), 1u);  // the floor is split
        ASSERT_EQ(store_->treeCount(), 2 * (patches_ - 1));
    }
    Scene scene_;
    std::unique_ptr<EmbreeScene> bvh_;
    std::unique_ptr<VisibilityStore> store_;
    size_t patches_ = 0;
};

// Moved by (0.25, -0.125, 0): x in [3, 3.5], y = 0.875, outside every shaft of light 0 before and
// after. Kept: light 0's P - 1 trees but the one whose receiver is light 1, P - 2.
TEST_F(MovedLightTrees, AMoveOutsideTheOtherLightsShaftsKeepsItsTrees) {
    const Moved m = moveLightOne(scene_, *bvh_, *store_, LightMove{.translate = {0.25, -0.125, 0}});
    EXPECT_EQ(m.kept.noneBecause, "");
    EXPECT_EQ(m.kept.kept, patches_ - 2);
    EXPECT_EQ(expectKeptTreesAreRebuiltOnes(m), patches_ - 2);
    m.store->forEach([&](const PairKey& key, const PairRecord&) {
        EXPECT_EQ(key.lightFace, m.scene.lights[0]);
    });
}

// Moved by (-3, -0.375, 0): x in [-0.25, 0.25] at y = 0.625, between light 0 and its occluder,
// inside the shafts of light 0 to the floor under it: those trees go, the others stay true.
TEST_F(MovedLightTrees, AMoveIntoTheOtherLightsShaftsDropsThoseTrees) {
    const Moved m = moveLightOne(scene_, *bvh_, *store_, LightMove{.translate = {-3, -0.375, 0}});
    EXPECT_EQ(m.kept.noneBecause, "");
    EXPECT_LT(m.kept.kept, patches_ - 2);
    EXPECT_GT(m.kept.kept, 0u);  // the floor's far patches (x near 4) see light 0 past it
    // The occluder under light 0 is in its shadow now: its tree is not kept.
    const PairKey shadowed{1, 0, m.scene.lights[0]};
    EXPECT_EQ(m.store->find(shadowed), nullptr);
    EXPECT_EQ(expectKeptTreesAreRebuiltOnes(m), m.kept.kept);
}

// Moved up by 1: y = 2 is above the scene's bounds (y <= 1), which the receivers' patches follow.
TEST_F(MovedLightTrees, AMoveThatChangesTheBoundsKeepsNone) {
    const Moved m = moveLightOne(scene_, *bvh_, *store_, LightMove{.translate = {0, 1, 0}});
    EXPECT_EQ(m.kept.kept, 0u);
    EXPECT_NE(m.kept.noneBecause.find("bounds"), std::string::npos) << m.kept.noneBecause;
    EXPECT_EQ(m.store->treeCount(), 0u);
}

}  // namespace moved_light_trees_test
}  // namespace penumbra
