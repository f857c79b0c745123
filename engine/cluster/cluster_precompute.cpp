#include "engine/cluster/cluster_precompute.h"

#include <tbb/info.h>

#include <algorithm>
#include <cstring>
#include <deque>
#include <exception>
#include <optional>
#include <thread>

#include "engine/io/visibility_file.h"
#include "engine/precompute/scene_hash.h"

namespace penumbra::cluster {
namespace detail_cluster {

using Clock = std::chrono::steady_clock;
using State = PrecomputeProgress::State;
using Bytes = std::vector<unsigned char>;

constexpr auto kPoll = std::chrono::milliseconds(2);
constexpr auto kHeartbeat = std::chrono::seconds(1);
constexpr auto kProgressEvery = std::chrono::milliseconds(500);
constexpr size_t kMaxBatch = 64;
constexpr int kBatchesInFlight = 2;

void putU64(Bytes& b, uint64_t v) {
    for (int k = 0; k < 8; ++k) b.push_back(static_cast<unsigned char>(v >> (8 * k)));
}
uint64_t getU64(const Bytes& b, size_t at) {
    uint64_t v = 0;
    for (int k = 0; k < 8 && at + k < b.size(); ++k) v |= uint64_t{b[at + k]} << (8 * k);
    return v;
}

// HELLO: u8 ok, u64 scene hash, then the error text when not ok.
Bytes hello(bool ok, uint64_t hash, const std::string& error) {
    Bytes b{static_cast<unsigned char>(ok ? 1 : 0)};
    putU64(b, hash);
    b.insert(b.end(), error.begin(), error.end());
    return b;
}

// WORK: the keys, 3 x u32 each (little-endian, as the file).
Bytes encodeKeys(const std::vector<PairKey>& keys) {
    Bytes b;
    b.reserve(keys.size() * 12);
    for (const PairKey& k : keys)
        for (uint32_t v : {k.receiver, k.patch, k.lightFace})
            for (int s = 0; s < 4; ++s) b.push_back(static_cast<unsigned char>(v >> (8 * s)));
    return b;
}
std::vector<PairKey> decodeKeys(const Bytes& b) {
    std::vector<PairKey> keys(b.size() / 12);
    auto u32 = [&](size_t at) {
        return uint32_t{b[at]} | uint32_t{b[at + 1]} << 8 | uint32_t{b[at + 2]} << 16 |
               uint32_t{b[at + 3]} << 24;
    };
    for (size_t i = 0; i < keys.size(); ++i)
        keys[i] = {u32(12 * i), u32(12 * i + 4), u32(12 * i + 8)};
    return keys;
}

std::string text(const Bytes& b, size_t from = 0) {
    return from < b.size() ? std::string(b.begin() + static_cast<std::ptrdiff_t>(from), b.end())
                           : std::string();
}

bool allBuilt(const VisibilityStore& store, const std::vector<PairKey>& keys) {
    return std::all_of(keys.begin(), keys.end(),
                       [&](const PairKey& k) { return store.find(k) != nullptr; });
}

double seconds(Clock::duration d) { return std::chrono::duration<double>(d).count(); }

// What rank 0 knows of one worker.
struct Worker {
    std::string host;
    std::deque<std::vector<PairKey>> batches;  // handed out, not yet returned
    Clock::time_point lastHeard;
    bool alive = true;
    bool final = false;  // FINAL received (or given up on)
};

class Coordinator {
  public:
    Coordinator(MpiSession& session, VisibilityStore& store, const ClusterPrecomputeOptions& o)
        : session_(session), store_(store), options_(o), workers_(session.size()) {
        result_.treesByRank.assign(session.size(), 0);
        std::sort(options_.builtElsewhere.begin(), options_.builtElsewhere.end());
    }

    ClusterPrecomputeResult run(const std::function<bool()>& interrupted,
                                const std::function<void(const PrecomputeProgress&)>& onProgress,
                                const std::function<void()>& checkpoint);

