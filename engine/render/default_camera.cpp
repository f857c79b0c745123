#include "engine/render/default_camera.h"

#include <cmath>
#include <numbers>
#include <vector>

namespace penumbra {

Camera defaultCamera(const Scene& scene, const EmbreeScene& bvh, std::optional<Vec3> up) {
    if (scene.camera) {
        Camera c = *scene.camera;
        if (up) c.up = *up;
        return c;
    }
    const vis::Bounds3 bounds = scene.mesh.bounds();
    const double elevation = std::tan(20 * std::numbers::pi / 180);
    // Horizontal directions (in the plane normal to `up`), raised by `elevation` along `up`.
    const double h[8][2] = {{0, -1},      {0, 1},      {-1, 0},     {1, 0},
                            {-0.7, -0.7}, {0.7, -0.7}, {-0.7, 0.7}, {0.7, 0.7}};
    // y up first (OBJ's usual convention, the Cornell box), then z up (CAD-style scenes).
    const std::vector<Vec3> ups =
        up ? std::vector<Vec3>{*up} : std::vector<Vec3>{Vec3{0, 1, 0}, Vec3{0, 0, 1}};
    std::optional<Camera> best;
    int bestScore = -1;
    constexpr int kGrid = 24;
    for (const Vec3 u : ups) {
        // Two unit directions spanning the plane normal to u (any other up than +y and +z).
        const Vec3 n = normalize(u);
        const Vec3 a = normalize(cross(std::abs(n.x) < 0.9 ? Vec3{1, 0, 0} : Vec3{0, 1, 0}, n));
        const Vec3 b = cross(n, a);
        for (const auto& d : h) {
            const Vec3 from = u == Vec3{0, 1, 0}   ? Vec3{d[0], elevation, d[1]}
                              : u == Vec3{0, 0, 1} ? Vec3{d[0], d[1], elevation}
                                                   : a * d[0] + b * d[1] + n * elevation;
            const Camera c = Camera::fitting(bounds, from, 45, u);
            int score = 0;
            for (int y = 0; y < kGrid; ++y)
                for (int x = 0; x < kGrid; ++x) {
                    const Ray r = c.ray(x + 0.5, y + 0.5, kGrid, kGrid);
                    const auto hit = bvh.intersect(r.origin, r.direction);
                    if (hit && dot(scene.mesh.faceAreaNormal(hit->face), r.direction) < 0) ++score;
                }
            if (score > bestScore) {
                bestScore = score;
                best = c;
            }
        }
    }
    return *best;
}

}  // namespace penumbra
