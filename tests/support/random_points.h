// Random points for the tests: a random convex combination of given points (strictly inside their
// hull when every weight is positive), of a face's vertices, and points on a scene's surfaces.
#pragma once

#include <cstdint>
#include <random>
#include <span>
#include <utility>
#include <vector>

#include "engine/scene/scene.h"
#include "visibility/polygon_mesh.h"

namespace penumbra::test {

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

inline vis::Vec3 randomPointOn(const vis::PolygonMesh& m, uint32_t f, std::mt19937_64& rng) {
    std::vector<vis::Vec3> corners;
    for (uint32_t v : m.faces[f]) corners.push_back(m.vertices[v]);
    return randomCombination(corners, rng);
}

// `count` points on the faces of s, faces drawn in proportion to their area, never on a light.
inline std::vector<std::pair<uint32_t, vis::Vec3>> surfacePoints(const Scene& s, int count,
                                                                 uint64_t seed) {
    std::mt19937_64 rng(seed);
    std::vector<double> area(s.faceCount());
    for (uint32_t f = 0; f < s.faceCount(); ++f) area[f] = s.mesh.faceArea(f);
    for (uint32_t l : s.lights) area[l] = 0;
    std::discrete_distribution<uint32_t> pickFace(area.begin(), area.end());
    std::vector<std::pair<uint32_t, vis::Vec3>> out;
    while (static_cast<int>(out.size()) < count) {
        const uint32_t f = pickFace(rng);
        out.emplace_back(f, randomPointOn(s.mesh, f, rng));
    }
    return out;
}

}  // namespace penumbra::test
