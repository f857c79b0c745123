// VisibilityStore: the history trees of one scene, shared by every thread that needs them.
//
// A tree belongs to a (receiver face, receiver patch, light face) triple: receivers larger than
// patchFraction of the scene's diagonal are split into patches (visibility/receiver_patches.h),
// each with its own tree; a small face is one patch (patch 0, the whole face).
//
// Concurrency: find() never blocks on a build (it returns nullptr while a tree is missing or being
// built): the UI thread uses it. getOrBuild() builds a missing tree on the calling thread; when
// two threads ask for the same tree at once, one builds and the other waits for it. Trees never
// move once published: the pointers stay valid for the store's lifetime (clear() aside).
#pragma once

#include <array>
#include <atomic>
#include <compare>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <shared_mutex>
#include <unordered_map>
#include <vector>

#include "engine/scene/scene.h"
#include "visibility/history_tree.h"
#include "visibility/history_tree_builder.h"
#include "visibility/receiver_patches.h"

namespace penumbra {

class EmbreeScene;

struct PairKey {
    uint32_t receiver = 0;   // receiver face
    uint32_t patch = 0;      // patch of the receiver (0 for a face that is one patch)
    uint32_t lightFace = 0;  // light face (not the light number)
    auto operator<=>(const PairKey&) const = default;
};

// The hash of a PairKey for unordered containers (the store's shards, the scheduler's batch, the
// renderer's pair sets).
struct PairKeyHash {
    size_t operator()(const PairKey& k) const noexcept;
};

// A built tree and what building it took.
struct PairRecord {
    vis::HistoryTree tree;
    vis::BuildStats stats;
    // Of a partial tree's deferred occluders, those that lie in a face group of the store's BVH
    // (vis::FaceClusters::grouped), counted when the record is published (0 without a BVH): the
    // renderer answers such a tree's points without it when they are many (shading.cpp).
    size_t deferredGrouped = 0;
};

class VisibilityStore {
  public:
    struct Options {
        vis::BuildOptions build;
        // Receivers larger than this fraction of the scene diagonal are split; 0 = never.
        double patchFraction = 1.0 / 4;
    };

    // The scene (and the BVH, when given) must outlive the store. With a BVH, the occluder
    // candidates of a pair come from its shaft query; without, every face is a candidate.
    explicit VisibilityStore(const Scene& scene, const EmbreeScene* bvh = nullptr)
        : VisibilityStore(scene, bvh, Options{}) {}
    VisibilityStore(const Scene& scene, const EmbreeScene* bvh, const Options& options);
    ~VisibilityStore();
    VisibilityStore(const VisibilityStore&) = delete;
    VisibilityStore& operator=(const VisibilityStore&) = delete;

    const Scene& scene() const { return scene_; }
    const Options& options() const { return options_; }

    // The patches of a receiver face (computed on first use, thread-safe).
    const vis::ReceiverPatches& patches(uint32_t face) const;
    // How many patches a receiver face has (at least 1), without making them: what counting
    // every pair of a large scene needs (patches() keeps each face's patches once made).
    size_t patchCount(uint32_t face) const;
    // The key of the tree serving point x on `face` for light face `lightFace`: its patch's, or
    // where that pair was refined, the finest built sub-patch's tree holding x (below).
    // `patchHint`: a patch of `face` that held a neighbouring point (ReceiverPatches::find).
    PairKey keyAt(uint32_t face, const Vec3& x, uint32_t lightFace,
                  uint32_t patchHint = vis::ReceiverPatches::kNoHint) const;

    // Query-driven refinement. A pair whose queries the renderer found too expensive (a partial
    // tree of a patch under foliage) is refined: its patch is split into sub-patches
    // (kRefineCellsPerSide per side, subdivideReceiver's grid), each with its own tree, built
    // only for the sub-patches the caller asks for (those its expensive points lie in). A smaller
    // region of the receiver has a narrower shaft, fewer occluders and a tree that the build
    // budget completes more often. Each sub-patch tree is exact for the lines through its
    // sub-patch, like any patch's; keyAt returns it for x only once it is built, the parent's
    // otherwise, so the answer never waits for a build. Refined keys are levels below a patch
    // (at most kMaxRefineLevels), encoded in PairKey::patch above the patch's index; they are a
    // cache of the render: visibility files keep only the patches' own trees.
    static constexpr int kRefineCellsPerSide = 4;
    static constexpr int kMaxRefineLevels = 3;
    // How many levels below its receiver patch `key` is (0: a patch's own tree).
    static int refineLevel(const PairKey& key);
    // The index of the receiver patch `key` is for or lies in (PairKey::patch of level 0).
    static uint32_t patchOf(const PairKey& key);
    // Marks `key` refined (idempotent); false where it cannot be (kMaxRefineLevels reached, a
    // patch index too large for the encoding, a face too small to split).
    bool refine(const PairKey& key);
    // The key of the sub-patch of refined `key` that holds x (its tree may not be built).
    PairKey subKeyAt(const PairKey& key, const Vec3& x) const;
    // The part of the receiver the key's tree is for: its patch, or sub-patch (the whole face
    // when it is one patch).
    std::vector<Vec3> region(const PairKey& key) const;
    // Refined pairs so far.
    size_t refinedCount() const;

