#include "engine/precompute/visibility_store.h"

#include <chrono>
#include <condition_variable>
#include <stdexcept>
#include <string>

#include "engine/raytrace/embree_scene.h"

namespace penumbra {

struct VisibilityStore::Entry {
    std::atomic<const PairRecord*> ready{nullptr};
    std::mutex mutex;  // guards building / record
    std::condition_variable done;
    bool building = false;
    std::unique_ptr<PairRecord> record;
};

struct VisibilityStore::PatchSlot {
    std::once_flag once;
    vis::ReceiverPatches patches;
    std::atomic<bool> refined{false};  // some pair of this face was refined (keyAt's fast path)
};

namespace {
// PairKey::patch of a refined key: kRefinedFlag, the receiver patch's index in the low
// kBaseBits, then per level kLevelBits holding the sub-patch's index + 1 (0: no such level). A
// patch's own key is its index (a face with more patches than kBaseBits hold is not refined).
constexpr int kBaseBits = 13, kLevelBits = 6;
constexpr uint32_t kRefinedFlag = 0x80000000u;
constexpr uint32_t kLevelMask = (1u << kLevelBits) - 1;
constexpr uint32_t kMaxSubPatches = kLevelMask;  // indices + 1 up to the mask
static_assert(kBaseBits + VisibilityStore::kMaxRefineLevels * kLevelBits < 32);

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
}  // namespace

size_t PairKeyHash::operator()(const PairKey& k) const noexcept {
    uint64_t h = 0x9E3779B97F4A7C15ull;
    for (uint32_t v : {k.receiver, k.patch, k.lightFace}) {
        h ^= v;
        h *= 0xBF58476D1CE4E5B9ull;
        h ^= h >> 31;
    }
    return static_cast<size_t>(h);
}

VisibilityStore::VisibilityStore(const Scene& scene, const EmbreeScene* bvh, const Options& options)
    : scene_(scene), bvh_(bvh), options_(options) {
    maxPatchDiameter_ =
        options_.patchFraction > 0 ? options_.patchFraction * scene.mesh.bounds().diagonal() : 0;
    patchSlots_.resize(scene.faceCount());
    for (auto& slot : patchSlots_) slot = std::make_unique<PatchSlot>();
}

VisibilityStore::~VisibilityStore() = default;

const vis::ReceiverPatches& VisibilityStore::patches(uint32_t face) const {
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

size_t VisibilityStore::patchCount(uint32_t face) const {
    if (face >= patchSlots_.size())
        throw std::out_of_range("face " + std::to_string(face) + " out of range");
    std::vector<Vec3> polygon;
    for (uint32_t v : scene_.mesh.faces[face]) polygon.push_back(scene_.mesh.vertices[v]);
    return std::max<size_t>(1, vis::receiverPatchCount(polygon, maxPatchDiameter_));
}

PairKey VisibilityStore::keyAt(uint32_t face, const Vec3& x, uint32_t lightFace,
                               uint32_t patchHint) const {
    const vis::ReceiverPatches& p = patches(face);
    PairKey key{face, p.patches.size() <= 1 ? 0u : p.find(x, patchHint), lightFace};
    if (!patchSlots_[face]->refined.load(std::memory_order_acquire)) return key;
    std::shared_lock lock(refinedMutex_);
    for (auto it = refined_.find(key); it != refined_.end(); it = refined_.find(key)) {
        const PairKey sub = childKey(key, refineLevel(key), it->second->find(x));
        if (find(sub) == nullptr) break;  // not built (yet): the parent's tree answers
        key = sub;
    }
    return key;
}

uint32_t VisibilityStore::patchOf(const PairKey& key) {
    return (key.patch & kRefinedFlag) == 0 ? key.patch : key.patch & ((1u << kBaseBits) - 1);
}

bool VisibilityStore::wholeFace(const PairKey& key) const {
    return patches(key.receiver).patches.size() <= 1 && refineLevel(key) == 0;
}

int VisibilityStore::refineLevel(const PairKey& key) {
    if ((key.patch & kRefinedFlag) == 0) return 0;
    int level = 0;
    while (level < kMaxRefineLevels && levelField(key.patch, level + 1) != 0) ++level;
    return level;
}

const vis::ReceiverPatches* VisibilityStore::refinedPatches(const PairKey& key) const {
    std::shared_lock lock(refinedMutex_);
    const auto it = refined_.find(key);
    return it == refined_.end() ? nullptr : it->second.get();
}

std::vector<Vec3> VisibilityStore::region(const PairKey& key) const {
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

bool VisibilityStore::refine(const PairKey& key) {
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

PairKey VisibilityStore::subKeyAt(const PairKey& key, const Vec3& x) const {
    const vis::ReceiverPatches* sub = refinedPatches(key);
    if (sub == nullptr) throw std::logic_error("subKeyAt: the pair is not refined");
    return childKey(key, refineLevel(key), sub->find(x));
}

size_t VisibilityStore::refinedCount() const {
    std::shared_lock lock(refinedMutex_);
    return refined_.size();
}

VisibilityStore::Shard& VisibilityStore::shardOf(const PairKey& key) const {
    return shards_[PairKeyHash{}(key) % kShards];
}

const PairRecord* VisibilityStore::find(const PairKey& key) const {
    Shard& shard = shardOf(key);
    std::shared_lock lock(shard.mutex);
    const auto it = shard.entries.find(key);
    return it == shard.entries.end() ? nullptr : it->second->ready.load(std::memory_order_acquire);
}

VisibilityStore::Entry& VisibilityStore::entryFor(const PairKey& key) {
    Shard& shard = shardOf(key);
    {
        std::shared_lock lock(shard.mutex);
        const auto it = shard.entries.find(key);
        if (it != shard.entries.end()) return *it->second;
    }
    std::unique_lock lock(shard.mutex);
    auto& slot = shard.entries[key];
    if (!slot) slot = std::make_unique<Entry>();
    return *slot;
}

void VisibilityStore::publish(Entry& entry, std::unique_ptr<PairRecord> record) {
    if (bvh_ != nullptr) {
        const vis::FaceClusters& groups = bvh_->faceClusters();
        record->deferredGrouped = 0;
        for (const vis::DeferredOccluder& d : record->tree.deferred)
            record->deferredGrouped += groups.grouped(d.face);
    }
    const PairRecord* raw = record.get();
    bytes_.fetch_add(raw->tree.bytes() + raw->tree.nodeOccluder.size() * sizeof(uint32_t),
                     std::memory_order_relaxed);
    kinds_[static_cast<int>(raw->tree.kind)].fetch_add(1, std::memory_order_relaxed);
    if (raw->tree.partial()) partial_.fetch_add(1, std::memory_order_relaxed);
    treeCount_.fetch_add(1, std::memory_order_relaxed);
    entry.record = std::move(record);
    entry.ready.store(raw, std::memory_order_release);
}

std::vector<uint32_t> VisibilityStore::shaftCandidates(const PairKey& key) const {
    if (key.receiver >= scene_.faceCount() || key.lightFace >= scene_.faceCount())
        throw std::out_of_range("pair (" + std::to_string(key.receiver) + ", " +
                                std::to_string(key.lightFace) + ") out of range");
    const bool whole = wholeFace(key);
    const std::vector<Vec3> patch = region(key);  // checks the patch
    std::vector<uint32_t> candidates;
    if (bvh_ != nullptr) {
        // The patch's own shaft: a floor patch far from the scene's clutter sees none of it.
        candidates = whole ? bvh_->shaftCandidates(key.receiver, key.lightFace)
                           : bvh_->shaftCandidates(key.receiver, patch, key.lightFace);
        // An empty candidate list means "all faces" to the builder; the receiver alone never
        // occludes its own pair, so it stands for "none".
        if (candidates.empty()) candidates.push_back(key.receiver);
    }
    return candidates;
}

VisibilityStore::ShaftCount VisibilityStore::shaftCount(const PairKey& key) const {
    const std::vector<uint32_t> candidates = shaftCandidates(key);
    if (bvh_ == nullptr) return {scene_.faceCount(), 0};
    ShaftCount count{candidates.size(), 0};
    const vis::FaceClusters& groups = bvh_->faceClusters();
    for (uint32_t f : candidates) count.grouped += groups.grouped(f);
    return count;
}

std::unique_ptr<PairRecord> VisibilityStore::build(const PairKey& key,
                                                   const std::atomic<bool>* cancel) const {
    const std::vector<uint32_t> candidates = shaftCandidates(key);
    const std::vector<Vec3> patch = wholeFace(key) ? std::vector<Vec3>{} : region(key);
    auto record = std::make_unique<PairRecord>();
    vis::BuildOptions buildOptions = options_.build;
    if (cancel != nullptr) buildOptions.cancel = cancel;
    record->tree = vis::buildHistoryTree(scene_.mesh, key.receiver, key.lightFace, buildOptions,
                                         candidates, &record->stats, patch);
    return record;
}

const PairRecord& VisibilityStore::getOrBuild(const PairKey& key, const std::atomic<bool>* cancel) {
    Entry& entry = entryFor(key);
    if (const PairRecord* r = entry.ready.load(std::memory_order_acquire)) return *r;
    std::unique_lock lock(entry.mutex);
    // Another thread is building it: wait, but keep honouring our own cancel flag.
    while (entry.building) {
        if (cancel == nullptr) {
            entry.done.wait(lock);
        } else {
            if (cancel->load(std::memory_order_relaxed)) throw vis::BuildCancelled();
            entry.done.wait_for(lock, std::chrono::milliseconds(20));
        }
    }
    if (const PairRecord* r = entry.ready.load(std::memory_order_acquire)) return *r;
    entry.building = true;
    lock.unlock();
    std::unique_ptr<PairRecord> record;
    try {
        record = build(key, cancel);
    } catch (...) {
        lock.lock();
        entry.building = false;
        entry.done.notify_all();
        throw;
    }
    lock.lock();
    publish(entry, std::move(record));
    entry.building = false;
    entry.done.notify_all();
    return *entry.ready.load(std::memory_order_acquire);
}

bool VisibilityStore::insert(const PairKey& key, PairRecord record) {
    Entry& entry = entryFor(key);
    std::unique_lock lock(entry.mutex);
    if (entry.building || entry.ready.load(std::memory_order_acquire) != nullptr) return false;
    publish(entry, std::make_unique<PairRecord>(std::move(record)));
    return true;
}

void VisibilityStore::forEach(
    const std::function<void(const PairKey&, const PairRecord&)>& visit) const {
    for (const Shard& shard : shards_) {
        std::vector<std::pair<PairKey, const PairRecord*>> snapshot;
        {
            std::shared_lock lock(shard.mutex);
            for (const auto& [key, entry] : shard.entries)
                if (const PairRecord* r = entry->ready.load(std::memory_order_acquire))
                    snapshot.emplace_back(key, r);
        }
        for (const auto& [key, record] : snapshot) visit(key, *record);
    }
}

std::array<size_t, vis::kPairKindCount> VisibilityStore::kindCounts() const {
    std::array<size_t, vis::kPairKindCount> out{};
    for (size_t i = 0; i < out.size(); ++i) out[i] = kinds_[i].load(std::memory_order_relaxed);
    return out;
}

void VisibilityStore::clear() {
    for (Shard& shard : shards_) {
        std::unique_lock lock(shard.mutex);
        shard.entries.clear();
    }
    {
        std::unique_lock lock(refinedMutex_);
        refined_.clear();
    }
    for (auto& slot : patchSlots_) slot->refined.store(false, std::memory_order_relaxed);
    treeCount_ = 0;
    bytes_ = 0;
    for (auto& k : kinds_) k = 0;
    partial_ = 0;
}

}  // namespace penumbra
