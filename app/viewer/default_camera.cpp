#include "app/viewer/default_camera.h"

#include <cmath>
#include <numbers>

namespace penumbra::viewer {

Camera defaultCamera(const LoadedScene& s) {
    if (s.scene.camera) return *s.scene.camera;
    const double elevation = std::tan(20 * std::numbers::pi / 180);
    const Vec3 candidates[] = {{0, elevation, -1},      {0, elevation, 1},
                               {-1, elevation, 0},      {1, elevation, 0},
                               {-0.7, elevation, -0.7}, {0.7, elevation, -0.7},
                               {-0.7, elevation, 0.7},  {0.7, elevation, 0.7}};
    Camera best = Camera::fitting(s.bounds, candidates[0]);
    int bestScore = -1;
    constexpr int kGrid = 24;
    for (const Vec3& from : candidates) {
        const Camera c = Camera::fitting(s.bounds, from);
        int score = 0;
        for (int y = 0; y < kGrid; ++y)
            for (int x = 0; x < kGrid; ++x) {
                const Ray r = c.ray(x + 0.5, y + 0.5, kGrid, kGrid);
                const auto hit = s.bvh->intersect(r.origin, r.direction);
                if (hit && dot(s.scene.mesh.faceAreaNormal(hit->face), r.direction) < 0) ++score;
            }
        if (score > bestScore) {
            bestScore = score;
            best = c;
        }
    }
    return best;
}

}  // namespace penumbra::viewer
