// PatchLayout: which tree serves a point. On its own, keyAt serves a refined sub-patch only once
// its tree is built; in a store (query-driven refinement): a refined patch's sub-patch trees are
// exact for their sub-patches (checked against the exact CGAL reference and the parent's tree),
// keyAt serves them only once built, also to threads asking while another refines, the key
// encoding holds its levels, and visibility files keep the patches' own trees only. Built into
// penumbra_concurrency_tests, which CI also runs under ThreadSanitizer (scripts/run_tests.sh), all
// but the exact-reference test there.
#include "engine/precompute/patch_layout.h"

#include <gtest/gtest.h>

#include <atomic>
#include <filesystem>
#include <random>
#include <set>
#include <thread>
#include <vector>

#include "engine/io/visibility_file.h"
#include "engine/precompute/visibility_store.h"
#include "engine/raytrace/embree_scene.h"
#include "engine/scene/procedural_scenes.h"
#ifndef PENUMBRA_NO_EXACT_REFERENCE
#include "tests/support/exact_reference.h"
#endif
#include "tests/support/tree_reference.h"
#include "visibility/form_factor.h"
#include "visibility/fp_query/from_point_query.h"
#include "visibility/receiver_patches.h"

namespace penumbra {
namespace {

// The layout alone, with a set standing for the store's built trees: a refined patch's sub-patch
// key is served for x once (and only while) the set holds it; clearRefinements forgets the split.
TEST(PatchLayout, ServesASubPatchKeyOnlyOnceItsTreeIsBuilt) {
    const Scene scene = makeGrids();
    std::set<PairKey> built;
    PatchLayout layout(scene, VisibilityStore::Options{}.patchFraction,
                       [&](const PairKey& k) { return built.count(k) > 0; });
    const uint32_t light = scene.lights[0];
    const vis::ReceiverPatches& patches = layout.patches(0);
    ASSERT_GT(patches.patches.size(), 1u);
    EXPECT_EQ(layout.patchCount(0), patches.patches.size());
    const std::vector<Vec3>& t = patches.patches[patches.patches.size() / 2];
    const Vec3 x = t[0] * 0.2 + t[1] * 0.3 + t[2] * 0.5;
    const PairKey key = layout.keyAt(0, x, light);
    EXPECT_EQ(PatchLayout::refineLevel(key), 0);
    EXPECT_FALSE(layout.wholeFace(key));
    EXPECT_THROW(layout.subKeyAt(key, x), std::logic_error);

    ASSERT_TRUE(layout.refine(key));
    const PairKey sub = layout.subKeyAt(key, x);
    EXPECT_EQ(PatchLayout::refineLevel(sub), 1);
    EXPECT_EQ(PatchLayout::patchOf(sub), key.patch);
    EXPECT_FALSE(layout.wholeFace(sub));
    EXPECT_EQ(layout.region(sub).size(), 3u);
    EXPECT_EQ(layout.refinedCount(), 1u);
    EXPECT_EQ(layout.keyAt(0, x, light), key) << "served before it was built";
    built.insert(sub);
    EXPECT_EQ(layout.keyAt(0, x, light), sub);

    layout.clearRefinements();
    EXPECT_EQ(layout.refinedCount(), 0u);
    EXPECT_EQ(layout.keyAt(0, x, light), key);
    EXPECT_THROW(layout.region(sub), std::out_of_range);
}

// The table under its light (foliage: hundreds of leaves over the floor), with a small build
// budget so that the floor's patch trees are partial, as the renderer's are on the real scene.
struct TableRig {
    TableRig() : scene(makeTable()), bvh(scene.mesh), store(scene, &bvh, options()) {}
    static VisibilityStore::Options options() {
        VisibilityStore::Options o;
        o.build.maxLpSolves = 400;
        return o;
    }
    // The largest face that is not a light: the floor.
    uint32_t floor() const {
        uint32_t best = 0;
        for (uint32_t f = 0; f < scene.faceCount(); ++f)
            if (!scene.material(f).isEmissive() &&
                scene.mesh.faceArea(f) > scene.mesh.faceArea(best))
                best = f;
        return best;
    }
    Scene scene;
    EmbreeScene bvh;
    VisibilityStore store;
};

// The exact reference (CGAL) is not built under ThreadSanitizer (tests/CMakeLists.txt): this test
// runs no threads, and CI's TSan run would compile CGAL for it alone.
#ifndef PENUMBRA_NO_EXACT_REFERENCE

double visibleFraction(const Scene& scene, const vis::HistoryTree& tree, const Vec3& x) {
    vis::FromPointQuery query;
    const vis::FragmentList& list = query.run(scene.mesh, tree, x);
    double area = 0;
    for (size_t i = 0; i < list.size(); ++i) area += vis::polygonArea(list[i]);
    return area / scene.mesh.faceArea(tree.light);
}

// A point of triangle `t` shrunk by 1% about its centroid (inside it, away from its edges).
Vec3 pointIn(const std::vector<Vec3>& t, std::mt19937_64& rng) {
    std::uniform_real_distribution<double> u(0, 1);
    double a = u(rng), b = u(rng);
    if (a + b > 1) a = 1 - a, b = 1 - b;
    const Vec3 c = (t[0] + t[1] + t[2]) / 3.0;
    const Vec3 p = t[0] + (t[1] - t[0]) * a + (t[2] - t[0]) * b;
    return c + (p - c) * 0.99;
}

TEST(PatchLayout, RefinedSubPatchTreesMatchTheExactReferenceInTheirSubPatches) {
    TableRig rig;
    const uint32_t floor = rig.floor(), light = rig.scene.lights.at(0);
    // A floor patch in the penumbra whose tree is partial.
    std::mt19937_64 rng(7);
    PairKey key;
    Vec3 x;
    bool found = false;
    const vis::ReceiverPatches& patches = rig.store.layout().patches(floor);
    for (uint32_t p = 0; p < patches.patches.size() && !found; ++p) {
        const PairKey k{floor, p, light};
        const PairRecord& r = rig.store.getOrBuild(k);
        if (r.tree.kind != vis::PairKind::Penumbra || !r.tree.partial()) continue;
        for (int i = 0; i < 8 && !found; ++i) {
            const Vec3 y = pointIn(patches.patches[p], rng);
            const double f = visibleFraction(rig.scene, r.tree, y);
            if (f > 0.05 && f < 0.95 && rig.store.layout().keyAt(floor, y, light) == k) {
                key = k;
                x = y;
                found = true;
            }
        }
    }
    ASSERT_TRUE(found) << "no partial floor tree in the penumbra";
    ASSERT_EQ(PatchLayout::refineLevel(key), 0);

    // Two levels down from x's patch; keyAt moves to a sub-patch only once its tree is built.
    std::vector<PairKey> chain{key};
    for (int level = 1; level <= 2; ++level) {
        ASSERT_TRUE(rig.store.layout().refine(chain.back()));
        const PairKey sub = rig.store.layout().subKeyAt(chain.back(), x);
        EXPECT_EQ(PatchLayout::refineLevel(sub), level);
        EXPECT_EQ(rig.store.layout().keyAt(floor, x, light), chain.back())
            << "served before it was built";
        rig.store.getOrBuild(sub);
        EXPECT_EQ(rig.store.layout().keyAt(floor, x, light), sub);
        chain.push_back(sub);
    }
    // Each sub-patch lies in its parent (a quarter of its size per side, up to the growth).
    const std::vector<Vec3> outer = rig.store.layout().region(chain[0]),
                            inner = rig.store.layout().region(chain[2]);
    ASSERT_EQ(inner.size(), 3u);
    auto diameter = [](const std::vector<Vec3>& t) {
        return std::max({length(t[0] - t[1]), length(t[1] - t[2]), length(t[2] - t[0])});
    };
    EXPECT_NEAR(diameter(inner), diameter(outer) / 16, 1e-6 * diameter(outer));
    // A finer tree holds more of the shaft's occluders (fewer deferred to each point).
    const PairRecord& top = *rig.store.find(chain[0]);
    const PairRecord& finest = *rig.store.find(chain[2]);
    EXPECT_LT(finest.tree.deferred.size(), top.tree.deferred.size());

    // Points of the finest sub-patch: each tree of the chain (exact for its region, which holds
    // them) against the exact reference.
    int penumbra = 0;
    for (int i = 0; i < 10; ++i) {
        const Vec3 y = i == 0 ? x : pointIn(inner, rng);
        ASSERT_EQ(rig.store.layout().keyAt(floor, y, light), chain[2]);
        const double reference = test::exactReference(rig.scene.mesh, floor, light, y).fraction;
        penumbra += reference > 1e-6 && reference < 1 - 1e-6;
        for (const PairKey& k : chain)
            EXPECT_NEAR(visibleFraction(rig.scene, rig.store.find(k)->tree, y), reference, 1e-9)
                << "point " << i << ", level " << PatchLayout::refineLevel(k);
    }
    EXPECT_GT(penumbra, 0);
}

#endif  // PENUMBRA_NO_EXACT_REFERENCE

TEST(PatchLayout, RefinementStopsAtItsLevelsAndFilesKeepThePatchTreesOnly) {
    TableRig rig;
    const uint32_t floor = rig.floor(), light = rig.scene.lights.at(0);
    const Vec3 x = rig.store.layout().region({floor, 0, light})[0] * 0.5 +
                   rig.store.layout().region({floor, 0, light})[1] * 0.25 +
                   rig.store.layout().region({floor, 0, light})[2] * 0.25;
    PairKey key = rig.store.layout().keyAt(floor, x, light);
    rig.store.getOrBuild(key);
    for (int level = 0; level < PatchLayout::kMaxRefineLevels; ++level) {
        ASSERT_TRUE(rig.store.layout().refine(key));
        EXPECT_TRUE(rig.store.layout().refine(key));  // idempotent
        key = rig.store.layout().subKeyAt(key, x);
        rig.store.getOrBuild(key);
    }
    EXPECT_EQ(PatchLayout::refineLevel(key), PatchLayout::kMaxRefineLevels);
    EXPECT_FALSE(rig.store.layout().refine(key));
    EXPECT_EQ(rig.store.layout().keyAt(floor, x, light), key);
    EXPECT_EQ(rig.store.layout().refinedCount(),
              static_cast<size_t>(PatchLayout::kMaxRefineLevels));
    EXPECT_THROW(rig.store.layout().subKeyAt(key, x), std::logic_error);
    // A sub-patch key of a patch that was never refined names no region.
    PairKey stray{floor, 1, light};
    if (rig.store.layout().patches(floor).patches.size() > 1) {
        stray.patch |= 0x80000000u | (1u << 13);
        EXPECT_THROW(rig.store.layout().region(stray), std::out_of_range);
    }

    const auto file = std::filesystem::temp_directory_path() / "penumbra_refined_store.pvis";
    writeVisibilityFile(file, rig.store);
    VisibilityStore loaded(rig.scene, &rig.bvh, TableRig::options());
    EXPECT_EQ(readVisibilityFile(file, loaded), 1u);  // the patch's tree, not its sub-patches'
    EXPECT_EQ(loaded.layout().keyAt(floor, x, light),
              (PairKey{floor, PatchLayout::patchOf(key), light}));
    std::filesystem::remove(file);
}

// Query-driven refinement under concurrency: while one thread refines floor patches and builds
// their sub-patch trees, others ask keyAt for the same points. Each answer is the patch's key or
// the sub-patch's, never a tree not yet built; afterwards each sub-patch tree is the builder's own
// tree for that sub-patch, computed here from the patch by receiver_patches.h.
TEST(PatchLayout, KeyAtDuringRefinementServesOnlyBuiltTrees) {
    const Scene scene = makeGrids();
    VisibilityStore store(scene);  // no BVH: every face a candidate, as referenceTree builds
    const uint32_t light = scene.lights[0];
    const vis::ReceiverPatches& patches = store.layout().patches(0);
    ASSERT_GT(patches.patches.size(), 1u);
    std::vector<std::pair<PairKey, Vec3>> points;  // (patch key, a point inside its patch)
    for (uint32_t p = 0; p < patches.patches.size() && points.size() < 6; p += 3) {
        const std::vector<Vec3>& t = patches.patches[p];
        const Vec3 x = t[0] * 0.2 + t[1] * 0.3 + t[2] * 0.5;
        if (store.layout().keyAt(0, x, light) == PairKey{0, p, light})
            points.push_back({{0, p, light}, x});
    }
    ASSERT_GE(points.size(), 3u);
    for (const auto& [key, x] : points) store.getOrBuild(key);
    std::atomic<bool> done{false};
    std::atomic<int> wrong{0};
    auto ask = [&] {
        while (!done.load()) {
            for (const auto& [key, x] : points) {
                const PairKey k = store.layout().keyAt(0, x, light);
                if (k == key) continue;
                if (PatchLayout::refineLevel(k) != 1 || store.find(k) == nullptr ||
                    PatchLayout::patchOf(k) != key.patch)
                    wrong += 1;
            }
        }
    };
    std::thread a(ask), b(ask);
    std::vector<PairKey> subs;
    for (const auto& [key, x] : points) {
        ASSERT_TRUE(store.layout().refine(key));
        subs.push_back(store.layout().subKeyAt(key, x));
        store.getOrBuild(subs.back());
    }
    done = true;
    a.join();
    b.join();
    EXPECT_EQ(wrong.load(), 0);
    for (size_t i = 0; i < points.size(); ++i) {
        const auto& [key, x] = points[i];
        EXPECT_EQ(store.layout().keyAt(0, x, light), subs[i]);
        const vis::ReceiverPatches sub = vis::subdivideReceiverGrid(patches.patches[key.patch], 4);
        const vis::HistoryTree reference = vis::buildHistoryTree(
            scene.mesh, 0, light, store.options().build, {}, nullptr, sub.patches[sub.find(x)]);
        EXPECT_TRUE(test::sameTree(store.find(subs[i])->tree, reference)) << "point " << i;
    }
}

}  // namespace
}  // namespace penumbra
