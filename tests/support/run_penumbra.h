// Runs this build's `penumbra` executable (the PENUMBRA_EXE compile definition) as a real process,
// for the tests of its commands: the CLI, precompute, render and viewer tests share it.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

namespace penumbra::test {

struct ProcessResult {
    int exitCode = -1;     // the exit status, or 128 + the signal that ended the process
    std::string out, err;  // all it wrote to stdout and to stderr
};

// `s` as one word for the POSIX shell (single-quoted).
std::string shellQuote(const std::string& s);

// Runs `penumbra ARGS...` through the shell and waits for it, in `workingDirectory` when given
// (commands that read files relative to the current directory, such as the bench's default
// scenes). Its stdout and stderr go to two files in a fresh temporary directory, read back and
// removed with it. If it cannot be run at all: ADD_FAILURE and exit code -1.
ProcessResult runPenumbra(const std::vector<std::string>& args,
                          const std::filesystem::path& workingDirectory = {});

// True when this build's penumbra has the cluster precompute (MPI: PENUMBRA_MPIEXEC names the
// launcher).
bool haveMpi();
// The shell command line (no redirections) that runs `penumbra ARGS...` as `ranks` ranks of one
// mpirun on this machine (as root too, more ranks than cores) under `timeout` (exit status 124
// when it hangs). Empty without MPI. (The ranks end with _Exit after MPI_Finalize,
// app/cli/mpi_launch.h: no LeakSanitizer check runs in them, so nothing Open MPI keeps
// at exit needs a suppression.)
std::string mpirunCommand(int ranks, const std::vector<std::string>& args,
                          int timeoutSeconds = 120);

}  // namespace penumbra::test