  private:
    std::string name(int rank) const {
        const std::string& host = workers_[rank].host;
        return "rank " + std::to_string(rank) + (host.empty() ? "" : " (" + host + ")");
    }
    // The first failure stops the run (a failure while it stops for another reason is kept as
    // the error, the state stays).
    void fail(const std::string& error) {
        if (error_.empty()) error_ = error;
        if (state_ == State::Running) state_ = State::Failed;
    }
    // Rank `r` died or stopped answering: nothing more is sent to it or awaited from it, and the
    // run fails with `why` (which names it); MPI_Finalize would wait for it (lostRank).
    void lose(int r, const std::string& why) {
        Worker& w = workers_[r];
        if (!w.alive && w.final) return;
        w.alive = false;
        w.final = true;
        result_.lostRank = true;
        result_.silentRanks.push_back(r);
        fail(why);
    }
    // The next message; a receive that failed (its sender died mid-message) loses the sender.
    std::optional<MpiMessage> receive() {
        try {
            return session_.poll();
        } catch (const MpiError& e) {
            if (e.peer <= 0 || e.peer >= session_.size()) throw;
            lose(e.peer, name(e.peer) + ": " + e.what());
            return std::nullopt;
        }
    }
    void awaitHellos(const std::function<bool()>& interrupted);
    std::vector<PairKey> nextBatch() {
        const size_t ranks = static_cast<size_t>(session_.size());
        const size_t size = std::clamp<size_t>(queue_.size() / (4 * ranks), 1, kMaxBatch);
        std::vector<PairKey> batch;
        while (!queue_.empty() && batch.size() < size) {
            batch.push_back(queue_.front());
            queue_.pop_front();
        }
        return batch;
    }
    void handOut(int rank) {
        Worker& w = workers_[rank];
        while (state_ == State::Running && w.alive && !queue_.empty() &&
               w.batches.size() < kBatchesInFlight) {
            w.batches.push_back(nextBatch());
            try {
                session_.send(rank, kTagWork, encodeKeys(w.batches.back()));
            } catch (const MpiError& e) {
                // (Its batches are lost with it: the run fails, and a rerun builds them.)
                lose(rank, name(rank) + ": " + e.what());
            }
        }
    }
    void receiveTrees(int rank, const Bytes& bytes) {
        const auto start = Clock::now();
        // (Not the store's count before and after: rank 0's own builds land meanwhile.) With
        // shards, only the count: the trees stay in the worker's shard.
        const size_t added = options_.shards ? static_cast<size_t>(getU64(bytes, 0))
                                             : decodeTreeRecords(bytes, store_, name(rank));
        if (options_.shards) builtByWorkers_ += added;
        result_.treesReceived += added;
        result_.treesByRank[rank] += added;
        result_.bytesReceived += bytes.size();
        coordinatorTime_ += Clock::now() - start;
    }
    void handle(MpiMessage& m);
    void checkSilence() {
        const auto now = Clock::now();
        for (int r = 1; r < session_.size(); ++r) {
            Worker& w = workers_[r];
            if (!w.alive || w.final || now - w.lastHeard <= options_.silenceLimit) continue;
            lose(r, name(r) + " stopped answering: no message for " +
                        std::to_string(options_.silenceLimit.count() / 1000) +
                        " s (killed, hung, out of memory or its node lost)");
        }
    }
    PrecomputeProgress progress() const {
        PrecomputeProgress p;
        p.total = total_;
        p.done = loaded_ + (store_.treeCount() - storeLoaded_) + builtByWorkers_;
        p.seconds = seconds(Clock::now() - start_);
        const size_t built = p.done - loaded_;
        if (built > 0 && state_ == State::Running)
            p.secondsLeft = p.seconds * static_cast<double>(p.total - p.done) / built;
        p.bytes = store_.bytes();
        p.state = state_;
        p.error = error_;
        return p;
    }
    // Stops every worker and waits for their FINAL at most `limit`, or stopLimit once
    // `interrupted` says so (the launcher's SIGKILL follows its SIGTERM within a second or so).
    void stopEveryone(PrecomputeScheduler* local, std::chrono::milliseconds limit,
                      const std::function<bool()>& interrupted);

