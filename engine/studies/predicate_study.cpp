#include "engine/studies/predicate_study.h"

#include <cmath>
#include <random>

#include "engine/precompute/visibility_store.h"
#include "engine/raytrace/embree_scene.h"
#include "engine/render/cpu_time.h"
#include "engine/scene/procedural_scenes.h"
#include "engine/scene/surface_samples.h"
#include "visibility/form_factor.h"
#include "visibility/fp_query/from_point_query.h"

namespace penumbra {
namespace {

bool wrongAnswer(const vis::FragmentList& r, double refArea, std::span<const Vec3> light,
                 const Vec3& lightNormal, double lightArea) {
    double area = 0;
    for (size_t i = 0; i < r.size(); ++i) area += vis::polygonArea(r[i]);
    if (std::abs(area - refArea) > 1e-9 * lightArea) return true;
    if (area > lightArea * (1 + 1e-9)) return true;  // the fragments overlap
    const double scale = std::sqrt(lightArea);
    for (size_t i = 0; i < r.size(); ++i)
        for (const Vec3& v : r[i]) {
            if (std::abs(vis::dot(v - light[0], lightNormal)) > 1e-9 * scale) return true;
            for (size_t k = 0; k < light.size(); ++k) {
                const Vec3& a = light[k];
                const Vec3& b = light[(k + 1) % light.size()];
                if (vis::dot(vis::cross(b - a, v - a), lightNormal) < -1e-9 * scale * scale)
                    return true;  // outside L
            }
        }
    return false;
}

}  // namespace

PredicateStudy runPredicateStudy(int pointsPerPatch, int repeats, const StudyLog& log) {
    const vis::PredicateMode modes[3] = {
        vis::PredicateMode::Filtered, vis::PredicateMode::AlwaysExact, vis::PredicateMode::Naive};
    PredicateStudy st;
    st.repeats = std::max(1, repeats);
    st.modes[0].mode = "filtered";
    st.modes[1].mode = "alwaysExact";
    st.modes[2].mode = "naive";
    double wall[3] = {}, cpu[3] = {};
    for (const auto& [name, scene] : makeHardCases()) {
        PredicateCaseResult c;
        c.name = name;
        const EmbreeScene bvh(scene.mesh);
        VisibilityStore store(scene, &bvh);
        const vis::PolygonMesh& mesh = scene.mesh;
        std::mt19937_64 rng(7);
        for (uint32_t l : scene.lights) {
            std::vector<Vec3> light;
            for (uint32_t v : mesh.faces[l]) light.push_back(mesh.vertices[v]);
            const Vec3 ln = vis::normalize(mesh.faceAreaNormal(l));
            const double lightArea = mesh.faceArea(l);
            for (uint32_t f = 0; f < scene.faceCount(); ++f) {
                if (f == l) continue;
                const vis::ReceiverPatches& patches = store.layout().patches(f);
                for (uint32_t p = 0; p < patches.patches.size(); ++p) {
                    const PairRecord& rec = store.getOrBuild({f, p, l});
                    if (rec.tree.kind != vis::PairKind::Penumbra) continue;
                    const auto& poly = patches.patches[p];
                    std::vector<Vec3> xs;
                    for (size_t k = 0; k < poly.size(); ++k) {
                        xs.push_back(poly[k]);
                        xs.push_back((poly[k] + poly[(k + 1) % poly.size()]) * 0.5);
                    }
                    while (xs.size() < static_cast<size_t>(pointsPerPatch))
                        xs.push_back(randomCombination(poly, rng, 0.0));
                    std::vector<double> refArea(xs.size(), 0.0);
                    std::vector<size_t> refCount(xs.size(), 0), filteredCount(xs.size(), 0);
                    vis::FromPointQuery exact(vis::PredicateMode::AlwaysExact);
                    for (size_t i = 0; i < xs.size(); ++i) {
                        const vis::FragmentList& r = exact.run(mesh, rec.tree, xs[i]);
                        refCount[i] = r.size();
                        for (size_t k = 0; k < r.size(); ++k) refArea[i] += vis::polygonArea(r[k]);
                    }
                    for (int m = 0; m < 3; ++m) {
                        vis::FromPointQuery q(modes[m]);
                        for (size_t i = 0; i < xs.size(); ++i) {
                            const vis::FragmentList& r = q.run(mesh, rec.tree, xs[i]);
                            if (r.size() != refCount[i]) ++c.otherCount[m];
                            if (m == 0) filteredCount[i] = r.size();
                            if (m == 2 && r.size() != filteredCount[i]) ++c.naiveOtherThanFiltered;
                            if (wrongAnswer(r, refArea[i], light, ln, lightArea)) ++c.wrong[m];
                        }
                        size_t sink = 0;
                        const double c0 = processCpuSeconds();
                        const auto t0 = StudyClock::now();
                        for (int rep = 0; rep < st.repeats; ++rep)
                            for (const Vec3& x : xs) sink += q.run(mesh, rec.tree, x).size();
                        wall[m] += secondsBetween(t0, StudyClock::now());
                        cpu[m] += processCpuSeconds() - c0;
                        if (sink == SIZE_MAX) wall[m] = 0;  // keeps the loop from being elided
                    }
                    c.queries += xs.size();
                }
            }
        }
        st.queries += c.queries;
        for (int m = 0; m < 3; ++m) {
            st.modes[m].wrong += c.wrong[m];
            st.modes[m].otherCount += c.otherCount[m];
        }
        st.naiveOtherThanFiltered += c.naiveOtherThanFiltered;
        st.cases.push_back(c);
    }
    const double n = static_cast<double>(st.queries) * st.repeats;
    for (int m = 0; m < 3; ++m) {
        st.modes[m].usPerQuery = n > 0 ? wall[m] / n * 1e6 : 0;
        st.modes[m].cpuUsPerQuery = n > 0 ? cpu[m] / n * 1e6 : 0;
    }
    logLine(log, "predicates: %zu hard cases, %zu queries (x%d timed)", st.cases.size(), st.queries,
            st.repeats);
    for (const PredicateModeResult& m : st.modes)
        logLine(log, "  %-12s %.3f us per query, %zu wrong, %zu other fragment count",
                m.mode.c_str(), m.usPerQuery, m.wrong, m.otherCount);
    logLine(log, "  naive vs filtered: %zu answers with another fragment count",
            st.naiveOtherThanFiltered);
    return st;
}

}  // namespace penumbra
