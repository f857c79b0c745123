// How a command that an MPI launcher may have started runs (precompute, render): with more than
// one rank, its cluster form; with one, as without a launcher. Only in a build with MPI.
#pragma once

#ifdef PENUMBRA_HAVE_MPI

#include <cstdio>
#include <cstdlib>
#include <exception>
#include <functional>
#include <iostream>

#include "app/cli/commands.h"
#include "engine/cluster/mpi_session.h"

namespace penumbra::cli {

// Starts MPI (cluster::MpiSession), runs `cluster` (more than one rank) or `single` (one), and
// ends the process: the error is said before MPI_Finalize (the launcher may kill a rank during
// it, a second after its SIGTERM), then the rank ends with _Exit, because oneTBB's wait for its
// threads at exit (WorkerThreadsJoinedAtExit) was seen to never return on a worker rank after
// MPI_Finalize (1 run in 5, Open MPI 4.1.4, oneTBB 2021.8).
[[noreturn]] inline void runLaunched(const std::function<void(cluster::MpiSession&)>& cluster,
                                     const std::function<void()>& single) {
    int exitCode = kExitOk;
    {
        cluster::MpiSession session;
        try {
            if (session.size() > 1)
                cluster(session);
            else
                single();
        } catch (...) {
            exitCode = reportError(std::current_exception());
        }
        std::fflush(stdout);
        std::cerr.flush();
    }  // MPI_Finalize
    std::_Exit(exitCode);
}

}  // namespace penumbra::cli

#endif
