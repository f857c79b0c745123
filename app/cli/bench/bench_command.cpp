// penumbra bench [SCENES] --out DIR: what accuracy costs in time, every comparison
// measured in one run on one machine, written as DIR/bench.json, DIR/report.md and (through
// scripts/plot_bench.py) PNG plots. The studies are engine/studies/; this command parses the
// options, orders the studies on their scenes, writes bench.json (bench_json.h) and the report
// from it read back (bench_report.h):
//   table1     the paper's Table 1: 128-ray sampled rendering against the exact renderer (its
//              precompute of the trees the image needs, and all pairs for small scenes), the
//              visibility file's size, the speed-up; the image with every point exact and
//              sampling at equal error over its penumbra (equal_error_study.h); wall and CPU
//              times (the machine is shared).
//   accuracy   error against time: sampled with 1..1024 rays against the exact image, the exact
//              image against a converged reference, the equal-error time.
//   predicates FPQuery with filtered, always-exact and naive double predicates on the hard cases.
//   options    quadric pruning and leaf merging on and off.
//   scaling    precompute time and size against the triangle count (the dragon's resolutions).
//   per point  the from-point query plus the exact form factor against 16 and 128 shadow rays.
// A default scene whose meshes scripts/fetch_meshes.sh has not fetched (the bunny, the motorbike,
// the dragon) is skipped, with a warning and a line in the report (loadForStudy).
#include <CLI/CLI.hpp>
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "app/cli/arguments.h"
#include "app/cli/bench/bench_json.h"
#include "app/cli/bench/bench_report.h"
#include "app/cli/commands.h"
#include "engine/io/atomic_file.h"
#include "engine/io/finite_output.h"
#include "engine/io/text_input.h"
#include "engine/render/renderer.h"
#include "engine/scene/scene_error.h"
#include "engine/studies/study_harness.h"

#ifndef PENUMBRA_BUILD_TYPE
#define PENUMBRA_BUILD_TYPE "unknown"
#endif

