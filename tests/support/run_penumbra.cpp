#include "tests/support/run_penumbra.h"

#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <system_error>

#include "tests/support/test_files.h"

#ifndef PENUMBRA_EXE
#error "PENUMBRA_EXE must name the penumbra executable"
#endif

namespace penumbra::test {

namespace fs = std::filesystem;

std::string shellQuote(const std::string& s) {
    std::string q = "'";
    for (char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
    return q + "'";
}

bool haveMpi() {
#ifdef PENUMBRA_MPIEXEC
    return true;
#else
    return false;
#endif
}

std::string mpirunCommand(int ranks, const std::vector<std::string>& args, int timeoutSeconds) {
#ifdef PENUMBRA_MPIEXEC
    std::string c = "timeout " + std::to_string(timeoutSeconds) + " " +
                    shellQuote(PENUMBRA_MPIEXEC) + " --allow-run-as-root --oversubscribe -np " +
                    std::to_string(ranks) + " " + shellQuote(PENUMBRA_EXE);
    for (const std::string& a : args) c += " " + shellQuote(a);
    return c;
#else
    (void)ranks, (void)args, (void)timeoutSeconds;
    return {};
#endif
}

ProcessResult runPenumbra(const std::vector<std::string>& args, const fs::path& workingDirectory) {
    ProcessResult r;
    // A directory of its own (mkdtemp): tests running in parallel never share the files.
    std::string dirName = (fs::temp_directory_path() / "penumbra_run_XXXXXX").string();
    if (::mkdtemp(dirName.data()) == nullptr) {
        ADD_FAILURE() << "mkdtemp failed for " << dirName;
        return r;
    }
    const fs::path dir = dirName, out = dir / "stdout", err = dir / "stderr";
    std::string command;
    if (!workingDirectory.empty()) command = "cd " + shellQuote(workingDirectory.string()) + " && ";
    command += shellQuote(PENUMBRA_EXE);
    for (const std::string& a : args) command += " " + shellQuote(a);
    command += " >" + shellQuote(out.string()) + " 2>" + shellQuote(err.string());
    const int status = std::system(command.c_str());
    if (status == -1) {
        ADD_FAILURE() << "cannot run: " << command;
    } else {
        r.exitCode = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
        r.out = readFile(out);
        r.err = readFile(err);
    }
    std::error_code ec;
    fs::remove_all(dir, ec);
    return r;
}

}  // namespace penumbra::test
