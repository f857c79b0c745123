// penumbra_pair_stats SCENE [--max-lp-solves N] [--no-prune] [--no-merge] [--patch-fraction F]
//                     [--top K] [--tsv FILE]
//
// Builds the history tree of every (receiver patch, light) pair of SCENE on one thread, in face
// order, and prints where the precompute goes: totals of the builder's counters (BuildStats) per
// pair kind, and the K most expensive pairs with their counters. --tsv writes one line per pair.
// A developer's measuring tool for the visibility core (the product's precompute runs on the
// PrecomputeScheduler, penumbra precompute).
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "engine/io/scene_loader.h"
#include "engine/io/text_input.h"
#include "engine/precompute/visibility_store.h"
#include "engine/raytrace/embree_scene.h"

namespace {

using namespace penumbra;

struct Row {
    PairKey key;
    vis::PairKind kind;
    vis::BuildStats stats;
    size_t nodes = 0;
};

int usage() {
    std::fprintf(stderr,
                 "usage: penumbra_pair_stats SCENE [--max-lp-solves N] [--no-prune] [--no-merge] "
                 "[--patch-fraction F] [--top K] [--tsv FILE]\n");
    return 2;
}

// The options after SCENE.
struct Arguments {
    VisibilityStore::Options options;
    size_t top = 15;
    std::string tsv;
};

// nullopt (after a message where a value is missing or malformed) when they are not understood.
std::optional<Arguments> parseArguments(int argc, char** argv) {
    Arguments a;
    for (int i = 2; i < argc; ++i) {
        const std::string flag = argv[i];
        if (flag == "--no-prune") {
            a.options.build.quadricPruning = false;
            continue;
        }
        if (flag == "--no-merge") {
            a.options.build.mergeLeaves = false;
            continue;
        }
        if (flag != "--max-lp-solves" && flag != "--patch-fraction" && flag != "--top" &&
            flag != "--tsv")
            return std::nullopt;
        if (i + 1 >= argc) {
            std::fprintf(stderr, "penumbra_pair_stats: %s needs a value\n", flag.c_str());
            return std::nullopt;
        }
        const std::string_view value = argv[++i];
        const auto bad = [&] {
            std::fprintf(stderr, "penumbra_pair_stats: %s: not a %s: %s\n", flag.c_str(),
                         flag == "--patch-fraction" ? "finite number" : "non-negative integer",
                         quoteForMessage(value).c_str());
            return std::nullopt;
        };
        if (flag == "--tsv") {
            a.tsv = value;
        } else if (flag == "--patch-fraction") {
            const std::optional<double> fraction = parseFinite(value);
            if (!fraction) return bad();
            a.options.patchFraction = *fraction;
        } else {
            const std::optional<int64_t> n = parseInteger(value, {0, INT64_MAX});
            if (!n) return bad();
            if (flag == "--top")
                a.top = static_cast<size_t>(*n);
            else
                a.options.build.maxLpSolves = static_cast<uint64_t>(*n);
        }
    }
    return a;
}

}  // namespace

