// `penumbra merge -o FILE INPUT...`
//
// Joins visibility files of one scene and settings (the shards of `precompute --shards`, whole
// files, or both) into FILE, written atomically (engine/io/visibility_merge.h): byte for byte the
// file one process's precompute writes once the inputs cover every pair. No scene is read: the
// records are copied. A mismatch (another scene, other settings, a corrupt or truncated input, a
// pair built twice with different bytes) is refused naming the file (exit status 1). Missing pairs
// are counted (when a shard states the scene's total) and the file still written: `precompute`
// with that file finishes it.
#include <CLI/CLI.hpp>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <memory>
#include <string>
#include <vector>

#include "app/cli/commands.h"
#include "engine/io/visibility_file.h"
#include "engine/io/visibility_merge.h"

namespace penumbra::cli {
namespace {

namespace fs = std::filesystem;

struct MergeCommandOptions {
    std::string output;
    std::vector<std::string> inputs;
};

void runMergeCommand(const MergeCommandOptions& o) {
    const std::vector<fs::path> inputs(o.inputs.begin(), o.inputs.end());
    const auto start = std::chrono::steady_clock::now();
    VisibilityMergeResult r;
    try {
        r = mergeVisibilityFiles(o.output, inputs);
    } catch (const VisibilityFileError& e) {
        throw inputError(std::string(e.what()) + " (" + toString(e.status) + "); " + o.output +
                         " not written");
    }
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    std::printf("inputs   %zu files (%zu shards), %zu bytes\n", r.inputs, r.shards, r.bytesRead);
    std::printf("trees    %zu (%zu present twice with the same bytes, kept once)\n", r.trees,
                r.duplicates);
    if (!r.pairTotal)
        std::printf("pairs    %zu (no shard among the inputs: the scene's total is not known)\n",
                    r.trees);
    else if (r.trees >= *r.pairTotal)
        std::printf("pairs    %zu of %llu: complete\n", r.trees,
                    static_cast<unsigned long long>(*r.pairTotal));
    else
        std::printf("pairs    %zu of %llu: %llu missing\n", r.trees,
                    static_cast<unsigned long long>(*r.pairTotal),
                    static_cast<unsigned long long>(*r.pairTotal - r.trees));
    std::printf("file     %s: %zu bytes, written\n", o.output.c_str(), r.bytes);
    std::printf("seconds  %.3f\n", seconds);
    std::fflush(stdout);
    if (r.pairTotal && r.trees < *r.pairTotal)
        std::cerr << "penumbra: warning: " << o.output << " lacks " << *r.pairTotal - r.trees
                  << " of " << *r.pairTotal << " pairs; `penumbra precompute SCENE -o " << o.output
                  << "` (same settings) builds them\n";
}

}  // namespace

void registerMergeCommand(CLI::App& app) {
    auto options = std::make_shared<MergeCommandOptions>();
    CLI::App* sub = app.add_subcommand(
        "merge",
        "Join visibility files and shards (precompute --shards) of one scene into one file");
    sub->add_option("-o,--output", options->output, "Visibility file to write (.pvis)")->required();
    sub->add_option("inputs", options->inputs,
                    "Shards and visibility files of the same scene and settings")
        ->required();
    sub->callback([options] { runMergeCommand(*options); });
}

}  // namespace penumbra::cli
