#include "engine/cluster/cluster_render.h"

#include <tbb/info.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <atomic>
#include <bit>
#include <cstring>
#include <deque>
#include <optional>
#include <thread>
#include <unordered_set>

#include "engine/cluster/cluster_precompute.h"
#include "engine/io/visibility_file.h"

namespace penumbra::cluster {
namespace detail_render {

using Clock = std::chrono::steady_clock;
using Bytes = std::vector<unsigned char>;

constexpr auto kPoll = std::chrono::milliseconds(1);
constexpr auto kHeartbeat = std::chrono::seconds(1);
constexpr size_t kMaxTileBatch = 16;
constexpr size_t kBatchesInFlight = 2;

double seconds(Clock::duration d) { return std::chrono::duration<double>(d).count(); }

// Little-endian integers and doubles (their bits: exact) in a byte string.
class Writer {
  public:
    void u32(uint32_t v) { put(v, 4); }
    void u64(uint64_t v) { put(v, 8); }
    void f64(double v) { put(std::bit_cast<uint64_t>(v), 8); }
    void key(const PairKey& k) {
        u32(k.receiver);
        u32(k.patch);
        u32(k.lightFace);
    }
    void keys(const std::vector<PairKey>& ks) {
        u64(ks.size());
        for (const PairKey& k : ks) key(k);
    }
    template <typename Range>
    void u64s(const Range& values) {
        u64(values.size());
        for (uint64_t v : values) u64(v);
    }
    Bytes& bytes() { return bytes_; }

  private:
    void put(uint64_t v, int n) {
        for (int k = 0; k < n; ++k) bytes_.push_back(static_cast<unsigned char>(v >> (8 * k)));
    }
    Bytes bytes_;
};

class Reader {
  public:
    Reader(const Bytes& b, const std::string& source) : b_(b), source_(source) {}
    uint32_t u32() { return static_cast<uint32_t>(get(4)); }
    uint64_t u64() { return get(8); }
    double f64() { return std::bit_cast<double>(get(8)); }
    PairKey key() {
        PairKey k;
        k.receiver = u32();
        k.patch = u32();
        k.lightFace = u32();
        return k;
    }
    std::vector<PairKey> keys() {
        std::vector<PairKey> ks(count(12));
        for (PairKey& k : ks) k = key();
        return ks;
    }
    std::vector<uint64_t> u64s() {
        std::vector<uint64_t> vs(count(8));
        for (uint64_t& v : vs) v = u64();
        return vs;
    }
    // A count of items of at least `itemBytes` each, checked against what is left.
    size_t count(size_t itemBytes) {
        const uint64_t n = u64();
        if (n > (b_.size() - at_) / itemBytes) bad();
        return static_cast<size_t>(n);
    }