    // Non-blocking: the tree if it is built, else nullptr.
    const PairRecord* find(const PairKey& key) const;
    // Builds the tree if needed (on this thread) and returns it.
    const PairRecord& getOrBuild(const PairKey& key) { return getOrBuild(key, nullptr); }
    // The same, cancellable: when *cancel becomes true the build stops within a fraction of a
    // second and throws vis::BuildCancelled. Nothing is published then, and the entry can be
    // built again later (by this or another caller). A thread waiting for another's build of the
    // same key that gets cancelled takes the build over (with its own flag).
    const PairRecord& getOrBuild(const PairKey& key, const std::atomic<bool>* cancel);
    // The faces in a pair's shaft (the occluder candidates its tree is built from) and how many
    // of them lie in face groups of the BVH (vis::FaceClusters::grouped): what a tree would cost
    // and what the groups would spare, known before building it (an O(log n + faces) shaft
    // query). Without a BVH, every face is a candidate and none is grouped.
    struct ShaftCount {
        size_t faces = 0, grouped = 0;
    };
    ShaftCount shaftCount(const PairKey& key) const;
    // Adds a tree built elsewhere (e.g. read from a visibility file). Returns false (and keeps the
    // existing one) when the key is already present.
    bool insert(const PairKey& key, PairRecord record);

    // Every published tree, in no particular order (a snapshot; safe during builds).
    void forEach(const std::function<void(const PairKey&, const PairRecord&)>& visit) const;

    size_t treeCount() const { return treeCount_.load(std::memory_order_relaxed); }
    // Bytes of the published trees (HistoryTree::bytes plus debug data) — what the memory budget
    // of the precompute counts.
    size_t bytes() const { return bytes_.load(std::memory_order_relaxed); }
    // Published trees per PairKind (index = static_cast<int>(kind)).
    std::array<size_t, vis::kPairKindCount> kindCounts() const;
    // Published penumbra trees that are partial (the build budget stopped them).
    size_t partialCount() const { return partial_.load(std::memory_order_relaxed); }

    // Drops every tree (not thread-safe against concurrent users).
    void clear();

  private:
    struct Entry;
    struct Shard {
        mutable std::shared_mutex mutex;
        std::unordered_map<PairKey, std::unique_ptr<Entry>, PairKeyHash> entries;
    };
    struct PatchSlot;
    static constexpr size_t kShards = 64;

    Shard& shardOf(const PairKey& key) const;
    // Whether the key's tree is for the whole face (one patch, not refined): its shaft and
    // build take no receiver region.
    bool wholeFace(const PairKey& key) const;
    // The sub-patches of a refined key, or null.
    const vis::ReceiverPatches* refinedPatches(const PairKey& key) const;
    Entry& entryFor(const PairKey& key);
    void publish(Entry& entry, std::unique_ptr<PairRecord> record);
    std::unique_ptr<PairRecord> build(const PairKey& key, const std::atomic<bool>* cancel) const;
    // The pair's shaft candidates from the BVH (a non-empty list; the receiver alone stands for
    // "none"), or an empty list without a BVH (every face). Checks the key.
    std::vector<uint32_t> shaftCandidates(const PairKey& key) const;

    const Scene& scene_;
    const EmbreeScene* bvh_;
    Options options_;
    double maxPatchDiameter_ = 0;
    mutable std::array<Shard, kShards> shards_;
    std::vector<std::unique_ptr<PatchSlot>> patchSlots_;  // per face, filled on first use
    // The refined keys' sub-patches (never removed but by clear(); the pointers stay valid).
    mutable std::shared_mutex refinedMutex_;
    std::unordered_map<PairKey, std::unique_ptr<vis::ReceiverPatches>, PairKeyHash> refined_;
    std::atomic<size_t> treeCount_{0};
    std::atomic<size_t> bytes_{0};
    std::array<std::atomic<size_t>, vis::kPairKindCount> kinds_{};
    std::atomic<size_t> partial_{0};
};

}  // namespace penumbra
