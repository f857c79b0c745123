// The Markdown report of `penumbra bench` (DIR/report.md): the measurements of one run, as read
// back from DIR/bench.json (bench_json.h). It opens with the conclusion, computed from the same
// fields as the tables (exact against sampling per scene, at equal error and at equal time where
// the bench measured them), then the run and a glossary, then a section per study with its
// tables, what each column means and the plots when scripts/plot_bench.py drew them. A quick run
// says on its first line that its sizes are not for conclusions.
#pragma once

#include <string>

#include "app/cli/bench/bench_json.h"

namespace penumbra::cli {

// `v` printf-formatted with `format` (one conversion), as the report and the command line it
// quotes print numbers.
std::string fmt(const char* format, double v);

// What a quick run (--quick) is for, in one sentence: the first line of its report and of what
// the bench prints on stderr.
std::string quickRunNote(const BenchSettings& options);

// The report of a bench run. `plots`: the plot PNGs are next to the report; otherwise `plotNote`
// says why not.
std::string benchReport(const BenchResults& bench, bool plots, const std::string& plotNote);

}  // namespace penumbra::cli
