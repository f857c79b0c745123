#include "engine/studies/scaling_study.h"

#include <random>
#include <vector>

#include "engine/precompute/visibility_store.h"
#include "engine/raytrace/embree_scene.h"

namespace penumbra {
namespace scaling_detail {

// Every patch of the floor (the largest face) and of 32 faces drawn by a fixed seed (not the
// lights, not the floor again), against every light.
std::vector<PairKey> fixedPairs(const Scene& scene, const VisibilityStore& store) {
    uint32_t floor = 0;
    for (uint32_t f = 1; f < scene.faceCount(); ++f)
        if (scene.mesh.faceArea(f) > scene.mesh.faceArea(floor)) floor = f;
    std::vector<PairKey> keys;
    for (uint32_t l : scene.lights) {
        for (uint32_t p = 0; p < store.layout().patches(floor).patches.size(); ++p)
            keys.push_back({floor, p, l});
        std::mt19937_64 rng(3);
        std::uniform_int_distribution<uint32_t> pick(0, scene.faceCount() - 1);
        for (int i = 0; i < 32; ++i) {
            const uint32_t f = pick(rng);
            if (f == l || f == floor) continue;
            for (uint32_t p = 0; p < store.layout().patches(f).patches.size(); ++p)
                keys.push_back({f, p, l});
        }
    }
    return keys;
}

}  // namespace scaling_detail

ScalingRow runScalingStudy(const std::string& path, const Scene& scene, double loadSeconds,
                           double limit, const StudyLog& log) {
    const auto b0 = StudyClock::now();
    const EmbreeScene bvh(scene.mesh);
    ScalingRow row;
    row.scene = path;
    row.faces = scene.faceCount();
    row.loadSeconds = loadSeconds + secondsBetween(b0, StudyClock::now());
    VisibilityStore store(scene, &bvh);
    const std::vector<PairKey> keys = scaling_detail::fixedPairs(scene, store);
    row.precompute = precomputePairs(store, &keys, limit);
    const PrecomputeRun& r = row.precompute;
    logLine(log,
            "scaling %s: %u faces, %zu pairs, %.2f s wall, %.2f s cpu, %zu nodes, %zu bytes, %zu "
            "partial%s",
            path.c_str(), scene.faceCount(), keys.size(), r.seconds, r.cpu, r.nodes, r.bytes,
            store.partialCount(), r.complete ? "" : " (over the limit)");
    return row;
}

}  // namespace penumbra
