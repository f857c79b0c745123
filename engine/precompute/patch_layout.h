// PatchLayout: which history tree serves a point of a receiver, named by its PairKey.
//
// Receivers larger than patchFraction of the scene's diagonal are split into patches
// (visibility/receiver_patches.h), each with its own tree; a small face is one patch (patch 0, the
// whole face). Query-driven refinement splits a patch further where the renderer asks (refine,
// below). The VisibilityStore owns one layout (VisibilityStore::layout) and builds the trees it
// names; the layout asks the store only whether a tree is built (keyAt serves a sub-patch's key
// once its tree is there).
//
// Concurrency: every method may be called from any thread while others run, clearRefinements()
// aside. A face's patches are made on first use (once, under a std::once_flag) and never change;
// refine() adds sub-patches under a lock that keyAt, subKeyAt and region share; a refined
// pair's sub-patches never move (their pointers stay valid until clearRefinements()).
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <shared_mutex>
#include <unordered_map>
#include <vector>

#include "engine/precompute/pair_key.h"
#include "engine/scene/scene.h"
#include "visibility/receiver_patches.h"

namespace penumbra {

class PatchLayout {
  public:
    // Whether the tree of `key` is built (non-blocking): the store's find.
    using IsBuilt = std::function<bool(const PairKey& key)>;

    // Receivers larger than `patchFraction` of the scene's diagonal are split; 0 = never. The
    // scene must outlive the layout.
    PatchLayout(const Scene& scene, double patchFraction, IsBuilt isBuilt);
    ~PatchLayout();
    PatchLayout(const PatchLayout&) = delete;
    PatchLayout& operator=(const PatchLayout&) = delete;

    // The patches of a receiver face (computed on first use, thread-safe).
    const vis::ReceiverPatches& patches(uint32_t face) const;
    // The largest diameter a patch may have (patchFraction of the mesh's bounds' diagonal; 0:
    // faces are not split): two layouts with the same one split every unchanged face alike.
    double maxPatchDiameter() const { return maxPatchDiameter_; }
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
    // when it is one patch). Throws std::out_of_range for a key that names none.
    std::vector<Vec3> region(const PairKey& key) const;
    // Whether the key's tree is for the whole face (one patch, not refined): its shaft and
    // build take no receiver region.
    bool wholeFace(const PairKey& key) const;
    // Refined pairs so far.
    size_t refinedCount() const;
    // Forgets every refinement (not thread-safe against concurrent users): the store's clear().
    void clearRefinements();

  private:
    struct PatchSlot;
    // The sub-patches of a refined key, or null.
    const vis::ReceiverPatches* refinedPatches(const PairKey& key) const;

    const Scene& scene_;
    double maxPatchDiameter_ = 0;
    IsBuilt isBuilt_;
    std::vector<std::unique_ptr<PatchSlot>> patchSlots_;  // per face, filled on first use
    // The refined keys' sub-patches (never removed but by clearRefinements(); the pointers stay
    // valid).
    mutable std::shared_mutex refinedMutex_;
    std::unordered_map<PairKey, std::unique_ptr<vis::ReceiverPatches>, PairKeyHash> refined_;
};

}  // namespace penumbra
