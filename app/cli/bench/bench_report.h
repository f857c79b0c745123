// The Markdown report of `penumbra bench` (DIR/report.md): the measurements of one run, as read
// back from DIR/bench.json (bench_json.h), in a section per study with the tables, what each
// column means and the plots when scripts/plot_bench.py drew them.
#pragma once

#include <string>

#include "app/cli/bench/bench_json.h"

namespace penumbra::cli {

// `v` printf-formatted with `format` (one conversion), as the report and the command line it
// quotes print numbers.
std::string fmt(const char* format, double v);

// The report of a bench run. `plots`: the plot PNGs are next to the report; otherwise `plotNote`
// says why not.
std::string benchReport(const BenchResults& bench, bool plots, const std::string& plotNote);

}  // namespace penumbra::cli
