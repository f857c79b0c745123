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

struct P2 {
    double u, v;
};
P2 project(const Vec3& p, int drop) {
    return drop == 0 ? P2{p.y, p.z} : (drop == 1 ? P2{p.z, p.x} : P2{p.x, p.y});
}

// How far outside the convex polygon x lies: the largest signed distance past an edge, relative
// to that edge's length (<= 0 inside). Approximate: only chooses between overlapping patches.
double outside(std::span<const Vec3> poly, const Vec3& x, int drop) {
    const size_t n = poly.size();
    double orient = 0;
    for (size_t i = 0; i < n; ++i) {
        const P2 a = project(poly[i], drop), b = project(poly[(i + 1) % n], drop);
        orient += a.u * b.v - a.v * b.u;
    }
    const double s = orient >= 0 ? 1.0 : -1.0;
    const P2 q = project(x, drop);
    double worst = -std::numeric_limits<double>::infinity();
    for (size_t i = 0; i < n; ++i) {
        const P2 a = project(poly[i], drop), b = project(poly[(i + 1) % n], drop);
        const double eu = b.u - a.u, ev = b.v - a.v;
        const double len = std::hypot(eu, ev);
        if (len == 0) continue;
        const double cross = eu * (q.v - a.v) - ev * (q.u - a.u);
        worst = std::max(worst, -s * cross / len);
    }
    return worst;
}

}  // namespace

uint32_t ReceiverPatches::find(const Vec3& x) const {
    uint32_t best = 0;
    double bestOut = std::numeric_limits<double>::infinity();
    for (uint32_t i = 0; i < patches.size(); ++i) {
        const double o = outside(patches[i], x, dropAxis);
        if (o < bestOut) {
            bestOut = o;
            best = i;
        }
        if (o < 0) {
            // Prefer the patch where x is deepest inside: the one whose tree margin is largest.
            // Cheap: the first strictly-inside patch whose depth beats a relative threshold.
            if (-o > 1e-6 * diameter(patches[i])) return i;
        }
    }
    return best;
}

ReceiverPatches subdivideReceiver(std::span<const Vec3> face, double maxDiameter) {
    ReceiverPatches out;
    Vec3 n{};
    for (size_t i = 1; i + 1 < face.size(); ++i) n += cross(face[i] - face[0], face[i + 1] - face[0]);
    const double ax = std::fabs(n.x), ay = std::fabs(n.y), az = std::fabs(n.z);
    out.dropAxis = ax >= ay && ax >= az ? 0 : (ay >= az ? 1 : 2);
    const double d = diameter(face);
    if (maxDiameter <= 0 || d <= maxDiameter) {
        out.patches.emplace_back(face.begin(), face.end());
        return out;
    }
    const int levels = std::min(8, static_cast<int>(std::ceil(std::log2(d / maxDiameter))));
    const int k = 1 << levels;  // each fan triangle becomes k*k triangles
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

}  // namespace penumbra::vis
