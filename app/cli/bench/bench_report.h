// The Markdown report of `penumbra bench` (DIR/report.md): the measurements of one run, as the
// command writes them to DIR/bench.json (app/cli/bench/bench_command.cpp), in a section per study
// with the tables, what each column means and the plots when scripts/plot_bench.py drew them.
#pragma once

#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>

namespace penumbra::cli {

// Every (patch, light) pair of a scene above this many faces is not a precompute anyone would run
// (the image's pairs are the Table 1 figure there): the all-pairs column is skipped.
inline constexpr uint32_t kAllPairsMaxFaces = 10000;

// `v` printf-formatted with `format` (one conversion), as the report and the command line it
// quotes print numbers.
std::string fmt(const char* format, double v);

// The report of `bench` (the object written to bench.json). `plots`: the plot PNGs are next to the
// report; otherwise `plotNote` says why not.
std::string benchReport(const nlohmann::json& bench, bool plots, const std::string& plotNote);

}  // namespace penumbra::cli
