// DIR/bench.json of `penumbra bench`: every study's results (engine/studies/) in one schema,
// written from the study structs and read back through the same structs, so that the report
// (bench_report.h) reads typed fields. Each struct's keys are listed once (bench_json.cpp) for
// both directions; reading is strict: a missing key, a key nobody reads (one the writer renamed
// or added) or a value of the wrong type is an error naming its place ("table1[2].exact: missing
// \"renderWall\""), never a "-" in the report. Optional parts (a render cut at the limit, the
// all-pairs run of a large scene) are absent keys, as scripts/plot_bench.py expects.
#pragma once

#include <nlohmann/json.hpp>
#include <stdexcept>
#include <string>
#include <vector>

#include "engine/studies/accuracy_study.h"
#include "engine/studies/build_options_study.h"
#include "engine/studies/per_point_study.h"
#include "engine/studies/predicate_study.h"
#include "engine/studies/scaling_study.h"
#include "engine/studies/table1_study.h"

namespace penumbra::cli {

// Where the bench ran.
struct BenchMachine {
    std::string cpu;
    unsigned cores = 0;
    std::string loadavg;    // /proc/loadavg at the start
    std::string date;       // "YYYY-MM-DD HH:MM:SS UTC"
    std::string buildType;  // CMAKE_BUILD_TYPE
};

// The options the report quotes.
struct BenchSettings {
    std::string size, largeSize;
    int spp = 0;
    bool quick = false, skipLarge = false;
    double limit = 0;
    std::string exactCostSize;
};

// A scene a study left out because files it needs are missing (meshes not fetched).
struct SkippedScene {
    std::string study, scene;
    std::vector<std::string> missing;
};

struct BenchResults {
    BenchMachine machine;
    std::string command;  // the command line, every option spelled out
    BenchSettings options;
    std::vector<Table1Row> table1;
    AccuracyBenchRun accuracy;
    PredicateStudy predicates;
    std::vector<BuildOptionsRow> buildOptions;
    std::vector<ScalingRow> scaling;
    std::vector<PerPointRow> perPoint;
    std::vector<SkippedScene> skipped;
};

// A bench.json that does not hold what this program writes.
struct BenchJsonError : std::runtime_error {
    using std::runtime_error::runtime_error;
};

nlohmann::json benchJson(const BenchResults& results);

// Throws BenchJsonError for a missing or unknown key or a value of the wrong type.
BenchResults readBenchJson(const nlohmann::json& bench);

}  // namespace penumbra::cli
