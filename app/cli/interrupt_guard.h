// InterruptGuard: Ctrl-C (SIGINT) and, under an MPI launcher, its SIGTERM, turned into a flag that
// a long command polls (precompute, render under MPI) instead of the default exit.
//
// The one piece of global state of the commands: a signal handler can only reach a global, and
// only a lock-free atomic may be written from it.
#pragma once

#include <atomic>
#include <csignal>

namespace penumbra::cli {

// The exit status of an interrupted command (the shell's convention for a SIGINT).
inline constexpr int kExitInterrupted = 130;

// Set by the handler; the signal that set it (SIGINT or SIGTERM).
inline std::atomic<bool> gInterrupted{false};
inline std::atomic<int> gSignal{0};
static_assert(std::atomic<bool>::is_always_lock_free && std::atomic<int>::is_always_lock_free);

extern "C" inline void onInterrupt(int signal) {
    gSignal.store(signal, std::memory_order_relaxed);
    gInterrupted.store(true, std::memory_order_relaxed);
}

// Installs the handler of `signal` for the guard's lifetime and restores the previous one.
class InterruptGuard {
  public:
    explicit InterruptGuard(int signal) : signal_(signal) {
        gInterrupted.store(false);
        struct sigaction action {};
        action.sa_handler = &onInterrupt;
        sigemptyset(&action.sa_mask);
        installed_ = ::sigaction(signal_, &action, &previous_) == 0;
    }
    ~InterruptGuard() {
        if (installed_) ::sigaction(signal_, &previous_, nullptr);
    }
    InterruptGuard(const InterruptGuard&) = delete;
    InterruptGuard& operator=(const InterruptGuard&) = delete;

  private:
    int signal_;
    struct sigaction previous_ {};
    bool installed_ = false;
};

}  // namespace penumbra::cli
