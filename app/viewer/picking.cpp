#include "app/viewer/picking.h"

#include "engine/render/shading_point.h"

namespace penumbra::viewer {

std::optional<PickedPoint> pickSurface(const Scene& scene, const EmbreeScene& bvh,
                                       const Camera& camera, const Viewport& viewport, double px,
                                       double py) {
    if (!viewport.contains(px, py)) return std::nullopt;
    const Ray ray =
        camera.ray(px - viewport.x + 0.5, py - viewport.y + 0.5, viewport.width, viewport.height);
    const std::optional<EmbreeScene::Hit> hit = bvh.intersect(ray.origin, ray.direction);
    if (!hit) return std::nullopt;
    // The projected hit: the queries answer it at its answered point (shading_point.h).
    return PickedPoint{hit->face, shadingPoint(scene.mesh, hit->face, hit->point).input};
}

}  // namespace penumbra::viewer