    MpiSession& session_;
    VisibilityStore& store_;
    ClusterPrecomputeOptions options_;  // builtElsewhere sorted
    std::vector<Worker> workers_;
    std::deque<PairKey> queue_;
    std::vector<PairKey> localBatch_;
    size_t total_ = 0, loaded_ = 0;
    size_t storeLoaded_ = 0;     // rank 0's store at the start
    size_t builtByWorkers_ = 0;  // with shards: the trees the workers reported
    Clock::time_point start_;
    Clock::duration coordinatorTime_{};
    State state_ = State::Running;
    std::string error_;
    ClusterPrecomputeResult result_;
};

void Coordinator::awaitHellos(const std::function<bool()>& interrupted) {
    const uint64_t hash = sceneHash(store_.scene(), store_.options());
    int waiting = session_.size() - 1;
    const auto deadline = Clock::now() + options_.helloLimit;
    std::vector<bool> heard(session_.size(), false);
    while (waiting > 0) {
        std::optional<MpiMessage> m = receive();
        if (!m) {
            if (result_.lostRank) return;  // one died mid-HELLO: the run has failed
            // (A rank killed before its HELLO: the launcher's SIGTERM says so here.)
            if (interrupted()) {
                if (state_ == State::Running) state_ = State::Cancelled;
                return;
            }
            if (Clock::now() > deadline) {
                for (int r = 1; r < session_.size(); ++r)
                    if (!heard[r])
                        lose(r, name(r) + " did not answer within " +
                                    std::to_string(options_.helloLimit.count() / 1000) +
                                    " s of the start (could not start, or stuck loading the "
                                    "scene)");
                return;
            }
            std::this_thread::sleep_for(kPoll);
            continue;
        }
        if (m->tag != kTagHello || m->source <= 0 || heard[m->source]) continue;
        heard[m->source] = true;
        --waiting;
        Worker& w = workers_[m->source];
        w.lastHeard = Clock::now();
        const bool ok = !m->bytes.empty() && m->bytes[0] == 1;
        // The host name follows the hash, then a NUL, then the error (if any).
        const std::string rest = text(m->bytes, 9);
        const size_t nul = rest.find('\0');
        w.host = rest.substr(0, nul);
        const std::string error = nul == std::string::npos ? "" : rest.substr(nul + 1);
        if (!ok)
            fail(name(m->source) + ": " + error);
        else if (getU64(m->bytes, 1) != hash)
            fail(name(m->source) +
                 ": another scene or other settings there (its scene hash differs from rank "
                 "0's: is the scene file the same on every node?)");
    }
}

void Coordinator::handle(MpiMessage& m) {
    if (m.source <= 0 || m.source >= session_.size()) return;
    Worker& w = workers_[m.source];
    w.lastHeard = Clock::now();
    switch (m.tag) {
        case kTagResult: {
            if (!w.batches.empty()) w.batches.pop_front();
            receiveTrees(m.source, m.bytes);
            handOut(m.source);
            break;
        }
        case kTagFailure:
            if (text(m.bytes) == kStoppedBySignal) {
                if (state_ == State::Running) state_ = State::Cancelled;
                w.final = true;  // it ends on the stop, without FINAL
                break;
            }
            fail(name(m.source) + ": " + text(m.bytes));
            break;
        case kTagOverBudget:
            if (state_ == State::Running) state_ = State::OverBudget;
            break;
        case kTagFinal:
            receiveTrees(m.source, m.bytes);
            if (options_.shards && m.bytes.size() > 8)
                result_.shardErrors.push_back(name(m.source) + ": " + text(m.bytes, 8));
            w.batches.clear();
            w.final = true;
            break;
        default:  // HEARTBEAT, a late HELLO
            break;
    }
}

void Coordinator::stopEveryone(PrecomputeScheduler* local, std::chrono::milliseconds limit,
                               const std::function<bool()>& interrupted) {
    if (local) local->cancel();
    for (int r = 1; r < session_.size(); ++r) {
        if (!workers_[r].alive) continue;
        try {
            session_.send(r, kTagStop, {}, limit);
        } catch (const MpiError& e) {
            lose(r, name(r) + ": " + e.what());
        }
    }
    // Every live worker answers FINAL with what it finished, within `limit` (stopLimit once
    // interrupted: a failure, such as a send to a rank that had died, waits up to the silence
    // limit for the others, and the launcher's SIGTERM may come meanwhile).
    auto deadline = Clock::now() + limit;
    bool sawInterrupt = false;
    for (;;) {
        if (!sawInterrupt && interrupted && interrupted()) {
            sawInterrupt = true;
            limit = std::min(limit, options_.stopLimit);
            deadline = std::min(deadline, Clock::now() + options_.stopLimit);
        }
        bool waiting = false;
        for (int r = 1; r < session_.size(); ++r) waiting = waiting || !workers_[r].final;
        if (!waiting) break;
        if (std::optional<MpiMessage> m = receive()) {
            handle(*m);
            continue;
        }
        if (Clock::now() > deadline) {
            for (int r = 1; r < session_.size(); ++r)
                if (!workers_[r].final)
                    lose(r, name(r) + " did not answer the stop within " +
                                std::to_string(limit.count()) +
                                " ms (it had ended: killed or crashed)");
            break;
        }
        std::this_thread::sleep_for(kPoll);
    }
    if (local) local->wait();
}

ClusterPrecomputeResult Coordinator::run(
    const std::function<bool()>& interrupted,
    const std::function<void(const PrecomputeProgress&)>& onProgress,
    const std::function<void()>& checkpoint) {
    start_ = Clock::now();
    const std::vector<PairKey> keys = options_.keys ? *options_.keys : everyPairKey(store_);
    total_ = keys.size();
    storeLoaded_ = store_.treeCount();
    const auto& elsewhere = options_.builtElsewhere;
    for (const PairKey& k : keys) {
        if (store_.find(k) || std::binary_search(elsewhere.begin(), elsewhere.end(), k))
            ++loaded_;
        else
            queue_.push_back(k);
    }

    awaitHellos(interrupted);
    std::optional<PrecomputeScheduler> local;
    PrecomputeOptions localOptions;
    localOptions.threads = options_.threads;
    if (options_.coordinatorBuilds) local.emplace(store_, localOptions);
    result_.threads = local ? local->threads() : options_.threads;
    for (int r = 1; r < session_.size(); ++r) {
        workers_[r].lastHeard = Clock::now();
        if (state_ == State::Running) handOut(r);
    }

    auto lastProgress = Clock::now();
    const size_t budget = options_.memoryBudgetBytes;
    while (state_ == State::Running) {
        bool busy = false;
        while (std::optional<MpiMessage> m = receive()) {
            handle(*m);
            busy = true;
        }
        if (local) {
            const PrecomputeProgress lp = local->progress();
            if (lp.state == State::Failed) fail("rank 0: " + lp.error);
            if (allBuilt(store_, localBatch_)) {
                localBatch_.clear();
                if (state_ == State::Running && !queue_.empty()) {
                    localBatch_ = nextBatch();
                    local->request(localBatch_);
                }
            }
        }
        if (interrupted()) {
            state_ = State::Cancelled;
            break;
        }
        if (budget > 0 && store_.bytes() > budget && state_ == State::Running) {
            state_ = State::OverBudget;
            break;
        }
        checkSilence();
        bool outstanding = !localBatch_.empty();
        for (int r = 1; r < session_.size(); ++r)
            outstanding = outstanding || !workers_[r].batches.empty();
        if (queue_.empty() && !outstanding && state_ == State::Running) {
            state_ = State::Idle;
            break;
        }
        if (Clock::now() - lastProgress >= kProgressEvery) {
            onProgress(progress());
            lastProgress = Clock::now();
        }
        if (!busy) std::this_thread::sleep_for(kPoll);
    }
    // Interrupted: the launcher may kill every rank a second after its SIGTERM (Open MPI's
    // mpirun does, on Ctrl-C or when a rank died), so what rank 0 holds is written first, then the
    // workers get a short while to send what they finished.
    // (Also when a lost rank failed the run: the launcher's SIGTERM that followed its death
    // may be here already.)
    const bool stoppedBySignal = state_ == State::Cancelled || interrupted();
    if (stoppedBySignal) checkpoint();
    stopEveryone(local ? &*local : nullptr,
                 stoppedBySignal ? options_.stopLimit : options_.silenceLimit, interrupted);
    // Rank 0 built what neither the file nor the workers gave.
    result_.treesByRank[0] =
        store_.treeCount() - storeLoaded_ - (options_.shards ? 0 : result_.treesReceived);
    result_.progress = progress();
    result_.progress.secondsLeft = 0;
    result_.coordinatorSeconds = seconds(coordinatorTime_);
    return result_;
}

}  // namespace detail_cluster

ClusterPrecomputeResult coordinatePrecompute(
    MpiSession& session, VisibilityStore& store, const ClusterPrecomputeOptions& options,
    const std::function<bool()>& interrupted,
    const std::function<void(const PrecomputeProgress&)>& onProgress,
    const std::function<void()>& checkpoint) {
    detail_cluster::Coordinator coordinator(session, store, options);
    return coordinator.run(interrupted, onProgress, checkpoint);
}

void stopWorkers(MpiSession& session) {
    for (int r = 1; r < session.size(); ++r) {
        try {
            session.send(r, kTagStop, {}, std::chrono::seconds(5));
        } catch (const MpiError&) {
            // A worker that cannot be told ends with the job (the launcher stops it).
        }
    }
}

namespace detail_cluster {

// Waits (sleeping) for rank 0's STOP, sending a heartbeat every second.
void awaitStop(MpiSession& session) {
    auto lastBeat = Clock::now();
    for (;;) {
        while (std::optional<MpiMessage> m = session.poll())
            if (m->source == 0 && m->tag == kTagStop) return;
        if (Clock::now() - lastBeat >= kHeartbeat) {
            session.send(0, kTagHeartbeat, {});
            lastBeat = Clock::now();
        }
        std::this_thread::sleep_for(kPoll);
    }
}

Bytes helloFrom(MpiSession& session, bool ok, uint64_t hash, const std::string& error) {
    return hello(ok, hash, session.host() + '\0' + error);
}

}  // namespace detail_cluster

void refuseToServe(MpiSession& session, const std::string& error) {
    session.send(0, kTagHello, detail_cluster::helloFrom(session, false, 0, error));
    detail_cluster::awaitStop(session);
    session.send(0, kTagFinal, {});
}

void servePrecompute(MpiSession& session, VisibilityStore& store,
                     const ClusterPrecomputeOptions& options,
                     const std::function<bool()>& interrupted,
                     const std::function<std::string()>& writeShard) {
    using namespace detail_cluster;
    session.send(0, kTagHello,
                 helloFrom(session, true, sceneHash(store.scene(), store.options()), ""));
    PrecomputeOptions schedulerOptions;
    schedulerOptions.threads = options.threads;
    PrecomputeScheduler scheduler(store, schedulerOptions);
    std::deque<std::vector<PairKey>> batches;
    bool failed = false, signalled = false, overBudget = false;
    auto lastBeat = Clock::now();
    for (;;) {
        bool stop = false;
        while (std::optional<MpiMessage> m = session.poll()) {
            if (m->source != 0) continue;
            if (m->tag == kTagStop) {
                stop = true;
                break;
            }
            if (m->tag == kTagWork && !failed && !overBudget) {
                batches.push_back(decodeKeys(m->bytes));
                scheduler.request(batches.back());
            }
        }
        if (stop) break;
        if (interrupted()) {  // the launcher's SIGTERM reached this rank too
            signalled = true;
            break;
        }
        const size_t budget = options.memoryBudgetBytes;
        if (options.shards && budget > 0 && store.bytes() > budget && !overBudget) {
            overBudget = true;
            scheduler.cancel();
            session.send(0, kTagOverBudget, {});
        }
        const PrecomputeProgress p = scheduler.progress();
        if (p.state == State::Failed && !failed) {
            failed = true;
            const std::string& e = p.error;
            session.send(0, kTagFailure, Bytes(e.begin(), e.end()));
        }
        // Finished batches go back in the order they complete (any order: rank 0 sorts).
        for (auto it = batches.begin(); it != batches.end();) {
            if (allBuilt(store, *it)) {
                Bytes count;
                putU64(count, it->size());
                session.send(0, kTagResult, options.shards ? count : encodeTreeRecords(store, *it));
                it = batches.erase(it);
                lastBeat = Clock::now();
            } else {
                ++it;
            }
        }
        if (Clock::now() - lastBeat >= kHeartbeat) {
            session.send(0, kTagHeartbeat, {});
            lastBeat = Clock::now();
        }
        std::this_thread::sleep_for(kPoll);
    }
    scheduler.cancel();
    scheduler.wait();
    // The trees of unfinished batches that did finish: rank 0 writes every finished pair.
    std::vector<PairKey> finished;
    for (const auto& batch : batches)
        for (const PairKey& k : batch)
            if (store.find(k)) finished.push_back(k);
    if (options.shards) {
        // The shard first: with a SIGTERM, the launcher kills this rank about a second later.
        Bytes final;
        putU64(final, finished.size());
        std::string error;
        try {
            if (writeShard) error = writeShard();
        } catch (const std::exception& e) {
            error = e.what();
        }
        final.insert(final.end(), error.begin(), error.end());
        session.send(0, kTagFinal, final);
    } else {
        session.send(0, kTagFinal, encodeTreeRecords(store, finished));
    }
    if (signalled) awaitStop(session);  // rank 0 decides when the job ends
}

}  // namespace penumbra::cluster
