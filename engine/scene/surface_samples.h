// Random points on a scene's surfaces, the one area-weighted sampler of the tree: the bench's
// per-point and build-option studies and the tests draw their points here.
//
// A face is drawn with probability proportional to its area, never an area light's face; the
// point is a random convex combination of its vertices, each weight uniform in [minWeight, 1)
// before they are normalised, so strictly inside the face (a convex polygon) when minWeight > 0.
// Not uniform over the face's area (the weights favour its middle): a spread of points, not an
// estimator. The sequence is fixed by the seed (std::mt19937_64 and the standard distributions:
// the same points on every run of one standard library).
#pragma once

#include <cstddef>
#include <cstdint>
#include <random>
#include <span>
#include <vector>

#include "engine/scene/scene.h"
#include "visibility/polygon_mesh.h"

namespace penumbra {

// A random convex combination of `points` (weights uniform in [minWeight, 1), normalised).
inline vis::Vec3 randomCombination(std::span<const vis::Vec3> points, std::mt19937_64& rng,
                                   double minWeight = 0.02) {
    std::uniform_real_distribution<double> u(minWeight, 1.0);
    vis::Vec3 p{};
    double total = 0;
    for (const vis::Vec3& q : points) {
        const double w = u(rng);
        p += q * w;
        total += w;
    }
    return p / total;
}

// A random convex combination of face f's vertices: strictly inside the face.
inline vis::Vec3 randomPointOn(const vis::PolygonMesh& m, uint32_t f, std::mt19937_64& rng) {
    std::vector<vis::Vec3> corners;
    corners.reserve(m.faces[f].size());
    for (uint32_t v : m.faces[f]) corners.push_back(m.vertices[v]);
    return randomCombination(corners, rng);
}

struct SurfaceSample {
    uint32_t face = 0;
    vis::Vec3 x;  // strictly inside `face`
};

// Draws points one at a time (for callers that keep only some of them). The scene must outlive
// the sampler and have a face that is not a light.
class SurfaceSampler {
  public:
    SurfaceSampler(const Scene& scene, uint64_t seed) : mesh_(&scene.mesh), rng_(seed) {
        std::vector<double> area(scene.faceCount());
        for (uint32_t f = 0; f < scene.faceCount(); ++f) area[f] = scene.mesh.faceArea(f);
        for (uint32_t l : scene.lights) area[l] = 0;
        pickFace_ = std::discrete_distribution<uint32_t>(area.begin(), area.end());
    }

    SurfaceSample next() {
        const uint32_t f = pickFace_(rng_);
        return {f, randomPointOn(*mesh_, f, rng_)};
    }

  private:
    const vis::PolygonMesh* mesh_;
    std::mt19937_64 rng_;
    std::discrete_distribution<uint32_t> pickFace_;
};

// The first `count` points of SurfaceSampler(scene, seed).
inline std::vector<SurfaceSample> surfaceSamples(const Scene& scene, size_t count, uint64_t seed) {
    SurfaceSampler sampler(scene, seed);
    std::vector<SurfaceSample> out;
    out.reserve(count);
    while (out.size() < count) out.push_back(sampler.next());
    return out;
}

}  // namespace penumbra
