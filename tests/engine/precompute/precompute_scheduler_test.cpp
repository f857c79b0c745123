// PrecomputeScheduler: it builds exactly the requested pairs and they equal direct
// vis::buildHistoryTree results; cancellation stops the running builds and leaves the store
// consistent; the memory budget stops it; failures are reported. These tests also run under
// ThreadSanitizer (scripts/run_tests.sh, build-tsan); the store's own cancellation and refinement
// tests are in visibility_store_test.cpp.
#include "engine/precompute/precompute_scheduler.h"

#include <gtest/gtest.h>

#include <algorithm>
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

// Cancel in the middle of a batch of the grids' 1,616 pairs (a few seconds of work in all, cheap
// to check one by one): the batch's count freezes, no pair starts afterwards (at most the builds
// running at the cancel may still publish: one per thread), and the store stays consistent.
TEST(PrecomputeScheduler, CancelStopsPromptlyAndLeavesTheStoreConsistent) {
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
    scheduler.cancel();
    const PrecomputeProgress p = scheduler.progress();
    scheduler.wait();
    EXPECT_EQ(p.state, State::Cancelled);
    EXPECT_LT(p.done, total);
    // Every pair built by the cancel was counted (the store holds this batch's trees only); after
    // it, only the builds then running may have finished.
    const size_t built = store.treeCount();
    EXPECT_GE(built, p.done);
    EXPECT_LE(built, p.done + static_cast<size_t>(scheduler.threads()))
        << "pairs kept being built after the cancel";
    // Nothing is built after wait() returned, and the progress stays frozen.
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
    EXPECT_EQ(store.treeCount(), built);
    EXPECT_EQ(scheduler.progress().state, State::Cancelled);
    EXPECT_EQ(scheduler.progress().done, p.done);

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

// The builds running at a cancel stop at their next check of the flag, not at their end: cancelled
// in the middle of the table's floor patches (most of them penumbra pairs under the foliage, builds
// of up to a tenth of a second), no tree is published after the cancel. (A build that ended in the
// instant between publishing its tree and counting it would count here: some microseconds against
// builds of milliseconds.)
TEST(PrecomputeScheduler, CancelStopsPromptlyEvenInTheMiddleOfLongBuilds) {
    const Scene scene = makeTable();
    const EmbreeScene bvh(scene.mesh);
    VisibilityStore store(scene, &bvh);
    uint32_t floor = 0;
    for (uint32_t f = 0; f < scene.faceCount(); ++f)
        if (!scene.material(f).isEmissive() && scene.mesh.faceArea(f) > scene.mesh.faceArea(floor))
            floor = f;
    std::vector<PairKey> keys;
    for (const PairKey& k : allKeys(scene, store.options().patchFraction))
        if (k.receiver == floor) keys.push_back(k);
    ASSERT_GT(keys.size(), 10u);
    PrecomputeScheduler scheduler(store, PrecomputeOptions{0, 2});
    scheduler.request(keys);
    for (PrecomputeProgress q = scheduler.progress(); q.done < 3 && q.state == State::Running;
         q = scheduler.progress())
        std::this_thread::sleep_for(std::chrono::milliseconds(1));
    scheduler.cancel();
    const PrecomputeProgress p = scheduler.progress();
    scheduler.wait();
    EXPECT_EQ(p.state, State::Cancelled);
    EXPECT_LT(p.done, keys.size());
    EXPECT_EQ(store.treeCount(), p.done) << "a running build went on to its end after the cancel";
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
