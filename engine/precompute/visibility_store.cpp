#include "engine/precompute/visibility_store.h"

#include <chrono>
#include <condition_variable>
#include <mutex>
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

VisibilityStore::VisibilityStore(const Scene& scene, const EmbreeScene* bvh, const Options& options)
    : scene_(scene),
      bvh_(bvh),
      options_(options),
      layout_(scene, options.patchFraction,
              [this](const PairKey& key) { return find(key) != nullptr; }) {}

VisibilityStore::~VisibilityStore() = default;

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
    const bool whole = layout_.wholeFace(key);
    const std::vector<Vec3> patch = layout_.region(key);  // checks the patch
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
    const std::vector<Vec3> patch =
        layout_.wholeFace(key) ? std::vector<Vec3>{} : layout_.region(key);
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
    layout_.clearRefinements();
    treeCount_ = 0;
    bytes_ = 0;
    for (auto& k : kinds_) k = 0;
    partial_ = 0;
}

}  // namespace penumbra
