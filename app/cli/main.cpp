// penumbra: the command-line front end. Each subcommand is registered from its own file
// (app/cli/commands.h); this file builds the app and turns every exception into a message and an
// exit code.
#include <CLI/CLI.hpp>
#include <exception>
#include <iostream>
#include <new>
#include <string>
#include <vector>

#include "app/cli/commands.h"
#include "engine/scene/scene_error.h"
#include "engine/scene/worker_threads.h"

namespace {

constexpr const char* kVersion = "penumbra 0.1.0";

int run(int argc, char** argv) {
    CLI::App app{
        "penumbra: exact soft shadows from polygonal area lights (history trees of line space, "
        "Mora & Aveneau 2005).",
        "penumbra"};
    app.set_version_flag("--version", kVersion, "Print the version and exit");
    app.require_subcommand(1);
    penumbra::cli::registerQueryCommand(app);
    penumbra::cli::registerBenchCommand(app);
    penumbra::cli::registerViewCommand(app);
    penumbra::cli::registerScreenshotCommand(app);
    penumbra::cli::registerRenderCommand(app);
    penumbra::cli::registerPrecomputeCommand(app);
    penumbra::cli::registerMergeCommand(app);
    try {
        app.parse(argc, argv);
    } catch (const CLI::Success& e) {  // --help, --version
        return app.exit(e);
    } catch (const CLI::ParseError& e) {
        using penumbra::cli::fail;
        // An unknown subcommand is left over as an extra argument; name it rather than report
        // the missing subcommand.
        const std::vector<std::string> extras = app.remaining();
        if (app.get_subcommands().empty() && !extras.empty() && !extras.front().starts_with('-'))
            return fail(
                penumbra::cli::kExitUsageError,
                "unknown subcommand '" + extras.front() + "' (run 'penumbra --help' for the list)");
        return fail(penumbra::cli::kExitUsageError,
                    std::string(e.what()) + " (run 'penumbra --help' for usage)");
    }
    return penumbra::cli::kExitOk;
}

}  // namespace

int main(int argc, char** argv) {
    // Ended last: every worker thread has ended before the exit handlers run (worker_threads.h).
    const penumbra::WorkerThreadsJoinedAtExit workerThreads;
    try {
        return run(argc, argv);
    } catch (...) {
        return penumbra::cli::reportError(std::current_exception());
    }
}
