// penumbra bench: what exact visibility costs, per scene, measured in one run on one machine.
//   precompute  every (receiver patch, light) pair: how many are trivial (back-facing, fully
//               visible, fully hidden) and how many need a tree; nodes, bytes, time;
//   per point   the from-point query plus the exact form factor, against 16 and 128 Embree shadow
//               rays (the sampled estimate of the visible fraction) on the same points.
// Single-threaded, so the figures compare per core.
#include <CLI/CLI.hpp>

#include <chrono>
#include <cstdio>
#include <random>

#include "app/commands.h"
#include "engine/embree_scene.h"
#include "visibility/form_factor.h"
#include "visibility/fp_query.h"
#include "visibility/history_tree_builder.h"
#include "visibility/receiver_patches.h"

namespace penumbra::cli {
namespace {

using Clock = std::chrono::steady_clock;

struct BenchOptions {
    std::vector<std::string> scenes;
    int points = 2000;
    double patchFraction = 1.0 / 4;
};

double seconds(Clock::time_point a, Clock::time_point b) {
    return std::chrono::duration<double>(b - a).count();
}

struct PatchTree {
    uint32_t face = 0, light = 0;
    vis::HistoryTree tree;
};

void benchScene(const std::string& path, const BenchOptions& o) {
    const Scene scene = loadSceneFile(path);
    const vis::PolygonMesh& mesh = scene.mesh;
    const EmbreeScene embree(mesh);
    const double maxPatch = o.patchFraction * mesh.bounds().diagonal();

    // Precompute every pair.
    std::vector<vis::ReceiverPatches> patches(scene.faceCount());
    for (uint32_t f = 0; f < scene.faceCount(); ++f) {
        std::vector<Vec3> poly;
        for (uint32_t v : mesh.faces[f]) poly.push_back(mesh.vertices[v]);
        patches[f] = vis::subdivideReceiver(poly, maxPatch);
    }
    // trees[light][face] -> one tree per patch
    std::vector<std::vector<std::vector<vis::HistoryTree>>> trees(scene.lights.size());
    size_t kinds[vis::kPairKindCount] = {}, nodes = 0, bytes = 0, patchCount = 0;
    uint64_t uncertain = 0, exactCerts = 0, lps = 0;
    double worst = 0;
    const auto t0 = Clock::now();
    for (size_t k = 0; k < scene.lights.size(); ++k) {
        const uint32_t l = scene.lights[k];
        trees[k].resize(scene.faceCount());
        for (uint32_t f = 0; f < scene.faceCount(); ++f) {
            if (f == l) continue;
            std::vector<uint32_t> candidates = embree.shaftCandidates(f, l);
            // The builder reads an empty list as "every face"; the receiver itself is never an
            // occluder, so it stands for "none" here.
            if (candidates.empty()) candidates.push_back(f);
            const bool whole = patches[f].patches.size() == 1;
            for (const auto& patch : patches[f].patches) {
                vis::BuildStats st;
                trees[k][f].push_back(vis::buildHistoryTree(
                    mesh, f, l, {}, candidates, &st,
                    whole ? std::span<const Vec3>{} : std::span<const Vec3>(patch)));
                const vis::HistoryTree& t = trees[k][f].back();
                ++kinds[static_cast<int>(t.kind)];
                nodes += t.nodes.size();
                bytes += t.bytes();
                uncertain += st.uncertain;
                exactCerts += st.exactCertificates;
                lps += st.lpSolves;
                worst = std::max(worst, st.seconds);
                ++patchCount;
            }
        }
    }
    const double precompute = seconds(t0, Clock::now());

    std::printf("\n%s: %u faces, %zu lights, %zu receiver patches\n", path.c_str(),
                scene.faceCount(), scene.lights.size(), patchCount);
    std::printf("  pairs: %zu back-facing, %zu fully visible, %zu fully hidden, %zu with a tree, "
                "%zu too complex (sampled)\n",
                kinds[0], kinds[1], kinds[2], kinds[3], kinds[4]);
    std::printf("  trees: %zu nodes (%.1f per tree), %zu bytes (%.1f KB), precompute %.2f s "
                "(slowest pair %.3f s)\n",
                nodes, kinds[3] ? static_cast<double>(nodes) / kinds[3] : 0.0, bytes,
                bytes / 1024.0, precompute, worst);
    std::printf("  certificates: %llu linear programs, %llu exact fallbacks, %llu undecided "
                "(split conservatively)\n",
                static_cast<unsigned long long>(lps), static_cast<unsigned long long>(exactCerts),
                static_cast<unsigned long long>(uncertain));

    // Per-point costs on the same random points (faces chosen by area).
    std::mt19937_64 rng(1);
    std::vector<double> area(scene.faceCount());
    for (uint32_t f = 0; f < scene.faceCount(); ++f) area[f] = mesh.faceArea(f);
    std::discrete_distribution<uint32_t> pickFace(area.begin(), area.end());
    std::uniform_real_distribution<double> u(0.02, 1.0);
    struct Sample {
        uint32_t face, patch;
        Vec3 x;
    };
    std::vector<Sample> samples;
    while (samples.size() < static_cast<size_t>(o.points)) {
        const uint32_t f = pickFace(rng);
        if (f == scene.lights[0]) continue;
        Vec3 p{};
        double w = 0;
        for (uint32_t v : mesh.faces[f]) {
            const double a = u(rng);
            p += mesh.vertices[v] * a;
            w += a;
        }
        p = p / w;
        samples.push_back({f, 0, p});
    }
    double sink = 0;
    size_t visited = 0, fragments = 0;
    vis::FromPointQuery query;  // one reusable workspace, as a renderer thread keeps
    const auto q0 = Clock::now();
    for (Sample& s : samples) {
        const Vec3 n = vis::normalize(mesh.faceAreaNormal(s.face));
        s.patch = patches[s.face].find(s.x);
        const vis::HistoryTree& t = trees[0][s.face][s.patch];
        const vis::FragmentList& r = query.run(mesh, t, s.x);
        for (size_t i = 0; i < r.size(); ++i) sink += vis::formFactor(s.x, n, r[i]);
        visited += query.nodesVisited();
        fragments += r.size();
    }
    const double exactUs = seconds(q0, Clock::now()) / samples.size() * 1e6;
    auto timeRays = [&](int n) {
        const auto a = Clock::now();
        for (const Sample& s : samples)
            sink += embree.sampledFraction(s.face, scene.lights[0], s.x, n, 7);
        return seconds(a, Clock::now()) / samples.size() * 1e6;
    };
    const double rays16 = timeRays(16), rays128 = timeRays(128);
    std::printf("  per point (%d points, light 0): exact query + form factor %.2f us "
                "(%.1f nodes, %.2f fragments); 16 shadow rays %.2f us; 128 shadow rays %.2f us\n",
                o.points, exactUs, static_cast<double>(visited) / samples.size(),
                static_cast<double>(fragments) / samples.size(), rays16, rays128);
    std::printf("  exact is %.2fx the cost of 16 rays and %.2fx that of 128  (checksum %.3g)\n",
                exactUs / rays16, exactUs / rays128, sink);
}

}  // namespace

void registerBenchCommand(CLI::App& app) {
    auto options = std::make_shared<BenchOptions>();
    CLI::App* sub = app.add_subcommand(
        "bench", "Measure precompute size and time, and the exact query against shadow rays");
    sub->add_option("scenes", options->scenes, "Scene files (default: the committed assets)");
    sub->add_option("--points", options->points, "Query points per scene")
        ->check(CLI::PositiveNumber);
    sub->add_option("--patch-fraction", options->patchFraction,
                    "Receiver patch size as a fraction of the scene diagonal (0: whole faces)")
        ->check(CLI::Range(0.0, 1.0));
    sub->callback([options] {
        std::vector<std::string> scenes = options->scenes;
        if (scenes.empty())
            scenes = {"assets/stairs.obj", "assets/grids.obj", "assets/cornell_box.obj",
                      "assets/table.obj"};
        for (const std::string& s : scenes) benchScene(s, *options);
    });
}

}  // namespace penumbra::cli
