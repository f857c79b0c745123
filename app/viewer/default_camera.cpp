#include "app/viewer/default_camera.h"

#include <cmath>
#include <numbers>

namespace penumbra::viewer {

Camera defaultCamera(const LoadedScene& s) {
    if (s.scene.camera) return *s.scene.camera;
    const double elevation = std::tan(20 * std::numbers::pi / 180);
    // Horizontal directions (in the plane normal to `up`), raised by `elevation` along `up`.
    const double h[8][2] = {{0, -1},      {0, 1},      {-1, 0},     {1, 0},
                            {-0.7, -0.7}, {0.7, -0.7}, {-0.7, 0.7}, {0.7, 0.7}};
    Camera best = Camera::fitting(s.bounds, {h[0][0], elevation, h[0][1]});
    int bestScore = -1;
    constexpr int kGrid = 24;
    // y up first (OBJ's usual convention, the Cornell box), then z up (CAD-style scenes).
    for (const Vec3 up : {Vec3{0, 1, 0}, Vec3{0, 0, 1}}) {
        for (const auto& d : h) {
            const Vec3 from = up.y == 1 ? Vec3{d[0], elevation, d[1]} : Vec3{d[0], d[1], elevation};
            const Camera c = Camera::fitting(s.bounds, from, 45, up);
            int score = 0;
            for (int y = 0; y < kGrid; ++y)
                for (int x = 0; x < kGrid; ++x) {
                    const Ray r = c.ray(x + 0.5, y + 0.5, kGrid, kGrid);
                    const auto hit = s.bvh->intersect(r.origin, r.direction);
                    if (hit && dot(s.scene.mesh.faceAreaNormal(hit->face), r.direction) < 0)
                        ++score;
                }
            if (score > bestScore) {
                bestScore = score;
                best = c;
            }
        }
    }
    return best;
}

}  // namespace penumbra::viewer
