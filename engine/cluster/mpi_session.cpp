#include "engine/cluster/mpi_session.h"

#include <mpi.h>

#include <climits>
#include <cstdlib>
#include <functional>
#include <thread>

namespace penumbra::cluster {
namespace detail_mpi {

std::string errorText(int code) {
    char text[MPI_MAX_ERROR_STRING];
    int length = 0;
    if (MPI_Error_string(code, text, &length) != MPI_SUCCESS)
        return "MPI error " + std::to_string(code);
    return std::string(text, static_cast<size_t>(length));
}

// `peer`: the rank the call was a send to or a receive from (MpiError::peer), -1 for none.
void check(int code, const std::string& what, int peer = -1) {
    if (code != MPI_SUCCESS) throw MpiError(what + ": " + errorText(code), peer);
}

}  // namespace detail_mpi

bool launchedByMpiLauncher() {
    for (const char* name : {"OMPI_COMM_WORLD_SIZE", "PMIX_RANK", "PMI_SIZE", "PMI_RANK"})
        if (std::getenv(name) != nullptr) return true;
    return false;
}

MpiSession::MpiSession() {
    if (!launchedByMpiLauncher()) return;
    int initialised = 0;
    MPI_Initialized(&initialised);
    if (initialised) throw MpiError("MPI is already initialised (one MpiSession per process)");
    // FUNNELED: only the thread that made the session calls MPI; the builds run on oneTBB's
    // threads and never do.
    int provided = 0;
    detail_mpi::check(MPI_Init_thread(nullptr, nullptr, MPI_THREAD_FUNNELED, &provided),
                      "MPI_Init_thread");
    active_ = true;
    MPI_Comm_set_errhandler(MPI_COMM_WORLD, MPI_ERRORS_RETURN);
    MPI_Comm_rank(MPI_COMM_WORLD, &rank_);
    MPI_Comm_size(MPI_COMM_WORLD, &size_);
    char name[MPI_MAX_PROCESSOR_NAME];
    int length = 0;
    if (MPI_Get_processor_name(name, &length) == MPI_SUCCESS)
        host_.assign(name, static_cast<size_t>(length));
}

MpiSession::~MpiSession() {
    if (active_) MPI_Finalize();
}

namespace detail_mpi {

// Waits, sleeping, until `request` completes. Past `timeout`, or past
// MpiSession::kInterruptedGrace once `interrupted` says so, the request is cancelled and freed
// and the returned error says why (its buffer may still be written to: the caller keeps it).
std::optional<MpiError> await(MPI_Request& request, int peer, const std::string& what,
                              std::chrono::milliseconds timeout,
                              const std::function<bool()>& interrupted, const char* lateCause) {
    const auto start = std::chrono::steady_clock::now();
    auto deadline = start + timeout;
    bool sawInterrupt = false;
    auto pause = std::chrono::microseconds(20);
    for (;;) {
        int done = 0;
        check(MPI_Test(&request, &done, MPI_STATUS_IGNORE), what, peer);
        if (done) return std::nullopt;
        const auto now = std::chrono::steady_clock::now();
        if (!sawInterrupt && interrupted && interrupted()) {
            sawInterrupt = true;
            deadline = std::min(deadline, now + MpiSession::kInterruptedGrace);
        }
        if (now > deadline) {
            MPI_Cancel(&request);
            MPI_Request_free(&request);
            const auto waited =
                std::chrono::duration_cast<std::chrono::milliseconds>(now - start).count();
            return MpiError(what + ": " + lateCause + " after " + std::to_string(waited) +
                                " ms (the rank stopped answering" +
                                (sawInterrupt ? ", and this one was interrupted)" : ")"),
                            peer);
        }
        std::this_thread::sleep_for(pause);
        pause = std::min<std::chrono::microseconds>(pause * 2, std::chrono::milliseconds(2));
    }
}

}  // namespace detail_mpi

void MpiSession::send(int to, int tag, std::span<const unsigned char> bytes,
                      std::chrono::milliseconds timeout) {
    if (!active_) throw MpiError("no MPI session (not started by an MPI launcher)");
    if (bytes.size() > static_cast<size_t>(INT_MAX))
        throw MpiError("a message of " + std::to_string(bytes.size()) + " bytes to rank " +
                       std::to_string(to) + " (at most " + std::to_string(INT_MAX) + ")");
    MPI_Request request;
    const std::string what = "sending to rank " + std::to_string(to);
    detail_mpi::check(MPI_Isend(bytes.data(), static_cast<int>(bytes.size()), MPI_BYTE, to, tag,
                                MPI_COMM_WORLD, &request),
                      what, to);
    // (A send's buffer is the caller's, which the abort that follows a lost rank ends.)
    if (auto error = detail_mpi::await(request, to, what, timeout, interrupted_, "not received"))
        throw *error;
}

std::optional<MpiMessage> MpiSession::poll(std::chrono::milliseconds timeout) {
    if (!active_) return std::nullopt;
    int arrived = 0;
    MPI_Message handle;
    MPI_Status status;
    detail_mpi::check(
        MPI_Improbe(MPI_ANY_SOURCE, MPI_ANY_TAG, MPI_COMM_WORLD, &arrived, &handle, &status),
        "polling for messages");
    if (!arrived) return std::nullopt;
    int count = 0;
    MPI_Get_count(&status, MPI_BYTE, &count);
    MpiMessage m;
    m.source = status.MPI_SOURCE;
    m.tag = status.MPI_TAG;
    m.bytes.resize(static_cast<size_t>(count));
    // The matched message (MPI_Improbe: no other receive can take it), which may still be
    // arriving (mpi_session.h).
    const std::string what = "receiving from rank " + std::to_string(m.source);
    MPI_Request request;
    detail_mpi::check(MPI_Imrecv(m.bytes.data(), count, MPI_BYTE, &handle, &request), what,
                      m.source);
    if (auto error = detail_mpi::await(request, m.source, what, timeout, interrupted_,
                                       "the message stopped arriving")) {
        abandoned_.push_back(std::move(m.bytes));  // MPI may still write to it
        throw *error;
    }
    return m;
}

void MpiSession::abort(int exitCode) {
    if (active_) MPI_Abort(MPI_COMM_WORLD, exitCode);
    std::_Exit(exitCode);
}

}  // namespace penumbra::cluster
