#include "engine/studies/build_options_study.h"

#include <cstdio>
#include <utility>

#include "engine/precompute/visibility_store.h"
#include "engine/raytrace/embree_scene.h"
#include "engine/scene/surface_samples.h"
#include "visibility/fp_query/from_point_query.h"

namespace penumbra {
namespace build_options_detail {

// The mean query time at random points of the receivers, light 0: up to `points` points whose
// pair the store holds, out of at most 100 times as many drawn.
double queryMicros(const Scene& scene, const VisibilityStore& store, size_t points) {
    SurfaceSampler sampler(scene, 1);
    const uint32_t l = scene.lights[0];
    std::vector<std::pair<const PairRecord*, Vec3>> xs;
    for (size_t tries = 0; xs.size() < points && tries < 100 * points; ++tries) {
        const auto [f, x] = sampler.next();
        if (const PairRecord* r = store.find(store.layout().keyAt(f, x, l))) xs.push_back({r, x});
    }
    if (xs.empty()) return 0;
    vis::FromPointQuery q;
    double sink = 0;
    const auto t0 = StudyClock::now();
    for (const auto& [r, x] : xs) sink += q.run(scene.mesh, r->tree, x).size();
    const double t = secondsBetween(t0, StudyClock::now());
    if (sink < 0) std::printf("?");  // keeps the loop (sink is never negative)
    return t / xs.size() * 1e6;
}

}  // namespace build_options_detail

std::vector<BuildOptionsRow> runBuildOptionsStudy(const std::string& path, const Scene& scene,
                                                  double limit, size_t points,
                                                  const StudyLog& log) {
    const EmbreeScene bvh(scene.mesh);
    std::vector<BuildOptionsRow> rows;
    for (int merge = 1; merge >= 0; --merge)
        for (int quadric = 1; quadric >= 0; --quadric) {
            VisibilityStore::Options so;
            so.build.mergeLeaves = merge;
            so.build.quadricPruning = quadric;
            VisibilityStore store(scene, &bvh, so);
            BuildOptionsRow r;
            r.scene = path;
            r.mergeLeaves = merge;
            r.quadricPruning = quadric;
            r.precompute = precomputePairs(store, nullptr, limit);
            r.queryUs = build_options_detail::queryMicros(scene, store, points);
            logLine(log,
                    "options %s merge=%d quadric=%d: %zu nodes, %zu bytes, %.2f s, %.3f us/query",
                    path.c_str(), merge, quadric, r.precompute.nodes, r.precompute.bytes,
                    r.precompute.seconds, r.queryUs);
            rows.push_back(std::move(r));
        }
    return rows;
}

}  // namespace penumbra
