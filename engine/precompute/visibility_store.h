// VisibilityStore: the history trees of one scene, shared by every thread that needs them.
//
// A tree belongs to a (receiver face, receiver patch, light face) triple, a PairKey
// (pair_key.h); which key serves a point, the receivers' patches and their query-driven
// refinement are the store's PatchLayout (patch_layout.h, layout()).
//
// Concurrency: find() never blocks on a build (it returns nullptr while a tree is missing or being
// built): the UI thread uses it. getOrBuild() builds a missing tree on the calling thread; when
// two threads ask for the same tree at once, one builds and the other waits for it. Trees never
// move once published: the pointers stay valid for the store's lifetime (clear() aside). The
// layout is as thread-safe (patch_layout.h).
#pragma once

#include <array>
#include <atomic>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <shared_mutex>
#include <unordered_map>
#include <vector>

#include "engine/precompute/pair_key.h"
#include "engine/precompute/patch_layout.h"
#include "engine/scene/scene.h"
#include "visibility/history_tree.h"
#include "visibility/history_tree_builder.h"

namespace penumbra {

class EmbreeScene;

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

    // Which tree serves a point: the receivers' patches and their refinement. The non-const
    // one refines (PatchLayout::refine); both are safe to use from any thread.
    const PatchLayout& layout() const { return layout_; }
    PatchLayout& layout() { return layout_; }

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
    static constexpr size_t kShards = 64;

    Shard& shardOf(const PairKey& key) const;
    Entry& entryFor(const PairKey& key);
    void publish(Entry& entry, std::unique_ptr<PairRecord> record);
    std::unique_ptr<PairRecord> build(const PairKey& key, const std::atomic<bool>* cancel) const;
    // The pair's shaft candidates from the BVH (a non-empty list; the receiver alone stands for
    // "none"), or an empty list without a BVH (every face). Checks the key.
    std::vector<uint32_t> shaftCandidates(const PairKey& key) const;

    const Scene& scene_;
    const EmbreeScene* bvh_;
    Options options_;
    mutable std::array<Shard, kShards> shards_;
    PatchLayout layout_;
    std::atomic<size_t> treeCount_{0};
    std::atomic<size_t> bytes_{0};
    std::array<std::atomic<size_t>, vis::kPairKindCount> kinds_{};
    std::atomic<size_t> partial_{0};
};

}  // namespace penumbra
