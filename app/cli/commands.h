// The subcommands of the `penumbra` executable and what they share.
//
// Each subcommand lives in its own file app/<name>_command.cpp and exposes one
// register<Name>Command(CLI::App&) that adds the subcommand to the app with its options and a
// callback that runs it. A callback reports failure by throwing CommandError (or SceneError, an
// input error); main() turns every exception into "penumbra: error: ..." on stderr and an exit
// code (ExitCode). Commands write their results to stdout only.
#pragma once

#include <exception>
#include <filesystem>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>

#include "engine/io/load_options.h"
#include "engine/scene/scene.h"

namespace CLI {
class App;
}  // namespace CLI

namespace penumbra::cli {

enum ExitCode : int {
    kExitOk = 0,
    kExitInputError = 1,  // a file that cannot be read or is malformed, a value out of range
    kExitUsageError = 2,  // bad command line: unknown flag, missing or malformed value
};

// A failure of a command, with the exit code it calls for. what() is the message without the
// "penumbra: error: " prefix.
struct CommandError : std::runtime_error {
    CommandError(int exitCode_, const std::string& message)
        : std::runtime_error(message), exitCode(exitCode_) {}
    int exitCode;
};

inline CommandError usageError(const std::string& message) {
    return CommandError(kExitUsageError, message);
}
inline CommandError inputError(const std::string& message) {
    return CommandError(kExitInputError, message);
}

// "penumbra: error: MESSAGE" on stderr; returns `code`.
int fail(int code, const std::string& message);
// What main() does with an exception a command threw: its message on stderr (fail) and its exit
// code (CommandError's; SceneError, bad_alloc and any other: an input error). The cluster's ranks
// say it before MPI_Finalize (app/cli/mpi_launch.h).
int reportError(const std::exception_ptr& error);

// Loads a scene file with engine/io/scene_loader.h, choosing the reader by extension
// (case-insensitive): .obj (with its MTL libraries), .ply, .off, .stl, .gltf, .glb, .json, with
// the options of every command that loads a scene (SceneOptions::load, app/cli/arguments.h:
// --strict, --no-default-light). Prints the default light's announcement when it was added and
// the scene's warnings to stderr ("penumbra: warning: ...", one line each). Throws SceneError (an
// input error: exit status 1) for a missing file, a directory, an unknown extension or a malformed
// scene.
Scene loadSceneFile(const std::filesystem::path& path, const LoadOptions& options);

// `penumbra query`: exact light visibility at points (app/cli/query_command.cpp).
void registerQueryCommand(CLI::App& app);
void registerBenchCommand(CLI::App& app);
// `penumbra view` (app/cli/view_command.cpp) and `penumbra screenshot`
// (app/cli/screenshot_command.cpp): the viewer in a window, and its UI rendered offscreen.
void registerViewCommand(CLI::App& app);
void registerScreenshotCommand(CLI::App& app);
// `penumbra render`: an image with exact soft shadows (app/cli/render_command.cpp).
void registerRenderCommand(CLI::App& app);
// `penumbra precompute`: every pair's history tree into a visibility file
// (app/cli/precompute_command.cpp).
void registerPrecomputeCommand(CLI::App& app);
// `penumbra merge`: visibility files and shards joined into one file (app/cli/merge_command.cpp).
void registerMergeCommand(CLI::App& app);

}  // namespace penumbra::cli
