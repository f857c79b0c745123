#include "engine/scene/face_uv.h"

#include <algorithm>
#include <limits>

namespace penumbra {

std::optional<Uv> faceUvAt(const Scene& scene, uint32_t face, const Vec3& x) {
    if (face >= scene.faceUv.size()) return std::nullopt;
    const std::vector<Uv>& uvs = scene.faceUv[face];
    const auto ids = scene.mesh.face(face);
    if (uvs.size() != ids.size() || ids.size() < 3) return std::nullopt;
    const Vec3 a = scene.mesh.vertices[ids[0]];
    // Barycentrics of x in each fan triangle (a, b, c) from signed areas against the triangle's
    // normal; the first that holds x (all three >= 0), else the one x is least outside of.
    double best = -std::numeric_limits<double>::infinity();
    size_t bestK = 1;
    double bestL[3] = {1, 0, 0};
    for (size_t k = 1; k + 1 < ids.size(); ++k) {
        const Vec3 b = scene.mesh.vertices[ids[k]], c = scene.mesh.vertices[ids[k + 1]];
        const Vec3 n = cross(b - a, c - a);
        const double nn = dot(n, n);
        if (!(nn > 0)) continue;
        const double l[3] = {dot(n, cross(c - b, x - b)) / nn, dot(n, cross(a - c, x - c)) / nn,
                             dot(n, cross(b - a, x - a)) / nn};
        const double worst = std::min({l[0], l[1], l[2]});
        if (worst > best) {
            best = worst;
            bestK = k;
            std::copy(l, l + 3, bestL);
        }
        if (worst >= 0) break;
    }
    const Uv ua = uvs[0], ub = uvs[bestK], uc = uvs[bestK + 1];
    return Uv{bestL[0] * ua.u + bestL[1] * ub.u + bestL[2] * uc.u,
              bestL[0] * ua.v + bestL[1] * ub.v + bestL[2] * uc.v};
}

}  // namespace penumbra
