// Random points for the tests: a random convex combination of given points (strictly inside their
// hull when every weight is positive), and of a face's vertices.
#pragma once

#include <random>
#include <span>

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

}  // namespace penumbra::test
