#include "engine/precompute/precompute_scheduler.h"

#include <tbb/global_control.h>
#include <tbb/info.h>
#include <tbb/task_arena.h>
#include <tbb/task_group.h>

#include <algorithm>
#include <chrono>
#include <deque>
#include <mutex>
#include <unordered_map>
#include <unordered_set>

namespace penumbra {
namespace {

using Clock = std::chrono::steady_clock;
using State = PrecomputeProgress::State;

// ThreadSanitizer cannot see the synchronisation inside oneTBB (not instrumented): the enqueuing
// thread constructs the task (our lambda) and a worker runs it, and the end of a task is
// published to task_group::wait() - both through TBB's own atomics. These annotations state those
// two happens-before edges (which TBB guarantees) on one tag address, so that TSan checks our
// code without false reports. No-ops in other builds.
#if defined(__SANITIZE_THREAD__)
extern "C" void __tsan_acquire(void* addr);
extern "C" void __tsan_release(void* addr);
char* syncTag() {
    static char tag;  // only its address is used
    return &tag;
}
void handOff() { __tsan_release(syncTag()); }
void takeOver() { __tsan_acquire(syncTag()); }
#else
void handOff() {}
void takeOver() {}
#endif

// The builds that can really run at once: the request (default: the cores), capped by the TBB
// workers the process may have (max_allowed_parallelism - 1: one core is kept for the thread
// that would wait, which here never joins), and at least 1 (TBB always lends one worker to an
// arena with enqueued work).
int effectiveThreads(int requested) {
    const int wanted = requested > 0 ? requested : tbb::info::default_concurrency();
    const auto allowed = static_cast<int>(
        tbb::global_control::active_value(tbb::global_control::max_allowed_parallelism));
    return std::max(1, std::min(wanted, allowed - 1));
}

}  // namespace

const char* toString(PrecomputeProgress::State state) {
    switch (state) {
        case State::Idle:
            return "idle";
        case State::Running:
            return "running";
        case State::Cancelled:
            return "cancelled";
        case State::OverBudget:
            return "over budget";
        case State::Failed:
            return "failed";
    }
    return "?";
}

struct PrecomputeScheduler::Impl {
    // Where a key of the current batch is (a member type: a type of the anonymous namespace in
    // a member of this class would give it internal linkage in a unity build).
    enum class KeyState : uint8_t { Queued, Running, Done };

    // One pair handed to a worker, with the cancel flag and generation of the batch it came from
    // (cancel() replaces both, so a late finisher of a cancelled batch touches nothing new).
    struct Job {
        PairKey key;
        std::shared_ptr<std::atomic<bool>> cancel;
        uint64_t generation = 0;
    };

    Impl(VisibilityStore& s, const PrecomputeOptions& o)
        : store(s),
          options(o),
          threads(effectiveThreads(o.threads)),
          // No slot reserved for the caller: the UI thread never joins, the workers do the work.
          arena(threads, 0),
          cancelFlag(std::make_shared<std::atomic<bool>>(false)) {}

    VisibilityStore& store;
    const PrecomputeOptions options;
    const int threads;
    tbb::task_arena arena;
    tbb::task_group group;

    // Everything below is guarded by `mutex`; no build ever runs under it.
    mutable std::mutex mutex;
    // Pending keys, front first. May hold stale entries (keys moved to the front by a later
    // request, or no longer Queued): popNext() skips them; compact() drops them when they pile up.
    std::deque<PairKey> queue;
    std::unordered_map<PairKey, KeyState, PairKeyHash> batch;  // every key of the current batch
    size_t queued = 0;                                         // keys of the batch in state Queued
    size_t done = 0, total = 0, nodes = 0, built = 0;
    Clock::time_point start{};
    double frozenSeconds = 0;
    State state = State::Idle;
    std::string error;
    int workers = 0;   // worker tasks alive
    int inFlight = 0;  // builds running
    uint64_t generation = 0;
    std::shared_ptr<std::atomic<bool>> cancelFlag;

    bool overBudget() const {
        return options.memoryBudgetBytes > 0 && store.bytes() > options.memoryBudgetBytes;
    }
    double elapsed() const {
        return state == State::Running ? std::chrono::duration<double>(Clock::now() - start).count()
                                       : frozenSeconds;
    }
    // Leaves Running: freezes the clock, drops what is pending.
    void stop(State to) {
        frozenSeconds = elapsed();
        state = to;
        queue.clear();
        queued = 0;
    }
    void beginBatchIfNeeded() {
        if (state == State::Running) return;
        batch.clear();
        queue.clear();
        queued = done = total = nodes = built = 0;
        error.clear();
        start = Clock::now();
        frozenSeconds = 0;
        state = State::Running;
    }
    void finishIfIdle() {
        if (state == State::Running && queued == 0 && inFlight == 0) stop(State::Idle);
    }

    // Adds keys to the batch; those still to build go to the front (in order) or the back.
    void enqueue(const std::vector<PairKey>& keys, bool front) {
        beginBatchIfNeeded();
        if (overBudget()) {
            stop(State::OverBudget);
            return;
        }
        std::vector<PairKey> fresh;
        fresh.reserve(keys.size());
        for (const PairKey& key : keys) {
            const auto [it, inserted] = batch.try_emplace(key, KeyState::Queued);
            if (!inserted) {
                // Already queued: a request to the front moves it there (its old entry goes
                // stale). Running or done: nothing to do.
                if (front && it->second == KeyState::Queued) fresh.push_back(key);
                continue;
            }
            ++total;
            if (const PairRecord* r = store.find(key)) {
                it->second = KeyState::Done;
                ++done;
                nodes += r->tree.nodes.size();
                continue;
            }
            ++queued;
            fresh.push_back(key);
        }
        if (front)
            queue.insert(queue.begin(), fresh.begin(), fresh.end());
        else
            queue.insert(queue.end(), fresh.begin(), fresh.end());
        compact();
        spawnWorkers();
        finishIfIdle();
    }

