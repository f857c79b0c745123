// PrecomputeScheduler and the cancellable VisibilityStore::getOrBuild: the scheduler builds
// exactly the requested pairs and they equal direct vis::buildHistoryTree results; cancellation
// leaves the store consistent; the memory budget stops it; failures are reported. These tests
// also run under ThreadSanitizer (scripts/run_tests.sh, build-tsan).
#include "engine/precompute/precompute_scheduler.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <random>
#include <set>
#include <thread>

#include "engine/raytrace/embree_scene.h"
#include "engine/scene/procedural_scenes.h"
#include "tests/support/test_scale.h"
#include "tests/support/tree_reference.h"
#include "visibility/receiver_patches.h"

namespace penumbra {
namespace {

using State = PrecomputeProgress::State;
using Clock = std::chrono::steady_clock;

// Every (face, patch, light face) of a scene, enumerated here from the patches directly.
std::vector<PairKey> allKeys(const Scene& scene, double patchFraction) {
    const double maxPatch = patchFraction * scene.mesh.bounds().diagonal();
    std::vector<PairKey> keys;
    for (uint32_t f = 0; f < scene.faceCount(); ++f) {
        std::vector<Vec3> poly;
        for (uint32_t v : scene.mesh.faces[f]) poly.push_back(scene.mesh.vertices[v]);
        const size_t patches =
            std::max<size_t>(vis::subdivideReceiver(poly, maxPatch).patches.size(), 1);
        for (uint32_t p = 0; p < patches; ++p)
            for (uint32_t l : scene.lights)
                if (l != f) keys.push_back({f, p, l});
    }
    return keys;
}

std::set<PairKey> storedKeys(const VisibilityStore& store) {
    std::set<PairKey> out;
    store.forEach([&](const PairKey& k, const PairRecord&) { out.insert(k); });
    return out;
}

TEST(PrecomputeScheduler, BuildsExactlyTheRequestedPairsAsTheBuilderDoes) {
    const Scene scene = makeGrids();
    const EmbreeScene bvh(scene.mesh);
    VisibilityStore store(scene, &bvh);
    std::vector<PairKey> keys = allKeys(scene, store.options().patchFraction);
    std::mt19937_64 rng(5);
    std::shuffle(keys.begin(), keys.end(), rng);
    keys.resize(std::min<size_t>(keys.size(), test::scaled(60)));
    std::vector<PairKey> request = keys;
    request.push_back(keys[0]);  // duplicates are skipped
    request.push_back(keys[1]);
    PrecomputeScheduler scheduler(store, PrecomputeOptions{0, 2});
    scheduler.request(request);
    scheduler.wait();
    const PrecomputeProgress p = scheduler.progress();
    EXPECT_EQ(p.state, State::Idle);
    EXPECT_EQ(p.total, keys.size());
    EXPECT_EQ(p.done, keys.size());
    EXPECT_EQ(p.bytes, store.bytes());
    EXPECT_EQ(storedKeys(store), std::set<PairKey>(keys.begin(), keys.end()));
    size_t nodes = 0, penumbra = 0;
    for (const PairKey& k : keys) {
        const PairRecord* r = store.find(k);
        ASSERT_NE(r, nullptr);
        EXPECT_TRUE(test::sameTree(r->tree, test::referenceTree(store, k)))
            << "receiver " << k.receiver << " patch " << k.patch;
        nodes += r->tree.nodes.size();
        penumbra += r->tree.kind == vis::PairKind::Penumbra;
    }
    EXPECT_EQ(p.nodes, nodes);
    EXPECT_GT(penumbra, 0u);  // the sample must include real trees
}

TEST(PrecomputeScheduler, RequestAllCoversEveryPairOnce) {
    // A small hard case: every pair of its few faces.
    const auto cases = makeHardCases();
    const Scene& scene = cases.front().second;
    const EmbreeScene bvh(scene.mesh);
    VisibilityStore store(scene, &bvh);
    const std::vector<PairKey> expected = allKeys(scene, store.options().patchFraction);
    // One pair built beforehand counts as done without a build.
    store.getOrBuild(expected.back());
    PrecomputeScheduler scheduler(store);
    scheduler.requestAll();
    scheduler.requestAll();  // everything is queued or built already: nothing new
    scheduler.wait();
    const PrecomputeProgress p = scheduler.progress();
    EXPECT_EQ(p.state, State::Idle);
    EXPECT_EQ(p.total, expected.size());
    EXPECT_EQ(p.done, expected.size());
    EXPECT_EQ(storedKeys(store), std::set<PairKey>(expected.begin(), expected.end()));
    EXPECT_EQ(store.treeCount(), expected.size());
    EXPECT_EQ(p.secondsLeft, 0.0);
}

TEST(PrecomputeScheduler, LaterRequestIsServedFirst) {
    const Scene scene = makeGrids();
    const EmbreeScene bvh(scene.mesh);
    VisibilityStore store(scene, &bvh);
    const std::vector<PairKey> keys = allKeys(scene, store.options().patchFraction);
    ASSERT_GT(keys.size(), 400u);
    const std::vector<PairKey> older(keys.begin() + 200, keys.begin() + 400);
    const std::vector<PairKey> urgent(keys.end() - 3, keys.end());
    PrecomputeScheduler scheduler(store, PrecomputeOptions{0, 1});
    scheduler.request(older);
    scheduler.request(urgent);
    for (;;) {
        if (std::all_of(urgent.begin(), urgent.end(),
                        [&](const PairKey& k) { return store.find(k) != nullptr; }))
            break;
        std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
    const size_t olderDone =
        std::count_if(older.begin(), older.end(), [&](const PairKey& k) { return store.find(k); });
    scheduler.cancel();
    scheduler.wait();
    // One thread: at most the older pair it was building when the urgent ones arrived (and the
    // few it finished meanwhile) precede them; far from all 200.
    EXPECT_LT(olderDone, older.size() / 2);
}

TEST(PrecomputeScheduler, CancelStopsPromptlyAndLeavesTheStoreConsistent) {
    // The grids: 1,616 pairs, a few seconds of work in all, cheap to check one by one.
    const Scene scene = makeGrids();
    const EmbreeScene bvh(scene.mesh);
    VisibilityStore store(scene, &bvh);
    const std::vector<PairKey> keys = allKeys(scene, store.options().patchFraction);
    PrecomputeScheduler scheduler(store, PrecomputeOptions{0, 2});
    scheduler.request(keys);
    const size_t total = scheduler.progress().total;
    EXPECT_EQ(total, keys.size());
    // Let some builds run, then cancel in the middle of them.
    for (PrecomputeProgress q = scheduler.progress(); q.done < 5 && q.state == State::Running;
         q = scheduler.progress())
        std::this_thread::sleep_for(std::chrono::milliseconds(1));
    const auto t0 = Clock::now();
    scheduler.cancel();
    const auto t1 = Clock::now();
    const PrecomputeProgress p = scheduler.progress();
    scheduler.wait();
    const auto t2 = Clock::now();
    std::printf("cancel() returned in %.3f ms; running builds stopped %.1f ms after it\n",
                std::chrono::duration<double, std::milli>(t1 - t0).count(),
                std::chrono::duration<double, std::milli>(t2 - t1).count());
    EXPECT_EQ(p.state, State::Cancelled);
    EXPECT_LT(p.done, total);
    const size_t built = store.treeCount();
    EXPECT_LT(built, total);
    // Nothing is built after wait() returned, and the progress stays frozen.
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
    EXPECT_EQ(store.treeCount(), built);
    EXPECT_EQ(scheduler.progress().state, State::Cancelled);

    // Every published tree is whole (equal to a direct build); pairs not built (including the
    // ones whose build was cut short) build normally afterwards.
    std::vector<PairKey> missing;
    for (const PairKey& k : keys)
        if (store.find(k) == nullptr) missing.push_back(k);
    ASSERT_FALSE(missing.empty());
    size_t checked = 0;
    store.forEach([&](const PairKey& k, const PairRecord& r) {
        if (checked++ < 20) {
            EXPECT_TRUE(test::sameTree(r.tree, test::referenceTree(store, k)));
        }
    });
    missing.resize(std::min<size_t>(missing.size(), 8));
    for (const PairKey& k : missing)
        EXPECT_TRUE(test::sameTree(store.getOrBuild(k).tree, test::referenceTree(store, k)));
    // A new request after a cancel starts a new batch and completes.
    const std::vector<PairKey> more = {missing.begin(), missing.end()};
    scheduler.request(more);
    scheduler.wait();
    EXPECT_EQ(scheduler.progress().state, State::Idle);
    EXPECT_EQ(scheduler.progress().done, more.size());
}

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

// Query-driven refinement under concurrency: while one thread refines floor patches and builds
// their sub-patch trees, others ask keyAt for the same points. Each answer is the patch's key or
// the sub-patch's, never a tree not yet built; afterwards each sub-patch tree is the builder's own
// tree for that sub-patch, computed here from the patch by receiver_patches.h.
TEST(VisibilityStore, KeyAtDuringRefinementServesOnlyBuiltTrees) {
    const Scene scene = makeGrids();
    VisibilityStore store(scene);  // no BVH: every face a candidate, as referenceTree builds
    const uint32_t light = scene.lights[0];
    const vis::ReceiverPatches& patches = store.patches(0);
    ASSERT_GT(patches.patches.size(), 1u);
    std::vector<std::pair<PairKey, Vec3>> points;  // (patch key, a point inside its patch)
    for (uint32_t p = 0; p < patches.patches.size() && points.size() < 6; p += 3) {
        const std::vector<Vec3>& t = patches.patches[p];
        const Vec3 x = t[0] * 0.2 + t[1] * 0.3 + t[2] * 0.5;
        if (store.keyAt(0, x, light) == PairKey{0, p, light}) points.push_back({{0, p, light}, x});
    }
    ASSERT_GE(points.size(), 3u);
    for (const auto& [key, x] : points) store.getOrBuild(key);
    std::atomic<bool> done{false};
    std::atomic<int> wrong{0};
    auto ask = [&] {
        while (!done.load()) {
            for (const auto& [key, x] : points) {
                const PairKey k = store.keyAt(0, x, light);
                if (k == key) continue;
                if (VisibilityStore::refineLevel(k) != 1 || store.find(k) == nullptr ||
                    VisibilityStore::patchOf(k) != key.patch)
                    wrong += 1;
            }
        }
    };
    std::thread a(ask), b(ask);
    std::vector<PairKey> subs;
    for (const auto& [key, x] : points) {
        ASSERT_TRUE(store.refine(key));
        subs.push_back(store.subKeyAt(key, x));
        store.getOrBuild(subs.back());
    }
    done = true;
    a.join();
    b.join();
    EXPECT_EQ(wrong.load(), 0);
    for (size_t i = 0; i < points.size(); ++i) {
        const auto& [key, x] = points[i];
        EXPECT_EQ(store.keyAt(0, x, light), subs[i]);
        const vis::ReceiverPatches sub = vis::subdivideReceiverGrid(patches.patches[key.patch], 4);
        const vis::HistoryTree reference = vis::buildHistoryTree(
            scene.mesh, 0, light, store.options().build, {}, nullptr, sub.patches[sub.find(x)]);
        EXPECT_TRUE(test::sameTree(store.find(subs[i])->tree, reference)) << "point " << i;
    }
}

TEST(PrecomputeScheduler, MemoryBudgetStopsScheduling) {
    const Scene scene = makeGrids();
    const EmbreeScene bvh(scene.mesh);
    VisibilityStore store(scene, &bvh);
    PrecomputeScheduler scheduler(store, PrecomputeOptions{1, 1});  // one byte: the first tree
    scheduler.requestAll();
    scheduler.wait();
    const PrecomputeProgress p = scheduler.progress();
    EXPECT_EQ(p.state, State::OverBudget);
    EXPECT_GT(store.bytes(), 1u);
    EXPECT_LT(p.done, p.total);
    // One thread: the build that crossed the budget was the last one.
    EXPECT_EQ(store.kindCounts()[static_cast<int>(vis::PairKind::Penumbra)], 1u);
    // Over budget already: a new request schedules nothing.
    const size_t trees = store.treeCount();
    scheduler.request(allKeys(scene, store.options().patchFraction));
    scheduler.wait();
    EXPECT_EQ(scheduler.progress().state, State::OverBudget);
    EXPECT_EQ(store.treeCount(), trees);
}

TEST(PrecomputeScheduler, BuildErrorStopsWithAMessageNamingThePair) {
    const Scene scene = makeGrids();
    VisibilityStore store(scene);
    PrecomputeScheduler scheduler(store);
    scheduler.request({{1, 999, scene.lights[0]}});
    scheduler.wait();
    const PrecomputeProgress p = scheduler.progress();
    EXPECT_EQ(p.state, State::Failed);
    EXPECT_NE(p.error.find("patch 999"), std::string::npos) << p.error;
    EXPECT_NE(p.error.find("receiver 1"), std::string::npos) << p.error;
}

TEST(PrecomputeScheduler, DestructorCancelsRunningWork) {
    const Scene scene = makeTable();
    const EmbreeScene bvh(scene.mesh);
    VisibilityStore store(scene, &bvh);
    Clock::time_point leaving;
    {
        // The table's floor patches come first: builds of a second or more each.
        PrecomputeScheduler scheduler(store, PrecomputeOptions{0, 2});
        scheduler.requestAll();
        std::this_thread::sleep_for(std::chrono::milliseconds(100));
        leaving = Clock::now();
    }  // must return without finishing the table
    std::printf("destructor (cancel, then wait for the running floor builds) took %.1f ms\n",
                std::chrono::duration<double, std::milli>(Clock::now() - leaving).count());
    const size_t built = store.treeCount();
    EXPECT_LT(built, allKeys(scene, store.options().patchFraction).size());
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
    EXPECT_EQ(store.treeCount(), built);  // nothing runs any more
}

}  // namespace
}  // namespace penumbra