int main(int argc, char** argv) {
    if (argc < 2) return usage();
    const std::optional<Arguments> arguments = parseArguments(argc, argv);
    if (!arguments) return usage();
    const auto& [options, top, tsv] = *arguments;
    try {
        const Scene scene = loadScene(argv[1]);
        const EmbreeScene bvh(scene.mesh);
        VisibilityStore store(scene, &bvh, options);
        std::vector<Row> rows;
        const auto start = std::chrono::steady_clock::now();
        for (uint32_t f = 0; f < scene.faceCount(); ++f) {
            const auto patches = static_cast<uint32_t>(
                std::max<size_t>(store.layout().patches(f).patches.size(), 1));
            for (uint32_t p = 0; p < patches; ++p)
                for (uint32_t light : scene.lights) {
                    if (light == f) continue;
                    const PairKey key{f, p, light};
                    const PairRecord& r = store.getOrBuild(key);
                    rows.push_back({key, r.tree.kind, r.stats, r.tree.nodes.size()});
                }
        }
        const double seconds =
            std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        std::printf("%s: %u faces, %zu pairs, %.3f s on one thread\n", argv[1], scene.faceCount(),
                    rows.size(), seconds);
        std::printf("%-14s %6s %9s %9s %11s %11s %9s %9s %9s %9s\n", "kind", "pairs", "seconds",
                    "nodes", "classify", "lps", "uncertain", "pruned", "rl-tests", "occluders");
        double rlSeconds = 0;
        uint64_t rlLps = 0;
        for (const Row& r : rows) {
            rlSeconds += r.stats.realLineSeconds;
            rlLps += r.stats.realLineLpSolves;
        }
        for (int k = 0; k < vis::kPairKindCount; ++k) {
            Row sum{};
            size_t count = 0;
            uint64_t occluders = 0;
            for (const Row& r : rows) {
                if (static_cast<int>(r.kind) != k) continue;
                ++count;
                sum.stats.seconds += r.stats.seconds;
                sum.nodes += r.nodes;
                sum.stats.classifications += r.stats.classifications;
                sum.stats.lpSolves += r.stats.lpSolves;
                sum.stats.uncertain += r.stats.uncertain;
                sum.stats.prunedSplits += r.stats.prunedSplits;
                sum.stats.realLineTests += r.stats.realLineTests;
                occluders += r.stats.occludersInShaft;
            }
            if (count == 0) continue;
            std::printf("%-14s %6zu %9.3f %9zu %11llu %11llu %9llu %9llu %9llu %9llu\n",
                        std::string(vis::toString(static_cast<vis::PairKind>(k))).c_str(), count,
                        sum.stats.seconds, sum.nodes,
                        static_cast<unsigned long long>(sum.stats.classifications),
                        static_cast<unsigned long long>(sum.stats.lpSolves),
                        static_cast<unsigned long long>(sum.stats.uncertain),
                        static_cast<unsigned long long>(sum.stats.prunedSplits),
                        static_cast<unsigned long long>(sum.stats.realLineTests),
                        static_cast<unsigned long long>(occluders));
        }
        std::printf("real-line (quadric) tests: %.3f s, %llu linear programs\n", rlSeconds,
                    static_cast<unsigned long long>(rlLps));
        std::vector<const Row*> order;
        for (const Row& r : rows) order.push_back(&r);
        std::sort(order.begin(), order.end(),
                  [](const Row* a, const Row* b) { return a->stats.seconds > b->stats.seconds; });
        std::printf("\nmost expensive pairs:\n%-16s %-11s %8s %7s %9s %9s %7s %9s\n",
                    "face/patch/light", "kind", "seconds", "nodes", "lps", "inShaft", "inserted",
                    "pruned");
        for (size_t i = 0; i < std::min(top, order.size()); ++i) {
            const Row& r = *order[i];
            std::printf("%5u/%4u/%5u %-11s %8.3f %7zu %9llu %9u %7u %9llu\n", r.key.receiver,
                        r.key.patch, r.key.lightFace, std::string(vis::toString(r.kind)).c_str(),
                        r.stats.seconds, r.nodes, static_cast<unsigned long long>(r.stats.lpSolves),
                        r.stats.occludersInShaft, r.stats.occludersInserted,
                        static_cast<unsigned long long>(r.stats.prunedSplits));
        }
        if (!tsv.empty()) {
            FILE* out = std::fopen(tsv.c_str(), "w");
            if (out == nullptr) {
                std::fprintf(stderr, "penumbra_pair_stats: cannot write %s\n", tsv.c_str());
                return 1;
            }
            std::fprintf(out,
                         "receiver\tpatch\tlight\tkind\tseconds\tnodes\tlps\tclassifications\t"
                         "pruned\toccluders_in_shaft\toccluders_inserted\n");
            for (const Row& r : rows)
                std::fprintf(out, "%u\t%u\t%u\t%s\t%.6f\t%zu\t%llu\t%llu\t%llu\t%u\t%u\n",
                             r.key.receiver, r.key.patch, r.key.lightFace,
                             std::string(vis::toString(r.kind)).c_str(), r.stats.seconds, r.nodes,
                             static_cast<unsigned long long>(r.stats.lpSolves),
                             static_cast<unsigned long long>(r.stats.classifications),
                             static_cast<unsigned long long>(r.stats.prunedSplits),
                             r.stats.occludersInShaft, r.stats.occludersInserted);
            std::fclose(out);
        }
    } catch (const std::exception& e) {
        std::fprintf(stderr, "penumbra_pair_stats: error: %s\n", e.what());
        return 1;
    }
    return 0;
}
