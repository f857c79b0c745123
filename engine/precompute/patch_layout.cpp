#include "engine/precompute/patch_layout.h"

#include <algorithm>
#include <atomic>
#include <mutex>
#include <stdexcept>
#include <string>

namespace penumbra {

struct PatchLayout::PatchSlot {
    std::once_flag once;
    vis::ReceiverPatches patches;
    std::atomic<bool> refined{false};  // some pair of this face was refined (keyAt's fast path)
};

// A named namespace, not an anonymous one: the unity build puts files together.
namespace patch_layout_detail {
// PairKey::patch of a refined key: kRefinedFlag, the receiver patch's index in the low
// kBaseBits, then per level kLevelBits holding the sub-patch's index + 1 (0: no such level). A
// patch's own key is its index (a face with more patches than kBaseBits hold is not refined).
constexpr int kBaseBits = 13, kLevelBits = 6;
constexpr uint32_t kRefinedFlag = 0x80000000u;
constexpr uint32_t kLevelMask = (1u << kLevelBits) - 1;
constexpr uint32_t kMaxSubPatches = kLevelMask;  // indices + 1 up to the mask
static_assert(kBaseBits + PatchLayout::kMaxRefineLevels * kLevelBits < 32);

uint32_t levelField(uint32_t patch, int level) {  // level >= 1
    return (patch >> (kBaseBits + (level - 1) * kLevelBits)) & kLevelMask;
}
// The key of the sub-patch `sub` of `key` (at `level`, its refineLevel).
PairKey childKey(PairKey key, int level, uint32_t sub) {
    key.patch |= kRefinedFlag | ((sub + 1) << (kBaseBits + level * kLevelBits));
    return key;
}
// `key` one level up (its parent's key); level = refineLevel(key) >= 1.
PairKey parentKey(PairKey key, int level) {
    key.patch &= ~(kLevelMask << (kBaseBits + (level - 1) * kLevelBits));
    if (level == 1) key.patch &= ~kRefinedFlag;
    return key;
}
}  // namespace patch_layout_detail

PatchLayout::PatchLayout(const Scene& scene, double patchFraction, IsBuilt isBuilt)
    : scene_(scene), isBuilt_(std::move(isBuilt)) {
    maxPatchDiameter_ = patchFraction > 0 ? patchFraction * scene.mesh.bounds().diagonal() : 0;
    patchSlots_.resize(scene.faceCount());
    for (auto& slot : patchSlots_) slot = std::make_unique<PatchSlot>();
}

PatchLayout::~PatchLayout() = default;

const vis::ReceiverPatches& PatchLayout::patches(uint32_t face) const {
    if (face >= patchSlots_.size())
        throw std::out_of_range("face " + std::to_string(face) + " out of range");
    PatchSlot& slot = *patchSlots_[face];
    std::call_once(slot.once, [&] {
        std::vector<Vec3> polygon;
        for (uint32_t v : scene_.mesh.faces[face]) polygon.push_back(scene_.mesh.vertices[v]);
        slot.patches = vis::subdivideReceiver(polygon, maxPatchDiameter_);
    });
    return slot.patches;
}

size_t PatchLayout::patchCount(uint32_t face) const {
    if (face >= patchSlots_.size())
        throw std::out_of_range("face " + std::to_string(face) + " out of range");
    std::vector<Vec3> polygon;
    for (uint32_t v : scene_.mesh.faces[face]) polygon.push_back(scene_.mesh.vertices[v]);
    return std::max<size_t>(1, vis::receiverPatchCount(polygon, maxPatchDiameter_));
}

PairKey PatchLayout::keyAt(uint32_t face, const Vec3& x, uint32_t lightFace,
                           uint32_t patchHint) const {
    using namespace patch_layout_detail;
    const vis::ReceiverPatches& p = patches(face);
    PairKey key{face, p.patches.size() <= 1 ? 0u : p.find(x, patchHint), lightFace};
    if (!patchSlots_[face]->refined.load(std::memory_order_acquire)) return key;
    std::shared_lock lock(refinedMutex_);
    for (auto it = refined_.find(key); it != refined_.end(); it = refined_.find(key)) {
        const PairKey sub = childKey(key, refineLevel(key), it->second->find(x));
        if (!isBuilt_(sub)) break;  // not built (yet): the parent's tree answers
        key = sub;
    }
    return key;
}

uint32_t PatchLayout::patchOf(const PairKey& key) {
    using namespace patch_layout_detail;
    return (key.patch & kRefinedFlag) == 0 ? key.patch : key.patch & ((1u << kBaseBits) - 1);
}

bool PatchLayout::wholeFace(const PairKey& key) const {
    return patches(key.receiver).patches.size() <= 1 && refineLevel(key) == 0;
}

int PatchLayout::refineLevel(const PairKey& key) {
    using namespace patch_layout_detail;
    if ((key.patch & kRefinedFlag) == 0) return 0;
    int level = 0;
    while (level < kMaxRefineLevels && levelField(key.patch, level + 1) != 0) ++level;
    return level;
}

const vis::ReceiverPatches* PatchLayout::refinedPatches(const PairKey& key) const {
    std::shared_lock lock(refinedMutex_);
    const auto it = refined_.find(key);
    return it == refined_.end() ? nullptr : it->second.get();
}

std::vector<Vec3> PatchLayout::region(const PairKey& key) const {
    using namespace patch_layout_detail;
    const int level = refineLevel(key);
    if (level == 0) {
        const vis::ReceiverPatches& p = patches(key.receiver);
        if (p.patches.empty() && key.patch == 0) return p.face;  // a degenerate face: itself
        if (key.patch >= p.patches.size())
            throw std::out_of_range("patch " + std::to_string(key.patch) + " of face " +
                                    std::to_string(key.receiver) + " out of range");
        return p.patches[key.patch];
    }
    const vis::ReceiverPatches* parent = refinedPatches(parentKey(key, level));
    const uint32_t sub = levelField(key.patch, level) - 1;
    if (parent == nullptr || sub >= parent->patches.size())
        throw std::out_of_range("sub-patch " + std::to_string(key.patch) + " of face " +
                                std::to_string(key.receiver) + " is not a refined one");
    return parent->patches[sub];
}

bool PatchLayout::refine(const PairKey& key) {
    using namespace patch_layout_detail;
    const int level = refineLevel(key);
    // Room for one more level: a patch index within kBaseBits, a well-formed key.
    const uint32_t used = kBaseBits + static_cast<uint32_t>(level) * kLevelBits;
    if (level >= kMaxRefineLevels || ((key.patch & ~kRefinedFlag) >> used) != 0) return false;
    if (refinedPatches(key) != nullptr) return true;
    const std::vector<Vec3> polygon = region(key);  // checks the key
    auto sub = std::make_unique<vis::ReceiverPatches>(
        vis::subdivideReceiverGrid(polygon, kRefineCellsPerSide, patches(key.receiver).dropAxis));
    if (sub->patches.size() < 2 || sub->patches.size() > kMaxSubPatches) return false;
    std::unique_lock lock(refinedMutex_);
    refined_.try_emplace(key, std::move(sub));
    patchSlots_[key.receiver]->refined.store(true, std::memory_order_release);
    return true;
}

PairKey PatchLayout::subKeyAt(const PairKey& key, const Vec3& x) const {
    using namespace patch_layout_detail;
    const vis::ReceiverPatches* sub = refinedPatches(key);
    if (sub == nullptr) throw std::logic_error("subKeyAt: the pair is not refined");
    return childKey(key, refineLevel(key), sub->find(x));
}

size_t PatchLayout::refinedCount() const {
    std::shared_lock lock(refinedMutex_);
    return refined_.size();
}

void PatchLayout::clearRefinements() {
    {
        std::unique_lock lock(refinedMutex_);
        refined_.clear();
    }
    for (auto& slot : patchSlots_) slot->refined.store(false, std::memory_order_relaxed);
}

}  // namespace penumbra
