// Picking: the surface point under a pixel, by casting the camera ray through the pixel centre
// into the Embree BVH (EmbreeScene::intersect). The hit (float precision in Embree) becomes the
// point the renderer takes there (shadingPoint's input: projected onto the face's plane in
// double); every query answers it at the same point as the renderer does (answeredPointOn: on the
// face's closed front side, with the contact rule decided at the projection).
#pragma once

#include <optional>

#include "app/viewer/viewport.h"
#include "engine/raytrace/embree_scene.h"
#include "engine/scene/camera.h"
#include "engine/scene/scene.h"

namespace penumbra::viewer {

struct PickedPoint {
    uint32_t face = 0;
    Vec3 point;
};

// (px, py): framebuffer pixel (top-left origin); nullopt outside the viewport or on a miss.
std::optional<PickedPoint> pickSurface(const Scene& scene, const EmbreeScene& bvh,
                                       const Camera& camera, const Viewport& viewport, double px,
                                       double py);

}  // namespace penumbra::viewer
