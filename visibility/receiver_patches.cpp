#include "visibility/receiver_patches.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace penumbra::vis {
namespace {

double diameter(std::span<const Vec3> p) {
    double d = 0;
    for (size_t i = 0; i < p.size(); ++i)
        for (size_t j = i + 1; j < p.size(); ++j) d = std::max(d, length(p[i] - p[j]));
    return d;
}

// k, the cells per side of each fan triangle's grid: 1 (no subdivision) for a face of diameter
// d <= maxDiameter.
int cellsPerSide(double d, double maxDiameter) {
    if (maxDiameter <= 0 || d <= maxDiameter) return 1;
    return 1 << std::min(8, static_cast<int>(std::ceil(std::log2(d / maxDiameter))));
}

struct P2 {
    double u, v;
};
P2 project(const Vec3& p, int drop) {
    return drop == 0 ? P2{p.y, p.z} : (drop == 1 ? P2{p.z, p.x} : P2{p.x, p.y});
}

}  // namespace

uint32_t ReceiverPatches::find(const Vec3& x) const {
    if (patches.size() <= 1) return 0;
    const int k = cellsPerSide;
    const uint32_t perFan = static_cast<uint32_t>(k * k);
    const P2 q = project(x, dropAxis);
    uint32_t best = 0;
    double bestOut = std::numeric_limits<double>::infinity();
    for (size_t t = 1; t + 1 < face.size(); ++t) {
        // Barycentric coordinates (u along a->b, v along a->c) in the projection.
        const P2 a = project(face[0], dropAxis), b = project(face[t], dropAxis),
                 c = project(face[t + 1], dropAxis);
        const double det = (b.u - a.u) * (c.v - a.v) - (b.v - a.v) * (c.u - a.u);
        if (det == 0) continue;
        const double u = ((q.u - a.u) * (c.v - a.v) - (q.v - a.v) * (c.u - a.u)) / det;
        const double v = ((b.u - a.u) * (q.v - a.v) - (b.v - a.v) * (q.u - a.u)) / det;
        const double out = std::max({-u, -v, u + v - 1});
        if (out < bestOut) {
            bestOut = out;
            // Cell (i, j) of the grid, clamped into the triangle; lower or upper triangle of it.
            const double su = std::clamp(u, 0.0, 1.0) * k, sv = std::clamp(v, 0.0, 1.0) * k;
            int i = std::min(k - 1, static_cast<int>(su));
            int j = std::min(k - 1 - i, static_cast<int>(sv));
            const bool upper = i + j + 1 < k && (su - i) + (sv - j) > 1;
            // Patches were emitted per i, then per j: lower (i, j) then upper (i, j) if any.
            uint32_t index = static_cast<uint32_t>(t - 1) * perFan;
            for (int r = 0; r < i; ++r) index += static_cast<uint32_t>(2 * (k - r) - 1);
            index += static_cast<uint32_t>(2 * j) + (upper ? 1 : 0);
            best = index;
        }
        if (out <= 0) break;
    }
    return best;
}

ReceiverPatches subdivideReceiver(std::span<const Vec3> face, double maxDiameter) {
    return subdivideReceiverGrid(face, cellsPerSide(diameter(face), maxDiameter));
}

ReceiverPatches subdivideReceiverGrid(std::span<const Vec3> face, int k) {
    ReceiverPatches out;
    Vec3 n{};
    for (size_t i = 1; i + 1 < face.size(); ++i)
        n += cross(face[i] - face[0], face[i + 1] - face[0]);
    const double ax = std::fabs(n.x), ay = std::fabs(n.y), az = std::fabs(n.z);
    out.dropAxis = ax >= ay && ax >= az ? 0 : (ay >= az ? 1 : 2);
    out.face.assign(face.begin(), face.end());
    if (k <= 1) {  // each fan triangle: k*k triangles
        out.patches.emplace_back(face.begin(), face.end());
        return out;
    }
    out.cellsPerSide = k;
    for (size_t t = 1; t + 1 < face.size(); ++t) {
        const Vec3 a = face[0], b = face[t], c = face[t + 1];
        auto at = [&](int i, int j) {  // barycentric grid point (i along ab, j along ac)
            const double u = static_cast<double>(i) / k, v = static_cast<double>(j) / k;
            return a * (1 - u - v) + b * u + c * v;
        };
        auto add = [&](Vec3 p, Vec3 q, Vec3 r) {
            const Vec3 centroid = (p + q + r) / 3.0;
            constexpr double kGrow = 1e-7;
            out.patches.push_back({p + (p - centroid) * kGrow, q + (q - centroid) * kGrow,
                                   r + (r - centroid) * kGrow});
        };
        for (int i = 0; i < k; ++i)
            for (int j = 0; i + j < k; ++j) {
                add(at(i, j), at(i + 1, j), at(i, j + 1));
                if (i + j + 1 < k) add(at(i + 1, j), at(i + 1, j + 1), at(i, j + 1));
            }
    }
    return out;
}

size_t receiverPatchCount(std::span<const Vec3> face, double maxDiameter) {
    const size_t k = static_cast<size_t>(cellsPerSide(diameter(face), maxDiameter));
    return k == 1 ? 1 : (face.size() >= 3 ? face.size() - 2 : 0) * k * k;
}

}  // namespace penumbra::vis
