// MpiSession: MPI for a process that an MPI launcher started (mpirun, mpiexec, Slurm's srun),
// and nothing at all for any other run.
//
// MPI is initialised only when the environment says a launcher started the process
// (launchedByMpiLauncher: Open MPI's OMPI_COMM_WORLD_SIZE, PMIx's PMIX_RANK, PMI's PMI_SIZE,
// PMI_RANK), so that a plain `penumbra precompute` neither pays MPI_Init nor depends on MPI's
// runtime: a singleton MPI_Init + MPI_Finalize (Open MPI 4.1 starts its runtime daemon for it)
// took 0.6-0.8 s here, against 0.2 s for the whole precompute of the Cornell box. The session
// owns MPI_Init_thread / MPI_Finalize (one session per process).
//
// Messages are tagged byte strings on MPI_COMM_WORLD, sent and received without ever blocking
// in MPI: Open MPI's blocking calls spin a core, which the trees need (the coordinator would
// take a core from the builds of its own node), and they cannot time out. MPI_ERRORS_RETURN is
// set on the communicator, so a failed call becomes an MpiError naming the peer rather than the
// default abort without a word.
#pragma once

#include <chrono>
#include <cstdint>
#include <functional>
#include <optional>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

namespace penumbra::cluster {

// An MPI call failed, or a peer did not answer in time. what() names the rank and the cause;
// `peer` is that rank when the failure was a send to it or a receive from it (a rank that died
// or stopped answering), so that a coordinator can treat it as that rank's loss. -1 otherwise.
struct MpiError : std::runtime_error {
    explicit MpiError(const std::string& what, int peer = -1)
        : std::runtime_error(what), peer(peer) {}
    int peer;
};

struct MpiMessage {
    int source = -1;
    int tag = -1;
    std::vector<unsigned char> bytes;
};

// True when an MPI launcher started this process (see above).
bool launchedByMpiLauncher();

class MpiSession {
  public:
    // Initialises MPI when launchedByMpiLauncher(), else makes an inactive session (rank 0 of 1).
    MpiSession();
    ~MpiSession();  // MPI_Finalize, when it initialised MPI
    MpiSession(const MpiSession&) = delete;
    MpiSession& operator=(const MpiSession&) = delete;

    bool active() const { return active_; }
    int rank() const { return rank_; }
    int size() const { return size_; }
    // This node's name (MPI_Get_processor_name), for messages.
    const std::string& host() const { return host_; }

    // Sends `bytes` to rank `to` with `tag` and waits (sleeping, not spinning) until MPI has
    // taken them; throws MpiError when that takes longer than `timeout` (a peer that stopped
    // receiving), or kInterruptedGrace once interrupted (below), or MPI reports an error.
    void send(int to, int tag, std::span<const unsigned char> bytes,
              std::chrono::milliseconds timeout = std::chrono::seconds(60));
    // The next message from any rank, if one has begun to arrive (never waits for one to
    // begin). A probed message may still be arriving: a large one comes in fragments, and a
    // sender that dies between them leaves its receive unfinished for ever (Open MPI's TCP
    // transport reports the broken connection on stderr, not to the receive). So the receive is
    // waited for like a send: at most `timeout`, or kInterruptedGrace once interrupted; then
    // MpiError naming the rank ("the message stopped arriving").
    std::optional<MpiMessage> poll(std::chrono::milliseconds timeout = std::chrono::seconds(60));

    // The process was interrupted (Ctrl-C; the launcher's SIGTERM, which Open MPI also sends
    // when another rank dies, a second before its SIGKILL): the waits above then give up after
    // kInterruptedGrace, so that rank 0 can still say which rank ended before the SIGKILL.
    void setInterrupted(std::function<bool()> interrupted) {
        interrupted_ = std::move(interrupted);
    }
    static constexpr std::chrono::milliseconds kInterruptedGrace{100};

    // Ends every process of the job (MPI_Abort) with this exit status.
    [[noreturn]] void abort(int exitCode);

  private:
    std::function<bool()> interrupted_;
    // The buffers of receives given up on (poll): kept while MPI might still write to them.
    std::vector<std::vector<unsigned char>> abandoned_;
    bool active_ = false;
    int rank_ = 0;
    int size_ = 1;
    std::string host_;
};

}  // namespace penumbra::cluster