    // Drops stale queue entries once they outnumber the live ones (amortised O(1) per entry).
    void compact() {
        if (queue.size() <= 2 * queued + 1024) return;
        std::unordered_set<PairKey, PairKeyHash> seen;
        std::deque<PairKey> kept;
        for (const PairKey& key : queue) {
            const auto it = batch.find(key);
            if (it != batch.end() && it->second == KeyState::Queued && seen.insert(key).second)
                kept.push_back(key);
        }
        queue.swap(kept);
    }

    void spawnWorkers() {
        while (workers < threads && static_cast<size_t>(workers) < queued) {
            ++workers;
            // (takeOver: a task's memory may be one a finished worker's task used before.)
            takeOver();
            tbb::task_handle task = group.defer([this] {
                takeOver();
                workerLoop();
                handOff();
            });
            handOff();
            // enqueue: fire and forget, the caller does not join the arena (never blocks).
            arena.enqueue(std::move(task));
        }
    }

    bool popNext(Job& job) {
        if (state != State::Running) return false;
        if (overBudget()) {
            stop(State::OverBudget);
            return false;
        }
        while (!queue.empty()) {
            const PairKey key = queue.front();
            queue.pop_front();
            const auto it = batch.find(key);
            if (it == batch.end() || it->second != KeyState::Queued) continue;  // stale
            it->second = KeyState::Running;
            --queued;
            job = Job{key, cancelFlag, generation};
            return true;
        }
        return false;
    }

    void workerLoop() {
        for (;;) {
            Job job;
            {
                std::lock_guard lock(mutex);
                if (!popNext(job)) {
                    --workers;
                    finishIfIdle();
                    return;
                }
                ++inFlight;
            }
            const PairRecord* record = nullptr;
            std::string failure;
            try {
                record = &store.getOrBuild(job.key, job.cancel.get());
            } catch (const vis::BuildCancelled&) {
                // The batch was cancelled: the store keeps nothing of this build.
            } catch (const std::exception& e) {
                failure = e.what();
            } catch (...) {
                failure = "unknown exception";
            }
            std::lock_guard lock(mutex);
            --inFlight;
            if (job.generation != generation) {  // a cancelled batch: its counters are gone
                finishIfIdle();
                continue;
            }
            if (record != nullptr) {
                batch[job.key] = KeyState::Done;
                ++done;
                ++built;
                nodes += record->tree.nodes.size();
                if (state == State::Running && overBudget()) stop(State::OverBudget);
            } else if (!failure.empty() && state == State::Running) {
                error = "pair (receiver " + std::to_string(job.key.receiver) + ", patch " +
                        std::to_string(job.key.patch) + ", light face " +
                        std::to_string(job.key.lightFace) + "): " + failure;
                stop(State::Failed);
            }
            finishIfIdle();
        }
    }

    void cancel() {
        std::lock_guard lock(mutex);
        cancelFlag->store(true, std::memory_order_relaxed);
        cancelFlag = std::make_shared<std::atomic<bool>>(false);
        ++generation;
        if (state == State::Running)
            stop(State::Cancelled);
        else {
            queue.clear();
            queued = 0;
        }
    }
};

PrecomputeScheduler::PrecomputeScheduler(VisibilityStore& store, size_t memoryBudgetBytes)
    : PrecomputeScheduler(store, PrecomputeOptions{memoryBudgetBytes, 0}) {}

PrecomputeScheduler::PrecomputeScheduler(VisibilityStore& store, const PrecomputeOptions& options)
    : impl_(std::make_unique<Impl>(store, options)) {}

PrecomputeScheduler::~PrecomputeScheduler() {
    cancel();
    wait();
}

void PrecomputeScheduler::request(std::vector<PairKey> keys) {
    std::lock_guard lock(impl_->mutex);
    impl_->enqueue(keys, true);
}

std::vector<PairKey> everyPairKey(const VisibilityStore& store) {
    const Scene& scene = store.scene();
    std::vector<PairKey> keys;
    for (uint32_t f = 0; f < scene.faceCount(); ++f) {
        const auto patches = static_cast<uint32_t>(store.layout().patchCount(f));
        for (uint32_t p = 0; p < patches; ++p)
            for (uint32_t light : scene.lights)
                if (light != f) keys.push_back({f, p, light});
    }
    return keys;
}

void PrecomputeScheduler::requestAll() {
    const std::vector<PairKey> keys = everyPairKey(impl_->store);
    std::lock_guard lock(impl_->mutex);
    impl_->enqueue(keys, false);
}

PrecomputeProgress PrecomputeScheduler::progress() const {
    std::lock_guard lock(impl_->mutex);
    const Impl& m = *impl_;
    PrecomputeProgress p;
    p.done = m.done;
    p.total = m.total;
    p.seconds = m.elapsed();
    if (m.state == State::Running && m.built > 0)
        p.secondsLeft = p.seconds * static_cast<double>(m.total - m.done) / m.built;
    p.bytes = m.store.bytes();
    p.nodes = m.nodes;
    p.state = m.state;
    p.error = m.error;
    return p;
}

void PrecomputeScheduler::cancel() { impl_->cancel(); }

void PrecomputeScheduler::wait() {
    impl_->arena.execute([this] { impl_->group.wait(); });
    takeOver();
}

int PrecomputeScheduler::threads() const { return impl_->threads; }

}  // namespace penumbra
