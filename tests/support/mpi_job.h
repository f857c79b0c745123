// MpiJobTest: a test fixture that runs `mpirun ... -np N penumbra ARGS...` as a child process,
// always under a timeout (test::mpirunCommand: a hang fails the test instead of blocking the
// suite), in the foreground or in the background, and finds its processes (a rank to kill, the
// launcher to interrupt). The cluster precompute and render tests share it.
#pragma once

#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <thread>
#include <vector>

#include "tests/support/run_penumbra.h"
#include "tests/support/test_files.h"

namespace penumbra::test {

#define SKIP_WITHOUT_MPI()                                                                  \
    if (!::penumbra::test::haveMpi())                                                       \
    GTEST_SKIP() << "this build has no MPI (Open MPI not found, or PENUMBRA_MPI=OFF): the " \
                    "cluster commands are not compiled in"

class MpiJobTest : public ::testing::Test {
  protected:
    using Clock = std::chrono::steady_clock;

    void SetUp() override {
        const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
        dir_ = std::filesystem::temp_directory_path() /
               ("penumbra_cluster_" + std::to_string(::getpid()) + "_" + info->name());
        std::filesystem::remove_all(dir_);
        std::filesystem::create_directories(dir_);
    }
    void TearDown() override {
        std::error_code ec;
        std::filesystem::remove_all(dir_, ec);
    }

    // `mpirun ... -np N penumbra ARGS...` writing to out/err.
    static std::string mpirunCommand(int ranks, const std::vector<std::string>& args,
                                     const std::filesystem::path& out,
                                     const std::filesystem::path& err) {
        return test::mpirunCommand(ranks, args) + " >" + shellQuote(out.string()) + " 2>" +
               shellQuote(err.string());
    }

    // When a rank dies, Open MPI's launcher sends the others SIGCONT, then SIGTERM and SIGKILL
    // each odls_base_sigkill_timeout (1 s by default) later; rank 0 names the dead rank about
    // 0.6 s after the SIGTERM (docs/cluster.md): a test about rank 0's message gives it
    // `seconds` instead, a margin for a CI machine running test shards in parallel (the
    // launcher's SIGTERM then also comes that much later).
    void giveRanksAfterSigterm(int seconds) {
        launcherEnv_ = "OMPI_MCA_odls_base_sigkill_timeout=" + std::to_string(seconds) + " ";
    }

    ProcessResult mpirun(int ranks, const std::vector<std::string>& args) {
        const std::filesystem::path out = dir_ / "mpi.out", err = dir_ / "mpi.err";
        const int status = std::system(mpirunCommand(ranks, args, out, err).c_str());
        ProcessResult r;
        r.exitCode = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
        r.out = readFile(out);
        r.err = readFile(err);
        return r;
    }

    // Starts mpirun in the background (its exit status into dir_/rc when it ends). The files an
    // earlier run left are removed first: the background shell truncates them only once it runs,
    // and until then awaitStderr would find the earlier run's lines (and awaitEnd its status).
    void start(int ranks, const std::vector<std::string>& args) {
        for (const char* name : {"mpi.out", "mpi.err", "rc", "rc.tmp"})
            std::filesystem::remove(dir_ / name);
        const std::string rcTmp = shellQuote((dir_ / "rc.tmp").string());
        const std::string c =
            "(" + launcherEnv_ + mpirunCommand(ranks, args, dir_ / "mpi.out", dir_ / "mpi.err") +
            "; echo $? >" + rcTmp + "; mv " + rcTmp + " " + shellQuote((dir_ / "rc").string()) +
            ") & echo $! >" + shellQuote((dir_ / "shell.pid").string());
        ASSERT_EQ(std::system(c.c_str()), 0);
    }
    // The exit status of the background run, waiting at most `limit`; -1 if it has not ended.
    int awaitEnd(std::chrono::seconds limit) {
        const auto deadline = Clock::now() + limit;
        while (Clock::now() < deadline) {
            if (std::filesystem::exists(dir_ / "rc")) return std::stoi(readFile(dir_ / "rc"));
            std::this_thread::sleep_for(std::chrono::milliseconds(50));
        }
        return -1;
    }
    // Waits until the background run's stderr holds `text`, at most `limit`.
    bool awaitStderr(const std::string& text, std::chrono::seconds limit) {
        const auto deadline = Clock::now() + limit;
        while (Clock::now() < deadline) {
            if (readFile(dir_ / "mpi.err").find(text) != std::string::npos) return true;
            std::this_thread::sleep_for(std::chrono::milliseconds(20));
        }
        return false;
    }

    // The pid of a process whose command line names `marker` and that `accept`s its command
    // line (NULs between the words) and environment (one variable a line), or -1.
    template <typename Accept>
    static pid_t findProcess(const std::string& marker, Accept accept) {
        for (const auto& entry : std::filesystem::directory_iterator("/proc")) {
            const std::string name = entry.path().filename().string();
            if (name.find_first_not_of("0123456789") != std::string::npos) continue;
            const std::string cmdline = readFile(entry.path() / "cmdline");
            if (cmdline.find(marker) == std::string::npos) continue;
            std::string env = readFile(entry.path() / "environ");
            for (char& c : env)
                if (c == '\0') c = '\n';
            if (accept(cmdline, "\n" + env)) return static_cast<pid_t>(std::stol(name));
        }
        return -1;
    }
    // The penumbra process of rank `rank` (Open MPI tells each its rank in the environment).
    static pid_t findRank(const std::string& marker, int rank) {
        const std::string variable = "\nOMPI_COMM_WORLD_RANK=" + std::to_string(rank) + "\n";
        return findProcess(marker, [&](const std::string&, const std::string& env) {
            return env.find(variable) != std::string::npos;
        });
    }
    // mpirun itself (not the shell or `timeout` that started it).
    static pid_t findLauncher(const std::string& marker) {
        return findProcess(marker, [](const std::string& cmdline, const std::string&) {
            const std::string program = cmdline.substr(0, cmdline.find('\0'));
            const std::string name = std::filesystem::path(program).filename().string();
            return name == "mpirun" || name == "mpiexec" || name == "orterun";
        });
    }

    std::filesystem::path dir_;
    std::string launcherEnv_;  // variables set for the launcher (giveRanksAfterSigterm)
};

}  // namespace penumbra::test