  private:
    uint64_t get(int n) {
        if (b_.size() - at_ < static_cast<size_t>(n)) bad();
        uint64_t v = 0;
        for (int k = 0; k < n; ++k) v |= uint64_t{b_[at_ + k]} << (8 * k);
        at_ += static_cast<size_t>(n);
        return v;
    }
    [[noreturn]] void bad() { throw MpiError(source_ + ": a truncated message"); }
    const Bytes& b_;
    std::string source_;
    size_t at_ = 0;
};

// The counts of ExactEvaluations, in one order for both ends (the cost samples apart: below).
// Every uint64_t count of ExactEvaluations and EvaluationCosts must be listed: a new one left out
// would read 0 on rank 0 for the workers' tiles, and the summary would differ from one
// process's. The size checks below fail to compile when a count is added without it.
constexpr size_t kEvaluationCounts =
    14 + vis::kEdgeDeclines + 2 * vis::kWorkStages + 2 * vis::kWorkStages;
constexpr size_t kCostCounts = 9;
static_assert(sizeof(ExactEvaluations) ==
                  kEvaluationCounts * sizeof(uint64_t) + sizeof(EvaluationCosts),
              "a count was added to ExactEvaluations: send it in forEachCount");
static_assert(sizeof(EvaluationCosts) == 3 * sizeof(CostSamples) + kCostCounts * sizeof(uint64_t),
              "a count was added to EvaluationCosts: send it in forEachCount");

template <typename E, typename F>
void forEachCount(E& e, F&& f) {
    for (auto* v : {&e.all,
                    &e.sampled,
                    &e.direct,
                    &e.sampledDirect,
                    &e.directGrouped,
                    &e.directSolid,
                    &e.directHiddenBySolid,
                    &e.partialByGroups,
                    &e.lightEdges,
                    &e.lightEdgesNotTaken,
                    &e.lightEdgesOverLimit,
                    &e.lightEdgesSkipped,
                    &e.retried,
                    &e.retriedOverLimit,
                    &e.costs.chainEvaluations,
                    &e.costs.chainOccluderEdges,
                    &e.costs.chainBoundaryEdges,
                    &e.costs.chainCells,
                    &e.costs.chainFragments,
                    &e.costs.lightEdgeEvaluations,
                    &e.costs.lightEdgesExamined,
                    &e.costs.lightEdgesWeighted,
                    &e.costs.lightEdgesInCone})
        f(*v);
    for (auto& v : e.lightEdgesDeclinedBy) f(v);
    for (auto& v : e.lightEdgesOverLimitAt) f(v);
    for (auto& v : e.overLimitAt) f(v);
    for (auto& stage : e.workAt)
        for (auto& v : stage) f(v);
}

void writeCosts(Writer& w, const CostSamples& c) {
    const CostSamples::Parts p = c.parts();
    w.u64(p.kept.size());
    for (float v : p.kept) w.u32(std::bit_cast<uint32_t>(v));
    w.u64(p.count);
    w.u64(p.stride);
    w.f64(p.sum);
}

CostSamples readCosts(Reader& r) {
    CostSamples::Parts p;
    p.kept.resize(r.count(4));
    for (float& v : p.kept) v = std::bit_cast<float>(r.u32());
    p.count = r.u64();
    p.stride = r.u64();
    p.sum = r.f64();
    if (p.stride == 0 || (p.stride & (p.stride - 1)) != 0) throw MpiError("a cost stride of 0");
    return CostSamples::fromParts(std::move(p));
}

// Rank 0 takes the pairs and faces as sets: each is sent once a batch.
template <typename T>
void sortUnique(std::vector<T>& v) {
    std::sort(v.begin(), v.end());
    v.erase(std::unique(v.begin(), v.end()), v.end());
}

void writeFindings(Writer& w, PassFindings& f) {
    sortUnique(f.usedKeys);
    sortUnique(f.facesSeen);
    sortUnique(f.directKeys);
    w.keys(f.usedKeys);
    w.u64(f.facesSeen.size());
    for (uint32_t face : f.facesSeen) w.u32(face);
    forEachCount(f.evaluations, [&](uint64_t& v) { w.u64(v); });
    for (const CostSamples* c : {&f.evaluations.costs.exactNs, &f.evaluations.costs.sampledNs,
                                 &f.evaluations.costs.attemptNs})
        writeCosts(w, *c);
    w.keys(f.directKeys);
    w.u64s(f.overLimitNow);
    w.u64s(f.edgeFailedNow);
    w.u64s(f.edgeDeclinedNow);
    w.u64(f.overLimitTrees.size());
    for (const OverLimitPoint& p : f.overLimitTrees) {
        w.key(p.key);
        w.f64(p.x.x);
        w.f64(p.x.y);
        w.f64(p.x.z);
        w.u64(p.cell);
    }
    w.u64(f.lightEdgeIndices.size());
    for (uint32_t k : f.lightEdgeIndices) w.u32(k);
}

PassFindings readFindings(Reader& r) {
    PassFindings f;
    f.usedKeys = r.keys();
    f.facesSeen.resize(r.count(4));
    for (uint32_t& face : f.facesSeen) face = r.u32();
    forEachCount(f.evaluations, [&](uint64_t& v) { v = r.u64(); });
    for (CostSamples* c : {&f.evaluations.costs.exactNs, &f.evaluations.costs.sampledNs,
                           &f.evaluations.costs.attemptNs})
        *c = readCosts(r);
    f.directKeys = r.keys();
    f.overLimitNow = r.u64s();
    f.edgeFailedNow = r.u64s();
    f.edgeDeclinedNow = r.u64s();
    f.overLimitTrees.resize(r.count(44));
    for (OverLimitPoint& p : f.overLimitTrees) {
        p.key = r.key();
        p.x.x = r.f64();
        p.x.y = r.f64();
        p.x.z = r.f64();
        p.cell = r.u64();
    }
    f.lightEdgeIndices.resize(r.count(4));
    for (uint32_t& k : f.lightEdgeIndices) k = r.u32();
    return f;
}

std::vector<uint64_t> sorted(const std::unordered_set<uint64_t>* cells) {
    std::vector<uint64_t> v;
    if (cells != nullptr) v.assign(cells->begin(), cells->end());
    std::sort(v.begin(), v.end());
    return v;
}

}  // namespace detail_render

using namespace detail_render;

RenderCoordinator::RenderCoordinator(MpiSession& session, VisibilityStore& store,
                                     ClusterRenderOptions options,
                                     std::function<bool()> interrupted)
    : session_(session),
      store_(store),
      options_(options),
      interrupted_(std::move(interrupted)),
      hosts_(static_cast<size_t>(session.size())),
      lost_(static_cast<size_t>(session.size()), false) {
    stats_.treesByRank.assign(static_cast<size_t>(session.size()), 0);
    stats_.tilesByRank.assign(static_cast<size_t>(session.size()), 0);
}

std::string RenderCoordinator::name(int rank) const { return "rank " + std::to_string(rank); }

void RenderCoordinator::send(int to, int tag, const std::vector<unsigned char>& bytes) {
    try {
        session_.send(to, tag, bytes, options_.silenceLimit);
    } catch (const MpiError& e) {
        lose(to, e.what());
    }
}

std::optional<MpiMessage> RenderCoordinator::receive() {
    try {
        return session_.poll();
    } catch (const MpiError& e) {
        if (e.peer <= 0 || e.peer >= session_.size()) throw;
        lose(e.peer, e.what());
    }
}

void RenderCoordinator::sendAll(int tag, const std::vector<unsigned char>& bytes) {
    for (int r = 1; r < session_.size(); ++r) {
        try {
            session_.send(r, tag, bytes, options_.silenceLimit);
        } catch (const MpiError& e) {
            lose(r, e.what());
        }
    }
}

bool RenderCoordinator::stopNote(const MpiMessage& m) {
    if (m.tag != kTagFailure || m.source <= 0 ||
        std::string_view(reinterpret_cast<const char*>(m.bytes.data()), m.bytes.size()) !=
            kStoppedBySignal)
        return false;
    peerStopped_ = true;
    return true;
}

void RenderCoordinator::lose(int rank, const std::string& why) {
    lostRank_ = true;
    throw MpiError(name(rank) + ": " + why);
}

namespace detail_render {

// What a build round said of the ranks it lost (killed: they did not answer its stop).
void noteLost(const ClusterPrecomputeResult& r, std::vector<bool>& lost, bool& lostRank,
              std::string& lostError) {
    if (!r.lostRank) return;
    lostRank = true;
    if (lostError.empty()) lostError = r.progress.error;
    for (int rank : r.silentRanks)
        if (rank > 0 && static_cast<size_t>(rank) < lost.size()) lost[rank] = true;
}

}  // namespace detail_render

ClusterPrecomputeResult RenderCoordinator::buildRound(const std::vector<PairKey>& keys,
                                                      bool coordinatorBuilds) {
    sendAll(kTagBuild, {});
    ClusterPrecomputeOptions o;
    o.threads = options_.threads;
    o.silenceLimit = options_.silenceLimit;
    o.helloLimit = options_.helloLimit;
    o.stopLimit = options_.stopLimit;
    o.keys = keys;
    o.coordinatorBuilds = coordinatorBuilds;
    return coordinatePrecompute(
        session_, store_, o, [this] { return interrupted(); }, [](const PrecomputeProgress&) {},
        [] {});
}

void RenderCoordinator::start() {
    // The HELLO round: one round of the cluster precompute with no key (each worker loads the
    // scene first, then says HELLO with its scene hash or its error).
    const ClusterPrecomputeResult r = buildRound({}, false);
    if (r.progress.state == PrecomputeProgress::State::Idle) return;
    // A worker that could not load the scene has ended; the others wait for DONE.
    noteLost(r, lost_, lostRank_, lostError_);
    finish(options_.stopLimit);
    throw MpiError(r.progress.state == PrecomputeProgress::State::Cancelled
                       ? std::string("interrupted while the ranks started")
                       : r.progress.error);
}

void RenderCoordinator::shareStore() {
    std::vector<PairKey> keys;
    store_.forEach([&](const PairKey& k, const PairRecord&) { keys.push_back(k); });
    if (keys.empty()) return;
    std::sort(keys.begin(), keys.end());
    const Bytes bytes = encodeTreeRecords(store_, keys);
    sendAll(kTagTrees, bytes);
    stats_.treeBytesFromRank0 += bytes.size() * static_cast<size_t>(session_.size() - 1);
}

bool RenderCoordinator::buildTrees(const std::vector<PairKey>& keys) {
    if (keys.empty()) return true;
    if (interrupted()) return false;  // nothing more is sent: rank 0 ends
    const auto t0 = Clock::now();
    const size_t before = store_.treeCount();
    const ClusterPrecomputeResult r = buildRound(keys, true);
    stats_.treeBytesToRank0 += r.bytesReceived;
    noteLost(r, lost_, lostRank_, lostError_);
    if (r.progress.state == PrecomputeProgress::State::Cancelled) {
        peerStopped_ = true;  // this rank's signal or a worker's: interrupted either way
        return false;
    }
    if (r.progress.state != PrecomputeProgress::State::Idle) throw MpiError(r.progress.error);
    const size_t added = store_.treeCount() - before;
    // Rank 0's own builds: what its store gained less what the workers sent.
    size_t builtByRanks = added - std::min(added, r.treesReceived);
    stats_.treesByRank[0] += builtByRanks;

    // Every worker gets the round's trees; each answers what it had built itself (its store's
    // own count, not what it sent) and what it added.
    const auto c0 = Clock::now();
    const Bytes bytes = encodeTreeRecords(store_, keys);
    sendAll(kTagTrees, bytes);
    stats_.treeBytesFromRank0 += bytes.size() * static_cast<size_t>(session_.size() - 1);
    std::vector<bool> acked(static_cast<size_t>(session_.size()), false);
    int waiting = session_.size() - 1;
    auto lastHeard = Clock::now();
    while (waiting > 0) {
        std::optional<MpiMessage> m = receive();
        if (!m) {
            if (interrupted()) return false;
            if (Clock::now() - lastHeard > options_.silenceLimit)
                for (int w = 1; w < session_.size(); ++w)
                    if (!acked[w])
                        lose(w, "stopped answering: no message for " +
                                    std::to_string(options_.silenceLimit.count() / 1000) +
                                    " s (killed, hung, out of memory or its node lost)");
            std::this_thread::sleep_for(kPoll);
            continue;
        }
        lastHeard = Clock::now();
        if (stopNote(*m)) continue;
        if (m->tag == kTagFailure) lose(m->source, std::string(m->bytes.begin(), m->bytes.end()));
        if (m->tag != kTagTreesAck || acked[m->source]) continue;
        Reader rd(m->bytes, name(m->source));
        const uint64_t builtHere = rd.u64(), held = rd.u64();
        acked[m->source] = true;
        --waiting;
        stats_.treesByRank[m->source] += builtHere;
        builtByRanks += builtHere;
        if (held != store_.treeCount())
            lose(m->source, "holds " + std::to_string(held) + " trees after the round, rank 0 " +
                                std::to_string(store_.treeCount()));
    }
    stats_.treesBuilt += added;
    stats_.duplicateTrees += builtByRanks - std::min(builtByRanks, added);
    stats_.coordinatorSeconds += seconds(Clock::now() - c0);
    stats_.buildSeconds += seconds(Clock::now() - t0);
    return true;
}

void RenderCoordinator::refined(const std::vector<PairKey>& keys) {
    if (keys.empty()) return;
    Writer w;
    w.keys(keys);
    sendAll(kTagRefine, w.bytes());
}

bool RenderCoordinator::shadePass(int pass, int width, int height, const PassCells& cells,
                                  TileSchedule& schedule, std::vector<Vec3>& image,
                                  const std::function<void()>& shadeHere,
                                  std::atomic<bool>& stopHere, PassFindings& found,
                                  const std::atomic<bool>* cancel) {
    const int ranks = session_.size();
    // Interrupted (a build round may have seen it first): nothing more is sent, rank 0 ends.
    if ((cancel != nullptr && cancel->load()) || interrupted()) return false;
    {
        Writer w;
        w.u32(static_cast<uint32_t>(pass));
        w.u64s(sorted(cells.overLimit));
        w.u64s(sorted(cells.edgeFailed));
        w.u64s(sorted(cells.edgeDeclined));
        sendAll(kTagPass, w.bytes());
        stats_.passBytes += w.bytes().size() * static_cast<size_t>(ranks - 1);
    }
    // This rank's threads shade from the same schedule; this thread hands out and gathers.
    std::atomic<bool> localDone{false};
    tbb::task_arena arena(std::max(1, options_.threads), 0);
    arena.enqueue([&] {
        shadeHere();
        localDone.store(true, std::memory_order_release);
    });
    std::vector<std::deque<std::vector<int>>> inFlight(static_cast<size_t>(ranks));
    std::vector<Clock::time_point> lastHeard(static_cast<size_t>(ranks), Clock::now());
    bool stopped = false;
    std::string failure;
    int failedRank = -1;
    auto handOut = [&](int r) {
        while (!stopped && inFlight[r].size() < kBatchesInFlight) {
            const size_t size = std::clamp<size_t>(
                schedule.remaining() / (4 * static_cast<size_t>(ranks)), 1, kMaxTileBatch);
            std::vector<int> batch;
            for (int t; batch.size() < size && (t = schedule.next()) >= 0;) batch.push_back(t);
            if (batch.empty()) return;
            Writer w;
            w.u64(batch.size());
            for (int t : batch) w.u32(static_cast<uint32_t>(t));
            send(r, kTagTiles, w.bytes());
            stats_.tileBytes += w.bytes().size();
            inFlight[r].push_back(std::move(batch));
        }
    };
    const auto stopLocal = [&] {
        stopHere.store(true);
        while (!localDone.load(std::memory_order_acquire)) std::this_thread::sleep_for(kPoll);
    };
    try {
        for (int r = 1; r < ranks; ++r) handOut(r);
        for (;;) {
            bool busy = false;
            while (std::optional<MpiMessage> m = receive()) {
                busy = true;
                const int r = m->source;
                if (r <= 0 || r >= ranks) continue;
                lastHeard[r] = Clock::now();
                if (stopNote(*m)) continue;
                if (m->tag == kTagFailure) {
                    failedRank = r;
                    failure = std::string(m->bytes.begin(), m->bytes.end());
                    break;
                }
                if (m->tag != kTagTilesDone || inFlight[r].empty()) continue;
                const auto c0 = Clock::now();
                const std::vector<int> batch = std::move(inFlight[r].front());
                inFlight[r].pop_front();
                Reader rd(m->bytes, name(r));
                const size_t n = rd.count(8);
                if (n != batch.size()) lose(r, "answered " + std::to_string(n) + " tiles");
                for (int t : batch) schedule.record(t, static_cast<int64_t>(rd.u64()));
                const size_t pixels = rd.count(24);
                size_t at = 0;
                for (int t : batch) {
                    const Tile tile = TileSchedule::tileAt(t, width, height);
                    for (int y = tile.y0; y < tile.y1; ++y)
                        for (int x = tile.x0; x < tile.x1; ++x, ++at) {
                            if (at >= pixels) lose(r, "sent too few pixels");
                            Vec3& p = image[static_cast<size_t>(y) * width + x];
                            p.x = rd.f64();
                            p.y = rd.f64();
                            p.z = rd.f64();
                        }
                }
                stats_.pixelBytes += 16 + 8 * n + 24 * pixels;
                stats_.findingsBytes += m->bytes.size() - (16 + 8 * n + 24 * pixels);
                found.add(readFindings(rd));
                stats_.tilesByRank[r] += n;
                stats_.coordinatorSeconds += seconds(Clock::now() - c0);
                handOut(r);
            }
            if (failedRank > 0) lose(failedRank, failure);
            if ((cancel != nullptr && cancel->load(std::memory_order_relaxed)) || interrupted()) {
                stopped = true;
                stopHere.store(true);
                // The workers are asked first, and a dead one named, before this rank waits for
                // its own tiles: the launcher kills every rank a second after its SIGTERM.
                const std::vector<int> silent = finish(options_.stopLimit);
                if (!silent.empty() && lostError_.empty()) {
                    lostRank_ = true;
                    std::string ranks;
                    for (int r : silent) ranks += (ranks.empty() ? "" : ", ") + name(r);
                    lostError_ = ranks + " did not answer the stop within " +
                                 std::to_string(options_.stopLimit.count()) +
                                 " ms (it had ended: killed or crashed)";
                }
                stopLocal();
                return false;
            }
            const auto now = Clock::now();
            bool outstanding = false;
            for (int r = 1; r < ranks; ++r) {
                if (inFlight[r].empty()) continue;
                outstanding = true;
                if (now - lastHeard[r] > options_.silenceLimit)
                    lose(r, "stopped answering: no message for " +
                                std::to_string(options_.silenceLimit.count() / 1000) +
                                " s (killed, hung, out of memory or its node lost)");
            }
            if (!outstanding && localDone.load(std::memory_order_acquire)) break;
            if (!busy) std::this_thread::sleep_for(kPoll);
        }
    } catch (...) {
        stopped = true;
        stopLocal();
        throw;
    }
    return true;
}

std::vector<int> RenderCoordinator::finish(std::chrono::milliseconds limit) {
    if (finished_) return silent_;
    finished_ = true;
    std::vector<int>& silent = silent_;
    std::vector<bool> answered = lost_;
    for (int r = 1; r < session_.size(); ++r) {
        if (lost_[r]) {
            silent.push_back(r);
            continue;
        }
        try {
            session_.send(r, kTagDone, {}, limit);
        } catch (const MpiError&) {
            answered[r] = true;
            silent.push_back(r);
        }
    }
    const auto deadline = Clock::now() + limit;
    for (;;) {
        bool waiting = false;
        for (int r = 1; r < session_.size(); ++r) waiting = waiting || !answered[r];
        if (!waiting) break;
        std::optional<MpiMessage> m;
        try {
            m = session_.poll();
        } catch (const MpiError& e) {
            if (e.peer <= 0 || e.peer >= session_.size()) throw;
            if (!answered[e.peer]) silent.push_back(e.peer);  // it died mid-message
            answered[e.peer] = true;
            continue;
        }
        if (m) {
            if (m->tag == kTagFinal && m->source > 0 && m->source < session_.size())
                answered[m->source] = true;
            continue;
        }
        if (Clock::now() > deadline) {
            for (int r = 1; r < session_.size(); ++r)
                if (!answered[r]) silent.push_back(r);
            break;
        }
        std::this_thread::sleep_for(kPoll);
    }
    std::sort(silent.begin(), silent.end());
    return silent;
}

void serveRender(MpiSession& session, VisibilityStore& store, ProgressiveRenderer& renderer,
                 const Camera& camera, const RenderSettings& settings,
                 const ClusterRenderOptions& options, const std::function<bool()>& interrupted) {
    const std::string source = "rank 0";
    std::unordered_set<uint64_t> overLimit, edgeFailed, edgeDeclined;
    int pass = 0;
    size_t builtHere = 0;
    std::deque<std::vector<int>> batches;
    tbb::task_arena arena(std::max(1, options.threads), 0);
    // The batch being shaded on the arena, and what it gives.
    std::atomic<bool> shading{false}, shaded{false}, stopShading{false};
    std::vector<Vec3> pixels;
    std::vector<int64_t> costs;
    PassFindings found;
    std::string failure;
    // (The batch in flight is dropped: rank 0 ends the render.)
    const auto awaitShaded = [&] {
        while (shading.load() && !shaded.load(std::memory_order_acquire))
            std::this_thread::sleep_for(kPoll);
        shading.store(false);
    };
    auto lastBeat = Clock::now();
    auto send = [&](int tag, const Bytes& bytes) {
        session.send(0, tag, bytes);
        lastBeat = Clock::now();
    };
    for (;;) {
        while (std::optional<MpiMessage> m = session.poll()) {
            if (m->source != 0) continue;
            switch (m->tag) {
                case kTagStop:  // rank 0 could not start the render
                    return;
                case kTagDone:
                    stopShading.store(true);
                    awaitShaded();
                    send(kTagFinal, {});
                    return;
                case kTagBuild: {
                    const size_t before = store.treeCount();
                    ClusterPrecomputeOptions o;
                    o.threads = options.threads;
                    servePrecompute(session, store, o, interrupted);
                    builtHere = store.treeCount() - before;
                    lastBeat = Clock::now();
                    if (interrupted()) return;
                    break;
                }
                case kTagTrees: {
                    decodeTreeRecords(m->bytes, store, source);
                    Writer w;
                    w.u64(builtHere);
                    w.u64(store.treeCount());
                    builtHere = 0;
                    send(kTagTreesAck, w.bytes());
                    break;
                }
                case kTagRefine: {
                    Reader r(m->bytes, source);
                    for (const PairKey& k : r.keys()) store.layout().refine(k);
                    break;
                }
                case kTagPass: {
                    Reader r(m->bytes, source);
                    pass = static_cast<int>(r.u32());
                    for (auto* cells : {&overLimit, &edgeFailed, &edgeDeclined}) {
                        const std::vector<uint64_t> v = r.u64s();
                        cells->clear();
                        cells->insert(v.begin(), v.end());
                    }
                    break;
                }
                case kTagTiles: {
                    Reader r(m->bytes, source);
                    std::vector<int> batch(r.count(4));
                    for (int& t : batch) t = static_cast<int>(r.u32());
                    batches.push_back(std::move(batch));
                    break;
                }
                default:
                    break;
            }
        }
        if (interrupted()) {  // the launcher's SIGTERM reached this rank too
            stopShading.store(true);
            awaitShaded();
            // Rank 0 is told (a signal to this rank alone would leave it waiting), and decides
            // when the job ends: its DONE is answered, so that it can tell a stop from a death.
            send(kTagFailure, Bytes(kStoppedBySignal.begin(), kStoppedBySignal.end()));
            for (;;) {
                while (std::optional<MpiMessage> m = session.poll()) {
                    if (m->source != 0) continue;
                    if (m->tag == kTagStop) return;
                    if (m->tag == kTagDone) {
                        send(kTagFinal, {});
                        return;
                    }
                }
                if (Clock::now() - lastBeat >= kHeartbeat) send(kTagHeartbeat, {});
                std::this_thread::sleep_for(kPoll);
            }
        }
        if (shading.load() && shaded.load(std::memory_order_acquire)) {
            shading.store(false);
            if (!failure.empty()) {
                send(kTagFailure, Bytes(failure.begin(), failure.end()));
                failure.clear();
            } else {
                Writer w;
                w.u64(costs.size());
                for (int64_t c : costs) w.u64(static_cast<uint64_t>(c));
                w.u64(pixels.size());
                for (const Vec3& p : pixels) {
                    w.f64(p.x);
                    w.f64(p.y);
                    w.f64(p.z);
                }
                writeFindings(w, found);
                send(kTagTilesDone, w.bytes());
            }
            batches.pop_front();
        }
        if (!shading.load() && !batches.empty()) {
            shading.store(true);
            shaded.store(false);
            arena.enqueue([&, tiles = batches.front(), passNow = pass] {
                try {
                    const PassCells cells{&overLimit, &edgeFailed, &edgeDeclined};
                    renderer.shadeTiles(camera, settings, passNow, cells, tiles, pixels, costs,
                                        found, &stopShading);
                } catch (const std::exception& e) {
                    failure = e.what();
                }
                shaded.store(true, std::memory_order_release);
            });
        }
        if (Clock::now() - lastBeat >= kHeartbeat) send(kTagHeartbeat, {});
        std::this_thread::sleep_for(kPoll);
    }
}

}  // namespace penumbra::cluster
