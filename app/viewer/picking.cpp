#include "app/viewer/picking.h"

namespace penumbra::viewer {

std::optional<PickedPoint> pickSurface(const Scene& scene, const EmbreeScene& bvh,
                                       const Camera& camera, const Viewport& viewport, double px,
                                       double py) {
    if (!viewport.contains(px, py)) return std::nullopt;
    const Ray ray =
        camera.ray(px - viewport.x + 0.5, py - viewport.y + 0.5, viewport.width, viewport.height);
    const std::optional<EmbreeScene::Hit> hit = bvh.intersect(ray.origin, ray.direction);
    if (!hit) return std::nullopt;
    const vis::PolygonMesh& mesh = scene.mesh;
    const Vec3 n = normalize(mesh.faceAreaNormal(hit->face));
    const Vec3 onPlane =
        hit->point - n * dot(n, hit->point - mesh.vertices[mesh.faces[hit->face][0]]);
    return PickedPoint{hit->face, onPlane};
}

}  // namespace penumbra::viewer