namespace penumbra::cli {
namespace {

namespace fs = std::filesystem;

struct BenchOptions {
    std::vector<std::string> scenes;
    std::string out;
    std::string size = "512x512";
    std::string largeSize = "256x256";
    int spp = 16;
    std::string accuracyScene = "assets/scenes/cornell_box.json";
    std::string accuracySize = "128x128";
    int accuracySpp = 4;
    int maxRays = 1024;
    int referenceRays = 2048;
    int points = 2000;
    double limit = 180;  // seconds per precompute before it is cancelled
    bool quick = false;
    bool skipLarge = false;
    bool noPlots = false;
    SceneOptions sceneOptions;
    bool reportOnly = false;  // DIR/report.md again from DIR/bench.json, nothing measured
    // The image of the per-point cost with every point exact, for the scenes whose Table 1 image
    // is too costly to render without the work limit (the large ones, and those above
    // kAllPairsMaxFaces faces): one sample per pixel.
    std::string exactCostSize = "128x128";
    // The equal-error study's largest shadow-ray count per light (Table 1).
    int equalErrorMaxRays = 4096;
    // Table 1's exact render: the light-edge path's own limit (RenderSettings).
    uint64_t lightEdgeWorkLimit = RenderSettings{}.lightEdgeWorkLimit;
};

// A study's progress line, on stdout as it comes.
void printLine(const std::string& line) {
    std::printf("%s\n", line.c_str());
    std::fflush(stdout);
}

// ---- Scenes with fetched meshes --------------------------------------------------------------

// The scene `study` measures, or nullopt when a file it needs is missing: the scene file itself,
// or a mesh file it names (the committed scenes of the bunny, the motorbike and the dragon name
// meshes that scripts/fetch_meshes.sh downloads into assets/external/, too large to commit, so a
// fresh clone lacks them). Then says on stderr which file is missing and records the skip in
// `skipped` (the report lists it under the study): the one way the bench leaves out a scene, so
// that a fresh clone still gets a report. Other load errors are thrown.
std::optional<Scene> loadForStudy(const std::string& path, const std::string& study,
                                  const LoadOptions& load, std::vector<SkippedScene>& skipped) {
    std::optional<std::string> missing;
    if (!fs::exists(path)) {
        missing = path;
    } else {
        try {
            return loadSceneFile(path, load);
        } catch (const SceneError& e) {
            // A mesh file the scene names is not there (SceneError::Kind::MissingFile); any other
            // error (a scene that does not parse) is thrown: loading it says what is wrong.
            if (e.kind != SceneError::Kind::MissingFile) throw;
            missing = fs::path(e.missingFile).lexically_normal().string();
        }
    }
    std::fprintf(stderr,
                 "penumbra: warning: %s: %s skipped, missing %s (run scripts/fetch_meshes.sh to "
                 "fetch the meshes)\n",
                 study.c_str(), path.c_str(), missing->c_str());
    skipped.push_back({study, path, {*missing}});
    return std::nullopt;
}

// ---- The studies, in the report's order ------------------------------------------------------

Table1Options table1Options(const BenchOptions& o, const fs::path& dir, bool large) {
    Table1Options t;
    const auto [w, h] =
        parseSize(large ? "--large-size" : "--size", large ? o.largeSize : o.size, kImageSize);
    t.width = w;
    t.height = h;
    t.spp = o.spp;
    t.limit = o.limit;
    t.quick = o.quick;
    t.large = large;
    const auto [cw, ch] = parseSize("--exact-cost-size", o.exactCostSize, kImageSize);
    t.exactCostWidth = cw;
    t.exactCostHeight = ch;
    t.outDir = dir;
    t.equalErrorMaxRays = o.equalErrorMaxRays;
    t.lightEdgeWorkLimit = o.lightEdgeWorkLimit;
    return t;
}

// Table 1 on the small scenes (the committed ones and the bunny, or those given), then the large
// ones (the motorbike, 332k faces of CAD parts, and the dragon, 871k of a scanned model) at
// --large-size. `small` gets the small scenes the other studies measure too.
std::vector<Table1Row> measureTable1(const BenchOptions& o, const fs::path& dir,
                                     std::vector<std::string>& small,
                                     std::vector<SkippedScene>& skipped) {
    small = o.scenes;
    std::vector<std::string> large;
    const std::string bunny = "assets/scenes/bunny_in_box.json";
    std::optional<Scene> bunnyScene;  // loaded to see whether it can be measured
    if (small.empty()) {
        small = {"assets/scenes/stairs.json", "assets/scenes/table.json",
                 "assets/scenes/grids.json", "assets/scenes/cornell_box.json"};
        if (!o.quick) bunnyScene = loadForStudy(bunny, "table1", o.sceneOptions.load(), skipped);
        if (bunnyScene) small.push_back(bunny);
        if (!o.skipLarge && !o.quick)
            large = {"assets/scenes/motorbike.json", "assets/scenes/dragon.json"};
    }
    for (const std::string& s : small)
        if (!fs::exists(s)) throw inputError(s + ": no such scene file");
    std::vector<Table1Row> rows;
    for (const std::string& path : small) {
        const Scene scene = path == bunny && bunnyScene
                                ? std::move(*bunnyScene)
                                : loadSceneFile(path, o.sceneOptions.load());
        rows.push_back(runTable1Study(path, scene, table1Options(o, dir, false), printLine));
    }
    for (const std::string& path : large)
        if (const std::optional<Scene> scene =
                loadForStudy(path, "table1", o.sceneOptions.load(), skipped))
            rows.push_back(runTable1Study(path, *scene, table1Options(o, dir, true), printLine));
    return rows;
}

AccuracyBenchRun measureAccuracy(const BenchOptions& o) {
    const Scene scene = loadSceneFile(o.accuracyScene, o.sceneOptions.load());
    AccuracyStudyOptions a;
    const auto [width, height] = parseSize("--accuracy-size", o.accuracySize, kImageSize);
    a.width = width;
    a.height = height;
    a.spp = o.accuracySpp;
    a.referenceRays = o.referenceRays;
    return runAccuracyBench(o.accuracyScene, scene, a, o.maxRays, printLine);
}

std::vector<BuildOptionsRow> measureBuildOptions(const BenchOptions& o) {
    std::vector<std::string> scenes = {"assets/scenes/stairs.json",
                                       "assets/scenes/cornell_box.json"};
    if (o.quick) scenes = {"assets/scenes/cornell_box.json"};
    std::vector<BuildOptionsRow> rows;
    for (const std::string& path : scenes) {
        const Scene scene = loadSceneFile(path, o.sceneOptions.load());
        for (BuildOptionsRow& r :
             runBuildOptionsStudy(path, scene, o.limit, static_cast<size_t>(o.points), printLine))
            rows.push_back(std::move(r));
    }
    return rows;
}

// The dragon's resolutions (none in a quick run; the two largest not with --skip-large).
std::vector<ScalingRow> measureScaling(const BenchOptions& o, std::vector<SkippedScene>& skipped) {
    std::vector<std::string> scenes;
    if (!o.quick) scenes = {"assets/scenes/dragon_res4.json", "assets/scenes/dragon_res3.json"};
    if (!o.quick && !o.skipLarge) {
        scenes.push_back("assets/scenes/dragon_res2.json");
        scenes.push_back("assets/scenes/dragon.json");
    }
    std::vector<ScalingRow> rows;
    for (const std::string& path : scenes) {
        const auto l0 = StudyClock::now();
        const std::optional<Scene> scene =
            loadForStudy(path, "scaling", o.sceneOptions.load(), skipped);
        if (!scene) continue;
        const double loadSeconds = secondsBetween(l0, StudyClock::now());
        rows.push_back(runScalingStudy(path, *scene, loadSeconds, o.limit, printLine));
    }
    return rows;
}

// ---- Machine and output ---------------------------------------------------------------------

BenchMachine machine() {
    BenchMachine m;
    m.cpu = "unknown";
    std::ifstream in("/proc/cpuinfo");
    for (std::string line; std::getline(in, line);)
        if (line.rfind("model name", 0) == 0) {
            m.cpu = line.substr(line.find(':') + 2);
            break;
        }
    std::ifstream la("/proc/loadavg");
    std::getline(la, m.loadavg);
    char date[64];
    const std::time_t now = std::time(nullptr);
    std::strftime(date, sizeof date, "%Y-%m-%d %H:%M:%S UTC", std::gmtime(&now));
    m.date = date;
    m.cores = std::thread::hardware_concurrency();
    m.buildType = PENUMBRA_BUILD_TYPE;
    return m;
}

void writeAtomically(const fs::path& path, const std::string& text) {
    try {
        writeFileAtomically(path, text);
    } catch (const AtomicWriteError& e) {
        throw inputError(e.what());
    }
}

// Runs scripts/plot_bench.py on DIR; true when it drew the plots, else `note` says why not.
bool drawPlots(const BenchOptions& o, std::string& note) {
    if (o.noPlots) {
        note = "--no-plots";
        return false;
    }
    if (!fs::exists("/usr/bin/python3") || !fs::exists("scripts/plot_bench.py")) {
        note = "/usr/bin/python3 or scripts/plot_bench.py not found";
        return false;
    }
    const std::string cmd = "/usr/bin/python3 scripts/plot_bench.py '" + o.out + "'";
    if (std::system(cmd.c_str()) == 0) return true;
    note = "`" + cmd + "` failed (matplotlib missing?)";
    return false;
}

void runBench(const BenchOptions& o, const std::string& commandLine) {
    if (o.out.empty()) throw usageError("--out DIR is required");
    // Every size now, not when its study comes after minutes of measuring.
    parseSize("--size", o.size, kImageSize);
    parseSize("--large-size", o.largeSize, kImageSize);
    parseSize("--accuracy-size", o.accuracySize, kImageSize);
    parseSize("--exact-cost-size", o.exactCostSize, kImageSize);
    const BenchSettings settings{o.size,      o.largeSize, o.spp,          o.quick,
                                 o.skipLarge, o.limit,     o.exactCostSize};
    // Before anything else on stderr (and first in the report): what a quick run's figures are
    // not for.
    if (o.quick) std::fprintf(stderr, "penumbra bench: %s\n", quickRunNote(settings).c_str());
    const StudyWorkers workers;
    std::error_code ec;
    fs::create_directories(o.out, ec);
    if (ec) throw inputError("cannot create " + o.out + ": " + ec.message());
    const fs::path dir = o.out;
    BenchResults b;
    b.machine = machine();
    b.command = commandLine;
    b.options = settings;
    std::vector<std::string> small;
    b.table1 = measureTable1(o, dir, small, b.skipped);
    b.accuracy = measureAccuracy(o);
    // Up to 200 points per penumbra patch; --points caps it (a smoke run asks for few).
    b.predicates =
        runPredicateStudy(o.quick ? 20 : std::min(200, o.points), o.quick ? 1 : 5, printLine);
    b.buildOptions = measureBuildOptions(o);
    b.scaling = measureScaling(o, b.skipped);
    for (const std::string& path : small)
        b.perPoint.push_back(runPerPointStudy(path, loadSceneFile(path, o.sceneOptions.load()),
                                              static_cast<size_t>(o.points), printLine));

    const nlohmann::json bench = benchJson(b);
    requireFinite(bench, (dir / "bench.json").string());
    writeAtomically(dir / "bench.json", bench.dump(2));
    std::printf("wrote %s\n", (dir / "bench.json").c_str());
    std::string note;
    const bool plots = drawPlots(o, note);
    // The report reads bench.json back: it shows what the file holds, and a key the writer and
    // the reader spell differently stops the bench here.
    writeAtomically(dir / "report.md", benchReport(readBenchJson(bench), plots, note));
    std::printf("wrote %s\n", (dir / "report.md").c_str());
}

// --report-only: DIR/report.md written again from DIR/bench.json, nothing measured (after a
// change to the report's layout); the plots already in DIR are shown, not drawn again.
void rewriteReport(const BenchOptions& o) {
    if (o.out.empty()) throw usageError("--out DIR is required");
    const fs::path dir = o.out;
    const fs::path file = dir / "bench.json";
    BenchResults b;
    try {
        b = readBenchJson(nlohmann::json::parse(readWholeFile(file)));
    } catch (const FileReadError& e) {
        throw inputError(e.what());
    } catch (const nlohmann::json::exception& e) {
        throw inputError(file.string() + ": " + e.what());
    } catch (const BenchJsonError& e) {
        throw inputError((dir / "").string() + e.what());  // ("bench.json: WHERE: WHY")
    }
    bool plots = true;
    for (const char* png : {"table1.png", "accuracy.png"}) plots = plots && fs::exists(dir / png);
    writeAtomically(dir / "report.md",
                    benchReport(b, plots, "table1.png or accuracy.png not in " + o.out));
    std::printf("wrote %s\n", (dir / "report.md").c_str());
}

}  // namespace

void registerBenchCommand(CLI::App& app) {
    auto o = std::make_shared<BenchOptions>();
    CLI::App* sub = app.add_subcommand(
        "bench",
        "Measure what accuracy costs in time: Table 1, error against time, predicates, "
        "build options, scaling; writes DIR/bench.json, DIR/report.md and plots");
    sub->add_option("scenes", o->scenes,
                    "Scene files for Table 1 and the per-point costs (default: the committed "
                    "assets, the bunny in the box, the motorbike and the dragon)");
    sub->add_option("--out", o->out, "Output directory")->required();
    sub->add_option("--size", o->size, "Image size of Table 1 (WxH)");
    sub->add_option("--large-size", o->largeSize, "Image size of Table 1 for the large scenes");
    sub->add_option("--spp", o->spp, "Primary samples per pixel of Table 1")
        ->check(CLI::PositiveNumber);
    sub->add_option("--accuracy-scene", o->accuracyScene, "Scene of the error-against-time study");
    sub->add_option("--accuracy-size", o->accuracySize, "Image size of the study (WxH)");
    sub->add_option("--accuracy-spp", o->accuracySpp, "Primary samples per pixel of the study")
        ->check(CLI::PositiveNumber);
    sub->add_option("--max-rays", o->maxRays, "Largest shadow-ray count of the study")
        ->check(CLI::PositiveNumber);
    sub->add_option("--reference-rays", o->referenceRays,
                    "Rays per reference image (the reference averages two)")
        ->check(CLI::PositiveNumber);
    sub->add_option("--points", o->points,
                    "Query points per scene (and at most per patch of the predicate study, up to "
                    "200)")
        ->check(CLI::PositiveNumber);
    sub->add_option("--limit", o->limit, "Seconds allowed per precompute before it is cancelled")
        ->check(CLI::PositiveNumber);
    sub->add_flag("--quick", o->quick,
                  "CI-sized run: small scenes, small images, few rays, 20 s precompute limit, no "
                  "scaling study; its figures are for CI and smoke tests, not for conclusions");
    sub->add_option("--exact-cost-size", o->exactCostSize,
                    "Image size (WxH, 1 spp) of the per-point cost with every point exact for "
                    "the scenes whose Table 1 image is too costly to render so");
    sub->add_option("--equal-error-max-rays", o->equalErrorMaxRays,
                    "Largest shadow-ray count per light the equal-error search of Table 1 tries "
                    "(n x n grids)")
        ->check(CLI::PositiveNumber);
    sub->add_option("--light-edge-work-limit", o->lightEdgeWorkLimit,
                    "Table 1's exact render: plane tests of the light-edge path on a point over "
                    "the work limit before it is sampled (0 = sampled at once)")
        ->capture_default_str();
    sub->add_flag("--skip-large", o->skipLarge, "Skip the scenes above 300k triangles");
    sub->add_flag("--no-plots", o->noPlots, "Do not run scripts/plot_bench.py");
    sub->add_flag("--report-only", o->reportOnly,
                  "Measure nothing: write DIR/report.md again from DIR/bench.json (the plots "
                  "already in DIR are shown)");
    addSceneOptions(*sub, o->sceneOptions);
    sub->callback([o, sub] {
        BenchOptions opt = *o;
        if (opt.reportOnly) return rewriteReport(opt);
        if (opt.quick) {
            if (sub->count("--size") == 0) opt.size = "64x64";
            if (sub->count("--spp") == 0) opt.spp = 2;
            if (sub->count("--accuracy-size") == 0) opt.accuracySize = "32x32";
            if (sub->count("--accuracy-spp") == 0) opt.accuracySpp = 1;
            if (sub->count("--max-rays") == 0) opt.maxRays = 64;
            if (sub->count("--reference-rays") == 0) opt.referenceRays = 256;
            if (sub->count("--points") == 0) opt.points = 200;
            if (sub->count("--limit") == 0) opt.limit = 20;
            if (sub->count("--equal-error-max-rays") == 0) opt.equalErrorMaxRays = 256;
        }
        std::string cmd = "penumbra bench";
        for (const std::string& s : o->scenes) cmd += " " + s;
        cmd += " --out " + opt.out + " --size " + opt.size + " --spp " + std::to_string(opt.spp);
        cmd += " --large-size " + opt.largeSize + " --limit " + fmt("%g", opt.limit) +
               " --accuracy-size " + opt.accuracySize + " --accuracy-spp " +
               std::to_string(opt.accuracySpp) + " --max-rays " + std::to_string(opt.maxRays) +
               " --reference-rays " + std::to_string(opt.referenceRays) + " --exact-cost-size " +
               opt.exactCostSize + " --equal-error-max-rays " +
               std::to_string(opt.equalErrorMaxRays);
        if (opt.lightEdgeWorkLimit != RenderSettings{}.lightEdgeWorkLimit)
            cmd += " --light-edge-work-limit " + std::to_string(opt.lightEdgeWorkLimit);
        if (opt.quick) cmd += " --quick";
        if (opt.skipLarge) cmd += " --skip-large";
        if (opt.sceneOptions.strict) cmd += " --strict";
        if (opt.sceneOptions.noDefaultLight) cmd += " --no-default-light";
        try {
            runBench(opt, cmd);
        } catch (const StudyError& e) {
            throw inputError(e.what());
        }
    });
}

}  // namespace penumbra::cli
